#include "oer/lighting/environment_source.hpp"

#include <array>

#include "oer/core/enum_names.hpp"
#include "oer/core/error.hpp"
#include "oer/lighting/environment_layouts.hpp"

namespace oer {

namespace {
constexpr EnumNames<EnvironmentLayout, 4> kLayoutNames = {
    {{EnvironmentLayout::Equirect, "equirect"},
     {EnvironmentLayout::Cross, "cross"},
     {EnvironmentLayout::MirrorBall, "mirror-ball"},
     {EnvironmentLayout::CubeFaces, "cube-faces"}}};
}  // namespace

std::string to_string(EnvironmentLayout layout) {
    return name_of(layout, kLayoutNames);
}

EnvironmentLayout environment_layout_from_string(const std::string& name) {
    return value_named(name, kLayoutNames, "layout");
}

namespace {

void add_counts(RepairCounts& total, const RepairCounts& more) {
    total.nan += more.nan;
    total.inf += more.inf;
    total.negative += more.negative;
}

}  // namespace

LoadedImage decode_environment(std::span<const EncodedImage> images, EnvironmentLayout layout,
                               const ImageLimits& limits) {
    const std::size_t expected = layout == EnvironmentLayout::CubeFaces ? 6 : 1;
    if (images.size() != expected) {
        throw Error(ErrorKind::InvalidInput, "layout " + to_string(layout) + " takes " +
                                                 std::to_string(expected) + " image(s), got " +
                                                 std::to_string(images.size()));
    }
    std::vector<LoadedImage> decoded;
    for (const EncodedImage& image : images) {
        decoded.push_back(load_image_memory(image.bytes, image.name, limits));
    }
    LoadedImage result;
    for (const LoadedImage& image : decoded) {
        add_counts(result.repaired, image.repaired);
    }
    const auto check_output = [&](int width) {
        if (std::uint64_t(width) * std::uint64_t(width / 2) > limits.max_pixels) {
            throw Error(
                ErrorKind::LimitExceeded,
                images[0].name + ": the resampled equirect map would exceed the pixel limit");
        }
    };
    switch (layout) {
        case EnvironmentLayout::Equirect:
            result.image = std::move(decoded[0].image);
            return result;
        case EnvironmentLayout::Cross: {
            const HdrImage& cross = decoded[0].image;
            const int face = std::min(cross.width, cross.height) / 3;
            check_output(4 * face);
            result.image = equirect_from_cross(cross, 4 * face);
            return result;
        }
        case EnvironmentLayout::MirrorBall: {
            check_output(2 * decoded[0].image.width);
            result.image = equirect_from_mirror_ball(decoded[0].image, 2 * decoded[0].image.width);
            return result;
        }
        case EnvironmentLayout::CubeFaces: {
            std::array<const HdrImage*, 6> faces{};
            for (std::size_t i = 0; i < 6; ++i) {
                faces[i] = &decoded[i].image;
            }
            check_output(4 * decoded[0].image.width);
            result.image = equirect_from_cube_faces(faces, 4 * decoded[0].image.width);
            return result;
        }
    }
    throw Error(ErrorKind::Internal, "unknown environment layout");
}

}  // namespace oer
