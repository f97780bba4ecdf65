// The Kubernetes manifests (docker/k8s) held to the image (docker/Dockerfile) and to the real
// oer-server: what a cluster would accept without a word and then run wrong. Probes on a path the
// server does not serve or on a port it does not listen on (pods never ready, or restarted for
// ever), a Service onto the wrong port (no answers), the store mounted beside the data folder
// (every replica with an empty store of its own), a volume only one node can mount, an
// autoscaler aimed at another name or at a metric nobody exports (it scales on nothing), a grace
// period shorter than a render, a GPU patch that adds a second container instead of changing the
// first. The container's environment is worked out as the kubelet would (the image's ENV, then
// envFrom, then env) and parsed by the server's own option parser; the probes' paths and the
// metrics are asked of a running oer-server started with that environment. Each check is shown
// to fail on a manifest broken in its way (EachCheckFailsOnAManifestBrokenSo).
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <map>
#include <memory>
#include <optional>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "http_support.hpp"
#include "oer/api/invalid_parameter.hpp"
#include "oer/server/service_config.hpp"
#include "server_process.hpp"

using namespace oer;
using namespace oer::ptest;

namespace {

namespace fs = std::filesystem;

const fs::path kDockerDir = OER_DOCKER_DIR;
const fs::path kBaseDir = kDockerDir / "k8s" / "base";
const fs::path kGpuDir = kDockerDir / "k8s" / "gpu";
const fs::path kAdapterRules = kDockerDir / "k8s" / "prometheus-adapter-rules.yaml";

// ---- The image: the ENV and USER of docker/Dockerfile's last stage (the one that runs). ----

struct Image {
    std::map<std::string, std::string> environment;
    std::string user;  // as USER gives it: "10001", "10001:10001" or a name
    std::string uid;   // USER's number, or the --uid that a RUN's useradd gave its name
};

std::string unquoted(std::string text) {
    if (text.size() >= 2 && (text.front() == '"' || text.front() == '\'') &&
        text.back() == text.front()) {
        return text.substr(1, text.size() - 2);
    }
    return text;
}

// Instructions with their continuation lines joined (Dockerfile reference: a backslash at the
// end of a line continues it; lines starting with # are comments, also inside continuations).
std::vector<std::string> dockerfile_instructions(const std::string& text) {
    std::vector<std::string> instructions;
    std::string current;
    std::istringstream lines(text);
    std::string line;
    while (std::getline(lines, line)) {
        const auto first = line.find_first_not_of(" \t");
        if (first == std::string::npos || line[first] == '#') {
            continue;
        }
        while (!line.empty() && std::isspace(static_cast<unsigned char>(line.back()))) {
            line.pop_back();
        }
        if (!line.empty() && line.back() == '\\') {
            current += line.substr(0, line.size() - 1) + " ";
            continue;
        }
        instructions.push_back(current + line);
        current.clear();
    }
    return instructions;
}

// The uid that `useradd ... --uid N ... NAME` (or -u N) gives each name, in a RUN's commands.
std::map<std::string, std::string> useradd_uids(const std::string& run) {
    std::map<std::string, std::string> uids;
    const std::regex command(R"(\buseradd\s+([^;&|]*))");
    for (auto match = std::sregex_iterator(run.begin(), run.end(), command);
         match != std::sregex_iterator(); ++match) {
        std::istringstream words((*match)[1].str());
        const std::vector<std::string> tokens{std::istream_iterator<std::string>(words), {}};
        for (std::size_t i = 0; i + 1 < tokens.size(); ++i) {
            if (tokens[i] == "--uid" || tokens[i] == "-u") {
                uids[tokens.back()] = tokens[i + 1];
            }
        }
    }
    return uids;
}

Image read_image(const fs::path& dockerfile) {
    Image image;
    std::map<std::string, std::string> uids;
    for (const std::string& instruction : dockerfile_instructions(read_text(dockerfile))) {
        std::istringstream words(instruction);
        std::string keyword;
        words >> keyword;
        std::transform(keyword.begin(), keyword.end(), keyword.begin(),
                       [](unsigned char c) { return char(std::toupper(c)); });
        if (keyword == "FROM") {
            image = Image{};  // a new stage: only the last one's settings reach the container
            uids.clear();
        } else if (keyword == "RUN") {
            uids.merge(useradd_uids(instruction));
        } else if (keyword == "USER") {
            words >> image.user;
            const std::string name = image.user.substr(0, image.user.find(':'));
            image.uid = uids.count(name) ? uids.at(name) : name;
        } else if (keyword == "ENV") {
            std::vector<std::string> tokens{std::istream_iterator<std::string>(words), {}};
            if (tokens.size() >= 2 && tokens[0].find('=') == std::string::npos) {
                // The legacy form "ENV NAME value with spaces".
                std::string value;
                for (std::size_t i = 1; i < tokens.size(); ++i) {
                    value += (i > 1 ? " " : "") + tokens[i];
                }
                image.environment[tokens[0]] = unquoted(value);
            } else {
                for (const std::string& token : tokens) {
                    const auto equals = token.find('=');
                    image.environment[token.substr(0, equals)] = unquoted(token.substr(equals + 1));
                }
            }
        }
    }
    return image;
}

// ---- The manifests. ----

// Every object of a kustomization's resources (files, not directories), by "Kind/name".
struct Objects {
    std::map<std::string, YAML::Node> by_key;

