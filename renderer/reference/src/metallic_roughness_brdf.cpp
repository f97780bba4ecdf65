#include "oer/reference/metallic_roughness_brdf.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include <glm/geometric.hpp>

#include "oer/lighting/light_location.hpp"
#include "oer/lighting/microfacet.hpp"
#include "oer/lighting/sampling.hpp"
#include "oer/lighting/split_sum.hpp"

namespace oer::reference {

namespace {

using std::numbers::pi;

// The split sum's (A, B) at 64 x 64 entries of 4096 samples (the rasteriser's is 32 x 32 of
// 1024: the reference's furnace must be exact to well under a percent at grazing angles), and
// per row its cosine-weighted averages 2 integral (A, B)(mu) mu dmu by the midpoint rule on the
// row's own entries. Built once per process (about 0.3 s).
struct AlbedoTables {
    DfgTable table = dfg_table(64, 4096);
    std::vector<glm::dvec2> row_averages;

    AlbedoTables() {
        const int size = table.size;
        for (int j = 0; j < size; ++j) {
            glm::dvec2 sum(0.0);
            for (int i = 0; i < size; ++i) {
                const double mu = (i + 0.5) / size;
                sum += glm::dvec2(table.scale_bias[std::size_t(j * size + i)]) * mu;
            }
            row_averages.push_back(2.0 * sum / double(size));
        }
    }

