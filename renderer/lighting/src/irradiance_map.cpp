#include "oer/lighting/irradiance_map.hpp"

#include "oer/lighting/equirect.hpp"
#include "oer/lighting/reference_irradiance.hpp"

namespace oer {

HdrImage irradiance_map_from_sh(const ShRgb& irradiance, int width, int height) {
    HdrImage out(width, height);
    const equirect::Grid grid(width, height);
    for (std::size_t i = 0; i < out.pixel_count(); ++i) {
        out.set(i, glm::vec3(irradiance.evaluate(grid.direction(i))));
    }
    return out;
}

HdrImage irradiance_map_exact(const HdrImage& environment_map, int width, int height,
                              std::size_t reference_samples) {
    const ReferenceIrradiance reference(environment_map, reference_samples);
    const equirect::Grid grid(width, height);
    std::vector<glm::dvec3> normals(std::size_t(width) * height);
    for (std::size_t i = 0; i < normals.size(); ++i) {
        normals[i] = grid.direction(i);
    }
    const std::vector<glm::dvec3> values = reference.at(normals);
    HdrImage out(width, height);
    for (std::size_t i = 0; i < values.size(); ++i) {
        out.set(i, glm::vec3(values[i]));
    }
    return out;
}

}  // namespace oer
