// The shaders of renderer/gl/shaders as the renderer assembles them: includes spliced in once
// each with #line directives that name every line's file and line, errors for what cannot be
// assembled, compiler logs named by file, the define strings checked against the table of frame
// programs, every texture unit and buffer binding named by gl_bindings.hpp; and every variant
// of that table compiled by glslangValidator (no GPU needed), so that a shader error fails the
// suite with its file and line.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <regex>
#include <set>
#include <span>
#include <string>
#include <vector>

#include "frame_programs.hpp"
#include "gl_bindings.hpp"
#include "gl_program.hpp"
#include "oer/core/error.hpp"
#include "oer/gl/gl_context.hpp"
#include "shader_sources.hpp"

using namespace oer;
using namespace oer::shaders;

namespace {

std::vector<std::string> lines_of(std::string_view text) {
    std::vector<std::string> lines;
    while (!text.empty()) {
        const std::size_t end = text.find('\n');
        lines.emplace_back(text.substr(0, end));
        text.remove_prefix(end == std::string_view::npos ? text.size() : end + 1);
    }
    return lines;
}

// The message of the oer::Error that `assemble` throws, or "" if it throws none.
template <typename Function>
std::string error_of(Function assemble) {
    try {
        assemble();
    } catch (const Error& error) {
        EXPECT_EQ(error.kind(), ErrorKind::Internal);
        return error.what();
    }
    return "";
}

struct Variant {
    const FrameProgram* program = nullptr;
    std::string defines;
};

// The values a define is compiled with: all of a switch's or a kind's (SURFACE's five); a
// count's ends and the value after the first (they only size arrays and loops, and #if tests
// only LIGHTS_ON > 0).
std::vector<int> values_of(const DefineRange& range) {
    if (range.max - range.min <= 4) {
        std::vector<int> values;
        for (int value = range.min; value <= range.max; ++value) {
            values.push_back(value);
        }
        return values;
    }
    return {range.min, range.min + 1, range.max};
}

// Every combination of the values_of each define of every frame program.
std::vector<Variant> frame_program_variants() {
    std::vector<Variant> variants;
    for (const FrameProgram& program : frame_programs()) {
        std::vector<Variant> partial{{&program, ""}};
        for (const DefineRange& range : program.defines) {
            std::vector<Variant> extended;
            for (const Variant& variant : partial) {
                for (const int value : values_of(range)) {
                    extended.push_back({&program, variant.defines + "#define " +
                                                      std::string(range.name) + " " +
                                                      std::to_string(value) + "\n"});
                }
            }
            partial = std::move(extended);
        }
        variants.insert(variants.end(), partial.begin(), partial.end());
    }
    return variants;
}

// Runs `command`, returning its standard output and error, and its exit status.
std::pair<std::string, int> run(const std::string& command) {
    std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen((command + " 2>&1").c_str(), "r"), pclose);
    if (!pipe) {
        return {"cannot run " + command, -1};
    }
    std::string output;
    std::array<char, 4096> buffer{};
    while (const std::size_t read = std::fread(buffer.data(), 1, buffer.size(), pipe.get())) {
        output.append(buffer.data(), read);
    }
    return {output, pclose(pipe.release())};
}

const std::array<ShaderFile, 4> kTestFiles{{
    {"stage.frag",
     "#version 450 core\n"
     "#extension GL_GOOGLE_include_directive : require\n"
     "#include \"a.glsl\"\n"
     "#include \"b.glsl\"\n"
     "void main() {}\n"},
    {"a.glsl", "// a\n#include \"common.glsl\"\nfloat a() { return c(); }\n"},
    {"b.glsl", "  #include \"common.glsl\"\n#include \"a.glsl\"\nfloat b() { return c(); }\n"},
    {"common.glsl", "#include \"a.glsl\"\nfloat c() { return 1.0; }\n"},
}};

}  // namespace