    std::vector<YAML::Node> of_kind(const std::string& kind) const {
        std::vector<YAML::Node> found;
        for (const auto& [key, node] : by_key) {
            if (key.starts_with(kind + "/")) {
                found.push_back(node);
            }
        }
        return found;
    }
};

struct Manifests {
    Objects base;
    YAML::Node gpu_kustomization;
    YAML::Node gpu_patch;
    YAML::Node adapter_rules;

    Manifests clone() const {
        Manifests copy;
        for (const auto& [key, node] : base.by_key) {
            copy.base.by_key[key] = YAML::Clone(node);
        }
        copy.gpu_kustomization = YAML::Clone(gpu_kustomization);
        copy.gpu_patch = YAML::Clone(gpu_patch);
        copy.adapter_rules = YAML::Clone(adapter_rules);
        return copy;
    }
    YAML::Node object(const std::string& key) { return base.by_key.at(key); }
};

Objects load_kustomization(const fs::path& folder) {
    Objects objects;
    const YAML::Node kustomization = YAML::LoadFile((folder / "kustomization.yaml").string());
    for (const YAML::Node& resource : kustomization["resources"]) {
        for (const YAML::Node& document :
             YAML::LoadAllFromFile((folder / resource.as<std::string>()).string())) {
            if (document.IsNull()) {
                continue;
            }
            objects.by_key.emplace(document["kind"].as<std::string>() + "/" +
                                       document["metadata"]["name"].as<std::string>(),
                                   document);
        }
    }
    return objects;
}

Manifests load_manifests() {
    Manifests manifests;
    manifests.base = load_kustomization(kBaseDir);
    manifests.gpu_kustomization = YAML::LoadFile((kGpuDir / "kustomization.yaml").string());
    manifests.gpu_patch = YAML::LoadFile((kGpuDir / "deployment-gpu.yaml").string());
    manifests.adapter_rules = YAML::LoadFile(kAdapterRules.string());
    return manifests;
}

// ---- What the running server says. ----

struct Server {
    std::function<int(const std::string& path)> admin_status;  // GET path on the admin listener
    std::map<std::string, std::string> metric_types;           // family -> gauge, counter, ...
};

// ---- The checks: each returns what is wrong, one sentence an item. ----

using Problems = std::vector<std::string>;

std::string text_of(const YAML::Node& node) {
    return node && node.IsScalar() ? node.Scalar() : std::string();
}

bool is_number(const std::string& text) {
    return !text.empty() && std::all_of(text.begin(), text.end(),
                                        [](unsigned char c) { return std::isdigit(c) != 0; });
}

// A port as a probe or a Service names it: a number, or the name of one of the container's
// ports; nullopt for a name the container does not have.
std::optional<int> resolve_port(const YAML::Node& port, const YAML::Node& container) {
    const std::string text = text_of(port);
    if (is_number(text)) {
        return std::stoi(text);
    }
    for (const YAML::Node& declared : container["ports"]) {
        if (text_of(declared["name"]) == text) {
            return declared["containerPort"].as<int>();
        }
    }
    return std::nullopt;
}

bool labels_select(const YAML::Node& selector, const YAML::Node& labels) {
    for (const auto& entry : selector) {
        if (text_of(labels[entry.first.Scalar()]) != entry.second.Scalar()) {
            return false;
        }
    }
    return selector && selector.size() > 0;
}

// The container's environment as the kubelet makes it: the image's ENV, then each envFrom
// source in order, then env (valueFrom entries are not known here and are left out).
std::map<std::string, std::string> container_environment(const Image& image, const Objects& objects,
                                                         const YAML::Node& container,
                                                         Problems& problems) {
    std::map<std::string, std::string> environment = image.environment;
    for (const YAML::Node& source : container["envFrom"]) {
        if (const YAML::Node reference = source["configMapRef"]) {
            const std::string name = text_of(reference["name"]);
            const auto found = objects.by_key.find("ConfigMap/" + name);
            if (found == objects.by_key.end()) {
                if (text_of(reference["optional"]) != "true") {
                    problems.push_back("envFrom names the ConfigMap " + name +
                                       ", which the kustomization does not make");
                }
                continue;
            }
            for (const auto& entry : found->second["data"]) {
                environment[entry.first.Scalar()] = entry.second.Scalar();
            }
        } else if (const YAML::Node secret = source["secretRef"]) {
            if (text_of(secret["optional"]) != "true") {
                problems.push_back("envFrom needs the Secret " + text_of(secret["name"]) +
                                   ", which nothing makes: mark it optional");
            }
        }
    }
    for (const YAML::Node& variable : container["env"]) {
        if (variable["value"]) {
            environment[text_of(variable["name"])] = text_of(variable["value"]);
        }
    }
    return environment;
}

// The server's configuration in that environment and with the container's args, parsed by
// oer-server's own parser; nullopt (and a problem) when the server would refuse to start.
std::optional<server::ServiceConfig> container_config(
    const std::map<std::string, std::string>& environment, const YAML::Node& container,
    Problems& problems) {
    std::vector<std::string> arguments;
    for (const YAML::Node& argument : container["args"]) {
        arguments.push_back(argument.Scalar());
    }
    try {
        const auto lookup = [&environment](const std::string& name) -> std::optional<std::string> {
            const auto found = environment.find(name);
            return found == environment.end() ? std::nullopt : std::optional(found->second);
        };
        return server::parse_service_command_line(arguments, lookup).config;
    } catch (const api::InvalidParameter& error) {
        problems.push_back(std::string("oer-server refuses the container's configuration: ") +
                           error.what());
        return std::nullopt;
    }
}

// Whether path lies under a volume the container mounts writable.
bool under_writable_mount(const std::string& path, const YAML::Node& container) {
    for (const YAML::Node& mount : container["volumeMounts"]) {
        const std::string mounted = text_of(mount["mountPath"]);
        if (text_of(mount["readOnly"]) != "true" &&
            (path == mounted || path.starts_with(mounted + "/"))) {
            return true;
        }
    }
    return false;
}

// Variables naming a folder a library writes its cache to (Mesa's MESA_SHADER_CACHE_DIR,
// NVIDIA's __GL_SHADER_DISK_CACHE_PATH): with a read-only root, they must point at a volume.
void check_cache_folders(const YAML::Node& env_entries,
                         const std::map<std::string, std::string>& environment,
                         const YAML::Node& container, const std::string& where,
                         Problems& problems) {
    std::set<std::string> names;
    for (const auto& [name, value] : environment) {
        names.insert(name);
    }
    for (const YAML::Node& variable : env_entries) {
        names.insert(text_of(variable["name"]));
    }
    for (const std::string& name : names) {
        if (!name.ends_with("CACHE_DIR") && !name.ends_with("CACHE_PATH")) {
            continue;
        }
        std::string value;
        if (const auto found = environment.find(name); found != environment.end()) {
            value = found->second;
        }
        for (const YAML::Node& variable : env_entries) {
            if (text_of(variable["name"]) == name) {
                value = text_of(variable["value"]);
            }
        }
        if (!under_writable_mount(value, container)) {
            problems.push_back(where + ": " + name + "=" + value +
                               " is on the read-only root file system, not on a volume");
        }
    }
}

// The seconds a preStop hook holds the container before SIGTERM: `sleep N` or the sleep action.
int pre_stop_seconds(const YAML::Node& container) {
    const YAML::Node pre_stop = container["lifecycle"]["preStop"];
    if (!pre_stop) {
        return 0;
    }
    if (const YAML::Node sleep = pre_stop["sleep"]) {
        return sleep["seconds"].as<int>();
    }
    const YAML::Node command = pre_stop["exec"]["command"];
    if (command && command.size() == 2 && fs::path(command[0].Scalar()).filename() == "sleep" &&
        is_number(command[1].Scalar())) {
        return std::stoi(command[1].Scalar());
    }
    return 0;
}

struct DeploymentView {
    std::string name;
    YAML::Node pod;        // spec.template
    YAML::Node container;  // the one container
    server::ServiceConfig config;
};

void check_probe(const std::string& kind, const YAML::Node& container,
                 const server::ServiceConfig& config, const Server& server, Problems& problems) {
    const YAML::Node probe = container[kind];
    if (!probe) {
        problems.push_back("the container has no " + kind);
        return;
    }
    const YAML::Node get = probe["httpGet"];
    if (!get) {
        problems.push_back(kind + " is not an httpGet probe");
        return;
    }
    const std::optional<int> port = resolve_port(get["port"], container);
    if (!port) {
        problems.push_back(kind + " port " + text_of(get["port"]) + " is no port of the container");
    } else if (*port != config.admin_port) {
        problems.push_back(kind + " port " + text_of(get["port"]) + " is " + std::to_string(*port) +
                           ", not the admin listener's OER_ADMIN_PORT " +
                           std::to_string(config.admin_port));
    }
    const std::string path = text_of(get["path"]);
    const int status = server.admin_status(path);
    if (status != 200) {
        problems.push_back(kind + " path " + path + " answers " + std::to_string(status) +
                           " on the admin listener of a ready server, not 200");
    }
}

std::optional<DeploymentView> check_deployment(const Image& image, const Objects& objects,
                                               const Server& server, Problems& problems) {
    const std::vector<YAML::Node> deployments = objects.of_kind("Deployment");
    if (deployments.size() != 1) {
        problems.push_back("expected one Deployment, found " + std::to_string(deployments.size()));
        return std::nullopt;
    }
    DeploymentView view;
    view.name = text_of(deployments[0]["metadata"]["name"]);
    view.pod = deployments[0]["spec"]["template"];
    const YAML::Node containers = view.pod["spec"]["containers"];
    if (!containers || containers.size() != 1) {
        problems.push_back("expected one container in the Deployment's pod");
        return std::nullopt;
    }
    view.container = containers[0];
    const YAML::Node& container = view.container;
    const YAML::Node pod_spec = view.pod["spec"];

    const auto environment = container_environment(image, objects, container, problems);
    const auto config = container_config(environment, container, problems);
    if (!config) {
        return std::nullopt;
    }
    view.config = *config;

    if (config->host.starts_with("127.") || config->host == "localhost" || config->host == "::1") {
        problems.push_back("OER_HOST " + config->host +
                           " is loopback: nothing outside the pod reaches it");
    }
    if (config->admin_port <= 0) {
        problems.push_back("no fixed admin port (OER_ADMIN_PORT): the probes have nothing to ask");
    }

    // The API port.
    bool api_port_declared = false;
    for (const YAML::Node& port : container["ports"]) {
        api_port_declared |= port["containerPort"].as<int>() == config->port;
    }
    if (!api_port_declared) {
        problems.push_back("no containerPort is OER_PORT " + std::to_string(config->port));
    }

    check_probe("startupProbe", container, *config, server, problems);
    check_probe("livenessProbe", container, *config, server, problems);
    check_probe("readinessProbe", container, *config, server, problems);
    if (text_of(container["livenessProbe"]["httpGet"]["path"]) ==
        text_of(container["readinessProbe"]["httpGet"]["path"])) {
        problems.push_back(
            "livenessProbe asks the readiness path: a replica whose queue is full would be "
            "restarted");
    }

    // The data folder on the shared claim.
    // (optional, not a YAML::Node assigned twice: yaml-cpp's assignment rebinds the node first
    // assigned, which would change the manifest.)
    std::optional<YAML::Node> data_mount;
    for (const YAML::Node& mount : container["volumeMounts"]) {
        if (text_of(mount["mountPath"]) == config->data_dir.string()) {
            data_mount.emplace(mount);
        }
    }
    if (!data_mount) {
        problems.push_back("no volume is mounted at OER_DATA_DIR " + config->data_dir.string() +
                           ": each replica would keep a store of its own");
    } else {
        std::optional<YAML::Node> claim;
        for (const YAML::Node& volume : pod_spec["volumes"]) {
            if (text_of(volume["name"]) == text_of((*data_mount)["name"]) &&
                volume["persistentVolumeClaim"]) {
                claim.emplace(volume["persistentVolumeClaim"]);
            }
        }
        const std::string claim_name = claim ? text_of((*claim)["claimName"]) : std::string();
        const auto pvc = objects.by_key.find("PersistentVolumeClaim/" + claim_name);
        if (!claim) {
            problems.push_back("the data folder's volume is not a PersistentVolumeClaim");
        } else if (pvc == objects.by_key.end()) {
            problems.push_back("the data folder's claim " + claim_name +
                               " is not made by the kustomization");
        } else {
            bool many = false;
            for (const YAML::Node& mode : pvc->second["spec"]["accessModes"]) {
                many |= mode.Scalar() == "ReadWriteMany";
            }
            if (!many) {
                problems.push_back(
                    "the PersistentVolumeClaim " + claim_name +
                    " is not ReadWriteMany: replicas on other nodes cannot mount it");
            }
        }
    }

    // The user and the read-only root.
    const YAML::Node pod_security = pod_spec["securityContext"];
    const YAML::Node security = container["securityContext"];
    const std::string run_as_user = text_of(security["runAsUser"]).empty()
                                        ? text_of(pod_security["runAsUser"])
                                        : text_of(security["runAsUser"]);
    if (text_of(pod_security["runAsNonRoot"]) != "true" &&
        text_of(security["runAsNonRoot"]) != "true") {
        problems.push_back("runAsNonRoot is not set");
    }
    if (is_number(image.uid) && run_as_user != image.uid) {
        problems.push_back("runAsUser " + run_as_user + " is not the image's user " + image.user +
                           " (uid " + image.uid + ")");
    }
    if (!is_number(image.user.substr(0, image.user.find(':'))) && run_as_user.empty()) {
        // Kubernetes: "container has runAsNonRoot and image has non-numeric user".
        problems.push_back("the image's USER " + image.user +
                           " is a name and no runAsUser is set: the kubelet refuses to start a "
                           "runAsNonRoot container it cannot check");
    }
    if (text_of(pod_security["fsGroup"]).empty()) {
        problems.push_back("no fsGroup: the claim's files may not be writable by the user");
    }
    if (text_of(security["readOnlyRootFilesystem"]) == "true") {
        if (!under_writable_mount("/tmp", container)) {
            problems.push_back("the root file system is read-only and /tmp is no volume");
        }
        check_cache_folders(container["env"], environment, container, "the Deployment", problems);
    }

    // The CPU request the autoscaler's utilisation is a share of.
    if (text_of(container["resources"]["requests"]["cpu"]).empty()) {
        problems.push_back("no CPU request: the autoscaler's CPU utilisation is unknown");
    }

    // Stopping: the preStop sleep, then requests in progress finish within their deadline.
    const int grace = pod_spec["terminationGracePeriodSeconds"]
                          ? pod_spec["terminationGracePeriodSeconds"].as<int>()
                          : 30;  // Kubernetes' default
    const int needed = pre_stop_seconds(container) + config->request_timeout_seconds;
    if (grace <= needed) {
        problems.push_back("terminationGracePeriodSeconds " + std::to_string(grace) +
                           " leaves no room for the preStop sleep and a request's " +
                           std::to_string(config->request_timeout_seconds) +
                           " s (OER_REQUEST_TIMEOUT_SECONDS): in-flight renders are killed");
    }

    // Prometheus's scrape annotations.
    const YAML::Node annotations = view.pod["metadata"]["annotations"];
    if (const YAML::Node port = annotations["prometheus.io/port"]) {
        if (port.Scalar() != std::to_string(config->admin_port)) {
            problems.push_back("prometheus.io/port " + port.Scalar() + " is not the admin port " +
                               std::to_string(config->admin_port));
        }
        const std::string path = text_of(annotations["prometheus.io/path"]);
        if (server.admin_status(path.empty() ? "/metrics" : path) != 200) {
            problems.push_back("prometheus.io/path " + path + " is not served on the admin port");
        }
    }
    return view;
}

void check_service(const DeploymentView& deployment, const Objects& objects, Problems& problems) {
    // The replicas' Service: the one that selects their pods (the job queue's, redis.yaml,
    // selects its own).
    std::vector<YAML::Node> services;
    for (const YAML::Node& service : objects.of_kind("Service")) {
        if (labels_select(service["spec"]["selector"], deployment.pod["metadata"]["labels"])) {
            services.push_back(service);
        }
    }
    if (services.size() != 1) {
        problems.push_back("expected one Service selecting the Deployment's pods, found " +
                           std::to_string(services.size()));
        return;
    }
    const YAML::Node spec = services[0]["spec"];
    bool serves_api = false;
    for (const YAML::Node& port : spec["ports"]) {
        const YAML::Node target = port["targetPort"] ? port["targetPort"] : port["port"];
        const std::optional<int> resolved = resolve_port(target, deployment.container);
        if (!resolved) {
            problems.push_back("the Service's targetPort " + text_of(target) +
                               " is no port of the container");
        } else if (*resolved == deployment.config.admin_port) {
            problems.push_back("the Service exposes the admin port " + std::to_string(*resolved));
        } else if (*resolved == deployment.config.port) {
            serves_api |= port["port"].as<int>() == 80;
        }
    }
    if (!serves_api) {
        problems.push_back("the Service has no port 80 onto OER_PORT " +
                           std::to_string(deployment.config.port));
    }
}

// OER_QUEUE (redis://HOST:PORT) names a Service of the kustomization, on that port, selecting
// the pods of the queue's StatefulSet (redis.yaml).
void check_queue(const DeploymentView& deployment, const Objects& objects, Problems& problems) {
    const std::string& url = deployment.config.queue;
    if (url.empty()) {
        return;
    }
    const std::string address = url.substr(std::string("redis://").size());
    const std::string host = address.substr(0, address.find(':'));
    const std::string port =
        address.find(':') == std::string::npos ? "6379" : address.substr(address.find(':') + 1);
    const auto service = objects.by_key.find("Service/" + host);
    if (service == objects.by_key.end()) {
        problems.push_back("OER_QUEUE names the Service " + host +
                           ", which the kustomization does not make");
        return;
    }
    bool has_port = false;
    for (const YAML::Node& declared : service->second["spec"]["ports"]) {
        has_port |= text_of(declared["port"]) == port;
    }
    if (!has_port) {
        problems.push_back("the Service " + host + " has no port " + port);
    }
    bool selects = false;
    for (const YAML::Node& set : objects.of_kind("StatefulSet")) {
        selects |= labels_select(service->second["spec"]["selector"],
                                 set["spec"]["template"]["metadata"]["labels"]);
    }
    if (!selects) {
        problems.push_back("the Service " + host + " selects no StatefulSet's pods");
    }
}

void check_disruption_budget(const DeploymentView& deployment, const Objects& objects,
                             Problems& problems) {
    for (const YAML::Node& budget : objects.of_kind("PodDisruptionBudget")) {
        if (!labels_select(budget["spec"]["selector"]["matchLabels"],
                           deployment.pod["metadata"]["labels"])) {
            problems.push_back("the PodDisruptionBudget does not select the Deployment's pods");
        }
    }
}

// The series a prometheus-adapter rule reads: the metric name its seriesQuery starts with.
std::string rule_series(const YAML::Node& rule) {
    const std::string query = text_of(rule["seriesQuery"]);
    return query.substr(0, query.find('{'));
}

// The name the adapter serves a rule's series under (its name.as, else the series' own).
std::string rule_served_name(const YAML::Node& rule) {
    const std::string as = text_of(rule["name"]["as"]);
    return as.empty() ? rule_series(rule) : as;
}

void check_autoscaler(const DeploymentView& deployment, const Manifests& manifests,
                      const Server& server, Problems& problems) {
    const std::vector<YAML::Node> autoscalers = manifests.base.of_kind("HorizontalPodAutoscaler");
    if (autoscalers.size() != 1) {
        problems.push_back("expected one HorizontalPodAutoscaler, found " +
                           std::to_string(autoscalers.size()));
        return;
    }
    const YAML::Node spec = autoscalers[0]["spec"];
    const YAML::Node target = spec["scaleTargetRef"];
    if (text_of(target["kind"]) != "Deployment" || text_of(target["name"]) != deployment.name ||
        text_of(target["apiVersion"]) != "apps/v1") {
        problems.push_back("the autoscaler targets " + text_of(target["apiVersion"]) + " " +
                           text_of(target["kind"]) + " " + text_of(target["name"]) +
                           ", not apps/v1 Deployment " + deployment.name);
    }
    for (const YAML::Node& metric : spec["metrics"]) {
        if (text_of(metric["type"]) != "Pods") {
            continue;
        }
        const std::string name = text_of(metric["pods"]["metric"]["name"]);
        bool served = false;
        for (const YAML::Node& rule : manifests.adapter_rules["rules"]) {
            served |= rule_served_name(rule) == name;
        }
        if (!served) {
            problems.push_back("the autoscaler's Pods metric " + name +
                               " is served by no rule of prometheus-adapter-rules.yaml");
        }
    }
    for (const YAML::Node& rule : manifests.adapter_rules["rules"]) {
        const std::string series = rule_series(rule);
        const auto type = server.metric_types.find(series);
        if (type == server.metric_types.end()) {
            problems.push_back("the adapter rule's series " + series +
                               " is not a metric of oer-server's /metrics");
        } else if (type->second != "gauge") {
            problems.push_back("the adapter rule's series " + series + " is a " + type->second +
                               ", not a gauge to average");
        }
    }
}

void check_gpu_overlay(const Image& image, const DeploymentView& deployment,
                       const Manifests& manifests, Problems& problems) {
    const YAML::Node kustomization = manifests.gpu_kustomization;
    bool base_listed = false;
    for (const YAML::Node& resource : kustomization["resources"]) {
        std::error_code error;
        base_listed |= fs::equivalent(kGpuDir / resource.Scalar(), kBaseDir, error);
    }
    bool patch_listed = false;
    for (const YAML::Node& patch : kustomization["patches"]) {
        patch_listed |= text_of(patch["path"]) == "deployment-gpu.yaml";
    }
    if (!base_listed || !patch_listed) {
        problems.push_back(
            "gpu/kustomization.yaml does not patch ../base with deployment-gpu.yaml");
    }
    const YAML::Node patch = manifests.gpu_patch;
    if (text_of(patch["kind"]) != "Deployment" ||
        text_of(patch["metadata"]["name"]) != deployment.name) {
        problems.push_back("the GPU patch names " + text_of(patch["kind"]) + " " +
                           text_of(patch["metadata"]["name"]) + ", not Deployment " +
                           deployment.name + ": it patches nothing");
    }
    const YAML::Node pod_spec = patch["spec"]["template"]["spec"];
    if (text_of(pod_spec["runtimeClassName"]).empty()) {
        problems.push_back("the GPU patch sets no runtimeClassName");
    }
    const YAML::Node containers = pod_spec["containers"];
    if (!containers || containers.size() != 1 ||
        text_of(containers[0]["name"]) != text_of(deployment.container["name"])) {
        problems.push_back("the GPU patch's container is not the Deployment's " +
                           text_of(deployment.container["name"]) +
                           ": a strategic merge would add a second container");
        return;
    }
    const YAML::Node container = containers[0];
    const std::string gpus = text_of(container["resources"]["limits"]["nvidia.com/gpu"]);
    if (!is_number(gpus) || std::stoi(gpus) < 1) {
        problems.push_back("the GPU patch asks for no nvidia.com/gpu");
    }
    std::string capabilities;
    for (const YAML::Node& variable : container["env"]) {
        if (text_of(variable["name"]) == "NVIDIA_DRIVER_CAPABILITIES") {
            capabilities = text_of(variable["value"]);
        }
    }
    if (capabilities.find("graphics") == std::string::npos && capabilities != "all") {
        problems.push_back("NVIDIA_DRIVER_CAPABILITIES " + capabilities +
                           " lacks graphics: the toolkit mounts no EGL or OpenGL library");
    }
    // The patched container's environment: the base's, then the patch's env entries.
    Problems ignored;  // the base's own problems are reported by check_deployment
    auto environment = container_environment(image, manifests.base, deployment.container, ignored);
    for (const YAML::Node& variable : container["env"]) {
        environment[text_of(variable["name"])] = text_of(variable["value"]);
    }
    container_config(environment, deployment.container, problems);
    if (text_of(deployment.container["securityContext"]["readOnlyRootFilesystem"]) == "true") {
        check_cache_folders(container["env"], {}, deployment.container, "the GPU patch", problems);
    }
}

Problems manifest_problems(const Image& image, const Manifests& manifests, const Server& server) {
    Problems problems;
    for (const auto& [key, object] : manifests.base.by_key) {
        if (object["metadata"]["namespace"]) {
            problems.push_back(key + " names a namespace: the manifests are namespace-free");
        }
    }
    const std::optional<DeploymentView> deployment =
        check_deployment(image, manifests.base, server, problems);
    if (!deployment) {
        return problems;
    }
    check_service(*deployment, manifests.base, problems);
    check_queue(*deployment, manifests.base, problems);
    check_disruption_budget(*deployment, manifests.base, problems);
    check_autoscaler(*deployment, manifests, server, problems);
    check_gpu_overlay(image, *deployment, manifests, problems);
    return problems;
}

std::string listed(const Problems& problems) {
    std::string text;
    for (const std::string& problem : problems) {
        text += "  - " + problem + "\n";
    }
    return text;
}

}  // namespace

