#!/usr/bin/env bash
# Installs what is missing (test data included), builds, and runs every test once: each test
# executable either in an optimised build or under AddressSanitizer and UBSan, then the fuzzers
# for a bounded time. Prints each phase's wall time at the end, so that a CI log says where its
# time went.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
jobs=$(nproc)

phase_names=()
phase_seconds=()
# phase NAME COMMAND...: runs the command, records its wall time.
phase() {
    local name=$1
    shift
    local start=$SECONDS
    echo "test.sh: $name" >&2
    "$@"
    phase_names+=("$name")
    phase_seconds+=($((SECONDS - start)))
}
report_phases() {
    local i
    for i in "${!phase_names[@]}"; do
        printf 'test.sh: %-34s %4d s\n' "${phase_names[$i]}" "${phase_seconds[$i]}"
    done
    printf 'test.sh: %-34s %4d s\n' "total" "$SECONDS"
}
trap report_phases EXIT

phase "packages" "$root/scripts/setup-debian.sh" --with-test-data

# Both builds compile in unity batches (CMakeLists.txt's OER_UNITY_BUILD): a clean build in
# about half the CPU time of one file at a time.
phase "build (gcc, optimised)" "$root/scripts/build.sh" "$root/build" -DOER_WERROR=ON \
    -DOER_UNITY_BUILD=ON

# Each test executable runs in one build of the two (its ctest label is its library's name,
# tests/CMakeLists.txt). Under the sanitizers: the parsers of untrusted input (api, image, mesh,
# the stored transfer), the server's own code and the API end to end over HTTP (integration),
# which reaches the renderer, the lighting and the GL code with the requests a client sends.
# In the optimised build: the rest, whose cost is numerical work or processes (lighting, gl,
# reference, cli, process, bench), the slow suites, and the tests of files and tools (lint,
# deploy, browser, report).
sanitized='^(api|image|mesh|server|transfer|integration)$'
phase "tests (optimised)" ctest --test-dir "$root/build" --output-on-failure -j "$jobs" \
    -LE "$sanitized"

# The sanitizer build with clang, -O1 without debug info: the sanitizers need frame pointers
# (OER_SANITIZE keeps them), not -O2 and DWARF. clang, not gcc: with both sanitizers gcc 12 takes
# three times as long over a library file (server/src/service.cpp: 12.3 s of CPU, clang 4.1 s)
# and 1.6 times over a test file; gcc's sanitizer build alone took 20 minutes on a 2-core machine.
# Warnings are the gcc build's to fail on (clang 14 warns on the vendored MikkTSpace). Only the
# test executables run here are built.
phase "build (clang, sanitizers)" env OER_BUILD_TARGETS="oer_api_tests oer_image_tests \
oer_mesh_tests oer_server_tests oer_transfer_tests oer_integration_tests" \
    "$root/scripts/build.sh" "$root/build-sanitize" \
    -DOER_SANITIZE=ON -DCMAKE_BUILD_TYPE=None -DOER_UNITY_BUILD=ON \
    -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_C_FLAGS=-O1 \
    -DCMAKE_CXX_FLAGS=-O1 -DOER_BUILD_BENCHMARKS=OFF
# Their slow suites are the optimised build's.
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 \
    phase "tests (sanitizers)" ctest --test-dir "$root/build-sanitize" --output-on-failure \
    -j "$jobs" -L "$sanitized"

# The fuzzers (tests/fuzz, built with clang into build-fuzz): each parser of untrusted input for
# 15 s from its seeds, one per core at a time; a finding fails the run. Longer runs by hand: tests/fuzz/README.md.
phase "fuzzers (build and 10 s each)" "$root/scripts/fuzz.sh" 10