TEST(ShaderSources, DefinesFollowTheVersionLineAndLineOneOfTheStageFollowsThem) {
    // The bindings' defines first, then the program's.
    const std::string bindings = gl_bindings::binding_defines();
    EXPECT_TRUE(bindings.starts_with("#define GBUFFER_POSITIONS_UNIT 0\n")) << bindings;
    const ShaderSource source = program_source("resolve.frag", "#define DISPLAY_OUTPUT 1\n");
    EXPECT_TRUE(source.text.starts_with("#version 450 core\n" + bindings +
                                        "#define DISPLAY_OUTPUT 1\n#line 2 0\n"))
        << source.text.substr(0, 100);
    // A define string without its final newline gets one.
    EXPECT_TRUE(program_source("resolve.frag", "#define DISPLAY_OUTPUT 0")
                    .text.starts_with("#version 450 core\n" + bindings +
                                      "#define DISPLAY_OUTPUT 0\n#line 2 0\n"));
}

namespace {

struct DeclaredBinding {
    std::string value;  // as written after "binding ="
    gl_bindings::BindingKind kind;
    std::string line;
};

// The `layout(... binding = X ...)` declarations of `text`, with the kind of what they bind:
// a `buffer` block's shader storage binding or a sampler's texture unit.
std::vector<DeclaredBinding> declared_bindings(std::string_view text) {
    static const std::regex binding(R"(layout\s*\([^)]*\bbinding\s*=\s*(\w+))");
    std::vector<DeclaredBinding> declared;
    for (const std::string& line : lines_of(text)) {
        std::smatch match;
        if (!std::regex_search(line, match, binding)) {
            continue;
        }
        const gl_bindings::BindingKind kind = line.find(" buffer ") != std::string::npos
                                                  ? gl_bindings::BindingKind::ShaderStorage
                                                  : gl_bindings::BindingKind::TextureUnit;
        EXPECT_TRUE(kind == gl_bindings::BindingKind::ShaderStorage ||
                    line.find("sampler") != std::string::npos)
            << "neither a buffer block nor a sampler: " << line;
        declared.push_back({match[1].str(), kind, line});
    }
    return declared;
}

const gl_bindings::Binding* find_binding(std::string_view glsl) {
    for (const gl_bindings::Binding& binding : gl_bindings::kBindings) {
        if (binding.glsl == glsl) {
            return &binding;
        }
    }
    return nullptr;
}

// The pairs of `used` (the bindings one program reads) at one unit or binding point, as "A and
// B, both at N".
std::vector<std::string> shared_points(const std::vector<const gl_bindings::Binding*>& used) {
    std::vector<std::string> shared;
    for (std::size_t i = 0; i < used.size(); ++i) {
        for (std::size_t j = i + 1; j < used.size(); ++j) {
            if (used[i]->kind == used[j]->kind && used[i]->index == used[j]->index) {
                shared.push_back(std::string(used[i]->glsl) + " and " + std::string(used[j]->glsl) +
                                 ", both at " + std::to_string(used[i]->index));
            }
        }
    }
    return shared;
}

}  // namespace

// Every binding a shader declares is one of gl_bindings.hpp, by its name and of its kind, and
// every one of gl_bindings.hpp is declared by some shader; the names are distinct from each
// other and from the programs' defines.
TEST(ShaderSourcesBindings, EveryShaderBindingIsANameOfTheHeader) {
    std::set<std::string> names;
    for (const gl_bindings::Binding& binding : gl_bindings::kBindings) {
        EXPECT_TRUE(names.insert(std::string(binding.glsl)).second) << binding.glsl << " twice";
    }
    for (const FrameProgram& program : frame_programs()) {
        for (const DefineRange& range : program.defines) {
            EXPECT_FALSE(names.contains(std::string(range.name)))
                << range.name << " is both a binding and a define of " << program.name;
        }
    }
    std::set<std::string> declared;
    for (const ShaderFile& file : shader_files()) {
        for (const DeclaredBinding& binding : declared_bindings(file.text)) {
            const gl_bindings::Binding* named = find_binding(binding.value);
            if (named == nullptr) {
                ADD_FAILURE() << file.name << " binds " << binding.value
                              << ", which gl_bindings.hpp does not name: " << binding.line;
                continue;
            }
            EXPECT_TRUE(named->kind == binding.kind) << file.name << " binds " << binding.value
                                                     << " as the other kind: " << binding.line;
            declared.insert(binding.value);
        }
    }
    for (const gl_bindings::Binding& binding : gl_bindings::kBindings) {
        EXPECT_TRUE(declared.contains(std::string(binding.glsl)))
            << binding.glsl << " is bound by no shader";
    }
}

