#!/usr/bin/env bash
# Regenerates the bundled packings in problems/ exactly (same parameters, same seeds, one
# thread: the same bits). Usage: scripts/make-problems.sh [BUILD_DIR]
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
unjam="${1:-$root/build}/unjam"
cd "$root"
# The default packing of `unjam` without arguments: a small pile settled under gravity.
"$unjam" pack --protocol gravity --n 100 --width 15 --mu 0.5 --seed 1 -o problems/default.unjam --quiet