// One oer-server for the suite (a suite is one process: tests/CMakeLists.txt), started with the
// OER_* variables the container would have; its ports and data folder are the test's own.
class K8sManifests : public ::testing::Test {
  protected:
    static void SetUpTestSuite() {
        image_ = read_image(kDockerDir / "Dockerfile");
        manifests_ = load_manifests();
        root_ = std::make_unique<itest::TempRoot>();
        fs::create_directories(root_->data());
        ServerLaunch launch(root_->data(), root_->root());
        Problems ignored;
        const std::vector<YAML::Node> deployments = manifests_.base.of_kind("Deployment");
        ASSERT_EQ(deployments.size(), 1u);
        const YAML::Node container = deployments[0]["spec"]["template"]["spec"]["containers"][0];
        for (const auto& [name, value] :
             container_environment(image_, manifests_.base, container, ignored)) {
            // Only the server's own variables: the others (Mesa's cache folder, say) name the
            // container's file system, not this machine's.
            if (name.starts_with("OER_")) {
                launch.environment.push_back(name + "=" + value);
            }
        }
        server_ = std::make_unique<ServerProcess>(launch);
        ASSERT_TRUE(server_->running());
        // Ready: the renderer up (llvmpipe), so /readyz is 200 as on a replica in service.
        ASSERT_TRUE(itest::eventually(
            [] {
                const auto ready = server_->admin_client()->Get("/readyz");
                return ready && ready->status == 200;
            },
            std::chrono::seconds(60)));
        const itest::Metrics metrics = itest::scrape(*server_->admin_client());
        facts_.metric_types = metrics.types;
        facts_.admin_status = [](const std::string& path) {
            static std::map<std::string, int> answers;
            if (!answers.count(path)) {
                const auto answer = server_->admin_client()->Get(path.c_str());
                answers[path] = answer ? answer->status : -1;
            }
            return answers.at(path);
        };
    }
    void SetUp() override {
        ASSERT_TRUE(server_ && server_->running()) << "the suite's oer-server did not start";
    }
    static void TearDownTestSuite() {
        server_.reset();
        root_.reset();
    }

