#!/usr/bin/env bash
# Writes the reproduction report: runs each experiment named on the command line with --check,
# draws its figures with its gnuplot script, opens the report with the table of all the study's
# numbers (build/bin/rbcflow summary) and records the commit, date, machine and command.
# Called by `make reproduce`: the full report goes to paper/report/README.md (committed); with
# QUICK=1 (the CI parameters) to results/report/README.md, so that a quick run never overwrites
# the committed full-parameter report. REUSE=1 reads the finished runs under results/ (the
# experiments' --reuse) instead of running them again, and recomputes every verdict.
#
# Sections. Each experiment's comparison (check.csv, from which the table of all the study's
# numbers is made) and its provenance (command, commit, date) are kept in
# <report>/data/<experiment>/, its section in the report itself. ONLY="exp ..." runs
# those experiments and rewrites their sections only, keeping the others as they were written
# (each says by which run): the full reproduction takes longer than one working session on two
# cores, and its parts are rerun where they changed. COLLECT=1 (with ONLY) runs no case and reads
# the cases finished so far (the experiments' --collect; the others' rows say "not run").
# Exit status: 0, or 1 if an experiment stopped with an error, a figure failed or a row FAILed.
set -uo pipefail
cd "$(dirname "$0")/.."
BUILD=${BUILD:-build}
QUICK=${QUICK:-0}
ONLY=${ONLY:-}
COLLECT=${COLLECT:-0}
results=results
mkdir -p "$results"
if [ "$QUICK" = "1" ]; then report=$results/report; else report=paper/report; fi
mkdir -p "$report/figures" "$report/data"
quick_flag=""; [ "$QUICK" = "1" ] && quick_flag="--quick"
command="make reproduce$([ "$QUICK" = "1" ] && echo ' QUICK=1')$([ "${REUSE:-0}" = "1" ] && echo ' REUSE=1')$([ -n "$ONLY" ] && echo " ONLY=\"$ONLY\"")$([ "$COLLECT" = "1" ] && echo ' COLLECT=1')"
commit=$(git rev-parse --short HEAD 2>/dev/null || echo unknown)
dirty=$(git status --porcelain -- . ':!paper/report' 2>/dev/null | grep -qv '^??' && echo " (with uncommitted changes)" || true)  # the report itself does not count
cpu=$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ *//')
date_now=$(date -u '+%Y-%m-%d %H:%M UTC')
parameters=$([ "$QUICK" = "1" ] && echo 'quick (CI)' || echo "full length (each row's scheme, Δt and departures: column 'how run')")

# The experiments this run writes: ONLY's (each must be one of the report's), or all of them.
run_list=("$@")
if [ -n "$ONLY" ]; then
  run_list=()
  for exp in $ONLY; do
    case " $* " in *" $exp "*) run_list+=("$exp") ;; *) echo "rbcflow: ONLY names '$exp', not an experiment of the report (one of: $*)" >&2; exit 2 ;; esac
  done
fi
if [ "$COLLECT" = "1" ] && [ -z "$ONLY" ]; then
  echo "rbcflow: COLLECT=1 needs ONLY=\"experiment ...\" (it rewrites those sections from the cases finished so far)" >&2; exit 2
fi
sections=$(mktemp -d)  # this run's sections; the others are read from the report as it was
trap 'rm -rf "$sections"' EXIT

