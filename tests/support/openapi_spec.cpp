#include "openapi_spec.hpp"

#include <fstream>
#include <sstream>

namespace oer::testing {

using Json = nlohmann::json;

// The build gives the spec's absolute path (tests/CMakeLists.txt), not __FILE__: the compiler
// cache makes source paths relative to the build folder (cmake/compiler_cache.cmake).
const std::filesystem::path& openapi_path() {
    static const std::filesystem::path path = OER_OPENAPI_PATH;
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

namespace {

// yaml-cpp tags a plain (unquoted) scalar "?", a quoted or block one "!".
bool plain(const YAML::Node& node) {
    return node.Tag() == "?";
}

// A scalar as written: quoted ones keep their quotes, so that callers tell '85' from 85.
std::string scalar_text(const YAML::Node& node) {
    return plain(node) ? node.Scalar() : "'" + node.Scalar() + "'";
}

Json node_json(const YAML::Node& node) {
    switch (node.Type()) {
        case YAML::NodeType::Map: {
            Json object = Json::object();
            for (const auto& entry : node) {
                object[entry.first.Scalar()] = node_json(entry.second);
            }
            return object;
        }
        case YAML::NodeType::Sequence: {
            Json list = Json::array();
            for (const auto& item : node) {
                list.push_back(node_json(item));
            }
            return list;
        }
        case YAML::NodeType::Scalar:
            return plain(node) ? scalar_json(node.Scalar()) : Json(node.Scalar());
        case YAML::NodeType::Null:
        case YAML::NodeType::Undefined:
            return nullptr;
    }
    return nullptr;
}

}  // namespace

Spec::Spec(const std::filesystem::path& path) {
    std::ifstream in(path);
    for (std::string line; std::getline(in, line);) {
        lines_.push_back(line);
    }
    root_ = YAML::LoadFile(path.string());
}

Spec::Block Spec::child(const Block& block, const std::string& key) const {
    if (!block.found || !block.node->IsMap()) {
        return {};
    }
    const YAML::Node& map = *block.node;
    const YAML::Node found = map[key];
    return found.IsDefined() ? Block{std::make_shared<const YAML::Node>(found), true} : Block{};
}

Spec::Block Spec::at(Block block, const std::vector<std::string>& keys) const {
    for (const std::string& key : keys) {
        block = child(block, key);
    }
    return block;
}

std::optional<std::string> Spec::value(const Block& block, const std::string& key) const {
    const Block found = child(block, key);
    if (!found.found) {
        return std::nullopt;
    }
    const YAML::Node& node = *found.node;
    if (node.IsScalar()) {
        return scalar_text(node);
    }
    if (node.IsSequence() && node.Style() == YAML::EmitterStyle::Flow) {
        std::string list;
        for (const auto& item : node) {
            list += (list.empty() ? "" : ", ") + scalar_text(item);
        }
        return "[" + list + "]";
    }
    if (node.IsMap() && node.Style() == YAML::EmitterStyle::Flow && node.size() == 0) {
        return "{}";
    }
    return std::nullopt;
}

std::vector<std::string> Spec::keys(const Block& block) const {
    std::vector<std::string> keys;
    if (block.found && block.node->IsMap()) {
        for (const auto& entry : *block.node) {
            keys.push_back(entry.first.Scalar());
        }
    }
    return keys;
}

std::vector<Spec::Block> Spec::items(const Block& block) const {
    std::vector<Block> items;
    if (block.found && block.node->IsSequence()) {
        for (const auto& item : *block.node) {
            items.push_back({std::make_shared<const YAML::Node>(item), true});
        }
    }
    return items;
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
    for (const Block& parameter : items(block)) {
        if (value(parameter, "in") == "query") {
            if (const auto name = value(parameter, "name")) {
                names.insert(unquote(*name));
            }
        }
    }
    return names;
}

Json Spec::to_json(const Block& block) const {
    return block.found ? node_json(*block.node) : Json();
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
