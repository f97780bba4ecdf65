#!/usr/bin/env bash
# The main job: install what is missing, build, and preprocess the built-in default
# environment, printing its light rig (the server takes over this role in a later issue).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/setup-debian.sh"
"$root/scripts/build.sh" "$root/build"
exec "$root/build/bin/oer" preprocess default "$@"
