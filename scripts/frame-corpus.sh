#!/usr/bin/env bash
# Renders a fixed corpus of frames, rigs and maps with one build's `oer`, so that a refactoring
# can be checked to change nothing: render the corpus with the build before and the build after,
# then compare the two folders byte for byte.
#
#   scripts/frame-corpus.sh BIN_DIR OUT_DIR          render (BIN_DIR holds oer and oer-render)
#   scripts/frame-corpus.sh --compare DIR_A DIR_B    exit 0 when every file is identical
#
# Every option of `oer render` is varied at least once (the same parser as GET /v1/render), on
# the built-in studio and dress form, a real map and meshes from Debian's packages (the test
# data of scripts/setup-debian.sh --with-test-data): a glossy glTF, a textured one, an OBJ.
# Frames are small (96x96) so that the corpus takes a few minutes on 2 cores.
set -euo pipefail

if [[ "${1:-}" == "--compare" ]]; then
    a=$2
    b=$3
    differing=0
    total=0
    for file in "$a"/*; do
        name=$(basename "$file")
        total=$((total + 1))
        # EXR files carry the time they were written (DateTime): their pixels are compared,
        # exactly, by OpenImageIO's idiff; every other file byte for byte.
        if [[ "$name" == *.exr ]]; then
            same() { idiff -q -fail 0 -failpercent 0 -warn 0 "$1" "$2" >/dev/null 2>&1; }
        else
            same() { cmp -s "$1" "$2"; }
        fi
        if ! same "$file" "$b/$name"; then
            echo "frame-corpus: $name differs"
            differing=$((differing + 1))
        fi
    done
    if [[ $(ls "$b" | wc -l) -ne $total ]]; then
        echo "frame-corpus: $a has $total files, $b has $(ls "$b" | wc -l)"
        differing=$((differing + 1))
    fi
    echo "frame-corpus: $((total - differing)) of $total identical"
    ((differing == 0))
    exit
fi

bin=$1
out=$2
mkdir -p "$out"
world=/usr/share/blender/datafiles/studiolights/world
interior=$world/interior.exr
courtyard=$world/courtyard.exr
bunny=/usr/share/glmark2/models/bunny.obj
glossy=/usr/share/assimp/models/glTF2/ClearCoat-glTF/ClearCoatTest.gltf
textured=/usr/share/assimp/models/glTF2/BoxTextured-glTF-Binary/BoxTextured.glb
engine=/usr/share/assimp/models/glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb
for file in "$interior" "$courtyard" "$bunny" "$glossy" "$textured" "$engine"; do
    [[ -f "$file" ]] || {
        echo "frame-corpus: $file is missing (scripts/setup-debian.sh --with-test-data)" >&2
        exit 1
    }
done

# name|arguments of `oer render` (after --size 96x96 and before -o)
frames=(
    "default|--env default --mesh default"
    "ground-off|--env default --mesh default --ground off"
    "occlusion-off|--env default --mesh default --occlusion off"
    "bounce-none|--env default --mesh default --bounce none"
    "occlusion-off-ground-off|--env default --mesh default --occlusion off --ground off"
    "shadows-off|--env default --mesh default --shadows off"
    "shadow-hard|--env default --mesh default --shadow-filter hard"
    "shadow-256|--env default --mesh default --shadow-resolution 256"
    "shadow-64-hard|--env default --mesh default --shadow-resolution 64 --shadow-filter hard"
    "samples-1|--env default --mesh default --samples 1"
    "samples-2|--env default --mesh default --samples 2"
    "samples-8|--env default --mesh default --samples 8"
    "exposure-plus|--env default --mesh default --exposure 1.5"
    "exposure-minus|--env default --mesh default --exposure -2"
    "tonemap-aces|--env default --mesh default --tonemap aces"
    "tonemap-none|--env default --mesh default --tonemap none"
    "background-transparent|--env default --mesh default --background transparent"
    "background-color|--env default --mesh default --background #3366cc"
    "base-color|--env default --mesh default --base-color 0.8,0.1,0.1"
    "yaw-90|--env default --mesh default --yaw 90"
    "yaw-minus-200|--env default --mesh default --yaw -200"
    "eye|--env default --mesh default --eye 1,1.5,3"
    "eye-target|--env default --mesh default --eye -2,1,2 --target 0,0.5,0"
    "fov|--env default --mesh default --eye 0,1,4 --fov 25"
    "up|--env default --mesh default --eye 0,1,4 --up 0.2,1,0"
    "lights-off|--env default --mesh default --lights 0,0,0"
    "lights-dim|--env default --mesh default --lights 0.5,1,2"
    "quality-40|--env default --mesh default --quality 40"
    "two-meshes|--env default --mesh default --mesh $bunny"
    "light-count-2|--env default --mesh default --light-count 2"
    "sh-order-3|--env default --mesh default --sh-order 3"
    "model-thesis|--env default --mesh default --model thesis"
    "window-hanning|--env default --mesh default --window hanning"
    "clustering-pixels|--env default --mesh default --clustering pixels"
    "interior-bunny|--env $interior --mesh $bunny"
    "interior-bunny-ground-off|--env $interior --mesh $bunny --ground off"
    "interior-bunny-occlusion-off|--env $interior --mesh $bunny --occlusion off"
    "interior-bunny-bounce-none|--env $interior --mesh $bunny --bounce none"
    "interior-bunny-lights|--env $interior --mesh $bunny --lights 1,0,0.5"
    "interior-bunny-transparent|--env $interior --mesh $bunny --background transparent"
    "interior-bunny-eye|--env $interior --mesh $bunny --eye 0.3,0.2,0.4 --target 0,0.1,0"
    "courtyard-bunny|--env $courtyard --mesh $bunny --yaw 45"
    "courtyard-bunny-hard|--env $courtyard --mesh $bunny --shadow-filter hard --samples 1"
    "glossy|--env default --mesh $glossy"
    "glossy-interior|--env $interior --mesh $glossy"
    "glossy-occlusion-off|--env $interior --mesh $glossy --occlusion off"
    "glossy-ground-off|--env $interior --mesh $glossy --ground off"
    "glossy-thesis|--env $interior --mesh $glossy --model thesis"
    "glossy-aces|--env $courtyard --mesh $glossy --tonemap aces --exposure 0.5"
    "glossy-yaw|--env $courtyard --mesh $glossy --yaw 120"
    "glossy-base-color|--env default --mesh $glossy --base-color 0.2,0.6,0.3"
    "textured|--env default --mesh $textured"
    "textured-interior|--env $interior --mesh $textured --eye 2,2,3"
    "engine|--env default --mesh $engine"
    "engine-interior|--env $interior --mesh $engine --occlusion off"
    "engine-dressform|--env $courtyard --mesh $engine --mesh default"
)
# Formats: most frames as PNG (lossless, every bit compared), a few as JPEG and EXR.
formats=(png png png jpg png exr)
for i in "${!frames[@]}"; do
    name=${frames[$i]%%|*}
    read -r -a arguments <<<"${frames[$i]#*|}"
    format=${formats[$((i % ${#formats[@]}))]}
    "$bin/oer" render "${arguments[@]}" --size 96x96 -o "$out/$name.$format" 2>"$out/$name.log" ||
        echo "oer render failed: $(tail -1 "$out/$name.log")" >"$out/$name.failed"
    rm -f "$out/$name.log"
done
# Wide and tall frames, a larger one, the linear EXR of a glossy scene.
"$bin/oer" render --env default --mesh default --size 160x64 -o "$out/wide.png"
"$bin/oer" render --env default --mesh default --size 48x128 -o "$out/tall.png"
"$bin/oer" render --env "$interior" --mesh "$glossy" --size 256x192 -o "$out/glossy-256.png"
"$bin/oer" render --env "$interior" --mesh "$glossy" --size 96x96 -o "$out/glossy-linear.exr"
without_timings() {
    python3 -c 'import json, sys; rig = json.load(sys.stdin); rig.pop("timings_ms"); print(json.dumps(rig, indent=2))'
}
# The preprocessing alone: rigs, irradiance maps and masks.
for map in default "$interior" "$courtyard"; do
    name=$(basename "$map" .exr)
    # A rig's timings_ms are the preprocessing's wall times: left out of the comparison.
    "$bin/oer" preprocess "$map" | without_timings >"$out/rig-$name.json"
    "$bin/oer" preprocess "$map" --light-count 3 --window lanczos | without_timings \
        >"$out/rig-$name-3.json"
    "$bin/oer" irradiance-map "$map" --size 64x32 -o "$out/irradiance-$name.exr"
    "$bin/oer" masks "$map" -o "$out/masks-$name.png"
done
echo "frame-corpus: $(ls "$out" | wc -l) files in $out"
