#!/usr/bin/env bash
# Installs the Debian 12 packages the project needs, and only those that are missing.
# Used by scripts/run.sh, scripts/test.sh and (through test.sh) by CI.
set -euo pipefail

build_packages=(
    build-essential cmake pkg-config git clang-format
    libopenimageio-dev openimageio-tools libopenexr-dev
    libglm-dev nlohmann-json3-dev libtinygltf-dev libstb-dev libtinyobjloader-dev
    libmeshoptimizer-dev
    libcpp-httplib-dev libturbojpeg0-dev libjpeg62-turbo-dev
    libegl-dev libopengl-dev libegl-mesa0 libgl1-mesa-dri libgl-dev
    libssl-dev libcli11-dev
    libgtest-dev libgmock-dev
    libyaml-cpp-dev
    glslang-tools binutils
)
# Real-world data for tests (DESIGN.md section 5); the service itself never needs them.
test_packages=(blender-data glmark2-data assimp-testmodels)

wanted=("${build_packages[@]}")
if [[ "${1:-}" == "--with-test-data" ]]; then
    wanted+=("${test_packages[@]}")
fi

missing=()
for package in "${wanted[@]}"; do
    if ! dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed"; then
        missing+=("$package")
    fi
done

if ((${#missing[@]} == 0)); then
    exit 0
fi

sudo_cmd=()
if [[ $(id -u) -ne 0 ]]; then
    sudo_cmd=(sudo)
fi
echo "setup: installing ${missing[*]}" >&2
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -q
"${sudo_cmd[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}"
