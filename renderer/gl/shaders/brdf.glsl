// The glTF 2.0 metallic-roughness BRDF (specification, Appendix B) in the split-sum form of
// image-based lighting: one function per formula. The DFG table they read is
// renderer/lighting/src/split_sum.cpp's.

// Reflectance at normal incidence: 0.04 for dielectrics (an index of refraction of 1.5), the
// base colour for metals, blended by metallic (glTF 2.0 Appendix B.3.5, "f0 = lerp(0.04,
// baseColor, metallic)").
vec3 specular_f0(vec3 base, float metallic) {
    return mix(vec3(0.04), base, metallic);
}

// The Lambertian lobe's colour: metals have none (glTF 2.0 Appendix B.3.5, "c_diff =
// lerp(baseColor, black, metallic)").
vec3 diffuse_color(vec3 base, float metallic) {
    return base * (1.0 - metallic);
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
// its listing for image-based lighting): the single-scattering weight FssEss = F0 A + B of the prefiltered
// radiance, and the multiple-scattering weight Fms Ems of the irradiance E / pi, with
// Ess = A + B, Ems = 1 - Ess, Favg = F0 + (1 - F0) / 21 and Fms = FssEss Favg / (1 - Ems Favg).
// A white furnace is exact with them: a white metal reflects Ess + Ems = 1.
void split_sum_weights(vec3 f0, vec2 dfg, out vec3 single_scattering,
                       out vec3 multiple_scattering) {
    single_scattering = f0 * dfg.x + dfg.y;
    float e_ms = 1.0 - (dfg.x + dfg.y);
    vec3 f_avg = f0 + (1.0 - f0) / 21.0;
    vec3 f_ms = single_scattering * f_avg / (1.0 - e_ms * f_avg);
    multiple_scattering = f_ms * e_ms;
}
