#include "frame_programs.hpp"

#include <algorithm>
#include <charconv>
#include <map>
#include <string>

#include "oer/core/error.hpp"
#include "oer/lighting/sh.hpp"

namespace oer::shaders {

namespace {

const DefineRange kShOrder{"SH_ORDER", 1, kMaxShOrder};
const DefineRange kShadows{"SHADOWS", 0, 1};
const DefineRange kPcf{"PCF", 0, 1};
const DefineRange kDisplayOutput{"DISPLAY_OUTPUT", 0, 1};
const DefineRange kSpecular{"SPECULAR", 0, 1};
const DefineRange kAlphaTest{"ALPHA_TEST", 0, 1};
const DefineRange kLightsOn{"LIGHTS_ON", 0, kMaxFrameLights};
const DefineRange kTransfer{"TRANSFER", 0, 1};

const std::vector<FrameProgram> kPrograms{
    {"depth", "mesh.vert", "depth.frag", {kAlphaTest}},
    {"geometry",
     "mesh.vert",
     "geometry.frag",
     {kAlphaTest, {"MATERIAL_TEXTURES", 0, 1}, kTransfer, {"MATERIAL_LAYERS", 0, 1}}},
    // Baked only for a light that is on and casts shadows.
    {"ground visibility",
     "fullscreen.vert",
     "ground_visibility.frag",
     {kShOrder, {"LIGHTS_ON", 1, kMaxFrameLights}, {"SHADOWS", 1, 1}, kPcf}},
    {"shade",
     "fullscreen.vert",
     "shade.frag",
     {kShOrder,
      kLightsOn,
      kShadows,
      kPcf,
      {"ENVIRONMENT_BACKGROUND", 0, 1},
      kDisplayOutput,
      kSpecular,
      {"SURFACE", 0, 4},
      kTransfer}},
    {"transparent",
     "mesh.vert",
     "transparent.frag",
     {kShOrder, kLightsOn, kShadows, kPcf, kSpecular, kTransfer, {"MATERIAL_LAYERS", 0, 1}}},
    {"resolve", "fullscreen.vert", "resolve.frag", {kDisplayOutput}},
};

}  // namespace

std::span<const FrameProgram> frame_programs() {
    return kPrograms;
}

const FrameProgram& frame_program(std::string_view name) {
    for (const FrameProgram& program : kPrograms) {
        if (program.name == name) {
            return program;
        }
    }
    throw Error(ErrorKind::Internal, "no frame program is named '" + std::string(name) + "'");
}

void check_defines(const FrameProgram& program, std::string_view defines) {
    const auto fail = [&](const std::string& message) {
        throw Error(ErrorKind::Internal, "program '" + std::string(program.name) + "': " + message +
                                             " (renderer/gl/src/frame_programs.cpp lists the "
                                             "defines the shader test checks)");
    };
    std::map<std::string_view, int> values;
    constexpr std::string_view kDefine = "#define ";
    while (!defines.empty()) {
        const std::size_t end = defines.find('\n');
        const std::string_view line = defines.substr(0, end);
        defines.remove_prefix(end == std::string_view::npos ? defines.size() : end + 1);
        const std::size_t space = line.find(' ', kDefine.size());
        int value = 0;
        const bool parsed = [&] {
            if (!line.starts_with(kDefine) || space == std::string_view::npos) {
                return false;
            }
            const char* const value_end = line.data() + line.size();
            const auto [stop, error] = std::from_chars(line.data() + space + 1, value_end, value);
            return stop == value_end && error == std::errc{};
        }();
        if (!parsed) {
            fail("expected '#define NAME integer', got '" + std::string(line) + "'");
        }
        const std::string_view name = line.substr(kDefine.size(), space - kDefine.size());
        const auto range = std::find_if(program.defines.begin(), program.defines.end(),
                                        [&](const DefineRange& r) { return r.name == name; });
        if (range == program.defines.end()) {
            fail("defines " + std::string(name) + ", which it does not take");
        }
        if (value < range->min || value > range->max) {
            fail(std::string(name) + " = " + std::to_string(value) + " is outside " +
                 std::to_string(range->min) + ".." + std::to_string(range->max));
        }
        if (!values.emplace(name, value).second) {
            fail(std::string(name) + " is defined twice");
        }
    }
    for (const DefineRange& range : program.defines) {
        if (!values.contains(range.name)) {
            fail(std::string(range.name) + " is not defined");
        }
    }
}

}  // namespace oer::shaders
