#!/usr/bin/env bash
# Builds the libFuzzer targets (tests/fuzz) with clang into build-fuzz/ and runs each for a
# bounded time from its seeds, one per core at a time: prints per target the executions reached,
# the coverage (edges and features) and any finding, and exits non-zero if any target found
# something. tests/fuzz/README.md says what counts as a finding and how to reproduce one.
#
#   scripts/fuzz.sh [SECONDS_PER_TARGET] [TARGET...]     (default: 15 s each, every target)
#
# Kept between runs in build-fuzz/ (never committed): corpus/TARGET, the inputs each run found
# new coverage with (the next run starts from them and the seeds); findings/TARGET, the input
# of each finding (crash-*, timeout-*, oom-*, leak-*); logs/TARGET.log, libFuzzer's output.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
seconds=${1:-15}
shift || true
build="$root/build-fuzz"
seeds="$root/tests/fuzz/seeds"
hostile="$root/tests/data/hostile"

# Per target: its seed folder, the hostile files it also starts from, and the largest input
# libFuzzer makes (bounded so that an execution stays fast; the seeds fit well within it).
declare -A seed_dir=([fuzz_image]=image [fuzz_gltf]=gltf [fuzz_gltf_meshopt]=gltf_meshopt
    [fuzz_gltf_draco]=gltf_draco [fuzz_obj]=obj
    [fuzz_render_json]=render_json [fuzz_render_query]=render_query
    [fuzz_stored_rig]=stored_rig [fuzz_texture_webp]=texture_webp
    [fuzz_texture_avif]=texture_avif [fuzz_texture_ktx2]=texture_ktx2)
declare -A hostile_files=([fuzz_image]="*.hdr *.exr *.png *.jpg" [fuzz_gltf]="*.gltf")
declare -A max_len=([fuzz_image]=16384 [fuzz_gltf]=16384 [fuzz_gltf_meshopt]=16384
    [fuzz_gltf_draco]=16384 [fuzz_obj]=8192
    [fuzz_render_json]=8192 [fuzz_render_query]=2048 [fuzz_stored_rig]=16384
    [fuzz_texture_webp]=4096 [fuzz_texture_avif]=4096 [fuzz_texture_ktx2]=4096)
targets=("$@")
if ((${#targets[@]} == 0)); then
    targets=(fuzz_image fuzz_gltf fuzz_gltf_meshopt fuzz_gltf_draco fuzz_obj fuzz_render_json
        fuzz_render_query fuzz_stored_rig fuzz_texture_webp fuzz_texture_avif fuzz_texture_ktx2)
fi

# -O1 without debug info, as the sanitizer build of scripts/test.sh: the sanitizers need frame
# pointers, not -O2 and DWARF (function names come from the symbol table). Warnings are left to
# the gcc build, which treats them as errors: clang 14 warns on the vendored MikkTSpace.
# A new build folder uses Ninja and unity batches (CMakeLists.txt's OER_UNITY_BUILD), as the
# test builds do: this folder is mostly built from clean.
generator=()
if [[ ! -f "$build/CMakeCache.txt" ]] && command -v ninja >/dev/null; then
    generator=(-G Ninja)
fi
cmake -S "$root" -B "$build" "${generator[@]}" -DOER_FUZZ=ON -DOER_UNITY_BUILD=ON \
    -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
    -DCMAKE_BUILD_TYPE=None -DCMAKE_C_FLAGS=-O1 -DCMAKE_CXX_FLAGS=-O1 \
    >/dev/null
cmake --build "$build" -j "$(nproc)" --target "${targets[@]}"

export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-halt_on_error=1:print_stacktrace=1}

# fuzz_one TARGET: runs one target for the time given, then writes its exit status to
# results/TARGET.
fuzz_one() {
    local target=$1
    local corpus="$build/corpus/$target"
    local findings="$build/findings/$target"
    local start="$build/start/$target"  # the seeds and hostile files, copied afresh each run
    local log="$build/logs/$target.log"
    rm -rf "$start"
    mkdir -p "$corpus" "$findings" "$start" "$(dirname "$log")" "$build/results"
    cp "$seeds/${seed_dir[$target]}"/* "$start/"
    if [[ -n "${hostile_files[$target]:-}" ]]; then
        (cd "$hostile" && cp ${hostile_files[$target]} "$start/")
    fi
    # -rss_limit_mb and -malloc_limit_mb: an input that makes the process hold 2 GiB, or ask for
    # it at once, is a memory bomb (the sanitizers' own overhead included); -timeout: an input
    # that takes 10 s is a hang (the slowest seeds take under 0.1 s).
    # A target's dictionary (tests/fuzz/NAME.dict: its member names and values), where it has one.
    local dictionary=()
    if [[ -f "$root/tests/fuzz/${seed_dir[$target]}.dict" ]]; then
        dictionary=(-dict="$root/tests/fuzz/${seed_dir[$target]}.dict")
    fi
    local status=0
    nice -n 5 "$build/bin/$target" "$corpus" "$start" "${dictionary[@]}" -max_total_time="$seconds" \
        -max_len="${max_len[$target]}" -timeout=10 -rss_limit_mb=2048 -malloc_limit_mb=2048 \
        -artifact_prefix="$findings/" -print_final_stats=1 >"$log" 2>&1 || status=$?
    echo "$status" >"$build/results/$target"
}

# One target per core at a time (each libFuzzer process is single-threaded).
rm -rf "$build/results"
for target in "${targets[@]}"; do
    while (($(jobs -rp | wc -l) >= $(nproc))); do
        wait -n
    done
    fuzz_one "$target" &
done
wait

failed=0
for target in "${targets[@]}"; do
    log="$build/logs/$target.log"
    status=$(cat "$build/results/$target" 2>/dev/null || echo "no result")
    runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log")
    coverage=$(grep -E '^#[0-9]+.*cov: ' "$log" | tail -1 |
        sed -E 's/.*cov: ([0-9]+) ft: ([0-9]+) corp: ([0-9]+).*/\1 edges, \2 features, \3 inputs in the corpus/')
    if [[ "$status" == 0 ]]; then
        echo "fuzz: $target: ${runs:-?} executions in ${seconds} s, ${coverage:-no coverage line}; no finding"
    else
        failed=$((failed + 1))
        echo "fuzz: $target: FINDING after ${runs:-?} executions (${coverage:-no coverage line}), exit $status:"
        grep -E '^==[0-9]+==ERROR|^==== FINDING|^SUMMARY|Test unit written to' "$log" | sed 's/^/    /'
        echo "    log: $log"
    fi
done
# The plain closing line CI reads: a target without a finding passed.
echo "fuzz: $((${#targets[@]} - failed)) passed, $failed failed"
((failed == 0))
