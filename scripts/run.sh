#!/usr/bin/env bash
# Fresh machine to result: install dependencies, build, run the main job on the default packing.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/scripts/install-deps.sh"
"$root/scripts/build.sh"
cd "$root"
exec "$root/build/unjam" "$@"