    // (A_avg, B_avg) at a roughness, linear between rows as sample_dfg reads them.
    glm::dvec2 average(double roughness) const {
        const int size = table.size;
        const double x = std::clamp(roughness * size - 0.5, 0.0, double(size - 1));
        const int low = std::min(int(x), size - 2);
        return glm::mix(row_averages[std::size_t(low)], row_averages[std::size_t(low + 1)],
                        x - low);
    }
};

const AlbedoTables& albedo_tables() {
    static const AlbedoTables tables;
    return tables;
}

}  // namespace

double ggx_alpha(double roughness) {
    return std::max(roughness * roughness, 1e-4);
}

MetallicRoughnessBrdf::MetallicRoughnessBrdf(const SurfaceMaterial& material, const glm::dvec3& n,
                                             const glm::dvec3& v)
    : material_(material), n_(n), v_(v) {
    n_dot_v_ = glm::dot(n, v);
    if (n_dot_v_ < 1e-4) {
        // Bent into the hemisphere to n.v = 1e-4 (the sampled lobe needs v above it).
        v_ = glm::normalize(v - n * n_dot_v_ + n * 1e-4 * glm::length(v - n * n_dot_v_));
        n_dot_v_ = glm::dot(n, v_);
    }
    if (!material.glossy) {
        diffuse_color_ = material.base_color;
        return;
    }
    alpha_ = ggx_alpha(material.roughness);
    f0_ = glm::mix(glm::dvec3(0.04), material.base_color, material.metallic);
    diffuse_color_ = material.base_color * (1.0 - material.metallic);
    const AlbedoTables& tables = albedo_tables();
    const glm::dvec2 average = tables.average(material.roughness);
    white_albedo_average_ = average.x + average.y;
    const glm::dvec3 fresnel_average = f0_ + (1.0 - f0_) / 21.0;
    if (white_albedo_average_ < 1.0 - 1e-9) {
        multiple_scattering_fresnel_ = fresnel_average * fresnel_average * white_albedo_average_ /
                                       (1.0 - fresnel_average * (1.0 - white_albedo_average_));
    }
    const glm::dvec2 at_v = sample_dfg(tables.table, n_dot_v_, material.roughness);
    white_albedo_v_ = at_v.x + at_v.y;
    specular_albedo_v_ = specular_albedo(at_v);
    specular_albedo_average_ = specular_albedo(average);
    const glm::dvec3 single_scattering = f0_ * at_v.x + at_v.y;
    const double total =
        luminance(specular_albedo_v_ + diffuse_color_ * (1.0 - specular_albedo_v_));
    specular_share_ =
        total > 0.0 ? std::clamp(luminance(single_scattering) / total, 0.0, 1.0) : 1.0;
}

glm::dvec3 MetallicRoughnessBrdf::specular_albedo(const glm::dvec2& scale_bias) const {
    return f0_ * scale_bias.x + scale_bias.y +
           multiple_scattering_fresnel_ * (1.0 - (scale_bias.x + scale_bias.y));
}

glm::dvec3 MetallicRoughnessBrdf::evaluate(const glm::dvec3& l) const {
    const double n_dot_l = glm::dot(n_, l);
    if (n_dot_l <= 0.0) {
        return glm::dvec3(0.0);
    }
    if (!material_.glossy) {
        return diffuse_color_ / pi;
    }
    const glm::dvec3 h = glm::normalize(v_ + l);
    const double v_dot_h = std::max(glm::dot(v_, h), 0.0);
    const double n_dot_h = glm::dot(n_, h);
    const glm::dvec3 fresnel = f0_ + (1.0 - f0_) * std::pow(1.0 - v_dot_h, 5.0);
    glm::dvec3 f = fresnel * sampling::ggx_distribution(alpha_ * alpha_, n_dot_h * n_dot_h) *
                   smith_visibility(n_dot_v_, n_dot_l, alpha_);
    const glm::dvec2 at_l = sample_dfg(albedo_tables().table, n_dot_l, material_.roughness);
    if (white_albedo_average_ < 1.0 - 1e-9) {
        f += multiple_scattering_fresnel_ * ((1.0 - white_albedo_v_) * (1.0 - (at_l.x + at_l.y)) /
                                             (pi * (1.0 - white_albedo_average_)));
    }
    f += diffuse_color_ / pi * (1.0 - specular_albedo_v_) * (1.0 - specular_albedo(at_l)) /
         glm::max(1.0 - specular_albedo_average_, glm::dvec3(1e-9));
    return f;
}

double MetallicRoughnessBrdf::vndf_pdf(const glm::dvec3& l) const {
    const glm::dvec3 h = glm::normalize(v_ + l);
    const double n_dot_h = glm::dot(n_, h);
    // D_v(h) / (4 v.h) = G1(v) D(h) / (4 n.v): the reflection's Jacobian 1 / (4 v.h).
    return smith_masking(n_dot_v_, alpha_) *
           sampling::ggx_distribution(alpha_ * alpha_, n_dot_h * n_dot_h) / (4.0 * n_dot_v_);
}

double MetallicRoughnessBrdf::pdf(const glm::dvec3& l) const {
    const double n_dot_l = glm::dot(n_, l);
    if (n_dot_l <= 0.0) {
        return 0.0;
    }
    const double cosine = n_dot_l / pi;
    if (specular_share_ <= 0.0) {
        return cosine;
    }
    return specular_share_ * vndf_pdf(l) + (1.0 - specular_share_) * cosine;
}

std::optional<BrdfSample> MetallicRoughnessBrdf::sample(double u_lobe, double u1, double u2) const {
    glm::dvec3 l;
    if (u_lobe < specular_share_) {
        const sampling::TangentFrame frame = sampling::tangent_frame(n_);
        const glm::dvec3 v_local(glm::dot(v_, frame.t), glm::dot(v_, frame.s), n_dot_v_);
        const glm::dvec3 h_local = sampling::ggx_visible_normal(v_local, alpha_, u1, u2);
        const glm::dvec3 h = h_local.x * frame.t + h_local.y * frame.s + h_local.z * n_;
        l = glm::reflect(-v_, h);
    } else {
        l = sampling::cosine_direction(n_, u1, u2);
    }
    const double density = pdf(l);
    if (!(density > 0.0)) {
        return std::nullopt;
    }
    return BrdfSample{l, evaluate(l) * (glm::dot(n_, l) / density), density};
}

glm::dvec3 MetallicRoughnessBrdf::directional_albedo() const {
    if (!material_.glossy) {
        return diffuse_color_;
    }
    return specular_albedo_v_ + diffuse_color_ * (1.0 - specular_albedo_v_);
}

}  // namespace oer::reference