    static Image image_;
    static Manifests manifests_;
    static std::unique_ptr<itest::TempRoot> root_;
    static std::unique_ptr<ServerProcess> server_;
    static Server facts_;
};

Image K8sManifests::image_;
Manifests K8sManifests::manifests_;
std::unique_ptr<itest::TempRoot> K8sManifests::root_;
std::unique_ptr<ServerProcess> K8sManifests::server_;
Server K8sManifests::facts_;

TEST_F(K8sManifests, KustomizationListsEveryManifestFile) {
    const YAML::Node kustomization = YAML::LoadFile((kBaseDir / "kustomization.yaml").string());
    std::set<std::string> resources;
    for (const YAML::Node& resource : kustomization["resources"]) {
        resources.insert(resource.Scalar());
    }
    for (const auto& entry : fs::directory_iterator(kBaseDir)) {
        const std::string name = entry.path().filename().string();
        if (entry.is_regular_file() && entry.path().extension() == ".yaml" &&
            name != "kustomization.yaml") {
            EXPECT_TRUE(resources.count(name)) << name << " is not in kustomization.yaml";
        }
    }
    for (const char* kind : {"ConfigMap", "Deployment", "PersistentVolumeClaim",
                             "HorizontalPodAutoscaler", "StatefulSet"}) {
        EXPECT_EQ(manifests_.base.of_kind(kind).size(), 1u) << kind;
    }
    EXPECT_EQ(manifests_.base.of_kind("Service").size(), 2u) << "the replicas' and the queue's";
}

