// The service's configuration: defaults, every option as a flag (both spellings) and as an
// environment variable, the flag winning, every kind of error naming its flag or variable, and
// the --help text generated from the same table.
#include <gtest/gtest.h>

#include <cstdlib>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "oer/api/invalid_parameter.hpp"
#include "oer/server/service_config.hpp"

using oer::api::InvalidParameter;
using namespace oer::server;

namespace {

EnvironmentLookup environment(std::map<std::string, std::string> variables) {
    return [variables =
                std::move(variables)](const std::string& name) -> std::optional<std::string> {
        const auto found = variables.find(name);
        return found == variables.end() ? std::nullopt : std::optional<std::string>(found->second);
    };
}

ServiceConfig parse(const std::vector<std::string>& arguments,
                    const std::map<std::string, std::string>& variables = {}) {
    const ServiceCommandLine command_line =
        parse_service_command_line(arguments, environment(variables));
    EXPECT_FALSE(command_line.help);
    return command_line.config;
}

// The InvalidParameter's parameter and message, or a test failure when nothing is thrown.
using Failure = std::pair<std::string, std::string>;
Failure failure(const std::vector<std::string>& arguments,
                const std::map<std::string, std::string>& variables = {}) {
    try {
        parse_service_command_line(arguments, environment(variables));
    } catch (const InvalidParameter& error) {
        return {error.parameter(), error.what()};
    }
    ADD_FAILURE() << "no InvalidParameter thrown";
    return {};
}

const std::vector<std::string> kEveryFlag{
    "host",
    "port",
    "admin-port",
    "data-dir",
    "api-key",
    "cors-origins",
    "max-upload-bytes",
    "max-image-pixels",
    "max-triangles",
    "max-concurrent-uploads",
    "upload-memory-bytes",
    "max-upload-expansion",
    "max-frame-width",
    "max-frame-height",
    "max-queue-depth",
    "render-workers",
    "request-timeout-seconds",
    "idle-timeout-seconds",
    "header-timeout-seconds",
    "keep-alive-max-count",
    "http-threads",
    "max-connections-per-client",
    "frame-cache-bytes",
    "transfer-ray-budget",
    "max-render-memory-bytes",
    "max-render-seconds",
    "client-render-rate",
    "max-transfer-bytes",
    "transfer-store-bytes",
    "job-max-frames",
    "job-max-pixels",
    "client-job-frames",
    "client-job-pixels",
    "job-retention-hours",
    "queue",
    "access-log",
    "warm-default-scene",
};

// One value per flag, none of them a default, in kEveryFlag's order.
// clang-format off
const std::vector<std::string> kEveryValue{
    "0.0.0.0", "9000", "9001", "/var/lib/oer", "secret",
    "https://a.example, http://b.example:3000",
    "1000", "2000", "3000", "3", "5000000", "20",
    "640", "480", "4", "2", "60", "10", "7", "50", "16", "8", "0", "250000",
    "1073741824", "20", "0.25", "33554432", "268435456",
    "500", "100000000", "900", "200000000", "24", "redis://127.0.0.1:6390", "off", "off",
};
// clang-format on

void expect_every_value(const ServiceConfig& config) {
    EXPECT_EQ(config.host, "0.0.0.0");
    EXPECT_EQ(config.port, 9000);
    EXPECT_EQ(config.admin_port, 9001);
    EXPECT_EQ(config.data_dir, "/var/lib/oer");
    EXPECT_EQ(config.api_key, "secret");
    EXPECT_EQ(config.cors_origins,
              (std::vector<std::string>{"https://a.example", "http://b.example:3000"}));
    EXPECT_EQ(config.max_upload_bytes, 1000u);
    EXPECT_EQ(config.max_image_pixels, 2000u);
    EXPECT_EQ(config.max_triangles, 3000u);
    EXPECT_EQ(config.max_concurrent_uploads, 3);
    EXPECT_EQ(config.upload_memory_bytes, 5'000'000u);
    EXPECT_EQ(config.max_upload_expansion, 20u);
    EXPECT_EQ(config.max_frame_width, 640);
    EXPECT_EQ(config.max_frame_height, 480);
    EXPECT_EQ(config.max_queue_depth, 4);
    EXPECT_EQ(config.render_workers, 2);
    EXPECT_EQ(config.request_timeout_seconds, 60);
    EXPECT_EQ(config.idle_timeout_seconds, 10);
    EXPECT_EQ(config.header_timeout_seconds, 7);
    EXPECT_EQ(config.keep_alive_max_count, 50);
    EXPECT_EQ(config.http_threads, 16);
    EXPECT_EQ(config.max_connections_per_client, 8);
    EXPECT_EQ(config.frame_cache_bytes, 0u);
    EXPECT_EQ(config.transfer_ray_budget, 250'000u);
    EXPECT_EQ(config.max_render_memory_bytes, 1u << 30);
    EXPECT_EQ(config.max_render_seconds, 20);
    EXPECT_EQ(config.client_render_rate, 0.25);
    EXPECT_EQ(config.max_transfer_bytes, 32u << 20);
    EXPECT_EQ(config.transfer_store_bytes, 256u << 20);
    EXPECT_EQ(config.job_max_frames, 500u);
    EXPECT_EQ(config.job_max_pixels, 100'000'000u);
    EXPECT_EQ(config.client_job_frames, 900u);
    EXPECT_EQ(config.client_job_pixels, 200'000'000u);
    EXPECT_EQ(config.job_retention_hours, 24);
    EXPECT_EQ(config.queue, "redis://127.0.0.1:6390");
    EXPECT_FALSE(config.access_log);
    EXPECT_FALSE(config.warm_default_scene);
}

}  // namespace

TEST(ServiceConfig, DefaultsWithoutFlagsOrVariables) {
    const ServiceConfig config = parse({});
    EXPECT_EQ(config.host, "127.0.0.1");
    EXPECT_EQ(config.port, 8080);
    EXPECT_EQ(config.admin_port, -1);
    EXPECT_EQ(config.data_dir, "./oer-data");
    EXPECT_EQ(config.api_key, "");
    EXPECT_TRUE(config.cors_origins.empty());
    EXPECT_EQ(config.max_upload_bytes, 268'435'456u);
    EXPECT_EQ(config.max_image_pixels, 33'554'432u);  // 8192 x 4096
    EXPECT_EQ(config.max_triangles, 5'000'000u);
    EXPECT_EQ(config.max_concurrent_uploads, 2);
    EXPECT_EQ(config.upload_memory_bytes, 2'147'483'648u);
    EXPECT_EQ(config.max_upload_expansion, 200u);
    EXPECT_EQ(config.max_frame_width, 4096);
    EXPECT_EQ(config.max_frame_height, 4096);
    EXPECT_EQ(config.max_queue_depth, 16);
    EXPECT_EQ(config.render_workers, 1);
    EXPECT_EQ(config.request_timeout_seconds, 30);
    EXPECT_EQ(config.idle_timeout_seconds, 5);
    EXPECT_EQ(config.header_timeout_seconds, 5);
    EXPECT_EQ(config.keep_alive_max_count, 100);
    EXPECT_EQ(config.http_threads, 256);
    EXPECT_EQ(config.max_connections_per_client, 64);
    EXPECT_EQ(config.frame_cache_bytes, 268'435'456u);
    EXPECT_EQ(config.transfer_ray_budget, 6'000'000u);
    EXPECT_EQ(config.max_render_memory_bytes, 2u << 30);
    EXPECT_EQ(config.max_render_seconds, 30);
    EXPECT_EQ(config.client_render_rate, 1.0);
    EXPECT_EQ(config.max_transfer_bytes, 64u << 20);
    EXPECT_EQ(config.transfer_store_bytes, 1u << 30);
    EXPECT_EQ(config.job_retention_hours, 168);
    EXPECT_TRUE(config.access_log);
    EXPECT_TRUE(config.warm_default_scene);
}

TEST(ServiceConfig, EveryFlagAsNameSpaceValue) {
    std::vector<std::string> arguments;
    for (std::size_t i = 0; i < kEveryFlag.size(); ++i) {
        arguments.push_back("--" + kEveryFlag[i]);
        arguments.push_back(kEveryValue[i]);
    }
    expect_every_value(parse(arguments));
}

TEST(ServiceConfig, EveryFlagAsNameEqualsValue) {
    std::vector<std::string> arguments;
    for (std::size_t i = 0; i < kEveryFlag.size(); ++i) {
        arguments.push_back("--" + kEveryFlag[i] + "=" + kEveryValue[i]);
    }
    expect_every_value(parse(arguments));
}

TEST(ServiceConfig, EveryOptionAsAnEnvironmentVariable) {
    std::map<std::string, std::string> variables;
    for (std::size_t i = 0; i < kEveryFlag.size(); ++i) {
        variables[environment_variable_of(kEveryFlag[i])] = kEveryValue[i];
    }
    EXPECT_EQ(variables.count("OER_DATA_DIR"), 1u);
    EXPECT_EQ(variables.count("OER_REQUEST_TIMEOUT_SECONDS"), 1u);
    expect_every_value(parse({}, variables));
}

TEST(ServiceConfig, AFlagWinsOverItsVariable) {
    const ServiceConfig config =
        parse({"--port", "9001", "--api-key="},
              {{"OER_PORT", "9002"}, {"OER_API_KEY", "k"}, {"OER_HOST", "::1"}});
    EXPECT_EQ(config.port, 9001);
    EXPECT_EQ(config.api_key, "");
    EXPECT_EQ(config.host, "::1");
}

TEST(ServiceConfig, AFlagWinsEvenOverAnInvalidVariable) {
    EXPECT_EQ(parse({"--port", "9001"}, {{"OER_PORT", "not a port"}}).port, 9001);
}

TEST(ServiceConfig, TheLastOfARepeatedFlagCounts) {
    EXPECT_EQ(parse({"--port", "1", "--port=2"}).port, 2);
}

TEST(ServiceConfig, ValuesMayLookLikeFlagsOrContainEquals) {
    const ServiceConfig config = parse({"--api-key", "--a=b", "--data-dir=x=y"});
    EXPECT_EQ(config.api_key, "--a=b");
    EXPECT_EQ(config.data_dir, "x=y");
}

TEST(ServiceConfig, RangeLimitsAreInclusive) {
    EXPECT_EQ(parse({"--port", "0"}).port, 0);
    EXPECT_EQ(parse({"--port", "65535"}).port, 65535);
    EXPECT_EQ(parse({"--frame-cache-bytes", "1099511627776"}).frame_cache_bytes, 1ull << 40);
    EXPECT_EQ(parse({"--job-retention-hours", "0"}).job_retention_hours, 0);  // kept for ever
    EXPECT_EQ(parse({"--cors-origins", "*"}).cors_origins, std::vector<std::string>{"*"});
    EXPECT_TRUE(parse({"--cors-origins", " "}).cors_origins.empty());
}

TEST(ServiceConfig, UnknownFlagsAndStrayArguments) {
    EXPECT_EQ(failure({"--bogus", "1"}),
              (Failure{"--bogus", "--bogus: unknown option (oer-server --help lists them)"}));
    EXPECT_EQ(failure({"--Port", "1"}).first, "--Port");
    EXPECT_EQ(failure({"--port_number=1"}).first, "--port_number");
    EXPECT_EQ(failure({"8080"}),
              (Failure{"8080", "8080: unexpected argument; options are --name VALUE"}));
    EXPECT_EQ(failure({"-p", "8080"}).first, "-p");
}

TEST(ServiceConfig, MissingValue) {
    EXPECT_EQ(failure({"--host", "h", "--port"}),
              (Failure{"--port", "--port: missing value (PORT)"}));
}

TEST(ServiceConfig, NotANumberOrOutOfRange) {
    EXPECT_EQ(failure({"--port", "abc"}),
              (Failure{"--port", "--port: expected an integer 0..65535, got \"abc\""}));
    EXPECT_EQ(failure({"--port=65536"}).second,
              "--port: expected an integer 0..65535, got \"65536\"");
    EXPECT_EQ(failure({"--port", "-1"}).second, "--port: expected an integer 0..65535, got \"-1\"");
    EXPECT_EQ(failure({"--port", "80.5"}).second,
              "--port: expected an integer 0..65535, got \"80.5\"");
    EXPECT_EQ(failure({"--port", " 80"}).second,
              "--port: expected an integer 0..65535, got \" 80\"");
    EXPECT_EQ(failure({"--port="}).second, "--port: expected an integer 0..65535, got \"\"");
    EXPECT_EQ(failure({"--render-workers", "0"}).second,
              "--render-workers: expected an integer 1..64, got \"0\"");
    EXPECT_EQ(failure({"--max-upload-bytes", "99999999999999999999999"}).second,
              "--max-upload-bytes: expected an integer 1..1099511627776, got "
              "\"99999999999999999999999\"");
    EXPECT_EQ(failure({"--max-frame-width", "16385"}).first, "--max-frame-width");
    EXPECT_EQ(failure({"--job-retention-hours", "-1"}).second,
              "--job-retention-hours: expected an integer 0..1000000, got \"-1\"");
}

TEST(ServiceConfig, InvalidTextValues) {
    EXPECT_EQ(failure({"--host", ""}).second, "--host: expected a non-empty value");
    EXPECT_EQ(failure({"--data-dir="}).second, "--data-dir: expected a folder, got an empty value");
    EXPECT_EQ(failure({"--access-log", "yes"}).second,
              "--access-log: expected on or off, got \"yes\"");
    EXPECT_EQ(failure({"--admin-port", "none"}).second,
              "--admin-port: expected an integer 0..65535 or off, got \"none\"");
    EXPECT_EQ(failure({"--admin-port", "70000"}).second,
              "--admin-port: expected an integer 0..65535 or off, got \"70000\"");
    EXPECT_EQ(parse({"--admin-port", "9001", "--admin-port", "off"}).admin_port, -1);
    for (const char* origins : {"shop.example", "https://a.example/", "https://a.example,",
                                "https://a b.example", "https://a.example,,https://b.example"}) {
        EXPECT_EQ(failure({"--cors-origins", origins}).first, "--cors-origins") << origins;
    }
}

TEST(ServiceConfig, AnInvalidVariableIsNamed) {
    EXPECT_EQ(failure({}, {{"OER_PORT", "http"}}),
              (Failure{"OER_PORT", "OER_PORT: expected an integer 0..65535, got \"http\""}));
    EXPECT_EQ(failure({}, {{"OER_ACCESS_LOG", ""}}).first, "OER_ACCESS_LOG");
}

TEST(ServiceConfig, ControlCharactersInARejectedValueAreEscaped) {
    EXPECT_EQ(failure({"--port", std::string("1\n2\0", 4)}).second,
              "--port: expected an integer 0..65535, got \"1\\n2\\u0000\"");
}

TEST(ServiceConfig, HelpIsAskedForAndListsEveryOptionOnce) {
    for (const char* flag : {"--help", "-h"}) {
        const ServiceCommandLine command_line =
            parse_service_command_line({"--port", "1", flag}, environment({}));
        EXPECT_TRUE(command_line.help) << flag;
    }
    std::vector<std::string> listed;
    std::istringstream lines(service_help_text());
    std::string line;
    while (std::getline(lines, line)) {
        if (line.starts_with("  --")) {
            listed.push_back(line.substr(4, line.find(' ', 4) - 4));
        }
    }
    EXPECT_EQ(listed, kEveryFlag);
    const std::string help = service_help_text();
    EXPECT_NE(help.find("  --port PORT\n      TCP port to listen on; 0 picks a free one (OER_PORT; "
                        "default: 8080)\n"),
              std::string::npos)
        << help;
    EXPECT_NE(help.find("(OER_API_KEY; default: none)"), std::string::npos);
    EXPECT_NE(help.find("(OER_MAX_UPLOAD_BYTES; default: 268435456)"), std::string::npos);
    EXPECT_NE(help.find("(OER_ACCESS_LOG; default: on)"), std::string::npos);
}

TEST(ServiceConfig, VariableNames) {
    EXPECT_EQ(environment_variable_of("port"), "OER_PORT");
    EXPECT_EQ(environment_variable_of("data-dir"), "OER_DATA_DIR");
    EXPECT_EQ(environment_variable_of("keep-alive-max-count"), "OER_KEEP_ALIVE_MAX_COUNT");
}

TEST(ServiceConfig, ProcessEnvironmentReadsTheRealEnvironment) {
    const std::string name = "OER_SERVICE_CONFIG_TEST_VARIABLE";
    ASSERT_EQ(::setenv(name.c_str(), "value", 1), 0);
    EXPECT_EQ(process_environment(name), "value");
    ASSERT_EQ(::unsetenv(name.c_str()), 0);
    EXPECT_EQ(process_environment(name), std::nullopt);
}