// Within one program (its two stages with their includes), two names of one unit or binding
// point would read one texture or buffer as two: only the header's alternative pairs, which no
// variant reads together, may share one.
TEST(ShaderSourcesBindings, NoProgramReadsTwoNamesOfOnePoint) {
    for (const FrameProgram& program : frame_programs()) {
        std::vector<const gl_bindings::Binding*> used;
        for (const std::string_view stage : {program.vertex, program.fragment}) {
            for (const DeclaredBinding& binding :
                 declared_bindings(program_source(stage, "").text)) {
                const gl_bindings::Binding* named = find_binding(binding.value);
                ASSERT_NE(named, nullptr) << binding.line;
                if (std::find(used.begin(), used.end(), named) == used.end()) {
                    used.push_back(named);
                }
            }
        }
        for (const std::string& shared : shared_points(used)) {
            ADD_FAILURE() << "program '" << program.name << "' reads " << shared;
        }
    }
}

// A shader that binds by a literal, or by a name the header lacks, is found; so is a program
// that reads two names of one unit.
TEST(ShaderSourcesBindings, TheChecksFindALiteralAnUnknownNameAndASharedUnit) {
    const std::vector<DeclaredBinding> declared = declared_bindings(
        "layout(binding = 3) uniform sampler2D u_a;\n"
        "layout(std430, binding = NO_SUCH_BINDING) readonly buffer B { vec4 b[]; };\n"
        "uniform float u_c;\n");
    ASSERT_EQ(declared.size(), 2u);
    EXPECT_EQ(declared[0].value, "3");
    EXPECT_TRUE(declared[0].kind == gl_bindings::BindingKind::TextureUnit);
    EXPECT_EQ(find_binding(declared[0].value), nullptr);
    EXPECT_EQ(declared[1].value, "NO_SUCH_BINDING");
    EXPECT_TRUE(declared[1].kind == gl_bindings::BindingKind::ShaderStorage);
    EXPECT_EQ(find_binding(declared[1].value), nullptr);
    // Unit 0 is the G-buffer's positions in the shading program and the radiance in the
    // resolve's: one program reading both would read one texture as two.
    EXPECT_EQ(
        shared_points({&gl_bindings::kGBufferPositions, &gl_bindings::kResolveRadiance}),
        std::vector<std::string>{"GBUFFER_POSITIONS_UNIT and RESOLVE_RADIANCE_UNIT, both at 0"});
    EXPECT_TRUE(shared_points({&gl_bindings::kGBufferTransferred, &gl_bindings::kGroundTransfer,
                               &gl_bindings::kIrradianceSets, &gl_bindings::kGBufferPositions})
                    .empty());
}

TEST(ShaderSources, EachFileIsIncludedOnceWhateverIncludesIt) {
    const ShaderSource source = program_source("stage.frag", "", kTestFiles);
    // common.glsl includes a.glsl, which is under way: a cycle, cut as an include guard would.
    EXPECT_EQ(source.files,
              (std::vector<std::string>{"stage.frag", "a.glsl", "common.glsl", "b.glsl"}));
    for (const std::string function : {"float a()", "float b()", "float c()"}) {
        const std::size_t first = source.text.find(function);
        ASSERT_NE(first, std::string::npos) << function;
        EXPECT_EQ(source.text.find(function, first + 1), std::string::npos) << function;
    }
    EXPECT_EQ(source.text.find("#include"), std::string::npos) << source.text;
    EXPECT_EQ(source.text.find("GL_GOOGLE_include_directive"), std::string::npos);

    // The frame's shading program: math_constants.glsl comes through surface_shading.glsl,
    // shadow_filter.glsl and specular_lighting.glsl, and is there once.
    const ShaderSource shade = program_source("shade.frag", "");
    EXPECT_EQ(shade.files,
              (std::vector<std::string>{"shade.frag", "surface_shading.glsl", "math_constants.glsl",
                                        "sh_lighting.glsl", "shadow_filter.glsl", "brdf.glsl",
                                        "specular_lighting.glsl", "ground_lighting.glsl",
                                        "layer_gbuffer.glsl", "display.glsl"}));
    const std::size_t pi = shade.text.find("const float PI");
    ASSERT_NE(pi, std::string::npos);
    EXPECT_EQ(shade.text.find("const float PI", pi + 1), std::string::npos);
}

