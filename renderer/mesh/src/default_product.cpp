// The built-in default product (see oer/default_product.hpp): a dress form made of surfaces of
// revolution. A torso lathed from a profile through hips, waist, bust, shoulders and neck,
// with separate half-widths in x and z (wider than deep) interpolated without overshoot; a
// pole; a round base. Every part is closed by flat caps, wound counter-clockwise seen from
// outside, with analytic normals (smooth along each surface, sharp where a cap meets it).
#include "oer/mesh/default_product.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "mesh_finishing.hpp"

namespace oer {

namespace {

// A horizontal elliptical ring of a surface of revolution, with the rate of change of its
// half-widths with height (for the normals).
struct Ring {
    float y;
    float rx;
    float rz;
    float drx_dy = 0.0f;
    float drz_dy = 0.0f;
};

// The torso's profile: height, half-width in x, half-depth in z (metres, roughly a
// dress form of European size 38).
struct ProfilePoint {
    double y;
    double rx;
    double rz;
};

constexpr std::array<ProfilePoint, 14> torso_profile{{
    {0.900, 0.150, 0.115},  // lower edge
    {0.960, 0.178, 0.135},  // hips
    {1.030, 0.172, 0.128},
    {1.120, 0.145, 0.105},
    {1.180, 0.130, 0.095},  // waist
    {1.250, 0.145, 0.110},
    {1.320, 0.165, 0.125},  // bust
    {1.380, 0.163, 0.115},
    {1.440, 0.185, 0.105},  // shoulders
    {1.480, 0.175, 0.095},
    {1.510, 0.130, 0.080},
    {1.535, 0.070, 0.060},
    {1.550, 0.052, 0.050},  // neck
    {1.600, 0.048, 0.048},  // neck top
}};

// Monotone cubic (Fritsch-Carlson) interpolation of one column of the profile as a function
// of y: no overshoot, so the waist stays the narrowest point between hips and bust.
class MonotoneCubic {
  public:
    MonotoneCubic(std::vector<double> x, std::vector<double> f)
        : x_(std::move(x)), f_(std::move(f)), m_(x_.size(), 0.0) {
        const std::size_t n = x_.size();
        std::vector<double> secant(n - 1);
        for (std::size_t k = 0; k + 1 < n; ++k) {
            secant[k] = (f_[k + 1] - f_[k]) / (x_[k + 1] - x_[k]);
        }
        m_[0] = secant[0];
        m_[n - 1] = secant[n - 2];
        for (std::size_t k = 1; k + 1 < n; ++k) {
            m_[k] = secant[k - 1] * secant[k] > 0.0 ? (secant[k - 1] + secant[k]) / 2.0 : 0.0;
        }
        for (std::size_t k = 0; k + 1 < n; ++k) {
            if (secant[k] == 0.0) {
                m_[k] = m_[k + 1] = 0.0;
                continue;
            }
            const double alpha = m_[k] / secant[k];
            const double beta = m_[k + 1] / secant[k];
            const double norm = alpha * alpha + beta * beta;
            if (norm > 9.0) {
                const double tau = 3.0 / std::sqrt(norm);
                m_[k] = tau * alpha * secant[k];
                m_[k + 1] = tau * beta * secant[k];
            }
        }
    }

    // The value and its derivative at y (clamped to the profile's range).
    std::pair<double, double> operator()(double y) const {
        std::size_t k = 0;
        while (k + 2 < x_.size() && y > x_[k + 1]) {
            ++k;
        }
        const double h = x_[k + 1] - x_[k];
        const double t = std::clamp((y - x_[k]) / h, 0.0, 1.0);
        const double t2 = t * t;
        const double t3 = t2 * t;
        const double value = (2 * t3 - 3 * t2 + 1) * f_[k] + (t3 - 2 * t2 + t) * h * m_[k] +
                             (-2 * t3 + 3 * t2) * f_[k + 1] + (t3 - t2) * h * m_[k + 1];
        const double slope = ((6 * t2 - 6 * t) * f_[k] + (3 * t2 - 4 * t + 1) * h * m_[k] +
                              (-6 * t2 + 6 * t) * f_[k + 1] + (3 * t2 - 2 * t) * h * m_[k + 1]) /
                             h;
        return {value, slope};
    }

