#include "shader_sources.hpp"

#include <algorithm>
#include <regex>

#include "gl_bindings.hpp"
#include "oer/core/error.hpp"
#include "shader_files.hpp"

namespace oer::shaders {

namespace {

constexpr std::string_view kIncludeExtension = "#extension GL_GOOGLE_include_directive";
constexpr std::string_view kInclude = "#include";

bool starts_with_directive(std::string_view line, std::string_view directive) {
    const std::size_t start = line.find_first_not_of(" \t");
    return start != std::string_view::npos && line.substr(start).starts_with(directive);
}

// The file name of `#include "name"`, or nothing if the line is not of that form.
std::string_view included_name(std::string_view line) {
    line.remove_prefix(line.find(kInclude) + kInclude.size());
    const std::size_t open = line.find_first_not_of(" \t");
    if (open == std::string_view::npos || line[open] != '"') {
        return {};
    }
    const std::size_t close = line.find('"', open + 1);
    if (close == std::string_view::npos ||
        line.find_first_not_of(" \t\r", close + 1) != std::string_view::npos) {
        return {};
    }
    return line.substr(open + 1, close - open - 1);
}

// Appends the lines of `name`, the last of source.files (so its source-string number is its
// index there), from line first_line on (`text` starts there), splicing in its includes.
void append_file(ShaderSource& source, std::span<const ShaderFile> files, const std::string& name,
                 std::string_view text, int first_line) {
    const std::size_t number = source.files.size() - 1;
    int line_number = first_line;
    while (!text.empty()) {
        const std::size_t end = text.find('\n');
        const std::string_view line = text.substr(0, end);
        text.remove_prefix(end == std::string_view::npos ? text.size() : end + 1);
        if (starts_with_directive(line, kIncludeExtension)) {
            // GL knows no such extension; a blank line keeps the lines' numbers.
            source.text += '\n';
        } else if (starts_with_directive(line, kInclude)) {
            const std::string where = name + ":" + std::to_string(line_number);
            const std::string_view part = included_name(line);
            if (part.empty()) {
                throw Error(ErrorKind::Internal, "shader " + where +
                                                     ": expected #include \"file.glsl\", got '" +
                                                     std::string(line) + "'");
            }
            if (std::find(source.files.begin(), source.files.end(), part) != source.files.end()) {
                source.text += '\n';  // included already: each file once
            } else {
                std::string_view part_text;
                try {
                    part_text = shader_file(part, files);
                } catch (const Error& error) {
                    throw Error(ErrorKind::Internal,
                                "shader " + where + " includes " + error.what());
                }
                source.files.emplace_back(part);
                source.text += "#line 1 " + std::to_string(source.files.size() - 1) + "\n";
                append_file(source, files, std::string(part), part_text, 1);
                source.text += "#line " + std::to_string(line_number + 1) + " " +
                               std::to_string(number) + "\n";
            }
        } else {
            source.text.append(line);
            source.text += '\n';
        }
        ++line_number;
    }
}

}  // namespace

std::string_view shader_file(std::string_view name, std::span<const ShaderFile> files) {
    std::string embedded;
    for (const ShaderFile& file : files) {
        if (file.name == name) {
            return file.text;
        }
        embedded += (embedded.empty() ? "" : ", ") + std::string(file.name);
    }
    throw Error(
        ErrorKind::Internal,
        "'" + std::string(name) + "', which is not a shader file (there are " + embedded + ")");
}

ShaderSource program_source(std::string_view file, std::string_view defines) {
    return program_source(file, defines, shader_files());
}

ShaderSource program_source(std::string_view file, std::string_view defines,
                            std::span<const ShaderFile> files) {
    const std::string_view text = shader_file(file, files);
    const std::size_t end_of_version = text.find('\n');
    if (!text.starts_with("#version") || end_of_version == std::string_view::npos) {
        throw Error(ErrorKind::Internal,
                    "shader " + std::string(file) + ": the first line must be #version");
    }
    ShaderSource source;
    source.files.emplace_back(file);
    source.text = std::string(text.substr(0, end_of_version + 1)) + gl_bindings::binding_defines() +
                  std::string(defines);
    if (!defines.empty() && !defines.ends_with('\n')) {
        source.text += '\n';
    }
    source.text += "#line 2 0\n";
    append_file(source, files, std::string(file), text.substr(end_of_version + 1), 2);
    return source;
}

std::string name_files(std::string_view log, const std::vector<std::string>& files) {
    // A position at the start of a line, after an optional "ERROR: " or "WARNING: ".
    static const std::regex position(R"(^((?:ERROR|WARNING): )?(\d{1,6}):(\d+))");
    std::string named;
    while (!log.empty()) {
        const std::size_t end = log.find('\n');
        const std::string line(log.substr(0, end));
        log.remove_prefix(end == std::string_view::npos ? log.size() : end + 1);
        std::smatch match;
        const std::size_t number =
            std::regex_search(line, match, position) ? std::stoul(match[2]) : files.size();
        if (number < files.size()) {
            named += match[1].str() + files[number] + ":" + match[3].str() + match.suffix().str();
        } else {
            named += line;
        }
        named += end == std::string_view::npos ? "" : "\n";
    }
    return named;
}

}  // namespace oer::shaders