// Follows the #line directives as a GLSL compiler does and checks that every other line is
// the line of the file they name, or a blank line where that one is an include directive.
TEST(ShaderSources, LineDirectivesNameTheFileAndLineOfEveryLine) {
    struct Assembled {
        ShaderSource source;
        std::span<const ShaderFile> files;
    };
    std::vector<Assembled> assembled{{program_source("stage.frag", "", kTestFiles), kTestFiles}};
    for (const FrameProgram& program : frame_programs()) {
        for (const std::string_view stage : {program.vertex, program.fragment}) {
            assembled.push_back({program_source(stage, "#define SH_ORDER 3\n"), shader_files()});
        }
    }
    for (const auto& [source, files] : assembled) {
        bool numbered = false;  // the #version line and the defines precede the first #line
        std::size_t file = 0;
        int line = 0;  // of the next line
        std::size_t checked = 0;
        for (const std::string& text : lines_of(source.text)) {
            unsigned next_line = 0;
            unsigned next_file = 0;
            if (std::sscanf(text.c_str(), "#line %u %u", &next_line, &next_file) == 2) {
                ASSERT_LT(next_file, source.files.size()) << text;
                numbered = true;
                line = int(next_line);
                file = next_file;
                continue;
            }
            if (numbered) {
                const std::vector<std::string> original =
                    lines_of(shader_file(source.files[file], files));
                ASSERT_LE(line, int(original.size())) << source.files[file];
                const std::string& expected = original[std::size_t(line - 1)];
                if (text.empty() && !expected.empty()) {
                    // Only an include directive (or the extension declaring them) is blanked.
                    EXPECT_TRUE(expected.find("#include") != std::string::npos ||
                                expected.find("GL_GOOGLE_include_directive") != std::string::npos)
                        << source.files[file] << ":" << line << " blanked: " << expected;
                } else {
                    EXPECT_EQ(text, expected) << source.files[file] << ":" << line;
                }
                ++checked;
            }
            ++line;
        }
        EXPECT_GT(checked, 0u) << source.files[0];
    }
}

TEST(ShaderSources, WhatCannotBeAssembledIsAnErrorWithItsFileAndLine) {
    const std::array<ShaderFile, 3> files{{
        {"missing.frag", "#version 450 core\n\n#include \"nowhere.glsl\"\nvoid main() {}\n"},
        {"malformed.frag", "#version 450 core\n#include <angled.glsl>\nvoid main() {}\n"},
        {"unversioned.frag", "void main() {}\n"},
    }};
    const std::string missing = error_of([&] { program_source("missing.frag", "", files); });
    EXPECT_NE(missing.find("missing.frag:3 includes 'nowhere.glsl', which is not a shader file"),
              std::string::npos)
        << missing;
    EXPECT_NE(missing.find("missing.frag, malformed.frag, unversioned.frag"), std::string::npos)
        << missing;
    const std::string malformed = error_of([&] { program_source("malformed.frag", "", files); });
    EXPECT_NE(malformed.find("malformed.frag:2: expected #include \"file.glsl\""),
              std::string::npos)
        << malformed;
    const std::string unversioned =
        error_of([&] { program_source("unversioned.frag", "", files); });
    EXPECT_NE(unversioned.find("unversioned.frag: the first line must be #version"),
              std::string::npos)
        << unversioned;
    const std::string unknown = error_of([] { program_source("nothing.frag", ""); });
    EXPECT_NE(unknown.find("'nothing.frag', which is not a shader file (there are "),
              std::string::npos)
        << unknown;
    EXPECT_NE(unknown.find("shade.frag"), std::string::npos) << unknown;
}

