#!/usr/bin/env bash
# Writes the seeds of fuzz_image: tiny maps in each format and layout the loader
# reads differently, made with OpenImageIO's oiiotool (package openimageio-tools), a few
# hundred bytes to a few KiB each. The hostile files of tests/data/hostile are added to the
# corpus by scripts/fuzz.sh.
set -euo pipefail
cd "$(dirname "$0")/image"
noise() { echo "--pattern noise $1 $2 --mulc $3"; }
# Radiance RGBE: run-length encoded scanlines (8 to 32767 wide) and flat ones (narrower).
oiiotool $(noise 16x8 3 4) -d float -o rle.hdr
oiiotool $(noise 4x2 3 4) -d float -o flat.hdr
# OpenEXR: float and half, scanline and tiled, RGB and RGBA, several compressions.
oiiotool $(noise 16x8 3 4) -d float --compression zip -o zip-float.exr
oiiotool $(noise 16x8 4 4) -d half --compression piz -o piz-half-rgba.exr
oiiotool $(noise 16x8 3 4) -d half --compression none --tile 8 8 -o tiled-half.exr
oiiotool $(noise 16x8 1 4) -d float --compression rle -o rle-grey.exr
oiiotool $(noise 16x8 3 4) -d half --compression b44 -o b44-half.exr
# PNG: 8 and 16 bits, grey, RGB, RGBA.
oiiotool $(noise 16x8 3 1) -d uint8 -o rgb8.png
oiiotool $(noise 8x4 4 1) -d uint16 -o rgba16.png
oiiotool $(noise 8x4 1 1) -d uint8 -o grey8.png
# JPEG: baseline and progressive, colour and grey.
oiiotool $(noise 16x8 3 1) -d uint8 -o baseline.jpg
oiiotool $(noise 16x8 3 1) -d uint8 --attrib jpeg:progressive 1 -o progressive.jpg
oiiotool $(noise 16x8 1 1) -d uint8 -o grey.jpg
