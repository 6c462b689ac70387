#!/usr/bin/env bash
# Regenerates the bundled packings in problems/ exactly (same parameters, same seeds, one
# thread: the same bits). Usage: scripts/make-problems.sh [BUILD_DIR] [NAME_PATTERN]
# Each packing is skipped when its file exists (delete it to remake it); a run prints its
# JSON summary to problems/logs/NAME.json.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
unjam="${1:-$root/build}/unjam"
pattern="${2:-}"
cd "$root"
mkdir -p problems/logs

make() {  # make NAME ARGS...
  local name="$1"; shift
  [[ -z "$pattern" || "$name" == *$pattern* ]] || return 0
  [ -e "problems/$name.unjam" ] && { echo "keep problems/$name.unjam"; return 0; }
  echo "make problems/$name.unjam: unjam pack $*"
  "$unjam" pack "$@" -o "problems/$name.unjam" --json --quiet >"problems/logs/$name.json"
}

# Homogeneous packings at constant external pressure P_ext = 1, fully periodic.
for mu in 0.5 1 10 0.1 0.01 0; do
  make "pressure-n500-mu$mu" --protocol pressure --n 500 --mu "$mu" --seed 1
done
make pressure-n3000-mu0.5 --protocol pressure --n 3000 --mu 0.5 --seed 1

# Piles settled under gravity g = 1 on a rough bed, periodic in x, width 100.
for mu in 0.1 1; do
  make "gravity-n1600-mu$mu" --protocol gravity --n 1600 --mu "$mu" --width 100 --seed 1
done

# A small pile: quick to load and solve (examples, smoke tests).
make gravity-n100-mu0.5 --protocol gravity --n 100 --width 15 --mu 0.5 --seed 1
