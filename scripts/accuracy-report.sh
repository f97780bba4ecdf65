#!/usr/bin/env bash
# The one command of issue 11's report: installs what is missing, builds the three sweeps and issue 12's material gallery, runs
# them into build/accuracy/ and writes docs/accuracy.md from what they measured
# (docs/accuracy/make_report.py).
# --quick: every sweep with --quick, and the report into build/accuracy/report/ rather than
# docs/, so that a check of the pipeline never overwrites the published figures.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
quick=()
report_dir="$root/docs"
if [[ "${1:-}" == "--quick" ]]; then
    quick=(--quick)
    report_dir="$root/build/accuracy/report"
elif [[ $# -gt 0 ]]; then
    echo "usage: $0 [--quick]" >&2
    exit 2
fi

"$root/scripts/setup-debian.sh" --with-test-data
"$root/scripts/build.sh" "$root/build"

out="$root/build/accuracy"
meshes="$out/meshes"
mkdir -p "$meshes" "$report_dir"
# glmark2 ships the horse and the cat as 3ds, which the renderer does not read; glTF binary it
# does. assimp's conversion would lay them on their side (see upright_glb.py).
for mesh in horse cat; do
    assimp export "/usr/share/glmark2/models/$mesh.3ds" "$out/$mesh-assimp.glb" >/dev/null
    /usr/bin/python3 "$root/docs/accuracy/upright_glb.py" "$out/$mesh-assimp.glb" \
        "$meshes/$mesh.glb"
    rm "$out/$mesh-assimp.glb"
done

bin="$root/build/bin"
"$bin/lighting_sweep" "${quick[@]}" --json "$out/lighting.json" --csv "$out/lighting.csv"
"$bin/light_location_sweep" "${quick[@]}" --json "$out/location.json" --csv "$out/location.csv"
"$bin/frame_sweep" "${quick[@]}" --mesh-dir "$meshes" --out "$out/frames"
"$bin/material_gallery" --out "$out/gallery"

/usr/bin/python3 "$root/docs/accuracy/make_report.py" --lighting "$out/lighting.json" \
    --location "$out/location.json" --frames "$out/frames" --materials "$out/gallery" \
    --out "$report_dir"
