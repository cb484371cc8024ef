#!/usr/bin/env bash
# Keeps the compact outputs of finished evidence runs in the repository, so that the evidence
# grows run by run on whatever machine ran it (paper/evidence/README.md, "Kept runs"):
#
#   paper/keep_evidence.sh RESULTS EXPERIMENT CASE...   or   paper/keep_evidence.sh RESULTS EXPERIMENT --all
#
# copies each finished case RESULTS/EXPERIMENT/CASE (its summary.json written, no failure.txt) to
# paper/evidence/data/EXPERIMENT/CASE/:
#   summary.json  as the run wrote it;
#   series.csv    the columns the rows read: every column of the channel and the crowd (t,
#                 velocities, Re, Hct, wall gaps) and, for runs of at most four bodies, each
#                 body's centroid, area and perimeter; every sample of the last kFull seconds (the
#                 rows' 1 ms windows) and one sample in ten before (1 ms apart at the runs'
#                 0.1 ms sampling: the curves against time); every sample of a run of at most 400;
#   code_id       the code that made the run (RESULTS/EXPERIMENT/code_id: the sources' hash,
#                 paper/make_report.sh) and commit (the commit it was built from, when RESULTS/commit
#                 names it).
# `make evidence COLLECT=1` puts every kept case whose folder under results/ is missing back in
# place before it collects, and each experiment's tables name the code of every case read back.
# A case already kept is replaced (the newer run of the same name). Exit status: 0; 2 on bad use
# or a case that is not finished.
set -euo pipefail
cd "$(dirname "$0")/.."
[ $# -ge 3 ] || { echo "usage: $0 RESULTS EXPERIMENT CASE... | --all" >&2; exit 2; }
results=$1 exp=$2; shift 2
src="$results/$exp"
[ -f "$src/code_id" ] || { echo "keep_evidence: $src/code_id missing: which code made these runs?" >&2; exit 2; }
code=$(cat "$src/code_id")
commit=$(cat "$results/commit" 2>/dev/null || echo unknown)
full=0.002   # s: kFull, the last seconds kept at every sample
if [ "$1" = --all ]; then
  # (not the cases put back from the kept evidence: they carry their own code_id)
  set -- $(for d in "$src"/*/; do [ -f "$d/summary.json" ] && [ ! -f "$d/failure.txt" ] && [ ! -f "$d/code_id" ] && basename "$d"; done)
fi
kept=0
for case in "$@"; do
  dir="$src/$case"
  if [ ! -f "$dir/summary.json" ] || [ ! -f "$dir/series.csv" ]; then
    echo "keep_evidence: $dir is not a finished run (no summary.json or series.csv)" >&2; exit 2
  fi
  if [ -f "$dir/code_id" ]; then
    echo "keep_evidence: $dir was put back from the kept evidence (its own code_id): already kept" >&2; exit 2
  fi
  if [ -f "$dir/failure.txt" ]; then
    echo "keep_evidence: $dir stopped early ($(sed -n 3p "$dir/failure.txt")): not kept" >&2; exit 2
  fi
  to=paper/evidence/data/$exp/$case
  mkdir -p "$to.tmp"
  cp "$dir/summary.json" "$to.tmp/summary.json"
  awk -F, -v full="$full" '
    NR == FNR { if (/^#/) next; if (rows++) last = $1; next }  # first pass: the last sample time, the rows
    /^# units: / { units = substr($0, 10); next }             # the units of the columns (older runs have none)
    /^#/ { next }
    !header {
      header = 1
      bodies = 0
      for (k = 1; k <= NF; ++k) if ($k ~ /^cell[0-9]+_x$/) ++bodies
      n = 0
      for (k = 1; k <= NF; ++k)
        if ($k !~ /^cell[0-9]+_/ || (bodies <= 4 && $k ~ /_(x|y|area|perimeter)$/)) keep[++n] = k
      short = (rows <= 401)
      if (units != "") {
        split(units, u, ",")
        line = "# units: " u[keep[1]]; for (k = 2; k <= n; ++k) line = line "," u[keep[k]]; print line
      }
      line = $(keep[1]); for (k = 2; k <= n; ++k) line = line "," $(keep[k]); print line
      next
    }
    short || ++r % 10 == 1 || $1 >= last - full {
      line = $(keep[1]); for (k = 2; k <= n; ++k) line = line "," $(keep[k]); print line
    }' "$dir/series.csv" "$dir/series.csv" > "$to.tmp/series.csv"
  printf '%s\n%s\n' "$code" "$commit" > "$to.tmp/code_id"
  rm -rf "$to"; mv "$to.tmp" "$to"
  kept=$((kept + 1))
done
echo "keep_evidence: $kept case(s) of $exp (code $code, commit $commit) in paper/evidence/data/$exp/"