status=0
for exp in "${run_list[@]}"; do
  dir="$results/$exp"
  # REUSE=1: write the report from results already on disk (from the same experiment binary and
  # parameters), e.g. after a long run started by hand; the report says so.
  reuse_flag=""; wall_note=""
  if [ "${REUSE:-0}" = "1" ] && "$BUILD/bin/$exp" --help 2>/dev/null | grep -q -- '--reuse'; then
    reuse_flag="--reuse"; wall_note=" (with --reuse: cases finished on disk are read back, not run again; each case's own run time is in the tables below)"
  fi
  start=$(date +%s)
  # An experiment made of independent cases (--list-cases) runs them with GNU parallel, one
  # thread per case on every core, then collects them with --check --reuse (README.md: the same
  # commands spread the cases over machines or a Slurm array).
  if [ "$COLLECT" = "1" ]; then
    if "$BUILD/bin/$exp" --help 2>/dev/null | grep -q -- '--collect'; then
      reuse_flag="--collect"; wall_note=" (with --collect: the cases finished on disk are read back and none is run; the tables say which were not run)"
    else
      reuse_flag="--reuse"; wall_note=" (with --reuse: cases finished on disk are read back, not run again)"
    fi
  elif "$BUILD/bin/$exp" --help 2>/dev/null | grep -q -- '--list-cases'; then
    mkdir -p "$dir"
    echo "rbcflow: running the cases of $exp $quick_flag with GNU parallel -j $(nproc)" >&2
    "$BUILD/bin/$exp" --list-cases $quick_flag | parallel --will-cite -j "$(nproc)" --joblog "$dir/joblog" \
      "$BUILD/bin/$exp" --out "$dir" $quick_flag $reuse_flag --only {} --threads 1 ">" "$dir/{}.log" "2>&1" \
      || echo "rbcflow: some cases of $exp stopped (their rows say why; logs in $dir/)" >&2
    [ -n "$reuse_flag" ] && wall_note=" (with --reuse: its cases finished on disk are read back through GNU parallel, not run again; each case's own run time is in the tables below)" \
      || wall_note=" (its cases run with GNU parallel on $(nproc) cores, one thread each; each case's wall time is in the tables below)"
    reuse_flag="--reuse"
  fi
  echo "rbcflow: running $exp $quick_flag --check $reuse_flag" >&2
  rm -f "$dir/check.csv"  # a failed check leaves none, not an older run's
  "$BUILD/bin/$exp" --out "$dir" --check $quick_flag $reuse_flag > "$dir.log" 2>&1
  rc=$?
  wall="$(( $(date +%s) - start )) s$wall_note"
  [ "$rc" -ne 0 ] && status=1  # 1: a row FAILed (the table says which); 2 or more: the run stopped
  [ "$rc" -ge 2 ] && tail -3 "$dir.log" >&2
  rm -f "$report/figures/${exp}"_*.png
  gnuplot -e "dir='$dir'; figdir='$report/figures'" "experiments/$exp/plot.gp" || status=1
  data="$report/data/$exp"
  mkdir -p "$data"
  if [ -f "$dir/check.csv" ]; then cp "$dir/check.csv" "$data/check.csv"; else rm -f "$data/check.csv"; fi
  echo "| $exp | \`$command\` | $commit$dirty | $date_now | $parameters |" > "$data/provenance.md"
  {
    echo "## $exp"
    echo
    sed -n '/^## Claim/,/^## /p' "experiments/$exp/README.md" | sed '1d;$d'
    echo
    echo "Written by \`$command\` at commit $commit$dirty, $date_now."
    echo
    echo "Run: \`$BUILD/bin/$exp --check $quick_flag $reuse_flag\` — wall time ${wall}, exit code $rc."
    if [ "${REUSE:-0}" = "1" ] || [ "$COLLECT" = "1" ]; then
      # Provenance of runs read back: when they finished (their summary.json files' times, UTC).
      span=$(find "$dir" -name summary.json -printf '%TY-%Tm-%Td %TH:%TM\n' 2>/dev/null | sort | sed -n '1p;$p' | tr '\n' ' ')
      [ -n "$span" ] && echo "Runs on disk finished between (UTC, first and last): $span."
    fi
    echo
    [ -f "$dir/check.md" ] && cat "$dir/check.md" || echo "(no comparison table: the run failed; see $dir.log)"
    echo
    if [ -f "$dir/regression.md" ]; then
      echo "The quick case's own numbers against its committed regression record (reference-data/regression/):"
      echo
      cat "$dir/regression.md"
      echo
    fi
    if [ -f "$dir/cases.csv" ]; then
      echo "Every run of this experiment (wall time per run, one thread each; columns as defined in the experiment's README):"
      echo
      awk -F, 'NR==1{h="|"; s="|"; for(i=1;i<=NF;i++){h=h" "$i" |"; s=s"---|"}; print h; print s; next}
               {r="|"; for(i=1;i<=NF;i++){r=r" "$i" |"}; print r}' "$dir/cases.csv"
      echo
    fi
    if [ -f "$dir/spread.md" ]; then
      echo "### The ensemble, the Δt sequences and the study's differences"
      echo
      cat "$dir/spread.md"
      echo
    fi
    if [ -f "$dir/validation/check.md" ]; then
      echo "### Our rigid disk against published data"
      echo
      echo "One disk at the parameters of Pan & Glowinski (2002), J. Comput. Phys. 181, 260-279 (reference-data/disk_validation.csv; the experiment's README):"
      echo
      cat "$dir/validation/check.md"
      echo
    fi
    if [ -f "$dir/ensemble.md" ]; then
      echo "### The ensemble of initial arrangements"
      echo
      cat "$dir/ensemble.md"
      echo
    fi
    if [ -f "$dir/convergence.md" ]; then
      echo "### Error against run time"
      echo
      cat "$dir/convergence.md"
      echo
    fi
    if [ -f "$dir/re_evidence.md" ]; then
      echo "### What could explain the Reynolds numbers with the cell"
      echo
      cat "$dir/re_evidence.md"
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
  } > "$sections/$exp.md"
