#!/usr/bin/env bash
# The container image's smoke test: builds docker/Dockerfile with whichever engine exists
# (docker, else podman), starts it, waits for /readyz, loads the page, uploads an environment
# and a mesh, renders a frame, checks the answer, and removes what it made. Prints the image's
# size and the build and start times. Too slow for every CI run (it builds the project inside
# the image); docker/README.md says when to run it.
#
#   docker/smoke.sh            (OER_CONTAINER_ENGINE=docker|podman to choose; OER_SMOKE_PORT)
#
# With podman on a machine that reaches no image registry, the debian:bookworm base is made
# locally (debootstrap --variant=minbase bookworm, then podman import); containers run under
# runc (crun refuses hybrid cgroup hierarchies) with the ulimits given in OER_SMOKE_ULIMITS
# (default: this project's CI machines' hard limits).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
image=oer:smoke
container=oer-smoke-$$
volume=oer-smoke-data-$$
port=${OER_SMOKE_PORT:-18080}
admin_port=$((port + 1))
work=$(mktemp -d)

log() { echo "smoke: $*" >&2; }
fail() {
    log "FAILED: $*"
    exit 1
}
seconds_since() { echo "$(($(date +%s) - $1))"; }
# The first "id" of an upload's answer (its top-level members come first, sorted by name).
json_id() { grep -o '"id" *: *"[0-9a-f]*"' "$1" | head -1 | sed 's/.*"\([0-9a-f]*\)"$/\1/'; }

engine=${OER_CONTAINER_ENGINE:-}
if [[ -z "$engine" ]]; then
    if command -v docker >/dev/null && docker info >/dev/null 2>&1; then
        engine=docker
    elif command -v podman >/dev/null; then
        engine=podman
    else
        fail "neither a running docker engine nor podman (Debian: apt-get install podman runc)"
    fi
fi
engine_args=()
build_args=()
if [[ "$engine" == podman ]]; then
    engine_args=(--runtime runc)
    # docker format keeps the HEALTHCHECK instruction (the OCI format has no field for it).
    build_args=(--runtime runc --format docker)
fi
read -r -a ulimits <<<"${OER_SMOKE_ULIMITS:---ulimit nofile=20000:20000 --ulimit nproc=32768:32768}"

cleanup() {
    "$engine" rm -f "$container" >/dev/null 2>&1 || true
    "$engine" volume rm -f "$volume" >/dev/null 2>&1 || true
    rm -rf "$work"
}
trap cleanup EXIT

