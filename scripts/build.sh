#!/usr/bin/env bash
# Configures and builds into build/ (or the directory given as first argument).
#
#   scripts/build.sh [BUILD_DIR] [CMAKE_CONFIGURE_ARGUMENTS...]
#
# OER_BUILD_TARGETS (space-separated) builds only those targets and what they need, as
# scripts/run.sh does with oer-server; unset, everything is built. A new build folder uses
# Ninja (scripts/setup-debian.sh installs it), which schedules the whole tree's compiles and
# links as one graph; a folder configured earlier keeps its generator.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build_dir=${1:-"$root/build"}
shift || true
generator=()
if [[ ! -f "$build_dir/CMakeCache.txt" ]] && command -v ninja >/dev/null; then
    generator=(-G Ninja)
fi
cmake -S "$root" -B "$build_dir" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
targets=()
for target in ${OER_BUILD_TARGETS:-}; do
    targets+=(--target "$target")
done
cmake --build "$build_dir" -j "$(nproc)" "${targets[@]}"
