#pragma once
// The glTF 2.0 metallic-roughness BRDF (specification, Appendix B) as the reference renderer
// evaluates and samples it: the ground truth of glossy frames.
//
//   f(v, l) = f_ss + f_ms + f_diffuse,
//   f_ss = F(v.h) D(h) V(v, l): GGX D, height-correlated Smith V, Schlick's
//          F = f0 + (1 - f0)(1 - v.h)^5, f0 = lerp(0.04, base, metallic) (Appendix B.3);
//   f_ms = F_ms (1 - E1(n.v)) (1 - E1(n.l)) / (pi (1 - E1_avg)): the energy single scattering
//          loses, given back as a lobe of its own (C. Kulla and A. Conty, "Revisiting Physically
//          Based Shading at Imageworks", SIGGRAPH 2017 course notes), E1 the directional albedo
//          of f_ss for a white metal, E1_avg = 2 integral E1(mu) mu dmu and
//          F_ms = F_avg^2 E1_avg / (1 - F_avg (1 - E1_avg)), F_avg = f0 + (1 - f0) / 21;
//   f_diffuse = c_diff / pi (1 - E(n.v)) (1 - E(n.l)) / (1 - E_avg): the Lambertian lobe under
//          what the specular lobes do not reflect, both ways (C. Kelemen and L. Szirmay-Kalos,
//          "A Microfacet Based Coupled Specular-Matte BRDF Model with Importance Sampling",
//          Eurographics 2001), E = E_ss + E_ms the specular albedo, c_diff = base (1 - metallic).
// Every term is symmetric in v and l, so f is reciprocal, and a white furnace is exact: a white
// metal reflects E1 + (1 - E1) = 1 and a white dielectric E + (1 - E) = 1 at every angle.
//
// How it differs from the rasteriser (renderer/gl/shaders/brdf.glsl), on purpose: there the
// multiple scattering is C. Fdez-Aguera's (JCGT 2019) F_ms E_ms at n.v, which also makes a white
// furnace exact but weights colour differently (F_ms = FssEss F_avg / (1 - E_ms F_avg)); and the
// diffuse lobe is weighted by (1 - E(n.v)) alone, which is not reciprocal. docs/glossy-reference.md
// gives both and the measured size of the difference.
//
// E1, E_ss and E come from the split sum's table (oer/lighting/split_sum.hpp: E_ss = f0 A + B)
// at a finer resolution than the rasteriser's. Sampling: with the share of E_ss in the
// directional albedo, the specular lobe by GGX's visible normals (E. Heitz, "Sampling the GGX
// Distribution of Visible Normals", JCGT 7(4), 2018), otherwise the cosine lobe; the density is
// the mixture of both (one-sample multiple importance sampling, balance heuristic).
#include <optional>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace oer::reference {

// A surface point's material, read as the rasteriser reads it (material.glsl).
struct SurfaceMaterial {
    glm::dvec3 base_color{0.0};  // linear; a Lambertian material's albedo
    double metallic = 0.0;
    double roughness = 1.0;  // perceptual; GGX's alpha is its square
    bool glossy = false;     // false: Lambertian, f = base / pi
};

// The GGX alpha of a perceptual roughness, kept above 1e-4 so that a roughness of 0 is a mirror
// to well under a hundredth of a degree while D stays finite.
double ggx_alpha(double roughness);

struct BrdfSample {
    glm::dvec3 direction;  // unit
    glm::dvec3 weight;     // f (n.l) / pdf
    double pdf = 0.0;      // per steradian
};

class MetallicRoughnessBrdf {
  public:
    // n: the unit shading normal; v: the unit direction towards the viewer. A v under the
    // shading normal's horizon (interpolated normals) is read at n.v = 1e-4, as the rasteriser
    // clamps it.
    MetallicRoughnessBrdf(const SurfaceMaterial& material, const glm::dvec3& n,
                          const glm::dvec3& v);

    // f(v, l) per steradian (0 for l under the horizon).
    glm::dvec3 evaluate(const glm::dvec3& l) const;
    // The density sample() draws l with.
    double pdf(const glm::dvec3& l) const;
    // u_lobe chooses the lobe and (u1, u2) the direction, all uniform in [0, 1); nullopt where
    // the drawn direction is under the horizon (the estimate is then 0).
    std::optional<BrdfSample> sample(double u_lobe, double u1, double u2) const;
    // The integral of f (n.l) over l: what a white furnace reflects towards v.
    glm::dvec3 directional_albedo() const;

  private:
    double vndf_pdf(const glm::dvec3& l) const;
    // E = f0 A + B + F_ms (1 - (A + B)) of a table entry (A, B): at one angle, or averaged
    // over the hemisphere (E_avg, from the averages of A and B, which E is linear in).
    glm::dvec3 specular_albedo(const glm::dvec2& scale_bias) const;

    SurfaceMaterial material_;
    glm::dvec3 n_, v_;
    double n_dot_v_ = 1.0;
    double alpha_ = 1.0;
    glm::dvec3 f0_{0.0};
    glm::dvec3 diffuse_color_{0.0};
    glm::dvec3 multiple_scattering_fresnel_{0.0};  // F_ms
    double white_albedo_v_ = 1.0;                  // E1(n.v)
    double white_albedo_average_ = 1.0;            // E1_avg
    glm::dvec3 specular_albedo_v_{0.0};            // E(n.v)
    glm::dvec3 specular_albedo_average_{0.0};      // E_avg
    double specular_share_ = 0.0;                  // the chance of sampling the GGX lobe
};

}  // namespace oer::reference