  private:
    std::vector<double> x_;
    std::vector<double> f_;
    std::vector<double> m_;
};

// The torso's rings, spaced evenly along the profile's length (so that the steep shoulders
// get as many rings as the gentle waist).
std::vector<Ring> torso_rings(int count) {
    std::vector<double> ys;
    std::vector<double> rxs;
    std::vector<double> rzs;
    for (const ProfilePoint& p : torso_profile) {
        ys.push_back(p.y);
        rxs.push_back(p.rx);
        rzs.push_back(p.rz);
    }
    const MonotoneCubic rx(ys, rxs);
    const MonotoneCubic rz(ys, rzs);
    const double y0 = ys.front();
    const double y1 = ys.back();

    constexpr int fine = 4000;
    std::vector<double> length(fine + 1, 0.0);
    for (int i = 1; i <= fine; ++i) {
        const double ya = y0 + (y1 - y0) * (i - 1) / fine;
        const double yb = y0 + (y1 - y0) * i / fine;
        const double ra = (rx(ya).first + rz(ya).first) / 2.0;
        const double rb = (rx(yb).first + rz(yb).first) / 2.0;
        length[std::size_t(i)] = length[std::size_t(i - 1)] + std::hypot(yb - ya, rb - ra);
    }
    std::vector<Ring> rings;
    std::size_t i = 0;
    for (int r = 0; r < count; ++r) {
        const double target = length[fine] * r / (count - 1);
        while (i + 1 < length.size() && length[i + 1] < target) {
            ++i;
        }
        double y = y1;
        if (r < count - 1) {
            const double span = length[i + 1] - length[i];
            const double t = span > 0.0 ? (target - length[i]) / span : 0.0;
            y = y0 + (y1 - y0) * (double(i) + t) / fine;
        }
        if (r == 0) {
            y = y0;
        }
        const auto [x_value, x_slope] = rx(y);
        const auto [z_value, z_slope] = rz(y);
        rings.push_back(
            Ring{float(y), float(x_value), float(z_value), float(x_slope), float(z_slope)});
    }
    return rings;
}

glm::vec3 ring_point(const Ring& ring, float cos_t, float sin_t) {
    return glm::vec3(ring.rx * cos_t, ring.y, ring.rz * sin_t);
}

// A closed surface of revolution through `rings` (bottom to top), `segments` around, with a
// flat cap at each end. Side normals are d/dy x d/dtheta of (rx cos t, y, rz sin t).
void add_lathe(Primitive& primitive, const std::vector<Ring>& rings, int segments) {
    const auto s = std::uint32_t(segments);
    std::vector<float> cosines(s);
    std::vector<float> sines(s);
    for (std::uint32_t j = 0; j < s; ++j) {
        const double theta = 2.0 * std::numbers::pi * j / segments;
        cosines[j] = float(std::cos(theta));
        sines[j] = float(std::sin(theta));
    }
    auto add_vertex = [&](const glm::vec3& position, const glm::vec3& normal) {
        primitive.positions.push_back(position);
        primitive.normals.push_back(normal);
        return std::uint32_t(primitive.positions.size() - 1);
    };
    auto add_triangle = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
        primitive.indices.insert(primitive.indices.end(), {a, b, c});
    };

    // The side.
    const auto side = std::uint32_t(primitive.positions.size());
    for (const Ring& ring : rings) {
        for (std::uint32_t j = 0; j < s; ++j) {
            const float c = cosines[j];
            const float n = sines[j];
            const glm::vec3 normal(ring.rz * c,
                                   -(ring.rx * ring.drz_dy * n * n + ring.drx_dy * ring.rz * c * c),
                                   ring.rx * n);
            add_vertex(ring_point(ring, c, n), glm::normalize(normal));
        }
    }
    for (std::uint32_t i = 0; i + 1 < rings.size(); ++i) {
        for (std::uint32_t j = 0; j < s; ++j) {
            const std::uint32_t a = side + i * s + j;
            const std::uint32_t b = side + i * s + (j + 1) % s;
            const std::uint32_t c = side + (i + 1) * s + j;
            const std::uint32_t d = side + (i + 1) * s + (j + 1) % s;
            add_triangle(a, c, b);
            add_triangle(b, c, d);
        }
    }

    // The caps: a fan around the centre, facing down at the bottom and up at the top.
    for (const bool top : {false, true}) {
        const Ring& ring = top ? rings.back() : rings.front();
        const glm::vec3 normal(0.0f, top ? 1.0f : -1.0f, 0.0f);
        const std::uint32_t centre = add_vertex(glm::vec3(0.0f, ring.y, 0.0f), normal);
        const auto edge = std::uint32_t(primitive.positions.size());
        for (std::uint32_t j = 0; j < s; ++j) {
            add_vertex(ring_point(ring, cosines[j], sines[j]), normal);
        }
        for (std::uint32_t j = 0; j < s; ++j) {
            const std::uint32_t p = edge + j;
            const std::uint32_t q = edge + (j + 1) % s;
            if (top) {
                add_triangle(centre, q, p);
            } else {
                add_triangle(centre, p, q);
            }
        }
    }
}

std::vector<Ring> cylinder(float y0, float y1, float radius) {
    return {Ring{y0, radius, radius}, Ring{y1, radius, radius}};
}

}  // namespace

Mesh make_default_product() {
    Mesh mesh;
    Material fabric;
    fabric.name = "dress form fabric";
    fabric.base_color = glm::vec4(0.85f, 0.80f, 0.75f, 1.0f);
    fabric.metallic = 0.0f;
    fabric.roughness = 0.9f;
    fabric.model = ShadingModel::Lambertian;
    fabric.double_sided = true;
    Material stand;
    stand.name = "dress form stand";
    stand.base_color = glm::vec4(0.10f, 0.10f, 0.10f, 1.0f);
    stand.metallic = 0.0f;
    stand.roughness = 0.35f;
    stand.model = ShadingModel::MetallicRoughness;
    stand.double_sided = true;
    mesh.materials = {fabric, stand};

    Primitive torso;
    torso.name = "dress form torso";
    torso.material = 0;
    add_lathe(torso, torso_rings(48), 64);

    Primitive base;
    base.name = "dress form stand";
    base.material = 1;
    add_lathe(base, cylinder(0.0f, 0.03f, 0.3f), 64);     // the round base
    add_lathe(base, cylinder(0.02f, 0.92f, 0.012f), 24);  // the pole, into both

    mesh.primitives.push_back(std::move(torso));
    mesh.primitives.push_back(std::move(base));
    mesh_detail::finish_mesh(mesh, "default product", MeshLimits{});
    return mesh;
}

}  // namespace oer
