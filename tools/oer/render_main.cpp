// `oer-render`: the render command of `oer`, alone in its executable because it is the one that
// links EGL and GL. `oer render ARGS` runs `oer-render ARGS`; it may also be run directly.
#include <string>
#include <vector>

#include "command_line.hpp"
#include "commands.hpp"

int main(int argc, char** argv) {
    return oer::cli::run_command("render", oer::cli::render_command, {argv + 1, argv + argc});
}
