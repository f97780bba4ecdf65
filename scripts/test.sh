#!/usr/bin/env bash
# Installs what is missing (test data included), builds, and runs every test: once in an
# optimised build, then the unit tests again under AddressSanitizer and UBSan, then the fuzzers
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

phase "build (gcc, optimised)" "$root/scripts/build.sh" "$root/build" -DOER_WERROR=ON
phase "tests (optimised)" ctest --test-dir "$root/build" --output-on-failure -j "$jobs"

# The sanitizer build with clang, -O1 without debug info: the sanitizers need frame pointers
# (OER_SANITIZE keeps them), not -O2 and DWARF. clang, not gcc: with both sanitizers gcc 12 takes
# three times as long over a library file (server/src/service.cpp: 12.3 s of CPU, clang 4.1 s)
# and 1.6 times over a test file; gcc's sanitizer build alone took 20 minutes on a 2-core machine.
# Warnings are the gcc build's to fail on (clang 14 warns on the vendored MikkTSpace).
phase "build (clang, sanitizers)" "$root/scripts/build.sh" "$root/build-sanitize" \
    -DOER_SANITIZE=ON -DCMAKE_BUILD_TYPE=None \
    -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_C_FLAGS=-O1 \
    -DCMAKE_CXX_FLAGS=-O1 -DOER_BUILD_BENCHMARKS=OFF
# The C++ tests only: the slow ones are the optimised build's, and the lint, deployment and
# browser tests check files and tools, not this build's code (the browser's server-side paths
# are the integration tests', which run here).
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 \
    phase "tests (sanitizers)" ctest --test-dir "$root/build-sanitize" --output-on-failure \
    -j "$jobs" -LE "slow|lint|deploy|browser|report"

# The fuzzers (tests/fuzz, built with clang into build-fuzz): each parser of untrusted input for
# 15 s from its seeds; a finding fails the run. Longer runs by hand: tests/fuzz/README.md.
phase "fuzzers (build and 15 s each)" "$root/scripts/fuzz.sh" 15