# The base image: from the registry where one is reachable, else made here with debootstrap.
if ! "$engine" image inspect debian:bookworm >/dev/null 2>&1 &&
    ! "$engine" pull -q debian:bookworm >/dev/null 2>&1; then
    [[ "$engine" == podman ]] || fail "no debian:bookworm image and none could be pulled"
    command -v debootstrap >/dev/null || fail "no debian:bookworm image and no debootstrap"
    log "no registry: making debian:bookworm with debootstrap --variant=minbase"
    start=$(date +%s)
    debootstrap --variant=minbase bookworm "$work/rootfs" http://deb.debian.org/debian \
        >"$work/debootstrap.log" 2>&1 || {
        tail -20 "$work/debootstrap.log" >&2
        fail "debootstrap"
    }
    rm -rf "$work"/rootfs/var/cache/apt/archives/*.deb "$work"/rootfs/var/lib/apt/lists/*
    tar -C "$work/rootfs" -c . | "$engine" import --change 'CMD ["bash"]' - debian:bookworm \
        >/dev/null
    rm -rf "$work/rootfs"
    log "base image made in $(seconds_since "$start") s"
fi

start=$(date +%s)
"$engine" build "${build_args[@]}" -f "$root/docker/Dockerfile" -t "$image" "$root" \
    >"$work/build.log" 2>&1 || {
    tail -40 "$work/build.log" >&2
    fail "the image did not build"
}
build_seconds=$(seconds_since "$start")
size_bytes=$("$engine" image inspect --format '{{.Size}}' "$image")
log "image built in ${build_seconds} s; size $((size_bytes / 1000000)) MB"

# No configuration at all: the image's own defaults (docker/Dockerfile's ENV) serve the page
# and the default scene.
start=$(date +%s)
"$engine" volume create "$volume" >/dev/null
"$engine" run -d "${engine_args[@]}" "${ulimits[@]}" --name "$container" \
    -p "127.0.0.1:$port:8080" -p "127.0.0.1:$admin_port:8081" -v "$volume:/var/lib/oer" \
    "$image" >/dev/null
api=http://127.0.0.1:$port
ready=false
for _ in $(seq 1 600); do
    if curl -fsS "http://127.0.0.1:$admin_port/readyz" >/dev/null 2>&1; then
        ready=true
        break
    fi
    if [[ "$("$engine" inspect --format '{{.State.Running}}' "$container")" != true ]]; then
        break
    fi
    sleep 0.1
done
if ! $ready; then
    "$engine" logs "$container" 2>&1 | tail -30 >&2
    fail "/readyz never answered 200"
fi
log "ready in $(seconds_since "$start") s after start"

user=$("$engine" exec "$container" id -u)
[[ "$user" != 0 ]] || fail "the service runs as root"

curl -fsS "$api/" -o "$work/page.html" || fail "GET / failed"
grep -q "<html" "$work/page.html" || fail "GET / is not the web page"

# A real map from blender's studio lights when installed, else one the image's own CLI writes
# (the irradiance of the built-in studio, an OpenEXR equirectangular map).
environment=/usr/share/blender/datafiles/studiolights/world/forest.exr
if [[ ! -f "$environment" ]]; then
    "$engine" exec "$container" oer irradiance-map default --size 512x256 -o /tmp/environment.exr \
        >/dev/null
    "$engine" cp "$container:/tmp/environment.exr" "$work/environment.exr"
    environment=$work/environment.exr
fi
code=$(curl -sS -o "$work/environment.json" -w '%{http_code}' -H 'Content-Type: image/x-exr' \
    --data-binary "@$environment" "$api/v1/environments")
[[ "$code" == 201 || "$code" == 200 ]] || fail "environment upload: $code $(cat "$work/environment.json")"
environment_id=$(json_id "$work/environment.json")
[[ -n "$environment_id" ]] || fail "no id in $(cat "$work/environment.json")"

# A unit cube as OBJ: eight corners, six quads.
cat >"$work/cube.obj" <<'OBJ'
v -0.5 -0.5 -0.5
v 0.5 -0.5 -0.5
v 0.5 0.5 -0.5
v -0.5 0.5 -0.5
v -0.5 -0.5 0.5
v 0.5 -0.5 0.5
v 0.5 0.5 0.5
v -0.5 0.5 0.5
f 1 4 3 2
f 5 6 7 8
f 1 2 6 5
f 4 8 7 3
f 1 5 8 4
f 2 3 7 6
OBJ
code=$(curl -sS -o "$work/mesh.json" -w '%{http_code}' -H 'Content-Type: model/obj' \
    --data-binary "@$work/cube.obj" "$api/v1/meshes")
[[ "$code" == 201 || "$code" == 200 ]] || fail "mesh upload: $code $(cat "$work/mesh.json")"
mesh_id=$(json_id "$work/mesh.json")
[[ -n "$mesh_id" ]] || fail "no id in $(cat "$work/mesh.json")"

code=$(curl -sS -o "$work/frame.png" -w '%{http_code}' \
    "$api/v1/render?environment=$environment_id&mesh=$mesh_id&width=256&height=256&format=png")
[[ "$code" == 200 ]] || fail "render: $code $(head -c 500 "$work/frame.png")"
# A PNG of 256x256: its signature, then the IHDR chunk's width and height.
header=$(head -c 24 "$work/frame.png" | od -An -tx1 | tr -d ' \n')
[[ "$header" == 89504e470d0a1a0a0000000d49484452000001000000010* ]] ||
    fail "the frame is not a 256x256 PNG (header $header)"
log "uploaded, rendered a 256x256 frame of $(stat -c %s "$work/frame.png") bytes"

# What was uploaded is in the volume, under the SHA-256 of its bytes (content addressing).
map_sha256=$(sha256sum "$environment" | cut -d' ' -f1)
"$engine" exec "$container" test -s "/var/lib/oer/environments/$map_sha256.exr" ||
    fail "the map is not in the data volume as environments/$map_sha256.exr"

# The image's own HEALTHCHECK command answers healthy (podman runs it on demand; docker on its
# schedule, so its status is polled).
if [[ "$engine" == podman ]]; then
    "$engine" healthcheck run "$container" || fail "the HEALTHCHECK command reports unhealthy"
else
    for _ in $(seq 1 30); do
        status=$("$engine" inspect --format '{{.State.Health.Status}}' "$container")
        [[ "$status" != healthy ]] || break
        sleep 1
    done
    [[ "$status" == healthy ]] || fail "the HEALTHCHECK reports $status"
fi
log "passed"
