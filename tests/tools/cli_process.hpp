#pragma once
// `oer` run as a real process by the command-line tests: its exit status and what it printed.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

struct ProcessResult {
    int status = -1;
    std::string out;
    std::string err;
};

inline std::string slurp(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Runs `EXECUTABLE ARGUMENTS` (through the shell, stdin empty), its output kept in files in
// `dir`.
inline ProcessResult run_executable(const std::string& executable, const std::string& arguments,
                                    const std::filesystem::path& dir) {
    const std::filesystem::path out = dir / "stdout", err = dir / "stderr";
    const std::string command =
        executable + " " + arguments + " >" + out.string() + " 2>" + err.string() + " </dev/null";
    const int raw = std::system(command.c_str());
    ProcessResult result;
    result.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
    result.out = slurp(out);
    result.err = slurp(err);
    return result;
}

// Runs `oer ARGUMENTS`, as run_executable.
inline ProcessResult run_oer(const std::string& arguments, const std::filesystem::path& dir) {
    return run_executable(OER_CLI_PATH, arguments, dir);
}

// A fixture whose tests each have a fresh folder dir_ (removed afterwards) and run `oer` in it.
class OerProcessTest : public ::testing::Test {
  protected:
    void SetUp() override {
        const auto* test = ::testing::UnitTest::GetInstance()->current_test_info();
        dir_ = std::filesystem::temp_directory_path() /
               ("oer-cli-test-" + std::to_string(::getpid()) + "-" + test->test_suite_name() + "-" +
                test->name());
        std::filesystem::create_directories(dir_);
    }
    void TearDown() override { std::filesystem::remove_all(dir_); }

    ProcessResult run(const std::string& arguments) { return run_oer(arguments, dir_); }

    std::filesystem::path dir_;
};
