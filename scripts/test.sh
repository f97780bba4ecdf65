#!/usr/bin/env bash
# Installs what is missing (test data included), builds, and runs every test: once in an
# optimised build, then the unit tests again under AddressSanitizer and UBSan, then the fuzzers
# for a bounded time.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
jobs=$(nproc)
"$root/scripts/setup-debian.sh" --with-test-data

"$root/scripts/build.sh" "$root/build" -DOER_WERROR=ON
ctest --test-dir "$root/build" --output-on-failure -j "$jobs"

# -O1 without debug info: the sanitizers need frame pointers (OER_SANITIZE keeps them), not -O2
# and DWARF. Measured on 2 cores: a RelWithDebInfo sanitizer build had reached 83 % after
# 7.5 minutes; with these flags the whole CI run (both builds, all tests) took 10.5 minutes.
"$root/scripts/build.sh" "$root/build-sanitize" -DOER_SANITIZE=ON -DOER_WERROR=ON -DCMAKE_BUILD_TYPE=None \
    -DCMAKE_CXX_FLAGS=-O1 -DOER_BUILD_BENCHMARKS=OFF
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 \
    ctest --test-dir "$root/build-sanitize" --output-on-failure -j "$jobs" -LE slow

# The fuzzers (tests/fuzz, built with clang into build-fuzz): each parser of untrusted input for
# 15 s from its seeds; a finding fails the run. Longer runs by hand: tests/fuzz/README.md.
"$root/scripts/fuzz.sh" 15
