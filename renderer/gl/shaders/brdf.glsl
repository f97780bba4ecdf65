// The glTF 2.0 metallic-roughness BRDF (specification, Appendix B) in the split-sum form of
// image-based lighting: one function per formula. The DFG table they read is
// renderer/lighting/src/split_sum.cpp's.
#include "math_constants.glsl"

// The layers of the glTF material extensions at a surface point (mesh.hpp's Material layers,
// docs/materials.md), as the BRDF uses them; plain_layers() is the core model's, which the
// deferred shading and every material without layers use.
struct SurfaceLayers {
    float ior;              // the dielectric's index of refraction
    vec3 dielectric_f0;     // its reflectance at normal incidence
    float dielectric_f90;   // and at grazing incidence
    float clearcoat;        // the coat's weight
    float clearcoat_roughness;
    vec3 clearcoat_normal;  // unit, on the side seen
    vec3 sheen_color;
    float sheen_roughness;
    float transmission;         // the share of the dielectric's diffuse lobe transmitted
    vec3 volume_transmittance;  // of the light transmitted, through the volume's thickness
};

// The reflectance at normal incidence of a dielectric of index ior in air (KHR_materials_ior:
// ((ior - 1) / (ior + 1))^2, 0.04 at glTF's 1.5; ior 0, the extension's special case, gives 1).
float ior_f0(float ior) {
    float r = (ior - 1.0) / (ior + 1.0);
    return r * r;
}

// KHR_materials_specular: f0 = min(f0(ior) specularColor, 1) specular and f90 = specular, the
// specular factor and texture weighting the whole dielectric reflection.
SurfaceLayers material_layers(float ior, float specular, vec3 specular_color, float clearcoat,
                              float clearcoat_roughness, vec3 clearcoat_normal, vec3 sheen_color,
                              float sheen_roughness, float transmission,
                              vec3 volume_transmittance) {
    return SurfaceLayers(ior, min(vec3(ior_f0(ior)) * specular_color, vec3(1.0)) * specular,
                         specular,
                         clearcoat, clearcoat_roughness, clearcoat_normal, sheen_color,
                         sheen_roughness, transmission, volume_transmittance);
}

// glTF 2.0's core model: f0 0.04 (an index of refraction of 1.5), f90 1, no layer.
SurfaceLayers plain_layers() {
    return SurfaceLayers(1.5, vec3(0.04), 1.0, 0.0, 0.0, vec3(0.0, 0.0, 1.0), vec3(0.0), 0.0, 0.0,
                         vec3(1.0));
}

// Reflectance at normal incidence: the dielectric's (0.04 without layers), the base colour for
// metals, blended by metallic (glTF 2.0 Appendix B.3.5, "f0 = lerp(0.04, baseColor,
// metallic)"); likewise at grazing incidence, where metals reflect everything.
vec3 specular_f0(SurfaceLayers layers, vec3 base, float metallic) {
    return mix(layers.dielectric_f0, base, metallic);
}
float specular_f90(SurfaceLayers layers, float metallic) {
    return mix(layers.dielectric_f90, 1.0, metallic);
}

// The clear coat's directional albedo, its Fresnel averaged over its GGX lobe: the split sum's
// single scattering at f0 0.04 (an index of 1.5) and F90 1, E_c = 0.04 A + B. It weights the
// coat's reflection and attenuates what lies beneath, 1 - clearcoat E_c: the coat's Fresnel over
// its lobe where KHR_materials_clearcoat's reference shader takes Schlick's at n.v, so that a
// white coat over a white base keeps a white furnace's energy exactly.
float clearcoat_albedo(vec2 dfg) {
    return 0.04 * dfg.x + dfg.y;
}

// The volume's Beer-Lambert transmittance over a thickness (KHR_materials_volume: attenuation
// coefficient -ln(attenuationColor) / attenuationDistance), 1 for a thin wall (thickness 0).
vec3 volume_transmittance(vec3 attenuation_coefficient, float thickness) {
    return thickness > 0.0 ? exp(-attenuation_coefficient * thickness) : vec3(1.0);
}

// The roughness of the transmitted lobe: a thin wall's two interfaces blur as the surface's
// roughness scaled by how much the index bends light, roughness clamp(2 ior - 2, 0, 1) (the
// Khronos glTF-Sample-Viewer's applyIorToRoughness for KHR_materials_transmission): no blur at
// an index of 1.
float transmission_roughness(float roughness, float ior) {
    return roughness * clamp(2.0 * ior - 2.0, 0.0, 1.0);
}

// KHR_materials_sheen's albedo scaling of the material under the sheen: 1 - max(sheenColor)
// E_sheen(n.v), E_sheen the sheen lobe's directional albedo
// (renderer/lighting/include/oer/lighting/sheen_albedo.hpp).
float sheen_albedo_scaling(vec3 sheen_color, float sheen_albedo) {
    return 1.0 - max(sheen_color.r, max(sheen_color.g, sheen_color.b)) * sheen_albedo;
}

