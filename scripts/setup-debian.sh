#!/usr/bin/env bash
# Installs the Debian 12 packages the project needs, and only those that are missing.
# Used by scripts/run.sh, scripts/test.sh and (through test.sh) by CI.
set -euo pipefail

# ninja-build and ccache: the generator of scripts/build.sh and the compiler cache of
# cmake/compiler_cache.cmake, which make a rebuild on the same machine cost hashes, not compiles;
# lld, the linker of cmake/linker.cmake, several times faster than GNU ld over the tests.
# libwebp-dev, libavif-dev: glTF's WebP and AVIF textures (EXT_texture_webp, EXT_texture_avif,
# renderer/mesh/src/texture_webp.cpp, texture_avif.cpp); libwebp-dev's libwebpmux also encodes
# batch jobs' turntables as animated WebP (server/src/spin_set.cpp). libhiredis-dev: the Redis
# client of the batch jobs' queue across replicas (server/src/redis_frame_queue.cpp).
build_packages=(
    build-essential cmake ninja-build ccache lld pkg-config git clang-format
    libopenimageio-dev openimageio-tools libopenexr-dev
    libglm-dev nlohmann-json3-dev libtinygltf-dev libstb-dev libtinyobjloader-dev
    libmeshoptimizer-dev libdraco-dev libembree-dev libwebp-dev libavif-dev
    libcpp-httplib-dev libturbojpeg0-dev libjpeg62-turbo-dev
    libegl-dev libopengl-dev libegl-mesa0 libgl1-mesa-dri libgl-dev
    libssl-dev libcli11-dev libhiredis-dev
    libgtest-dev libgmock-dev
    libyaml-cpp-dev
    glslang-tools binutils
)
# Real-world data for tests (docs/design.md section 5), and the browser the browser test drives
# (web/tests: /usr/bin/chromium through playwright-core, which downloads no browser of its own);
# the service itself never needs them. The accuracy report (scripts/accuracy-report.sh) converts
# glmark2's 3ds meshes to glTF with assimp-utils and draws its plots with python3-matplotlib.
# The sanitizer build of scripts/test.sh and the fuzzers (scripts/fuzz.sh, tests/fuzz) build with
# clang, whose libFuzzer and sanitizer runtimes are in libclang-rt-14-dev; llvm gives
# llvm-symbolizer, for their stack traces.
# gltfpack compresses the compressed-geometry tests' models (tests/mesh/compressed_gltf_test.cpp).
# nginx is the balancer of the multi-replica test (tests/process/replicas_test.cpp), which runs
# the deployment's docker/nginx/nginx.conf with Debian's /usr/sbin/nginx, in the foreground on a
# loopback port; it needs no nginx service (on a machine with systemd, Debian's package starts
# one on port 80: `systemctl disable --now nginx` stops it for good).
# redis-server is the batch jobs' queue of the multi-replica job test
# (tests/process/job_replicas_test.cpp), run in the foreground on a loopback port (Debian's
# package also starts one on port 6379 where systemd runs: `systemctl disable --now redis-server`).
test_packages=(blender-data glmark2-data assimp-testmodels chromium assimp-utils
    python3-matplotlib clang libclang-rt-14-dev llvm nginx gltfpack redis-server)

root=$(cd "$(dirname "$0")/.." && pwd)
with_test_data=false
if [[ "${1:-}" == "--with-test-data" ]]; then
    with_test_data=true
fi

wanted=("${build_packages[@]}")
if $with_test_data; then
    wanted+=("${test_packages[@]}")
    # Node.js runs the browser test and the API's linters; a machine may have it from elsewhere
    # (NodeSource's nodejs carries its own npm, which Debian's npm package would conflict with).
    if ! command -v node >/dev/null || ! command -v npm >/dev/null; then
        wanted+=(nodejs npm)
    fi
fi

# The tests' node modules, each folder pinned by its package-lock.json (npm, not Debian: Debian
# has none of them): playwright-core in web/tests (the browser test), Redocly's and Spectral's
# linters in api/lint (the api_lint test), glTF-Transform's CLI in tests/mesh/gltf_tools (the
# compressed-geometry tests, with Debian's gltfpack above). Installed when missing or older than
# the lock file, without install scripts, as cmake/npm_modules.cmake does when a test runs.
npm_test_folders=(web/tests api/lint tests/mesh/gltf_tools)
install_npm_test_modules() {
    if ! $with_test_data; then
        return
    fi
    for folder in "${npm_test_folders[@]}"; do
        local modules="$root/$folder/node_modules"
        if [[ ! -f "$modules/.package-lock.json" ||
            "$root/$folder/package-lock.json" -nt "$modules/.package-lock.json" ]]; then
            echo "setup: npm ci in $folder" >&2
            (cd "$root/$folder" && npm ci --ignore-scripts --no-audit --no-fund)
        fi
    done
}

missing=()
for package in "${wanted[@]}"; do
    if ! dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed"; then
        missing+=("$package")
    fi
done

if ((${#missing[@]} == 0)); then
    install_npm_test_modules
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
install_npm_test_modules