done

# The report, put together from every experiment's section as last written.
out="$report/README.md.tmp"
{
  echo "# rbcflow reproduction report"
  echo
  echo "Reproduction of L. Shi, T.-W. Pan, R. Glowinski, *Numerical simulation of lateral migration of red"
  echo "blood cells in Poiseuille flows*, Int. J. Numer. Meth. Fluids 68 (2012), DOI 10.1002/fld.2455."
  echo
  echo "| | |"
  echo "|---|---|"
  echo "| last command | \`$command\` |"
  echo "| commit | $commit$dirty |"
  echo "| date | $date_now |"
  echo "| machine | $(nproc) cores, $cpu, $(free -g | awk '/Mem:/{print $2}') GiB |"
  echo
  echo "Each experiment's section was written by the run below (\`make reproduce ONLY=...\` rewrites"
  echo "some sections and keeps the others; each section names its run again):"
  echo
  echo "| experiment | command | commit | date | parameters |"
  echo "|---|---|---|---|---|"
  for exp in "$@"; do
    if [ -f "$report/data/$exp/provenance.md" ]; then cat "$report/data/$exp/provenance.md"; else echo "| $exp | (not run yet) | | | |"; fi
  done
  echo
  echo "Every number is printed as ours ± u_num, our numerical uncertainty (Δt refinement, start ensemble,"
  echo "averaging window; the mesh apart, in the column 'converged in h'), against a tolerance from the study"
  echo "alone (reference-data/README.md). Verdicts: **PASS** within the tolerance with u_num no larger than it;"
  echo "**UNRESOLVED** u_num larger than the tolerance (or not measured) and ours ± u_num reaching it: our"
  echo "numerics cannot decide, counted as not reproduced; **DEVIATION** outside it and recorded in"
  echo "reference-data/deviations/ with our expected band, the cause we believe in and its evidence; **FAIL**"
  echo "outside the tolerance and not explained, or a recorded deviation that moved. Each experiment's section"
  echo "below has its full table (u_num's parts, how each row was run, the cause of every deviation), the run"
  echo "time and the figures."
  echo
  echo "## All the study's numbers"
  echo
  "$BUILD/bin/rbcflow" summary --results "$report/data" || { echo "(the summary table failed)"; status=1; }
  echo
  for exp in "$@"; do
    if [ -f "$sections/$exp.md" ]; then cat "$sections/$exp.md"
    elif [ -f "$report/README.md" ]; then  # as last written: from its heading to the next section's
      # A section judged before u_num and the study's tolerances (its check.csv has the old
      # columns) says so under its heading: its verdicts count as not run in the table above.
      stale=""
      [ "$(head -1 "$report/data/$exp/check.csv" 2>/dev/null | tr -d '\r')" = "id,ours,verdict,note" ] && \
        stale="**Written before u_num and the study's tolerances (reference-data/README.md): the verdicts below were judged by the old tolerance rule and count as not run until make reproduce ONLY=$exp runs it again.**"
      awk -v h="## $exp" -v stale="$stale" '$0 == h {on = 1; print; if (stale != "" && !done) {print ""; print stale; done = 1}; next} on && /^## / {exit} on && $0 ~ /^\*\*Written before u_num/ {next} on' "$report/README.md"
    fi
  done
  missing=""
  for exp in single_cell_migration four_cells_vs_disks cell_free_layer constriction; do
    [ -f "$report/data/$exp/check.csv" ] || missing="$missing $exp"
  done
  if [ -n "$missing" ]; then
    echo "## Not yet reproduced"
    echo
    for exp in $missing; do
      echo "- $exp: its published numbers are in reference-data/$exp.csv; no run of it is in this report yet."
    done
  fi
} > "$out"
mv "$out" "$report/README.md"
echo "rbcflow: report written to $report/README.md" >&2
exit $status
