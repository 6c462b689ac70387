#!/usr/bin/env bash
# Perturbation ensembles that take longer than one sitting: the top and bottom shifts of the
# bundled 1600-disk pile (docs/perturbations.md, "Ensembles longer than a session"). Their
# records live in the repository, bench/results/ensembles/NAME/records-*.jsonl.gz, so that
# each run continues where the last one stopped, on any machine, and adds what it finishes.
#
# Usage: scripts/long-ensembles.sh list
#        scripts/long-ensembles.sh run NAME [HOURS] [BUILD_DIR]
#            continue NAME for HOURS (default 1: no shift starts after it, those started
#            finish), then store its new records, its rows and its summary in
#            bench/results/ensembles/NAME/
#        scripts/long-ensembles.sh store NAME
#            store what the work directory holds now (after an interrupted run)
# The work directory is ${UNJAM_ENSEMBLES:-/tmp/unjam-ensembles}/NAME; UNJAM_ENSEMBLES_KEPT
# moves the kept records elsewhere (a trial run); UNJAM_MPIRUN launches the run under MPI;
# UNJAM_THREADS (default 0: every core) e.g. 1 runs one shift at a time beside another run.
# `demo` (10 shifts of the 100-disk pile, a second) tries the machinery.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
kept="${UNJAM_ENSEMBLES_KEPT:-$root/bench/results/ensembles}"
work_root="${UNJAM_ENSEMBLES:-/tmp/unjam-ensembles}"

# NAME -> the perturb arguments (the packing first). The options are those of the runs in
# docs/performance.md: lemke (named: `auto` gives piles of more than 2 000 contacts to
# newton, though --lemke-box-first would name it too; the records' header is the same),
# its box-form rate path first, a pivot budget that a 1600-disk shift needs, no fallback
# (ipopt does not resolve these steps either).
recipe() {
  local lemke=(--backend lemke --max-iter 3000000 --fallback none --lemke-box-first)
  case "$1" in
    gravity-n1600-mu0.1-top) echo problems/gravity-n1600-mu0.1.unjam --top "${lemke[@]}" ;;
    gravity-n1600-mu0.1-bottom) echo problems/gravity-n1600-mu0.1.unjam --bottom "${lemke[@]}" ;;
    demo) echo problems/gravity-n100-mu0.5.unjam --top ;;
    *) return 1 ;;
  esac
}
names=(gravity-n1600-mu0.1-top gravity-n1600-mu0.1-bottom)

die() { echo "long-ensembles.sh: $*" >&2; exit 2; }
lines() { [ -e "$1" ] && wc -l <"$1" || echo 0; }
# The kept records of NAME are chunks, each the lines one store added (the first holds the
# header), so that the repository keeps every record once.
chunks() { compgen -G "$kept/$1/records-*.jsonl.gz" | sort || true; }
kept_records() { local c; c=$(chunks "$1"); [ -z "$c" ] || gzip -dc $c; }

# The work directory starts from the kept records, or goes on from them (same first lines).
unpack() {
  local name="$1" dir="$work_root/$1"
  mkdir -p "$dir"
  local kept_lines work_lines
  kept_lines=$(kept_records "$name" | wc -l)
  [ "$kept_lines" -gt 0 ] || return 0
  work_lines=$(lines "$dir/records.jsonl")
  if [ "$work_lines" -lt "$kept_lines" ]; then
    kept_records "$name" >"$dir/records.jsonl.part" && mv "$dir/records.jsonl.part" "$dir/records.jsonl"
  elif ! cmp -s <(kept_records "$name") <(head -n "$kept_lines" "$dir/records.jsonl"); then
    die "$dir/records.jsonl does not go on from the kept records in $kept/$name: move it away"
  fi
}

store() {
  local name="$1" dir="$work_root/$1"
  [ -s "$dir/records.jsonl" ] || die "$dir/records.jsonl: nothing to store"
  unpack "$name"  # checks that the work goes on from what is kept
  mkdir -p "$kept/$name"
  local kept_lines complete next
  kept_lines=$(kept_records "$name" | wc -l)
  complete=$(wc -l <"$dir/records.jsonl")  # whole lines only: a run may be writing one
  if [ "$complete" -gt "$kept_lines" ]; then
    next=$(printf '%03d' "$(chunks "$name" | wc -l)")
    sed -n "$((kept_lines + 1)),${complete}p" "$dir/records.jsonl" | gzip -n -9 >"$kept/$name/records-$next.jsonl.gz.part"
    mv "$kept/$name/records-$next.jsonl.gz.part" "$kept/$name/records-$next.jsonl.gz"
  fi
  # The rows and summary of the last run that ended (of all records up to its end).
  for f in perturbations.csv summary.json; do
    if [ -e "$dir/$f" ]; then cp "$dir/$f" "$kept/$name/$f"; fi
  done
  echo "$name: $((complete - 1)) records kept in $kept/$name ($((complete - kept_lines)) new)"
}

case "${1:-}" in
  list)
    for n in "${names[@]}"; do
      done_lines=$(kept_records "$n" | wc -l)
      echo "$n: $(( done_lines > 0 ? done_lines - 1 : 0 )) records kept; unjam perturb $(recipe "$n")"
      # Where the finished shifts sit in their LP intervals (unjam bounds --top|--bottom).
      if [ "$done_lines" -gt 1 ] && [ -e "$kept/$n/bounds.csv" ]; then
        /usr/bin/python3 "$root/scripts/records_vs_bounds.py" "$kept/$n" "$kept/$n/bounds.csv" | sed -n '1,3s/^/    /p'
      fi
    done ;;
  run)
    name="${2:-}"; hours="${3:-1}"; build="${4:-$root/build}"
    args=$(recipe "$name") || die "unknown ensemble '$name' (scripts/long-ensembles.sh list)"
    [ -x "$build/unjam" ] || die "$build/unjam: not built (bash scripts/build.sh)"
    unpack "$name"
    seconds=$(/usr/bin/python3 -c "import sys; print(float(sys.argv[1]) * 3600)" "$hours")
    cd "$root"
    # UNJAM_MPIRUN (e.g. "mpirun -np 64 --hostfile HOSTS"): the ranks share the work
    # directory, which must then be one they all see (docs/perturbations.md, "Beyond one
    # machine: MPI").
    # shellcheck disable=SC2086  # the recipe and the launcher are word lists
    ${UNJAM_MPIRUN:-} "$build/unjam" perturb $args --threads "${UNJAM_THREADS:-0}" --time-limit "$seconds" -o "$work_root/$name" --json \
      >"$work_root/$name.json" || echo "long-ensembles.sh: unjam perturb exit $? (results so far kept)" >&2
    store "$name" ;;
  store)
    recipe "${2:-}" >/dev/null || die "unknown ensemble '${2:-}'"
    store "$2" ;;
  *) sed -n '2,17p' "$0" | sed 's/^# \{0,1\}//'; exit 2 ;;
esac