TEST(ShaderSources, CompilerLogsNameFilesInsteadOfSourceStringNumbers) {
    const std::vector<std::string> files{"shade.frag", "sh_lighting.glsl"};
    EXPECT_EQ(name_files("1:12(5): error: syntax error\n0:3(1): warning: unused\n", files),
              "sh_lighting.glsl:12(5): error: syntax error\nshade.frag:3(1): warning: unused\n");
    EXPECT_EQ(
        name_files("ERROR: 1:7: 'x' : undeclared identifier\nERROR: 1 compilation errors.", files),
        "ERROR: sh_lighting.glsl:7: 'x' : undeclared identifier\n"
        "ERROR: 1 compilation errors.");
    // A number that is no source string of the program stays as it is.
    EXPECT_EQ(name_files("2:4(1): error: x", files), "2:4(1): error: x");
}

TEST(ShaderSourcesDefines, TheRenderersDefineStringsPassAndOthersAreErrors) {
    const FrameProgram& resolve = frame_program("resolve");
    EXPECT_EQ(resolve.fragment, "resolve.frag");
    EXPECT_NO_THROW(check_defines(resolve, "#define DISPLAY_OUTPUT 1\n"));
    EXPECT_NO_THROW(check_defines(frame_program("depth"), "#define ALPHA_TEST 1\n"));
    EXPECT_NO_THROW(check_defines(frame_program("shade"),
                                  "#define SH_ORDER 16\n#define LIGHTS_ON 64\n#define SHADOWS 1\n"
                                  "#define PCF 0\n#define ENVIRONMENT_BACKGROUND 1\n"
                                  "#define DISPLAY_OUTPUT 0\n#define SPECULAR 1\n"
                                  "#define SURFACE 2\n#define TRANSFER 1\n"));
    const std::map<std::string, std::string> wrong{
        {"#define DISPLAY_OUTPUT 2\n", "DISPLAY_OUTPUT = 2 is outside 0..1"},
        {"#define DISPLAY_OUTPUT -1\n", "DISPLAY_OUTPUT = -1 is outside 0..1"},
        {"", "DISPLAY_OUTPUT is not defined"},
        {"#define DISPLAY_OUTPUT 1\n#define DISPLAY_OUTPUT 1\n", "DISPLAY_OUTPUT is defined twice"},
        {"#define DISPLAY_OUTPUT 1\n#define PCF 1\n", "defines PCF, which it does not take"},
        {"#define DISPLAY_OUTPUT one\n", "expected '#define NAME integer'"},
        {"#define DISPLAY_OUTPUT 1 \n", "expected '#define NAME integer'"},
        {"#ifdef DISPLAY_OUTPUT\n", "expected '#define NAME integer'"},
    };
    for (const auto& [defines, message] : wrong) {
        const std::string error =
            error_of([&, &defines = defines] { check_defines(resolve, defines); });
        EXPECT_NE(error.find("program 'resolve': " + message), std::string::npos)
            << defines << " -> " << error;
    }
    EXPECT_NE(error_of([] {
                  check_defines(frame_program("ground visibility"),
                                "#define SH_ORDER 3\n#define LIGHTS_ON 0\n"
                                "#define SHADOWS 1\n#define PCF 1\n");
              }).find("LIGHTS_ON = 0 is outside 1..64"),
              std::string::npos);
    EXPECT_NE(error_of([] { frame_program("tone map"); }).find("no frame program is named"),
              std::string::npos);
}

