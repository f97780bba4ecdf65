#pragma once
// A sweep executable (bench/lighting_sweep, bench/light_location_sweep) run as a process by its
// ctest, with --quick --json --csv into a fresh folder: its exit status and what it wrote.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

struct SweepOutput {
    int status = -1;
    std::string stdout_text;
    std::string stderr_text;
    nlohmann::json json;
    std::vector<std::vector<std::string>> csv;  // header first; fields split at commas
};

inline std::string read_whole_file(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Splits CSV lines at commas (the sweeps quote no field: names and numbers hold none).
inline std::vector<std::vector<std::string>> split_csv(const std::string& text) {
    std::vector<std::vector<std::string>> lines;
    std::istringstream in(text);
    std::string line;
    while (std::getline(in, line)) {
        std::vector<std::string> fields;
        std::size_t start = 0;
        while (true) {
            const std::size_t comma = line.find(',', start);
            fields.push_back(line.substr(start, comma - start));
            if (comma == std::string::npos) {
                break;
            }
            start = comma + 1;
        }
        lines.push_back(fields);
    }
    return lines;
}

// Runs `command` (its output redirected into `dir`), then reads the JSON and CSV it wrote; the
// JSON is parsed when the run succeeded, a parse failure is a test failure. Removes `dir`,
// after `inspect` has seen it.
template <class Inspect>
SweepOutput run_sweep_command(const std::string& command, const std::filesystem::path& dir,
                              const std::filesystem::path& json, const std::filesystem::path& csv,
                              Inspect&& inspect) {
    const std::filesystem::path out = dir / "stdout", err = dir / "stderr";
    const int raw =
        std::system((command + " >" + out.string() + " 2>" + err.string() + " </dev/null").c_str());
    SweepOutput output;
    output.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
    output.stdout_text = read_whole_file(out);
    output.stderr_text = read_whole_file(err);
    if (output.status == 0) {
        try {
            output.json = nlohmann::json::parse(read_whole_file(json));
        } catch (const std::exception& e) {
            ADD_FAILURE() << command << " wrote JSON that does not parse: " << e.what();
        }
        output.csv = split_csv(read_whole_file(csv));
        inspect(dir);
    }
    std::filesystem::remove_all(dir);
    return output;
}

inline std::filesystem::path fresh_sweep_folder(const std::string& executable) {
    const std::filesystem::path dir = std::filesystem::temp_directory_path() /
                                      ("oer-sweep-test-" + std::to_string(::getpid()) + "-" +
                                       std::filesystem::path(executable).filename().string());
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir;
}

// Runs `executable --quick --json F --csv F` in a fresh temporary folder (removed afterwards).
inline SweepOutput run_quick_sweep(const std::string& executable) {
    const std::filesystem::path dir = fresh_sweep_folder(executable);
    const std::filesystem::path json = dir / "sweep.json", csv = dir / "sweep.csv";
    return run_sweep_command(
        executable + " --quick --json " + json.string() + " --csv " + csv.string(), dir, json, csv,
        [](const std::filesystem::path&) {});
}
