#pragma once
// The render request's parameters (docs/design.md section 7), one row each: the one place that
// names a parameter in the JSON body, the GET query and the `oer` command line, says how it is
// read (type, range, default), how it enters the canonical document (and so the ETag) and where
// it lands in the frame request. Both parsers, the canonical document, the member lists, the
// CLI's flags and their --help, and the API description's test are derived from it: adding a
// scalar parameter is adding a row (render_parameters.cpp).
//
// Structured members (objects with their mesh, transform and base color, the camera's look-at
// or orbit or asset camera, the lights' weights) are rows too, naming themselves in each form;
// their row's readers are small dedicated ones, and the rows of their members carry names only.
#include <functional>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "oer/api/render_request.hpp"

namespace oer::api {

using RenderQuery = std::multimap<std::string, std::string>;

// How a value is spelled: in JSON, and as query text (the CLI's flags take the query's text).
enum class ParameterKind {
    ContentId,    // a string: a content id or "default"
    Boolean,      // JSON true or false; query on or off
    Switch,       // JSON true, false or one more name; query on, off or that name
    Integer,      // a number with no fraction
    Number,       // a finite number
    Name,         // a string among a fixed set (an enum's names, or a background's forms)
    Text,         // a string the asset defines (a variant's name)
    Vector3,      // JSON [x, y, z]; query "x,y,z"
    Matrix,       // JSON 16 numbers, column-major (no query form)
    Weights,      // JSON [w, ...] (true and false are 1 and 0); query "w,w,..."
    AssetCamera,  // JSON an index or a name; query "asset:N" or "asset:NAME"
    Object,       // a JSON object whose members are rows of their own
    ObjectArray   // a JSON array of such objects
};

// When the request does not give it.
enum class Presence {
    Defaulted,  // the default the row's help states (the canonical document holds it)
    Optional,   // absent (the canonical document leaves it out, or holds an empty list)
    Required    // an error
};

struct RenderParameter {
    std::string_view json;   // the member's path: "shadows/resolution" ("*": any array index)
    std::string_view query;  // the GET parameter; empty: JSON only
    std::string_view flag;   // the `oer render` flag, without "--"; empty: none
    ParameterKind kind;
    Presence presence;
    std::string value_name;  // the value as --help shows it: "on|off", "X,Y,Z"
    std::string help;        // what it means, its range and default
    // The GET form reads this row after all the others (in table order among themselves): the
    // order it has always read them in, which decides the parameter an error names when a
    // query holds several bad ones.
    bool query_second_pass = false;
    bool repeatable = false;  // the GET parameter may be given more than once (`mesh`)

    // Reads the member at `path` (present) into the spec. Empty for the members of a structured
    // member, which its own row reads.
    std::function<void(RenderSpec&, const nlohmann::json& value, const std::string& path,
                       const RenderLimits&)>
        read_json;
    // Reads the row's parameters from the query, when present. Empty where the JSON form alone
    // has the member, or a structured member's row reads it.
    std::function<void(RenderSpec&, const RenderQuery&, const RenderLimits&)> read_query;
    // Writes the spec's value into the canonical document (at the row's path). Empty where a
    // containing row writes it.
    std::function<void(const RenderSpec&, nlohmann::json& canonical)> write_canonical;
    // Sets the frame request's field; empty where the row lands elsewhere (the camera, the
    // meshes: to_frame_request resolves them) or a containing row sets it.
    std::function<void(const RenderSpec&, FrameRequest&)> to_frame;
};

// Every row: depth first in the body's order (a member's members follow it), which is the order
// the JSON form reads and lists them in.
const std::vector<RenderParameter>& render_parameters();

// The names of the members of the object at `parent` ("" the body, "camera/orbit",
// "objects/*"), in the table's order; empty for a path that is no object.
const std::vector<std::string_view>& render_member_names(std::string_view parent);

}  // namespace oer::api
