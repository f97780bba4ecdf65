#include "environment_input.hpp"

#include <algorithm>
#include <fstream>
#include <span>
#include <vector>

#include "oer/api/content_id.hpp"
#include "oer/api/invalid_parameter.hpp"
#include "oer/api/rig_options.hpp"
#include "oer/core/error.hpp"
#include "oer/lighting/default_environment.hpp"
#include "oer/lighting/environment_source.hpp"

namespace oer::cli {

namespace {

// The largest file we read into memory; the image limits then bound what it may decode to.
constexpr std::uintmax_t kMaxFileBytes = 2ull << 30;

std::vector<std::byte> read_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        throw Error(ErrorKind::Io, path + ": cannot open file");
    }
    in.seekg(0, std::ios::end);
    const std::streamoff size = in.tellg();
    if (size < 0) {
        throw Error(ErrorKind::Io, path + ": cannot read file (is it a directory?)");
    }
    if (std::uintmax_t(size) > kMaxFileBytes) {
        throw Error(ErrorKind::LimitExceeded, path + ": file is " + std::to_string(size) +
                                                  " bytes, over the limit of " +
                                                  std::to_string(kMaxFileBytes));
    }
    in.seekg(0);
    std::vector<std::byte> bytes(static_cast<std::size_t>(size));
    if (!in.read(reinterpret_cast<char*>(bytes.data()), size)) {
        throw Error(ErrorKind::Io, path + ": read failed");
    }
    return bytes;
}

std::vector<std::string> split(const std::string& text, char separator) {
    std::vector<std::string> parts;
    std::size_t start = 0;
    while (true) {
        const std::size_t end = text.find(separator, start);
        parts.push_back(text.substr(start, end - start));
        if (end == std::string::npos) {
            return parts;
        }
        start = end + 1;
    }
}

std::string option_to_flag(std::string option) {
    std::replace(option.begin(), option.end(), '_', '-');
    return option;
}

}  // namespace

void add_environment_flags(CLI::App& app, EnvironmentFlags& flags) {
    add_value_flag(app, "layout", "equirect|cross|mirror-ball|cube-faces",
                   [&flags](const std::string& text) { flags.layout = text; });
    add_value_flag(app, "max-pixels", "WxH",
                   [&flags](const std::string& text) { flags.max_pixels = text; });
    for (const std::string& option : api::rig_option_names()) {
        add_value_flag(
            app, option_to_flag(option), "VALUE",
            [&flags, option](const std::string& text) { flags.rig_options[option] = text; });
    }
}

EnvironmentInput read_environment(const std::string& map, const EnvironmentFlags& flags) {
    ImageLimits limits;
    if (const auto& max_pixels = flags.max_pixels) {
        const auto [width, height] = parse_size("max-pixels", *max_pixels, 1 << 20);
        limits.max_pixels = std::uint64_t(width) * std::uint64_t(height);
    }
    const EnvironmentLayout layout =
        environment_layout_from_string(flags.layout.value_or("equirect"));
    EnvironmentInput input;
    if (map == "default") {
        if (layout != EnvironmentLayout::Equirect) {
            throw UsageError("the built-in default environment takes no --layout");
        }
        input.loaded.image = make_default_environment();
        input.digest = api::sha256_hex(std::string_view("oer-builtin:default-studio:v1"));
        return input;
    }
    const std::vector<std::string> paths =
        layout == EnvironmentLayout::CubeFaces ? split(map, ',') : std::vector<std::string>{map};
    std::vector<std::vector<std::byte>> contents;
    std::vector<EncodedImage> encoded;
    std::string digests;
    for (const std::string& path : paths) {
        contents.push_back(read_file(path));
        digests += api::sha256_hex(contents.back());
    }
    for (std::size_t i = 0; i < paths.size(); ++i) {
        encoded.push_back({paths[i], contents[i]});
    }
    input.loaded = decode_environment(encoded, layout, limits);
    input.digest = paths.size() == 1 ? digests : api::sha256_hex(std::string_view(digests));
    return input;
}

RigOptions rig_options_from(const EnvironmentFlags& flags) {
    try {
        return api::parse_rig_options(flags.rig_options);
    } catch (const api::InvalidParameter& error) {
        throw usage_error(error);
    }
}

}  // namespace oer::cli
