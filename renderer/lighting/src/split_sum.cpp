// The split sum's DFG table (split_sum.hpp). Each entry integrates the glTF specular BRDF over
// the hemisphere by GGX importance sampling of the half vector (B. Karis, "Real Shading in
// Unreal Engine 4", SIGGRAPH 2013, the listing of its section "Environment BRDF"): a half vector
// h drawn with pdf D(h) (n.h), the light l = reflect(-v, h) then has pdf D (n.h) / (4 v.h), so
// each sample weighs f_spec / F (n.l) / pdf = V (4 (n.l) (v.h) / (n.h)), where V is glTF's
// height-correlated Smith visibility, the microfacet denominator 4 (n.l)(n.v) included
// (E. Heitz, "Understanding the Masking-Shadowing Function in Microfacet-Based BRDFs", JCGT
// 3(2), 2014, eq. 99; glTF 2.0 Appendix B.3.2). The samples are a Hammersley set (radical
// inverse in base 2; oer/lighting/sampling.hpp), the same for every entry.
#include "oer/lighting/split_sum.hpp"

#include <cmath>
#include <cstdint>
#include <numbers>
#include <string>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "oer/core/error.hpp"
#include "oer/lighting/microfacet.hpp"
#include "oer/lighting/sampling.hpp"
#include "table_lookup.hpp"

namespace oer {

namespace {

// (A, B) of one entry, n = +z, v in the xz plane.
glm::dvec2 integrate(double n_dot_v, double roughness, int samples) {
    const double alpha = roughness * roughness;
    const glm::dvec3 v(std::sqrt(1.0 - n_dot_v * n_dot_v), 0.0, n_dot_v);
    glm::dvec2 sum(0.0);
    for (int i = 0; i < samples; ++i) {
        // The polar angle from the radical inverse, the azimuth from the sample's index.
        const double phi = 2.0 * std::numbers::pi * (double(i) + 0.5) / double(samples);
        const double u = sampling::radical_inverse(std::uint32_t(i));
        const glm::dvec3 h = sampling::ggx_half_vector(alpha * alpha, u, phi).direction;
        const double n_dot_h = h.z;
        const double v_dot_h = glm::dot(v, h);
        const glm::dvec3 l = 2.0 * v_dot_h * h - v;
        const double n_dot_l = l.z;
        if (n_dot_l <= 0.0 || v_dot_h <= 0.0) {
            continue;
        }
        const double weight =
            smith_visibility(n_dot_v, n_dot_l, alpha) * 4.0 * n_dot_l * v_dot_h / n_dot_h;
        const double fresnel = std::pow(1.0 - v_dot_h, 5.0);
        sum += glm::dvec2((1.0 - fresnel) * weight, fresnel * weight);
    }
    return sum / double(samples);
}

}  // namespace

DfgTable dfg_table(int size, int samples) {
    if (size < 2 || size > 256) {
        throw Error(ErrorKind::InvalidInput,
                    "dfg_table: size must be in [2, 256], got " + std::to_string(size));
    }
    if (samples < 1 || samples > 65536) {
        throw Error(ErrorKind::InvalidInput,
                    "dfg_table: samples must be in [1, 65536], got " + std::to_string(samples));
    }
    DfgTable table;
    table.size = size;
    table.scale_bias.resize(std::size_t(size) * std::size_t(size));
    for (int j = 0; j < size; ++j) {
        const double roughness = (j + 0.5) / size;
        for (int i = 0; i < size; ++i) {
            const double n_dot_v = (i + 0.5) / size;
            table.scale_bias[std::size_t(j) * std::size_t(size) + std::size_t(i)] =
                glm::vec2(integrate(n_dot_v, roughness, samples));
        }
    }
    return table;
}

glm::dvec2 sample_dfg(const DfgTable& table, double n_dot_v, double roughness) {
    return detail::bilinear_lookup(table.size, n_dot_v, roughness, [&](int column, int row) {
        return glm::dvec2(
            table.scale_bias[std::size_t(row) * std::size_t(table.size) + std::size_t(column)]);
    });
}

}  // namespace oer
