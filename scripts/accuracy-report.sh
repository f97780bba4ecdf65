#!/usr/bin/env bash
# The one command of the accuracy report: installs what is missing, builds the three sweeps and the material gallery, runs
# them into build/accuracy/ and writes docs/accuracy.md from what they measured
# (docs/accuracy/make_report.py).
# --quick: every sweep with --quick, and the report into build/accuracy/report/ rather than
# docs/, so that a check of the pipeline never overwrites the published figures.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
quick=()
samples=()
report_dir="$root/docs"
while [[ $# -gt 0 ]]; do
    case "$1" in
        --quick)
            quick=(--quick)
            report_dir="$root/build/accuracy/report"
            shift ;;
        # The reference's sample cap (frame_sweep --max-samples, default 32768): a lower cap
        # bounds the run's time, and rows whose reference stays too noisy are marked as such.
        --max-samples)
            samples=(--max-samples "$2")
            shift 2 ;;
        *)
            echo "usage: $0 [--quick] [--max-samples N]" >&2
            exit 2 ;;
    esac
done

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
"$bin/frame_sweep" "${quick[@]}" "${samples[@]}" --mesh-dir "$meshes" --out "$out/frames"
"$bin/material_gallery" --out "$out/gallery"
"$bin/shadow_sweep" "${quick[@]}" --out "$out/shadows"

/usr/bin/python3 "$root/docs/accuracy/make_report.py" --lighting "$out/lighting.json" \
    --location "$out/location.json" --frames "$out/frames" --materials "$out/gallery" \
    --shadows "$out/shadows/shadow_sweep.json" \
    --shadows-before "$root/docs/accuracy/soft_shadows_before.json" --out "$report_dir"