// The driver's log names the part and line of an error, through the #line directives.
TEST(ShaderSourcesGl, CompileErrorsNameTheFileAndLine) {
    const std::unique_ptr<GlContext> context = GlContext::create();
    const std::array<ShaderFile, 3> files{{
        {"quad.vert", "#version 450 core\nvoid main() { gl_Position = vec4(0.0); }\n"},
        {"color.frag",
         "#version 450 core\n#extension GL_GOOGLE_include_directive : require\n"
         "#include \"broken.glsl\"\nout vec4 o;\nvoid main() { o = tint(); }\n"},
        {"broken.glsl", "// two lines\n// of comment\nvec4 tint() { return vec4(1.0) }\n"},
    }};
    const std::string error = error_of([&] {
        gl::Program program(program_source("quad.vert", "", files),
                            program_source("color.frag", "", files), "broken");
    });
    EXPECT_NE(error.find("shader 'broken' (fragment) does not compile: broken.glsl:3("),
              std::string::npos)
        << error;
}

// Every stage of every frame program, with every combination of the values its defines take
// (values_of), compiled by glslangValidator: what GL would be given, assembled by
// program_source, with errors named by file and line. The define table is the one the renderer
// checks its define strings against, so no variant it builds goes unchecked here.
TEST(ShaderSourcesGlslang, EveryVariantOfEveryFrameProgramCompiles) {
    const std::filesystem::path folder = std::filesystem::temp_directory_path() /
                                         ("oer_shader_variants_" + std::to_string(getpid()));
    std::filesystem::remove_all(folder);
    std::filesystem::create_directories(folder);
    struct Compiled {
        std::string description;
        ShaderSource source;
    };
    std::map<std::string, Compiled> by_path;
    std::vector<std::string> paths;
    const std::vector<Variant> variants = frame_program_variants();
    for (const Variant& variant : variants) {
        for (const std::string_view stage : {variant.program->vertex, variant.program->fragment}) {
            ShaderSource source = program_source(stage, variant.defines);
            const std::string path = (folder / (std::to_string(paths.size()) +
                                                std::string(stage.substr(stage.rfind('.')))))
                                         .string();
            std::ofstream(path) << source.text;
            paths.push_back(path);
            by_path.emplace(path, Compiled{std::string(variant.program->name) + ", " +
                                               std::string(stage) + " with\n" + variant.defines,
                                           std::move(source)});
        }
    }
    // The shading pass's 3 SH orders x 3 light counts x 320 switch combinations (5 surfaces), the
    // transparent pass's 3 x 3 x 32, the bake's 3 x 3 x 2, the resolve's 2, depth's 2 and
    // geometry's 16.
    EXPECT_EQ(variants.size(), 2880u + 288u + 18u + 2u + 2u + 16u);

    // Each distinct error once, with the variants that have it.
    std::map<std::string, std::vector<const Compiled*>> errors;
    constexpr std::size_t kBatch = 200;
    for (std::size_t first = 0; first < paths.size(); first += kBatch) {
        std::string command = OER_GLSLANG_VALIDATOR;
        for (std::size_t i = first; i < std::min(paths.size(), first + kBatch); ++i) {
            command += " " + paths[i];
        }
        const auto [output, status] = run(command);
        if (status == 0) {
            continue;
        }
        // glslangValidator prints each file's name on a line of its own, then its messages.
        std::size_t failing_files = 0;
        const Compiled* current = nullptr;
        std::string messages;
        const auto collect = [&] {
            if (current != nullptr && messages.find("ERROR") != std::string::npos) {
                errors[name_files(messages, current->source.files)].push_back(current);
                ++failing_files;
            }
            messages.clear();
        };
        for (const std::string& line : lines_of(output)) {
            const auto found = by_path.find(line);
            if (found != by_path.end()) {
                collect();
                current = &found->second;
            } else if (!line.empty()) {
                messages += line + "\n";
            }
        }
        collect();
        EXPECT_GT(failing_files, 0u)
            << "glslangValidator exited with " << status << " and no error of a file:\n"
            << output;
    }
    for (const auto& [log, failing] : errors) {
        ADD_FAILURE() << log << "in " << failing.size()
                      << " variant(s), the first: " << failing.front()->description;
    }
    std::filesystem::remove_all(folder);
    std::printf("glslangValidator compiled %zu stages of %zu program variants\n", paths.size(),
                variants.size());
}
