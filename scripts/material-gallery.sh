#!/usr/bin/env bash
# Issue 12's material gallery: installs what is missing, builds, and renders the bunny and the
# material spheres under every Blender world into docs/materials.md and docs/materials/
# (bench/material_gallery.cpp). About a minute on 2 cores.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/setup-debian.sh" --with-test-data
"$root/scripts/build.sh" "$root/build"
"$root/build/bin/material_gallery" --out "$root/docs"
