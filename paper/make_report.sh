#!/usr/bin/env bash
# Writes the reproduction report paper/report/README.md: runs each experiment named on the
# command line with --check, draws its figures with its gnuplot script, and records the commit,
# date, machine and command. Called by `make reproduce` (QUICK=1 for the CI parameters).
set -uo pipefail
cd "$(dirname "$0")/.."
BUILD=${BUILD:-build}
QUICK=${QUICK:-0}
report=paper/report
mkdir -p "$report/figures"
quick_flag=""; [ "$QUICK" = "1" ] && quick_flag="--quick"
command="make reproduce$([ "$QUICK" = "1" ] && echo ' QUICK=1')"
commit=$(git rev-parse --short HEAD 2>/dev/null || echo unknown)
dirty=$(git status --porcelain -- . ':!paper/report' 2>/dev/null | grep -qv '^??' && echo " (with uncommitted changes)" || true)  # the report itself does not count
cpu=$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ *//')

out="$report/README.md.tmp"
{
  echo "# rbcflow reproduction report"
  echo
  echo "Reproduction of L. Shi, T.-W. Pan, R. Glowinski, *Numerical simulation of lateral migration of red"
  echo "blood cells in Poiseuille flows*, Int. J. Numer. Meth. Fluids 68 (2012), DOI 10.1002/fld.2455."
  echo
  echo "| | |"
  echo "|---|---|"
  echo "| command | \`$command\` |"
  echo "| commit | $commit$dirty |"
  echo "| date | $(date -u '+%Y-%m-%d %H:%M UTC') |"
  echo "| machine | $(nproc) cores, $cpu, $(free -g | awk '/Mem:/{print $2}') GiB |"
  echo "| parameters | $([ "$QUICK" = "1" ] && echo 'quick (CI)' || echo 'full (the study'"'"'s)') |"
  echo
  echo "Each section: what the experiment checks, the comparison with reference-data/ (study, ours,"
  echo "tolerance, verdict), the run time and the figures. Experiments not yet implemented are listed"
  echo "at the end."
  echo
} > "$out"

status=0
for exp in "$@"; do
  dir="results/$exp"
  # REUSE=1: write the report from results already on disk (from the same experiment binary and
  # parameters), e.g. after a long run started by hand; the report says so.
  if [ "${REUSE:-0}" = "1" ] && [ -f "$dir/check.md" ]; then
    echo "rbcflow: reusing $dir" >&2
    grep -q FAIL "$dir/check.md" && rc=1 || rc=0
    wall="(reused results of an earlier run of the same command: see the run times below)"
  else
    echo "rbcflow: running $exp $quick_flag --check" >&2
    start=$(date +%s)
    "$BUILD/bin/$exp" --out "$dir" --check $quick_flag > "$dir.log" 2>&1
    rc=$?
    wall="$(( $(date +%s) - start )) s"
  fi
  [ "$rc" -ge 2 ] && status=1  # a failed row is reported in the table, not an error of the run
  gnuplot -e "dir='$dir'; figdir='$report/figures'" "experiments/$exp/plot.gp" || status=1
  {
    echo "## $exp"
    echo
    sed -n '/^## Claim/,/^## /p' "experiments/$exp/README.md" | sed '1d;$d'
    echo
    echo "Run: \`$BUILD/bin/$exp --check $quick_flag\` — wall time ${wall}, exit code $rc."
    echo
    [ -f "$dir/check.md" ] && cat "$dir/check.md" || echo "(no comparison table: the run failed; see $dir.log)"
    echo
    if [ -f "$dir/cases.csv" ]; then
      echo "Every run of this experiment (wall time per run, one thread each; Re averaged over the last sample interval):"
      echo
      awk -F, 'NR==1{h="|"; s="|"; for(i=1;i<=NF;i++){h=h" "$i" |"; s=s"---|"}; print h; print s; next}
               {r="|"; for(i=1;i<=NF;i++){r=r" "$i" |"}; print r}' "$dir/cases.csv"
      echo
    fi
    if [ -f "$dir/convergence.md" ]; then
      echo "### Error against run time"
      echo
      cat "$dir/convergence.md"
      echo
    fi
    if [ -f "$dir/units_evidence.md" ]; then
      echo "### Which reading of the 2D constants"
      echo
      sed -n '/^## Units/,/^## /p' "experiments/$exp/README.md" | sed '1d;$d'
      echo
      cat "$dir/units_evidence.md"
      echo
    fi
    if [ -f "experiments/$exp/README.md" ] && grep -q '^## Deviations' "experiments/$exp/README.md"; then
      echo "### Deviations and choices"
      echo
      sed -n '/^## Deviations/,/^## /p' "experiments/$exp/README.md" | sed '1d;$d'
      echo
    fi
    for fig in "$report/figures/${exp}"_*.png; do
      [ -f "$fig" ] && echo "![$(basename "$fig" .png)](figures/$(basename "$fig"))" && echo
    done
  } >> "$out"
done

{
  echo "## Not yet reproduced"
  echo
  for exp in single_cell_migration four_cells_vs_disks cell_free_layer constriction; do
    [ -x "$BUILD/bin/$exp" ] || echo "- $exp: its published numbers are in reference-data/$exp.csv, checked when it lands."
  done
} >> "$out"
mv "$out" "$report/README.md"
echo "rbcflow: report written to $report/README.md" >&2
exit $status