// The Lambertian lobe's colour: metals have none (glTF 2.0 Appendix B.3.5, "c_diff =
// lerp(baseColor, black, metallic)").
vec3 diffuse_color(vec3 base, float metallic) {
    return base * (1.0 - metallic);
}

// GGX's normal distribution D(h) from cos^2 of h's angle to the normal, alpha = roughness^2
// (B. Walter, S. Marschner, H. Li and K. Torrance, "Microfacet Models for Refraction through
// Rough Surfaces", EGSR 2007); renderer/lighting/src/sampling.cpp's ggx_distribution.
float ggx_distribution(float alpha, float cos2_theta) {
    float a2 = alpha * alpha;
    float denominator = cos2_theta * (a2 - 1.0) + 1.0;
    return a2 / (PI * denominator * denominator);
}

// The height-correlated Smith visibility G2 / (4 n.l n.v) (E. Heitz, "Understanding the
// Masking-Shadowing Function in Microfacet-Based BRDFs", JCGT 3(2), 2014);
// renderer/lighting/src/microfacet.cpp's smith_visibility.
float smith_visibility(float n_dot_v, float n_dot_l, float alpha) {
    float a2 = alpha * alpha;
    float view = n_dot_l * sqrt(n_dot_v * n_dot_v * (1.0 - a2) + a2);
    float light = n_dot_v * sqrt(n_dot_l * n_dot_l * (1.0 - a2) + a2);
    return 0.5 / (view + light);
}

// Schlick's Fresnel between f0 and f90 at v.h (glTF 2.0 Appendix B.3.4).
vec3 schlick_fresnel(vec3 f0, float f90, float v_dot_h) {
    return f0 + (f90 - f0) * pow(1.0 - clamp(v_dot_h, 0.0, 1.0), 5.0);
}

// Z(alpha), the integral of the prefiltering kernel D(h) (r.l) with n = v = r, in closed form:
// prefilter_kernel_integral (renderer/lighting/include/oer/lighting/specular_environment.hpp).
float prefilter_kernel_integral(float alpha) {
    float a2 = alpha * alpha;
    if (a2 > 0.999) {
        return 1.0 + 2.0 / 3.0 * (1.0 - a2);
    }
    float d = a2 - 1.0;
    return 8.0 * a2 / (d * d) * (log(2.0 * a2 / (1.0 + a2)) + (1.0 - a2) / (2.0 * a2));
}

// The direction the split sum's prefiltered radiance is read along: its lobe, prefiltered with
// n = v = r, is centred on the mirror direction r, where the BRDF's leans towards the normal as
// the lobe widens, all the more at grazing view (the off-specular peak). Lagarde and de Rousiers,
// "Moving Frostbite to Physically Based Rendering", SIGGRAPH 2014 course, section 4.9.3,
// listing 22: r at alpha 0, n at alpha 1, between them by (1 - alpha)(sqrt(1 - alpha) + alpha).
vec3 specular_dominant_direction(vec3 n, vec3 r, float alpha) {
    float smoothness = 1.0 - alpha;
    return normalize(mix(n, r, smoothness * (sqrt(smoothness) + alpha)));
}

// The share of the reflected environment that ambient occlusion leaves, from the occlusion of
// the diffuse light (S. Lagarde and C. de Rousiers, "Moving Frostbite to Physically Based
// Rendering 3.0", SIGGRAPH 2014 course notes, section 4.10.2, with their roughness as
// alpha): saturate((n.v + ao)^(2^(-16 alpha - 1)) - 1 + ao).
float specular_occlusion(float n_dot_v, float ao, float alpha) {
    return clamp(pow(n_dot_v + ao, exp2(-16.0 * alpha - 1.0)) - 1.0 + ao, 0.0, 1.0);
}

// The split sum's energy weights with multiple scattering (C. Fdez-Aguera, "A
// Multiple-Scattering Microfacet Model for Real-Time Image-based Lighting", JCGT 8(1), 2019,
// its listing for image-based lighting): the single-scattering weight FssEss = F0 A + F90 B of
// the prefiltered radiance, and the multiple-scattering weight Fms Ems of the irradiance E / pi,
// with Ess = A + B, Ems = 1 - Ess, Favg = F0 + (F90 - F0) / 21 and Fms = FssEss Favg / (1 - Ems
// Favg) (F90 is 1 but under KHR_materials_specular, whose factor scales it). A white furnace is
// exact with them: a white metal reflects Ess + Ems = 1.
void split_sum_weights(vec3 f0, float f90, vec2 dfg, out vec3 single_scattering,
                       out vec3 multiple_scattering) {
    single_scattering = f0 * dfg.x + f90 * dfg.y;
    float e_ms = 1.0 - (dfg.x + dfg.y);
    vec3 f_avg = f0 + (f90 - f0) / 21.0;
    vec3 f_ms = single_scattering * f_avg / (1.0 - e_ms * f_avg);
    multiple_scattering = f_ms * e_ms;
}
