#!/usr/bin/env bash
# The GPU path, checked in one short run wherever an NVIDIA GPU is at hand:
#  1. builds oer, oer-render and frame_benchmark (Release, unity) into BUILD_DIR;
#  2. renders the frame corpus (scripts/frame-corpus.sh: every render option, built-in and real
#     assets) through the default EGL device, which GlContext::create takes first when it is
#     hardware, and again through Mesa alone (glvnd given Mesa's vendor file only: llvmpipe);
#  3. compares each pair with OpenImageIO's idiff. A frame passes when at most 1 % of its pixels
#     differ by more than 0.03 (8/255) in a channel: rasterisation rules, depth precision and
#     texture filtering may move edges and shadow boundaries by a pixel, the lighting may not;
#  4. prints frame_benchmark's table through both, with the renderer each used.
# Exit 0 when every frame passes. Needs the project's packages and test data
# (scripts/setup-debian.sh --with-test-data).
#
#   scripts/gpu-check.sh [BUILD_DIR]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-"$root/build-gpu"}
mesa_vendor=/usr/share/glvnd/egl_vendor.d/50_mesa.json
[[ -f "$mesa_vendor" ]] || {
    echo "gpu-check: $mesa_vendor is missing (Debian's libegl-mesa0)" >&2
    exit 1
}

OER_BUILD_TARGETS="oer oer-render frame_benchmark" \
    "$root/scripts/build.sh" "$build" -DOER_UNITY_BUILD=ON >/dev/null
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

echo "gpu-check: the frame corpus through the default device"
"$root/scripts/frame-corpus.sh" "$build/bin" "$out/default" >/dev/null
echo "gpu-check: the frame corpus through Mesa's llvmpipe"
__EGL_VENDOR_LIBRARY_FILENAMES=$mesa_vendor \
    "$root/scripts/frame-corpus.sh" "$build/bin" "$out/llvmpipe" >/dev/null

failed=0
total=0
for frame in "$out/default"/*.png "$out/default"/*.jpg; do
    [[ -f "$frame" ]] || continue
    total=$((total + 1))
    name=$(basename "$frame")
    if ! verdict=$(idiff -fail 0.03 -failpercent 1 "$frame" "$out/llvmpipe/$name" 2>&1); then
        failed=$((failed + 1))
        echo "gpu-check: $name differs beyond the tolerance:"
        grep -E "Mean error|RMS error|Max error|pixels" <<<"$verdict" | sed 's/^/    /'
    fi
done
echo "gpu-check: $((total - failed)) of $total frames within the tolerance"

echo "gpu-check: frame_benchmark through the default device"
"$build/bin/frame_benchmark"
echo "gpu-check: frame_benchmark through Mesa's llvmpipe"
__EGL_VENDOR_LIBRARY_FILENAMES=$mesa_vendor "$build/bin/frame_benchmark"
((failed == 0))
