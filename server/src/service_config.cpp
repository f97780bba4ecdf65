#include "oer/server/service_config.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstdlib>
#include <memory>
#include <sstream>
#include <string_view>

#include <CLI/CLI.hpp>

#include "oer/api/invalid_parameter.hpp"
#include "quoted_excerpt.hpp"

namespace oer::server {

namespace {

using api::InvalidParameter;

// One option: how it is spelled, what it means, how a value is stored in the configuration and
// how the configuration's value is shown as the default in --help.
struct Option {
    std::string_view flag;  // without the leading "--"
    std::string_view value_name;
    std::string_view meaning;
    // source: "--flag" or "OER_FLAG", whichever gave the text, for the error message.
    std::function<void(ServiceConfig&, const std::string& source, const std::string& text)> set;
    std::function<std::string(const ServiceConfig&)> show;
};

// An on|off option.
Option switch_option(std::string_view flag, std::string_view meaning, bool ServiceConfig::*member) {
    return Option{
        flag, "on|off", meaning,
        [member](ServiceConfig& config, const std::string& source, const std::string& text) {
            if (text != "on" && text != "off") {
                throw InvalidParameter(source, "expected on or off, got " + quoted_excerpt(text));
            }
            config.*member = text == "on";
        },
        [member](const ServiceConfig& config) {
            return std::string(config.*member ? "on" : "off");
        }};
}

template <class Integer>
Option integer_option(std::string_view flag, std::string_view value_name, std::string_view meaning,
                      Integer ServiceConfig::*member, std::uint64_t low, std::uint64_t high) {
    return Option{flag, value_name, meaning,
                  [member, low, high](ServiceConfig& config, const std::string& source,
                                      const std::string& text) {
                      std::uint64_t value = 0;
                      const auto [end, error] =
                          std::from_chars(text.data(), text.data() + text.size(), value);
                      if (error != std::errc() || end != text.data() + text.size() || value < low ||
                          value > high) {
                          throw InvalidParameter(
                              source, "expected an integer " + std::to_string(low) + ".." +
                                          std::to_string(high) + ", got " + quoted_excerpt(text));
                      }
                      config.*member = Integer(value);
                  },
                  [member](const ServiceConfig& config) { return std::to_string(config.*member); }};
}

Option number_option(std::string_view flag, std::string_view value_name, std::string_view meaning,
                     double ServiceConfig::*member, double low, double high) {
    const auto text_of = [](double value) {
        std::ostringstream text;
        text << value;
        return text.str();
    };
    return Option{
        flag, value_name, meaning,
        [member, low, high, text_of](ServiceConfig& config, const std::string& source,
                                     const std::string& text) {
            double value = 0.0;
            const auto [end, error] =
                std::from_chars(text.data(), text.data() + text.size(), value);
            if (error != std::errc() || end != text.data() + text.size() ||
                !(value >= low && value <= high)) {
                throw InvalidParameter(source, "expected a number " + text_of(low) + ".." +
                                                   text_of(high) + ", got " + quoted_excerpt(text));
            }
            config.*member = value;
        },
        [member, text_of](const ServiceConfig& config) { return text_of(config.*member); }};
}

Option text_option(std::string_view flag, std::string_view value_name, std::string_view meaning,
                   std::string ServiceConfig::*member, bool may_be_empty) {
    return Option{flag, value_name, meaning,
                  [member, may_be_empty](ServiceConfig& config, const std::string& source,
                                         const std::string& text) {
                      if (text.empty() && !may_be_empty) {
                          throw InvalidParameter(source, "expected a non-empty value");
                      }
                      config.*member = text;
                  },
                  [member](const ServiceConfig& config) { return config.*member; }};
}

std::string_view trimmed(std::string_view text) {
    const auto first = text.find_first_not_of(" \t");
    if (first == std::string_view::npos) {
        return {};
    }
    return text.substr(first, text.find_last_not_of(" \t") - first + 1);
}

// "https://a.example, http://b.example:3000" or "*"; an origin is a scheme and a host (and a
// port), never a path, so it carries no trailing slash.
std::vector<std::string> parse_origins(const std::string& source, const std::string& text) {
    std::vector<std::string> origins;
    if (trimmed(text).empty()) {
        return origins;
    }
    std::string_view rest = text;
    while (true) {
        const auto comma = rest.find(',');
        const std::string_view origin = trimmed(rest.substr(0, comma));
        const bool has_scheme = origin.starts_with("http://") || origin.starts_with("https://");
        if (origin != "*" && (!has_scheme || origin.ends_with('/') ||
                              origin.find_first_of(" \t") != std::string_view::npos)) {
            throw InvalidParameter(source,
                                   "expected a comma-separated list of origins like "
                                   "https://shop.example or *, got " +
                                       quoted_excerpt(origin));
        }
        origins.emplace_back(origin);
        if (comma == std::string_view::npos) {
            return origins;
        }
        rest.remove_prefix(comma + 1);
    }
}

std::string join(const std::vector<std::string>& items) {
    std::string text;
    for (const std::string& item : items) {
        text += (text.empty() ? "" : ",") + item;
    }
    return text;
}

const std::vector<Option>& options() {
    static const std::vector<Option> table{
        text_option("host", "ADDRESS", "address to listen on", &ServiceConfig::host, false),
        integer_option("port", "PORT", "TCP port to listen on; 0 picks a free one",
                       &ServiceConfig::port, 0, 65535),
        Option{"admin-port", "PORT|off",
               "TCP port of the admin listener (/healthz, /readyz, /metrics on threads of their "
               "own); 0 picks a free one, off: none",
               [](ServiceConfig& config, const std::string& source, const std::string& text) {
                   if (text == "off") {
                       config.admin_port = -1;
                       return;
                   }
                   int value = -1;
                   const auto [end, error] =
                       std::from_chars(text.data(), text.data() + text.size(), value);
                   if (error != std::errc() || end != text.data() + text.size() || value < 0 ||
                       value > 65535) {
                       throw InvalidParameter(source, "expected an integer 0..65535 or off, got " +
                                                          quoted_excerpt(text));
                   }
                   config.admin_port = value;
               },
               [](const ServiceConfig& config) {
                   return config.admin_port < 0 ? std::string("off")
                                                : std::to_string(config.admin_port);
               }},
        Option{"data-dir", "DIR", "folder of the asset store, created if missing",
               [](ServiceConfig& config, const std::string& source, const std::string& text) {
                   if (text.empty()) {
                       throw InvalidParameter(source, "expected a folder, got an empty value");
                   }
                   config.data_dir = text;
               },
               [](const ServiceConfig& config) { return config.data_dir.string(); }},
        text_option("api-key", "KEY", "key every request must carry; empty: none",
                    &ServiceConfig::api_key, true),
        Option{"cors-origins", "LIST",
               "comma-separated origins allowed to call the API from a browser (* for any); "
               "empty: none",
               [](ServiceConfig& config, const std::string& source, const std::string& text) {
                   config.cors_origins = parse_origins(source, text);
               },
               [](const ServiceConfig& config) { return join(config.cors_origins); }},
        integer_option("max-upload-bytes", "BYTES", "largest request body",
                       &ServiceConfig::max_upload_bytes, 1, 1ull << 40),
        integer_option("max-image-pixels", "PIXELS",
                       "largest environment map (width x height; the default is an 8k map, "
                       "8192 x 4096)",
                       &ServiceConfig::max_image_pixels, 1, 1ull << 32),
        integer_option("max-triangles", "COUNT", "most triangles in one mesh",
                       &ServiceConfig::max_triangles, 1, 1ull << 32),
        integer_option("max-concurrent-uploads", "COUNT",
                       "uploads decoded and preprocessed at once; more are answered 503",
                       &ServiceConfig::max_concurrent_uploads, 1, 1024),
        integer_option("upload-memory-bytes", "BYTES",
                       "memory the uploads being decoded may hold together; more are answered 503",
                       &ServiceConfig::upload_memory_bytes, 1ull << 20, 1ull << 44),
        integer_option("max-upload-expansion", "RATIO",
                       "times its own size an upload may expand to when decoded (above 64 MiB); "
                       "0: any",
                       &ServiceConfig::max_upload_expansion, 0, 1'000'000),
        integer_option("max-frame-width", "PIXELS", "widest frame a request may ask for",
                       &ServiceConfig::max_frame_width, 1, 16384),
        integer_option("max-frame-height", "PIXELS", "tallest frame a request may ask for",
                       &ServiceConfig::max_frame_height, 1, 16384),
        integer_option("max-queue-depth", "COUNT",
                       "render requests that may wait for a worker; more wait up to 0.5 s for a "
                       "place, then are answered 503",
                       &ServiceConfig::max_queue_depth, 1, 10000),
        integer_option("render-workers", "COUNT", "frames rendered at once",
                       &ServiceConfig::render_workers, 1, 64),
        integer_option("request-timeout-seconds", "SECONDS",
                       "longest a request may take to arrive or be answered",
                       &ServiceConfig::request_timeout_seconds, 1, 3600),
        integer_option("idle-timeout-seconds", "SECONDS",
                       "longest an idle keep-alive connection stays open",
                       &ServiceConfig::idle_timeout_seconds, 1, 3600),
        integer_option("header-timeout-seconds", "SECONDS",
                       "longest a request's line and headers may take to arrive",
                       &ServiceConfig::header_timeout_seconds, 1, 3600),
        integer_option("keep-alive-max-count", "COUNT", "most requests on one connection",
                       &ServiceConfig::keep_alive_max_count, 1, 100000),
        integer_option("http-threads", "COUNT", "threads serving HTTP connections",
                       &ServiceConfig::http_threads, 1, 4096),
        integer_option("max-connections-per-client", "COUNT",
                       "connections one client address may hold; more are answered 429; 0: no "
                       "limit (behind a proxy)",
                       &ServiceConfig::max_connections_per_client, 0, 1'000'000),
        integer_option("frame-cache-bytes", "BYTES", "memory for encoded frames; 0: no cache",
                       &ServiceConfig::frame_cache_bytes, 0, 1ull << 40),
        integer_option("transfer-ray-budget", "RAYS",
                       "rays per phase of a scene's transfer bake, shared by its points (fewer: "
                       "faster bakes, noisier occlusion)",
                       &ServiceConfig::transfer_ray_budget, 100'000, 1'000'000'000),
        integer_option("max-render-memory-bytes", "BYTES",
                       "most memory one render may be estimated to take (meshes, frame targets, "
                       "shadow maps, transfer); more is answered 413 before it runs",
                       &ServiceConfig::max_render_memory_bytes, 64ull << 20, 1ull << 44),
        integer_option("max-render-seconds", "SECONDS",
                       "most time one render may be estimated to take on llvmpipe (drawing, "
                       "shading, baking its transfer); more is answered 413 before it runs",
                       &ServiceConfig::max_render_seconds, 1, 3600),
        number_option("client-render-rate", "SECONDS",
                      "seconds of render work each client address earns a second for uncached "
                      "frames, saved up to --max-render-seconds; past it, 429; 0: no limit "
                      "(behind a proxy)",
                      &ServiceConfig::client_render_rate, 0.0, 1000.0),
        integer_option("max-transfer-bytes", "BYTES",
                       "largest occlusion transfer one render may bake and store; larger is "
                       "answered 413 before it runs",
                       &ServiceConfig::max_transfer_bytes, 1ull << 20, 1ull << 40),
        integer_option("transfer-store-bytes", "BYTES",
                       "disk for stored occlusion transfers; past it the least recently used are "
                       "removed (and baked again when a frame needs one)",
                       &ServiceConfig::transfer_store_bytes, 1ull << 20, 1ull << 44),
        integer_option("job-max-frames", "COUNT", "most frames one batch job may hold; more: 413",
                       &ServiceConfig::job_max_frames, 1, 100000),
        integer_option("job-max-pixels", "PIXELS",
                       "most pixels one batch job's frames may hold together; more: 413",
                       &ServiceConfig::job_max_pixels, 1, 1ull << 40),
        integer_option("client-job-frames", "COUNT",
                       "most frames a client's unfinished batch jobs may still hold; more: 429",
                       &ServiceConfig::client_job_frames, 1, 1000000),
        integer_option("client-job-pixels", "PIXELS",
                       "most pixels a client's unfinished batch jobs may still hold; more: 429",
                       &ServiceConfig::client_job_pixels, 1, 1ull << 44),
        integer_option("job-retention-hours", "HOURS",
                       "hours a settled batch job (done, failed, cancelled) is kept after its "
                       "last change, then removed with its frames; 0: kept for ever",
                       &ServiceConfig::job_retention_hours, 0, 1'000'000),
        Option{"queue", "URL",
               "redis://HOST:PORT: the Redis stream replicas share batch jobs' frames through; "
               "empty: jobs stay in this replica",
               [](ServiceConfig& config, const std::string& source, const std::string& text) {
                   if (!text.empty() && !text.starts_with("redis://")) {
                       throw InvalidParameter(
                           source,
                           "expected redis://HOST:PORT or nothing, got " + quoted_excerpt(text));
                   }
                   config.queue = text;
               },
               [](const ServiceConfig& config) { return config.queue; }},
        switch_option("access-log", "one line per request on stderr", &ServiceConfig::access_log),
        switch_option("warm-default-scene",
                      "make the default scene's occlusion transfer and reflection cube before the "
                      "service is ready, so that its first frame waits for neither; off: a matte "
                      "test frame checks the renderer and the first default frame makes them",
                      &ServiceConfig::warm_default_scene),
    };
    return table;
}

const Option* find_option(std::string_view flag) {
    const auto& table = options();
    const auto found =
        std::find_if(table.begin(), table.end(), [&](const Option& o) { return o.flag == flag; });
    return found == table.end() ? nullptr : &*found;
}

// The --help text of the table: usage, then per option its flag and value, and on the next line
// its meaning, variable and default.
class HelpFormatter : public CLI::Formatter {
  public:
    std::string make_help(const CLI::App* app, std::string, CLI::AppFormatMode) const override {
        std::string text =
            "Usage: oer-server [--NAME VALUE | --NAME=VALUE]... | --help\n"
            "\n"
            "Every option is also the environment variable OER_NAME (upper case, dashes as\n"
            "underscores); an option on the command line wins over its variable.\n"
            "\n";
        for (const CLI::Option* option : app->get_options()) {
            if (option == app->get_help_ptr()) {
                continue;
            }
            const std::string& shown = option->get_default_str();
            text += "  " + option->get_name() + " " + option->get_type_name() + "\n      " +
                    option->get_description() + " (" +
                    environment_variable_of(option->get_name().substr(2)) +
                    "; default: " + (shown.empty() ? "none" : shown) + ")\n";
        }
        return text;
    }
};

// The table as a CLI11 app. Each option takes one value, kept as text so that the table's own
// parsers check it and name the flag or the variable that gave it. Variables are read after
// parsing through the caller's EnvironmentLookup, not through CLI11's envname: that calls getenv
// itself (bypassing the lookup) and drops a variable set to "", which must be an error for
// OER_ACCESS_LOG and a value (no key) for OER_API_KEY.
std::unique_ptr<CLI::App> service_app() {
    auto app = std::make_unique<CLI::App>("oer-server", "oer-server");
    app->allow_extras();
    app->formatter(std::make_shared<HelpFormatter>());
    const ServiceConfig defaults;
    for (const Option& option : options()) {
        const std::string flag(option.flag);
        app->add_option("--" + flag)
            ->description(std::string(option.meaning))
            ->type_name(std::string(option.value_name))
            ->default_str(option.show(defaults))
            ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
    }
    return app;
}

// CLI11 reads "--name=" as "--name" and would take the next argument as its value; an empty
// inline value is passed on as an argument of its own instead, so that it is checked as "".
std::vector<std::string> with_empty_values_apart(const std::vector<std::string>& arguments) {
    std::vector<std::string> split;
    bool is_value = false;  // the previous argument was a flag waiting for its value
    for (const std::string& argument : arguments) {
        if (!is_value && argument.starts_with("--") && argument.find('=') == argument.size() - 1) {
            split.push_back(argument.substr(0, argument.size() - 1));
            split.emplace_back();
            continue;
        }
        is_value = !is_value && argument.starts_with("--") &&
                   argument.find('=') == std::string::npos && find_option(argument.substr(2));
        split.push_back(argument);
    }
    return split;
}

}  // namespace

std::optional<std::string> process_environment(const std::string& name) {
    const char* value = std::getenv(name.c_str());
    return value ? std::optional<std::string>(value) : std::nullopt;
}

std::string environment_variable_of(const std::string& flag) {
    std::string name = "OER_";
    for (const char c : flag) {
        name += c == '-' ? '_' : char(std::toupper(static_cast<unsigned char>(c)));
    }
    return name;
}

ServiceCommandLine parse_service_command_line(const std::vector<std::string>& arguments,
                                              const EnvironmentLookup& environment) {
    ServiceCommandLine command_line;
    const std::unique_ptr<CLI::App> app = service_app();
    std::vector<std::string> reversed = with_empty_values_apart(arguments);
    std::reverse(reversed.begin(), reversed.end());  // CLI11 takes them last first
    try {
        app->parse(reversed);
    } catch (const CLI::CallForHelp&) {
        command_line.help = true;
        return command_line;
    } catch (const CLI::ArgumentMismatch&) {
        // Every option takes one value and CLI11 takes any next argument as it, so only the last
        // argument can be a flag without its value.
        const std::string& flag = arguments.back();
        throw InvalidParameter(
            flag, "missing value (" + std::string(find_option(flag.substr(2))->value_name) + ")");
    }
    if (const std::vector<std::string> extras = app->remaining(); !extras.empty()) {
        const std::string& first = extras.front();
        if (first.starts_with("--")) {
            throw InvalidParameter(first.substr(0, first.find('=')),
                                   "unknown option (oer-server --help lists them)");
        }
        throw InvalidParameter(first, "unexpected argument; options are --name VALUE");
    }
    for (const Option& option : options()) {
        const CLI::Option* parsed = app->get_option("--" + std::string(option.flag));
        if (parsed->count() > 0) {
            option.set(command_line.config, parsed->get_name(), parsed->results().back());
        } else if (const std::string variable = environment_variable_of(std::string(option.flag));
                   const auto value = environment(variable)) {
            option.set(command_line.config, variable, *value);
        }
    }
    return command_line;
}

std::string service_help_text() {
    return service_app()->help();
}

}  // namespace oer::server
