#include "openapi_spec.hpp"

#include <fstream>
#include <sstream>
#include <stdexcept>

namespace oer::testing {

using Json = nlohmann::json;

const std::filesystem::path& openapi_path() {
    static const std::filesystem::path path =
        std::filesystem::path(__FILE__).parent_path().parent_path().parent_path() / "api" /
        "openapi.yaml";
    return path;
}

std::string trim(const std::string& text) {
    const std::size_t first = text.find_first_not_of(' ');
    return first == std::string::npos ? ""
                                      : text.substr(first, text.find_last_not_of(' ') + 1 - first);
}

std::string unquote(const std::string& text) {
    if (text.size() >= 2 && (text.front() == '\'' || text.front() == '"') &&
        text.back() == text.front()) {
        return text.substr(1, text.size() - 2);
    }
    return text;
}

std::optional<std::vector<std::string>> flow_list(const std::string& text) {
    if (text.size() < 2 || text.front() != '[' || text.back() != ']') {
        return std::nullopt;
    }
    std::vector<std::string> items;
    std::stringstream in(text.substr(1, text.size() - 2));
    for (std::string item; std::getline(in, item, ',');) {
        if (!trim(item).empty()) {
            items.push_back(unquote(trim(item)));
        }
    }
    return items;
}

Json scalar_json(const std::string& text) {
    const Json parsed = Json::parse(text, nullptr, false);
    if (!parsed.is_discarded()) {
        return parsed;
    }
    if (const auto items = flow_list(text)) {
        Json list = Json::array();
        for (const std::string& item : *items) {
            const Json value = Json::parse(item, nullptr, false);
            list.push_back(value.is_discarded() ? Json(item) : value);
        }
        return list;
    }
    return Json(unquote(text));
}

Spec::Spec(const std::filesystem::path& path) {
    std::ifstream in(path);
    for (std::string line; std::getline(in, line);) {
        lines_.push_back(line);
    }
}

Spec::Block Spec::child(const Block& block, const std::string& key) const {
    const std::size_t top = top_indentation(block);
    for (std::size_t i = block.begin; block.found && i < block.end; ++i) {
        if (skip(lines_[i]) || indentation(lines_[i]) != top || key_of(lines_[i]) != key) {
            continue;
        }
        std::size_t end = i + 1;
        while (end < block.end && (skip(lines_[end]) || indentation(lines_[end]) > top)) {
            ++end;
        }
        return {i + 1, end, true};
    }
    return {};
}

Spec::Block Spec::at(Block block, const std::vector<std::string>& keys) const {
    for (const std::string& key : keys) {
        block = child(block, key);
    }
    return block;
}

std::optional<std::string> Spec::value(const Block& block, const std::string& key) const {
    const std::size_t top = top_indentation(block);
    for (std::size_t i = block.begin; block.found && i < block.end; ++i) {
        if (!skip(lines_[i]) && indentation(lines_[i]) == top && key_of(lines_[i]) == key) {
            const std::string line = trim(lines_[i]);
            const std::string rest = trim(line.substr(line.find(':') + 1));
            return rest.empty() ? std::nullopt : std::optional<std::string>(rest);
        }
    }
    return std::nullopt;
}

std::vector<std::string> Spec::keys(const Block& block) const {
    std::vector<std::string> keys;
    const std::size_t top = top_indentation(block);
    for (std::size_t i = block.begin; block.found && i < block.end; ++i) {
        if (!skip(lines_[i]) && indentation(lines_[i]) == top && !key_of(lines_[i]).empty()) {
            keys.push_back(key_of(lines_[i]));
        }
    }
    return keys;
}

Spec::Block Spec::reference(const std::string& pointer) const {
    std::vector<std::string> keys;
    std::stringstream in(unquote(pointer).substr(2));
    for (std::string key; std::getline(in, key, '/');) {
        keys.push_back(key);
    }
    return at(document(), keys);
}

Spec::Block Spec::resolved(Block block) const {
    for (int depth = 0; depth < 64; ++depth) {
        const auto target = value(block, "$ref");
        if (!target) {
            return block;
        }
        block = reference(*target);
        if (!block.found) {
            return block;
        }
    }
    return {};
}

std::set<std::string> Spec::query_parameters(const Block& block) const {
    std::set<std::string> names;
    for (std::size_t i = block.begin; block.found && i + 1 < block.end; ++i) {
        const std::string line = trim(lines_[i]);
        if (line.rfind("- name: ", 0) == 0 && trim(lines_[i + 1]) == "in: query") {
            names.insert(line.substr(8));
        }
    }
    return names;
}

bool Spec::skip(const std::string& line) {
    const std::string text = trim(line);
    return text.empty() || text[0] == '#';
}

std::size_t Spec::indentation(const std::string& line) {
    return line.find_first_not_of(' ');
}

std::string Spec::key_of(const std::string& line) {
    const std::string text = trim(line);
    const std::size_t colon = text.find(':');
    if (colon == std::string::npos || text[0] == '-' ||
        (colon + 1 < text.size() && text[colon + 1] != ' ')) {
        return "";
    }
    return unquote(text.substr(0, colon));
}

std::size_t Spec::top_indentation(const Block& block) const {
    for (std::size_t i = block.begin; block.found && i < block.end; ++i) {
        if (!skip(lines_[i])) {
            return indentation(lines_[i]);
        }
    }
    return 0;
}

namespace {

bool blank_or_comment(const std::string& line) {
    const std::string text = trim(line);
    return text.empty() || text[0] == '#';
}

std::size_t indent_of(const std::string& line) {
    return line.find_first_not_of(' ');
}

// Lines (a copy, so that list items can be re-indented) as JSON.
Json lines_to_json(const std::vector<std::string>& lines) {
    std::size_t first = 0;
    while (first < lines.size() && blank_or_comment(lines[first])) {
        ++first;
    }
    if (first == lines.size()) {
        return nullptr;
    }
    const std::size_t top = indent_of(lines[first]);
    // The body of the item or key on line i: the lines after it indented deeper.
    const auto body_end = [&](std::size_t i) {
        std::size_t end = i + 1;
        while (end < lines.size() &&
               (blank_or_comment(lines[end]) || indent_of(lines[end]) > top)) {
            ++end;
        }
        return end;
    };
    const bool list = trim(lines[first]) == "-" || trim(lines[first]).rfind("- ", 0) == 0;
    Json result = list ? Json::array() : Json::object();
    for (std::size_t i = first; i < lines.size();) {
        if (blank_or_comment(lines[i])) {
            ++i;
            continue;
        }
        if (indent_of(lines[i]) != top) {
            throw std::runtime_error("openapi.yaml: unexpected indentation: " + lines[i]);
        }
        const std::string text = trim(lines[i]);
        const std::size_t end = body_end(i);
        const std::vector<std::string> body(lines.begin() + std::ptrdiff_t(i + 1),
                                            lines.begin() + std::ptrdiff_t(end));
        if (list) {
            if (text.rfind("- ", 0) != 0) {
                throw std::runtime_error("openapi.yaml: not a list item: " + lines[i]);
            }
            const std::string item = trim(text.substr(2));
            const std::size_t colon = item.find(':');
            const bool mapping = colon != std::string::npos && item[0] != '[' && item[0] != '{' &&
                                 item[0] != '\'' && item[0] != '"' &&
                                 (colon + 1 == item.size() || item[colon + 1] == ' ');
            if (mapping) {
                std::vector<std::string> nested{std::string(top + 2, ' ') + item};
                nested.insert(nested.end(), body.begin(), body.end());
                result.push_back(lines_to_json(nested));
            } else if (item == "{}") {
                result.push_back(Json::object());
            } else {
                result.push_back(scalar_json(item));
            }
        } else {
            const std::size_t colon = text.find(':');
            if (colon == std::string::npos || text[0] == '-') {
                throw std::runtime_error("openapi.yaml: not a mapping entry: " + lines[i]);
            }
            const std::string key = unquote(text.substr(0, colon));
            const std::string rest = trim(text.substr(colon + 1));
            if (rest == "|") {
                std::string joined;
                std::size_t body_indent = std::string::npos;
                for (const std::string& line : body) {
                    if (!trim(line).empty()) {
                        body_indent = std::min(body_indent, indent_of(line));
                    }
                }
                for (const std::string& line : body) {
                    joined += (trim(line).empty() ? "" : line.substr(body_indent)) + "\n";
                }
                result[key] = joined;
            } else if (rest.empty()) {
                result[key] = lines_to_json(body);
            } else {
                result[key] = scalar_json(rest);
            }
        }
        i = end;
    }
    return result;
}

}  // namespace

Json Spec::node(std::size_t begin, std::size_t end) const {
    return lines_to_json(std::vector<std::string>(lines_.begin() + std::ptrdiff_t(begin),
                                                  lines_.begin() + std::ptrdiff_t(end)));
}

Json Spec::to_json(const Block& block) const {
    return block.found ? node(block.begin, block.end) : Json();
}

const Json& Spec::json() const {
    if (!json_) {
        json_ = to_json(document());
    }
    return *json_;
}

const Spec& openapi_spec() {
    static const Spec loaded(openapi_path());
    // Converted here, under the thread-safe initialisation of a local static, so that threads
    // may share the JSON afterwards.
    [[maybe_unused]] static const Json& converted = loaded.json();
    return loaded;
}

}  // namespace oer::testing
