#!/usr/bin/env bash
# The main job: install what is missing, build, and run the service (build/bin/oer-server) on
# its built-in default scene. Its banner ends with the page to open (the browser client, web/,
# served at /), and it serves until Ctrl-C; arguments are passed
# to oer-server (--port, --data-dir, ...; `--help` lists them). Only oer-server and the
# libraries it links are built (the tests and benchmarks are scripts/test.sh's).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/setup-debian.sh"
OER_BUILD_TARGETS=oer-server "$root/scripts/build.sh" "$root/build" -DOER_UNITY_BUILD=ON
exec "$root/build/bin/oer-server" "$@"