TEST_F(K8sManifests, AgreeWithTheImageAndTheServer) {
    // The manifests leave the listeners and the data folder to the image.
    for (const char* name : {"OER_HOST", "OER_PORT", "OER_ADMIN_PORT", "OER_DATA_DIR"}) {
        EXPECT_TRUE(image_.environment.count(name)) << "docker/Dockerfile sets no " << name;
    }
    const Problems problems = manifest_problems(image_, manifests_, facts_);
    EXPECT_TRUE(problems.empty()) << listed(problems);
}

TEST_F(K8sManifests, EachCheckFailsOnAManifestBrokenSo) {
    struct Breakage {
        std::string what;
        std::function<void(Manifests&)> apply;
        std::string expected;  // a part of the problem it must cause
    };
    const auto container = [](Manifests& m) {
        return m.object("Deployment/oer")["spec"]["template"]["spec"]["containers"][0];
    };
    const auto pod_spec = [](Manifests& m) {
        return m.object("Deployment/oer")["spec"]["template"]["spec"];
    };
    const std::vector<Breakage> breakages = {
        {"liveness on a path the server does not serve",
         [&](Manifests& m) { container(m)["livenessProbe"]["httpGet"]["path"] = "/health"; },
         "livenessProbe path /health answers 404"},
        {"readiness on the API port",
         [&](Manifests& m) { container(m)["readinessProbe"]["httpGet"]["port"] = 8080; },
         "readinessProbe port 8080 is 8080, not the admin listener's"},
        {"startup probe on a port name the container lacks",
         [&](Manifests& m) { container(m)["startupProbe"]["httpGet"]["port"] = "metrics"; },
         "startupProbe port metrics is no port of the container"},
        {"liveness on the readiness path",
         [&](Manifests& m) { container(m)["livenessProbe"]["httpGet"]["path"] = "/readyz"; },
         "livenessProbe asks the readiness path"},
        {"container port not OER_PORT",
         [&](Manifests& m) { container(m)["ports"][0]["containerPort"] = 8000; },
         "no containerPort is OER_PORT 8080"},
        {"the ConfigMap moves OER_PORT away from the container port",
         [](Manifests& m) { m.object("ConfigMap/oer-config")["data"]["OER_PORT"] = "9090"; },
         "no containerPort is OER_PORT 9090"},
        {"the ConfigMap moves the admin port away from the probes",
         [](Manifests& m) { m.object("ConfigMap/oer-config")["data"]["OER_ADMIN_PORT"] = "9091"; },
         "not the admin listener's OER_ADMIN_PORT 9091"},
        {"a value oer-server refuses",
         [](Manifests& m) {
             m.object("ConfigMap/oer-config")["data"]["OER_RENDER_WORKERS"] = "two";
         },
         "oer-server refuses the container's configuration"},
        {"the host on loopback",
         [](Manifests& m) { m.object("ConfigMap/oer-config")["data"]["OER_HOST"] = "127.0.0.1"; },
         "OER_HOST 127.0.0.1 is loopback"},
        {"envFrom names a ConfigMap that is not there",
         [&](Manifests& m) { container(m)["envFrom"][0]["configMapRef"]["name"] = "oer"; },
         "envFrom names the ConfigMap oer"},
        {"the store mounted beside the data folder",
         [&](Manifests& m) { container(m)["volumeMounts"][0]["mountPath"] = "/data"; },
         "no volume is mounted at OER_DATA_DIR /var/lib/oer"},
        {"the data folder on another claim",
         [&](Manifests& m) {
             pod_spec(m)["volumes"][0]["persistentVolumeClaim"]["claimName"] = "data";
         },
         "claim data is not made by the kustomization"},
        {"a claim one node mounts",
         [](Manifests& m) {
             m.object("PersistentVolumeClaim/oer-data")["spec"]["accessModes"][0] = "ReadWriteOnce";
         },
         "is not ReadWriteMany"},
        {"a user other than the image's",
         [&](Manifests& m) { pod_spec(m)["securityContext"]["runAsUser"] = 1000; },
         "runAsUser 1000 is not the image's user"},
        {"no runAsUser for the image's named USER",
         [&](Manifests& m) { pod_spec(m)["securityContext"].remove("runAsUser"); },
         "is a name and no runAsUser is set"},
        {"a read-only root without /tmp",
         [&](Manifests& m) { container(m)["volumeMounts"][1]["mountPath"] = "/scratch"; },
         "/tmp is no volume"},
        {"Mesa's cache on the read-only root",
         [](Manifests& m) {
             m.object("ConfigMap/oer-config")["data"]["MESA_SHADER_CACHE_DIR"] = "/cache/mesa";
         },
         "MESA_SHADER_CACHE_DIR=/cache/mesa is on the read-only root"},
        {"a grace period shorter than a render",
         [&](Manifests& m) { pod_spec(m)["terminationGracePeriodSeconds"] = 20; },
         "terminationGracePeriodSeconds 20 leaves no room"},
        {"a longer preStop sleep eating the grace period",
         [&](Manifests& m) { container(m)["lifecycle"]["preStop"]["exec"]["command"][1] = "20"; },
         "leaves no room"},
        {"no CPU request",
         [&](Manifests& m) { container(m)["resources"]["requests"].remove("cpu"); },
         "no CPU request"},
        {"metrics scraped from the API port",
         [](Manifests& m) {
             m.object("Deployment/oer")["spec"]["template"]["metadata"]["annotations"]
                                       ["prometheus.io/port"] = "8080";
         },
         "prometheus.io/port 8080 is not the admin port"},
        {"the Service onto the admin port",
         [](Manifests& m) { m.object("Service/oer")["spec"]["ports"][0]["targetPort"] = "admin"; },
         "the Service exposes the admin port 8081"},
        {"the Service selecting other pods",
         [](Manifests& m) {
             m.object("Service/oer")["spec"]["selector"]["app.kubernetes.io/name"] = "oer-server";
         },
         "expected one Service selecting the Deployment's pods, found 0"},
        {"the job queue named by a Service that is not made",
         [](Manifests& m) {
             m.object("ConfigMap/oer-config")["data"]["OER_QUEUE"] = "redis://oer-queue:6379";
         },
         "OER_QUEUE names the Service oer-queue"},
        {"the job queue's Service on another port",
         [](Manifests& m) { m.object("Service/oer-redis")["spec"]["ports"][0]["port"] = 6380; },
         "the Service oer-redis has no port 6379"},
        {"the disruption budget selecting other pods",
         [](Manifests& m) {
             m.object("PodDisruptionBudget/oer")["spec"]["selector"]["matchLabels"]
                                                ["app.kubernetes.io/name"] = "renderer";
         },
         "the PodDisruptionBudget does not select"},
        {"the autoscaler aimed at another name",
         [](Manifests& m) {
             m.object("HorizontalPodAutoscaler/oer")["spec"]["scaleTargetRef"]["name"] =
                 "oer-server";
         },
         "not apps/v1 Deployment oer"},
        {"the autoscaler on a metric no rule serves",
         [](Manifests& m) {
             m.object(
                 "HorizontalPodAutoscaler/oer")["spec"]["metrics"][1]["pods"]["metric"]["name"] =
                 "oer_queue_depth";
         },
         "Pods metric oer_queue_depth is served by no rule"},
        {"the adapter reading a metric the server does not export",
         [](Manifests& m) {
             m.adapter_rules["rules"][0]["seriesQuery"] = "oer_render_queue{namespace!=\"\"}";
         },
         "series oer_render_queue is not a metric"},
        {"the adapter averaging a counter",
         [](Manifests& m) {
             m.adapter_rules["rules"][0]["seriesQuery"] = "oer_renders_skipped_total{pod!=\"\"}";
         },
         "is a counter, not a gauge"},
        {"a GPU patch of another Deployment",
         [](Manifests& m) { m.gpu_patch["metadata"]["name"] = "oer-gpu"; }, "it patches nothing"},
        {"a GPU patch adding a second container",
         [](Manifests& m) {
             m.gpu_patch["spec"]["template"]["spec"]["containers"][0]["name"] = "renderer";
         },
         "a strategic merge would add a second container"},
        {"a GPU without the graphics capability",
         [](Manifests& m) {
             m.gpu_patch["spec"]["template"]["spec"]["containers"][0]["env"][0]["value"] =
                 "compute,utility";
         },
         "lacks graphics"},
        {"no GPU asked for",
         [](Manifests& m) {
             m.gpu_patch["spec"]["template"]["spec"]["containers"][0]["resources"]["limits"].remove(
                 "nvidia.com/gpu");
         },
         "asks for no nvidia.com/gpu"},
        {"NVIDIA's shader cache on the read-only root",
         [](Manifests& m) {
             m.gpu_patch["spec"]["template"]["spec"]["containers"][0]["env"][1]["value"] =
                 "/home/oer/.nv";
         },
         "__GL_SHADER_DISK_CACHE_PATH=/home/oer/.nv is on the read-only root"},
    };
    ASSERT_TRUE(manifest_problems(image_, manifests_, facts_).empty());
    for (const Breakage& breakage : breakages) {
        SCOPED_TRACE(breakage.what);
        Manifests broken = manifests_.clone();
        breakage.apply(broken);
        const Problems problems = manifest_problems(image_, broken, facts_);
        EXPECT_TRUE(std::any_of(problems.begin(), problems.end(),
                                [&](const std::string& problem) {
                                    return problem.find(breakage.expected) != std::string::npos;
                                }))
            << "expected a problem containing \"" << breakage.expected << "\", got:\n"
            << listed(problems);
    }
}
