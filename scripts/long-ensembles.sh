#!/usr/bin/env bash
# Perturbation ensembles that take longer than one sitting: the top and bottom shifts of the
# bundled 1600-disk piles (docs/perturbations.md, "Ensembles longer than a session"). Each
# ensemble has a run folder, ${UNJAM_ENSEMBLES:-out/ensembles}/NAME (out/ is git-ignored),
# where `unjam perturb -o` writes every record as it finishes and resumes, without losing or
# repeating a shift, and refuses a second writer.
#
# Usage: scripts/long-ensembles.sh list
#            each ensemble's command, its records so far and where they sit in their LP
#            intervals
#        scripts/long-ensembles.sh run NAME [HOURS] [BUILD_DIR]
#            continue NAME for HOURS (default 1: no shift starts after it, those started
#            finish); the LP intervals (unjam bounds) are computed once into the run
#            folder; the run's summary.json is copied to bench/results/ensembles/NAME.json
# UNJAM_MPIRUN launches the run under MPI (the run folder must then be shared);
# UNJAM_THREADS (default 0: every core) e.g. 1 runs one shift at a time beside another run.
# `demo` (10 shifts of the 100-disk pile, a second) tries the machinery.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
work_root="${UNJAM_ENSEMBLES:-$root/out/ensembles}"
summaries="$root/bench/results/ensembles"

# NAME -> the packing, the side and the perturb options: the default solve (the rate solve,
# the step backend where it gives no definite answer), as in docs/performance.md.
recipe() {
  case "$1" in
    gravity-n1600-mu0.1-top) echo "problems/gravity-n1600-mu0.1.unjam --top" ;;
    gravity-n1600-mu0.1-bottom) echo "problems/gravity-n1600-mu0.1.unjam --bottom" ;;
    gravity-n1600-mu1-top) echo "problems/gravity-n1600-mu1.unjam --top" ;;
    gravity-n1600-mu1-bottom) echo "problems/gravity-n1600-mu1.unjam --bottom" ;;
    demo) echo "problems/gravity-n100-mu0.5.unjam --top" ;;
    *) return 1 ;;
  esac
}
names=(gravity-n1600-mu0.1-top gravity-n1600-mu0.1-bottom gravity-n1600-mu1-top gravity-n1600-mu1-bottom)

die() { echo "long-ensembles.sh: $*" >&2; exit 2; }
records() { local f="$work_root/$1/records.jsonl"; [ -e "$f" ] && echo $(( $(wc -l <"$f") - 1 )) || echo 0; }

case "${1:-}" in
  list)
    for n in "${names[@]}"; do
      echo "$n: $(records "$n") records in $work_root/$n; unjam perturb $(recipe "$n")"
      if [ "$(records "$n")" -gt 0 ] && [ -e "$work_root/$n/bounds.csv" ]; then
        /usr/bin/python3 "$root/scripts/analysis/records_vs_bounds.py" "$work_root/$n" "$work_root/$n/bounds.csv" | sed -n '1,3s/^/    /p'
      fi
    done ;;
  run)
    name="${2:-}"; hours="${3:-1}"; build="${4:-$root/build}"
    args=$(recipe "$name") || die "unknown ensemble '$name' (scripts/long-ensembles.sh list)"
    [ -x "$build/unjam" ] || die "$build/unjam: not built (bash scripts/build.sh)"
    dir="$work_root/$name"
    mkdir -p "$dir"
    seconds=$(/usr/bin/python3 -c "import sys; print(float(sys.argv[1]) * 3600)" "$hours")
    cd "$root"
    read -r packing side _ <<<"$args"
    if [ ! -e "$dir/bounds.csv" ]; then
      "$build/unjam" bounds "$packing" "$side" -o "$dir/bounds.csv" >/dev/null  # resumes if interrupted
    fi
    # shellcheck disable=SC2086  # the recipe and the launcher are word lists
    ${UNJAM_MPIRUN:-} "$build/unjam" perturb $args --threads "${UNJAM_THREADS:-0}" --time-limit "$seconds" -o "$dir" --json \
      >"$dir.json" || echo "long-ensembles.sh: unjam perturb exit $? (results so far kept in $dir)" >&2
    if [ -e "$dir/summary.json" ] && [ "$name" != demo ]; then
      mkdir -p "$summaries"
      cp "$dir/summary.json" "$summaries/$name.json"
    fi
    echo "$name: $(records "$name") records in $dir" ;;
  *) sed -n '2,17p' "$0" | sed 's/^# \{0,1\}//'; exit 2 ;;
esac
