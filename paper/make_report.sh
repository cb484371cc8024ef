#!/usr/bin/env bash
# The two main jobs of rbcflow (README.md), called by make:
#
#   make_report.sh reproduce EXPERIMENT...   `make reproduce`: the study's own runs — the ones its
#       rows and figures read — from the current commit, then every experiment's comparison, its
#       figures and paper/report/README.md, whole. Each row's u_num is read from the record that
#       make evidence left in reference-data/uncertainty/ (its commit and code named in the report).
#   make_report.sh evidence EXPERIMENT...    `make evidence`: every run of every experiment (the
#       study's runs again where not on disk, the start ensembles, the Δt/h refinements, the error-
#       against-run-time studies, the stability map), then the record of u_num
#       (reference-data/uncertainty/<experiment>.csv, with this commit and code) and
#       paper/evidence/README.md.
#
# Every case is one process (one thread) in one GNU parallel pool over all the experiments, the
# longest first by the times of the last full run (paper/report/data/case_times.csv), two crowds
# not side by side (below), with one progress line a minute (cases done, elapsed, an estimate of
# the time left). Interruptible: Ctrl-C (or a killed machine) and the same command again
# continues — finished cases are read back, stopped ones resume from their checkpoints (written on
# the signal and every 5 minutes of wall time), the same numbers as a straight run
# (paper/stop_and_resume.md).
#
# Results are kept per code: results/<experiment>/code_id names the sources that made them (the
# .cpp, .hpp and .toml files of lib/ and experiments/, and CMakeLists.txt: not the documents or
# plot scripts); a folder made by other code is moved to results/older/ before anything runs, so
# that no number of the report comes from another commit's code.
#
# Environment (make's variables):
#   QUICK=1    the CI parameters (reproduce only): results under results/quick/, the report in
#              results/report/README.md (never over the committed one); an uncommitted tree is
#              allowed and said.
#   ONLY="exp ..."  these experiments only; the report goes to results/report/ (or results/evidence/),
#              the committed reports are only ever written whole (make evidence ONLY=... still
#              records those experiments' u_num).
#   COLLECT=1  run no case: write the report from the cases finished so far (e.g. after a Slurm
#              array, paper/running_at_scale.md); rows of missing cases say "not run", figures
#              whose runs' files are missing are left out, and make evidence keeps the recorded
#              u_num of the rows it could not measure.
#   JOBS       cases side by side (default: the number of cores).
#   RESULTS    the results folder (default results; the tests use their own).
# Exit status: 0; 1 if a row FAILed, an experiment stopped or a figure failed; 2 on bad use or a
# refused tree; 130 when interrupted (run the same command again to continue).
set -uo pipefail
cd "$(dirname "$0")/.."
mode=${1:-}; shift || true
case "$mode" in reproduce|evidence) ;; *) echo "usage: $0 reproduce|evidence EXPERIMENT..." >&2; exit 2 ;; esac
BUILD=${BUILD:-build}
QUICK=${QUICK:-0}
ONLY=${ONLY:-}
COLLECT=${COLLECT:-0}
JOBS=${JOBS:-$(nproc)}
start_all=$(date +%s)

if [ "$mode" = evidence ] && [ "$QUICK" = "1" ]; then
  echo "rbcflow: make evidence has no quick form (its runs measure the full runs' uncertainty)" >&2; exit 2
fi

# The experiments of this run: ONLY's (each one of the list), or all; make reproduce leaves out
# those made of evidence alone (none today: the stability map's report version, --study-only, is
# a few core-minutes).
all=("$@")
run_list=("$@")
if [ -n "$ONLY" ]; then
  run_list=()
  for exp in $ONLY; do
    case " ${all[*]} " in *" $exp "*) run_list+=("$exp") ;; *) echo "rbcflow: ONLY names '$exp', not one of: ${all[*]}" >&2; exit 2 ;; esac
  done
fi
evidence_only=" "  # (none: the stability map's report version is cheap enough for make reproduce)
if [ "$mode" = reproduce ]; then
  keep=(); for exp in "${run_list[@]}"; do [[ "$evidence_only" == *" $exp "* ]] || keep+=("$exp"); done; run_list=("${keep[@]}")
fi

# The tree: committed, unless QUICK (CI's own checkout is always clean; a quick run of a working
# tree says so). The code id: the sources that make the numbers.
sources=(lib experiments CMakeLists.txt)
numeric=(':(glob)lib/**/*.[ch]pp' ':(glob)experiments/**/*.[ch]pp' ':(glob)experiments/**/*.toml' CMakeLists.txt)
read -r code commit < <(sh cmake/code_id.sh)   # the one definition of the code id (every program's --version)
changes=$(git status --porcelain -- "${sources[@]}" reference-data 2>/dev/null)
dirty=""
if [ -n "$changes" ]; then
  if [ "$QUICK" != "1" ]; then
    echo "rbcflow: make $mode writes its report from one commit: commit or stash these changes first:" >&2
    echo "$changes" | sed 's/^/  /' >&2
    exit 2
  fi
  dirty=" (with uncommitted changes)"
fi
built=$("$BUILD/bin/rbcflow" --version 2>/dev/null | sed 's/.*code \([^,]*\),.*/\1/')
if [ -n "$built" ] && [ "$built" != "$code" ]; then
  echo "rbcflow: $BUILD was built from code $built, the tree is code $code: build it again (make build-runs)" >&2; exit 2
fi

results=${RESULTS:-results}; [ "$QUICK" = "1" ] && [ -z "${RESULTS:-}" ] && results=results/quick
quick_flag=""; [ "$QUICK" = "1" ] && quick_flag="--quick"
if [ "$mode" = evidence ]; then report=paper/evidence; [ -n "$ONLY" ] && report=${RESULTS:-results}/evidence
elif [ "$QUICK" = "1" ] || [ -n "$ONLY" ]; then report=${RESULTS:-results}/report
else report=paper/report; fi
# The report's copies of each experiment's table (and the case times while they are written): not
# in paper/evidence/data/, which holds the kept runs (paper/keep_evidence.sh) and is never cleared.
tables=$report/data; [ "$mode" = evidence ] && tables=$report/tables
times_record=paper/report/data/case_times.csv   # exp,case,seconds of the last full run (ordering, estimates)
command="make $mode$([ "$QUICK" = "1" ] && echo ' QUICK=1')$([ -n "$ONLY" ] && echo " ONLY=\"$ONLY\"")$([ "$COLLECT" = "1" ] && echo ' COLLECT=1')"
mkdir -p "$results" "$report"
log() { echo "rbcflow $mode: $*" >&2; }

# Results made by other code move aside (results/older/<experiment>.<code>), once per folder.
for exp in "${run_list[@]}"; do
  dir="$results/$exp"
  if [ -d "$dir" ] && [ "$(cat "$dir/code_id" 2>/dev/null)" != "$code" ]; then
    old=$(cat "$dir/code_id" 2>/dev/null || echo unknown)
    mkdir -p "$results/older"; rm -rf "$results/older/$exp.$old"; mv "$dir" "$results/older/$exp.$old"
    log "$dir was made by other code ($old, not $code): moved to $results/older/$exp.$old"
  fi
  mkdir -p "$dir"; echo "$code" > "$dir/code_id"
done

has_flag() { "$BUILD/bin/$1" --help 2>/dev/null | grep -q -- "$2"; }
part_flag() { [ "$mode" = reproduce ] && has_flag "$1" --study-only && echo --study-only; }

# The jobs: "experiment case" per line (each experiment's --list-cases; case "-": a program
# without cases, run whole).
jobs_file="$results/jobs_$mode.txt"
: > "$jobs_file"
for exp in "${run_list[@]}"; do
  if has_flag "$exp" --list-cases; then
    "$BUILD/bin/$exp" --list-cases $quick_flag $(part_flag "$exp") | sed "s/^/$exp /" >> "$jobs_file"
  else
    echo "$exp -" >> "$jobs_file"
  fi
done
# The longest first, by the last full run's times (unknown ones first: the order of --list-cases),
# except that two crowds (cell_free_layer's cases, 50 or 100 cells) do not run side by side while
# another case can take the other core. Two crowds slow each other by a third (their working sets
# share the last-level cache; measured one thread each, 2 cores: the 100 cells at 70–73 steps/s
# beside a four-cell or a one-cell case, 45–50 beside another crowd, the other pairs at full
# speed). The order is parallel's: planned by playing the list on JOBS cores with those times.
apart='^cell_free_layer '
if [ -f "$times_record" ] && [ "$QUICK" != "1" ]; then
  awk -F, 'NR == FNR {if (FNR > 1) t[$1 " " $2] = $3; next} {print (($0 in t) ? t[$0] : 1e9) "\t" NR "\t" $0}' \
    "$times_record" "$jobs_file" | sort -t$'\t' -k1,1gr -k2,2n | awk -F'\t' -v jobs="$JOBS" -v apart="$apart" '
    {t[NR] = $1; job[NR] = $3; crowd[NR] = ($3 ~ apart)}
    END {
      for (left = NR; left > 0; left--) {
        s = 1; for (k = 2; k <= jobs; k++) if (free[k] < free[s]) s = k   # the core that frees first
        busy = 0; for (k = 1; k <= jobs; k++) if (k != s && on[k] && free[k] > free[s]) busy = 1
        pick = 0
        for (i = 1; i <= NR && !pick; i++) if (!used[i] && !(busy && crowd[i])) pick = i
        for (i = 1; i <= NR && !pick; i++) if (!used[i]) pick = i       # only crowds left
        used[pick] = 1; print job[pick]; free[s] += t[pick]; on[s] = crowd[pick]
      }
    }' > "$jobs_file.sorted" && mv "$jobs_file.sorted" "$jobs_file"
fi

# The evidence kept in the repository (paper/keep_evidence.sh: paper/evidence/data/<experiment>/<case>,
# each with the code that made it): a kept case whose folder is missing goes into place when this
# command reads it without running it — make reproduce: the cases an experiment reads but never
# runs (--list-read-only --study-only: the crowds' arrangements its rows are judged by); make
# evidence: every kept case it does not run itself (with COLLECT=1: every kept case). Not in QUICK.
restored=0
if [ "$QUICK" != "1" ]; then
  for exp in "${run_list[@]}"; do
    read_only=""
    [ "$mode" = reproduce ] && has_flag "$exp" --list-read-only && read_only=$("$BUILD/bin/$exp" --list-read-only --study-only)
    for kept_case in paper/evidence/data/"$exp"/*/; do
      [ -f "$kept_case/summary.json" ] || continue
      name=$(basename "$kept_case")
      [ -e "$results/$exp/$name" ] && continue
      [ "$mode" = reproduce ] && ! grep -qx "$name" <<< "$read_only" && continue
      [ "$COLLECT" != "1" ] && grep -qx "$exp $name" "$jobs_file" && continue
      cp -r "$kept_case" "$results/$exp/$name" && restored=$((restored + 1))
    done
  done
  [ "$restored" -gt 0 ] && log "$restored kept case(s) put in place from paper/evidence/data/ (each with its code_id; the tables name it)"
fi

# One case: read back if finished, resumed from its checkpoint if stopped, else run.
run_one() {  # exp case
  local exp=$1 name=$2 dir="$results/$1"
  if [ "$name" = "-" ]; then
    "$BUILD/bin/$exp" --out "$dir" $quick_flag $(part_flag "$exp") --reuse --resume --threads 1 > "$dir/run.log" 2>&1
  else
    "$BUILD/bin/$exp" --out "$dir" $quick_flag $(part_flag "$exp") --reuse --resume --only "$name" --threads 1 > "$dir/$name.log" 2>&1
  fi
}
export -f run_one part_flag has_flag
export BUILD results quick_flag mode
export PARALLEL_SHELL=bash  # run_one is a bash function

# One progress line a minute: cases done, elapsed, and the time left estimated from the running
# cases' own ETA and the queued cases' last full-run times, shared over JOBS cores.
progress() {
  local joblog=$1 total=$2
  while sleep 60; do
    done_n=$(( $(wc -l < "$joblog" 2>/dev/null || echo 1) - 1 ))
    elapsed=$(( $(date +%s) - start_all ))
    running=$(ps -eo args= 2>/dev/null | awk -v b="$BUILD/bin/" -v r="$results/" '$1 ~ b && index($0, "--out " r) && / --resume / {
      n = "-"; for (i = 1; i <= NF; i++) if ($i == "--only") n = $(i + 1); print (n == "-" ? substr($1, length(b) + 1) : n)}' | sort -u)
    left=0; names=""
    for n in $running; do
      eta=$(grep -ho 'ETA [0-9hms]*' "$results"/*/"$n.log" "$results/$n/run.log" 2>/dev/null | tail -1 | awk '{s = $2; t = 0; if (s ~ /h/) {split(s, a, "h"); t += a[1] * 3600; s = a[2]} if (s ~ /m/) {split(s, a, "m"); t += a[1] * 60; s = a[2]} sub("s", "", s); print t + s}')
      left=$(( left + ${eta:-0} )); names="$names $n"
    done
    # The queued cases: those after the done and running ones in the jobs file (parallel's order).
    read -r queued_s unknown < <(tail -n +$((done_n + $(echo $running | wc -w) + 1)) "$jobs_file" | awk -v rec="$times_record" '
      BEGIN {while ((getline l < rec) > 0) {split(l, f, ","); t[f[1] " " f[2]] = f[3]}}
      {if ($0 in t) s += t[$0]; else u++} END {print int(s), u + 0}')
    left=$(( (left + ${queued_s:-0}) / JOBS ))
    printf 'rbcflow %s: %d/%d cases done, %dm elapsed, about %dm left%s (running:%s)\n' "$mode" "$done_n" "$total" $((elapsed / 60)) $((left / 60)) \
      "$([ "${unknown:-0}" != 0 ] && echo " and $unknown queued cases of no recorded length")" "$names" >&2
  done
}

interrupted=0
trap 'interrupted=1' INT TERM
total=$(wc -l < "$jobs_file")
# Cases finished at this code before this invocation (by an interrupted one of this command,
# whose time is in the wall total, or by another command such as make evidence, whose is not).
read_back=0
while read -r exp name; do
  [ -f "$results/$exp/$([ "$name" = - ] && echo run || echo "$name")/summary.json" ] && read_back=$((read_back + 1))
done < "$jobs_file"
if [ "$COLLECT" != "1" ] && [ "$total" -gt 0 ]; then
  joblog="$results/joblog_$mode"
  log "$total cases of ${run_list[*]} on $JOBS cores, the longest first, two crowds not side by side (jobs: $jobs_file, joblog: $joblog)"
  progress "$joblog" "$total" & progress_pid=$!
  # On Ctrl-C (or TERM) GNU parallel passes SIGINT on to every running case (each in its own
  # process group) and gives it a minute to write its checkpoint before TERM and KILL.
  parallel --will-cite -j "$JOBS" --colsep ' ' --joblog "$joblog" --termseq INT,60000,TERM,5000,KILL,25 run_one {1} {2} < "$jobs_file"
  kill "$progress_pid" 2>/dev/null; wait "$progress_pid" 2>/dev/null
  # A signal that reached GNU parallel alone (kill -INT on its pid) stops it before every case ran:
  # the same as an interrupted command, not a report of missing cases.
  [ "$(( $(wc -l < "$joblog") - 1 ))" -lt "$total" ] && interrupted=1
  if [ "$interrupted" = "1" ]; then
    echo "$code $(( $(date +%s) - start_all ))" >> "$results/wall_$mode.txt"
    log "interrupted after $(( $(date +%s) - start_all )) s: run '$command' again to continue (finished cases are read back, stopped ones resume)"
    exit 130
  fi
  failed=$(awk 'NR > 1 && $7 != 0' "$joblog" | wc -l)
  [ "$failed" -gt 0 ] && log "$failed cases stopped (their rows say why; logs in $results/<experiment>/<case>.log)"
fi
trap - INT TERM

# A report is written whole: nothing of an earlier one stays beside it (the run times record
# stays). Only now, with every case finished: an interrupted run leaves the last report intact.
# The report's movies as they are, kept where the new ones show the same frames (below).
kept=$(mktemp -d); cp "$report/figures/"*_movie.gif "$kept/" 2>/dev/null
[ "$COLLECT" != "1" ] && rm -rf "$report/figures" && find "$tables" -mindepth 1 -maxdepth 1 -type d -exec rm -rf {} + 2>/dev/null

# Collect every experiment: its comparison (check.md/.csv), figures, movie and section. The
# experiments are independent (each writes its own folder, its own figures and its section), so
# GNU parallel collects JOBS at a time; each leaves its section and its time in $sections (read
# back below, in the list's order) and exits 1 if anything of it went wrong.
movie_experiments=" single_cell_migration four_cells_vs_disks cell_free_layer constriction "
sections=$(mktemp -d); trap 'rm -rf "$sections" "$kept"' EXIT
collect_one() {  # exp
  local exp=$1 status=0
  local dir="$results/$exp" t0 flags rc figdir movie earlier fig cases_s seconds
  t0=$(date +%s)
  flags="--check $quick_flag $(part_flag "$exp")"
  if has_flag "$exp" --collect; then flags="$flags --collect"
  elif has_flag "$exp" --reuse; then flags="$flags --reuse"; fi
  has_flag "$exp" --threads && flags="$flags --threads 1"
  rm -f "$dir/check.csv" "$dir/uncertainty.csv"
  log "collecting $exp ($BUILD/bin/$exp --out $dir $flags)"
  "$BUILD/bin/$exp" --out "$dir" $flags > "$dir/check.log" 2>&1
  rc=$?
  [ "$rc" -ne 0 ] && status=1
  [ "$rc" -ge 2 ] && { log "$exp stopped (exit $rc):"; tail -3 "$dir/check.log" >&2; }
  figdir="$report/figures"; mkdir -p "$figdir"
  rm -f "$figdir/${exp}"_*.png "$figdir/${exp}"_*.gif
  # (COLLECT=1 reads what is kept, which holds no snapshots or fields: a figure that needs them is
  # left out, not an error of the collection.)
  if ! gnuplot -e "dir='$dir'; figdir='$figdir'" "experiments/$exp/plot.gp" > "$dir/plot.log" 2>&1; then
    if [ "$COLLECT" = "1" ]; then  # (gnuplot stops at the failing figure, which may be left half drawn)
      rm -f "$figdir/${exp}"_*.png "$figdir/${exp}"_*.gif
      log "$exp: its figures not drawn (COLLECT=1: its runs' files are not all kept; $dir/plot.log)"
    else status=1; log "$exp: a figure failed ($dir/plot.log)"; fi
  fi
  # gnuplot's GIFs place a few colours at other table slots from run to run: a movie that shows
  # the same frames as the report's keeps its bytes (no new copy in git for the same pixels).
  for movie in "$figdir/${exp}"_*.gif; do
    earlier="$kept/${movie##*/}"
    [ -f "$movie" ] && [ -f "$earlier" ] && python3 experiments/common/gif_same_frames.py "$earlier" "$movie" && mv "$earlier" "$movie"
  done
  # The evidence's figures (the evidence runs, the units) go to the evidence report, the study's
  # to the reproduction report; error against run time to both (make reproduce: the coarse meshes'
  # runs; make evidence: every h).
  for fig in "$figdir/${exp}"_*.png "$figdir/${exp}"_*.gif; do
    [ -f "$fig" ] || continue
    case "$(basename "$fig")" in *work_precision*) ;; *_evidence*|*_units*) [ "$mode" = reproduce ] && rm -f "$fig" ;; *) [ "$mode" = evidence ] && [ "$exp" != stability_map ] && rm -f "$fig" ;; esac
  done
  # Every experiment of the study's runs has its movie (its plot.gp, from the runs' frames.dat).
  if [ "$mode" = reproduce ] && [ "$COLLECT" != "1" ] && [[ "$movie_experiments" == *" $exp "* ]] && [ ! -s "$figdir/${exp}_movie.gif" ]; then
    status=1; log "$exp: no movie ($figdir/${exp}_movie.gif; its runs' frames.dat and $dir/plot.log)"
  fi
  mkdir -p "$tables/$exp"
  [ -f "$dir/check.csv" ] && cp "$dir/check.csv" "$tables/$exp/check.csv"
  # Each case's run time, for the next run's order and estimates; not the kept runs put in place
  # (their code_id: another command ran them, on another code).
  if [ -f "$dir/cases.csv" ]; then
    awk -F, -v e="$exp" 'NR == 1 {for (i = 1; i <= NF; i++) if ($i == "wall_seconds") w = i; next} w && $w != "" {print e "," $1 "," $w}' "$dir/cases.csv" |
      while IFS=, read -r e name s; do [ -f "$dir/$name/code_id" ] || echo "$e,$name,$s"; done > "$dir/case_times.csv"
  else  # (channel_flow, constriction, stability_map): each case's own wall time (its summary.json,
    # resumed sessions included), else (a stability map's point) its job's, when it computed rather
    # than read back
    : > "$dir/case_times.csv"
    for name in $(awk -v e="$exp" '$1 == e {print $2}' "$jobs_file"); do
      s=""
      for f in "$dir/$name/summary.json" "$dir/conv/$name/summary.json"; do
        [ -f "$f" ] && { s=$(sed -n 's/.*"wall_seconds": *\([0-9.e+]*\).*/\1/p' "$f" | head -1); break; }
      done
      [ -z "$s" ] && s=$(awk -F'\t' -v c="run_one $exp $name" 'NR > 1 && $9 == c && $4 > 0.3 {t = $4} END {if (t != "") print t}' "$results/joblog_$mode" 2>/dev/null)
      [ -n "$s" ] && echo "$exp,$name,$s" >> "$dir/case_times.csv"
    done
  fi
  # The experiment's run time: its cases' own (one thread each; a resumed case's includes the time
  # before its interruption) plus this step's.
  cases_s=$(awk -F, '{s += $3} END {printf "%d", s}' "$dir/case_times.csv" 2>/dev/null)
  seconds="$(( ${cases_s:-0} + $(date +%s) - t0 ))"
  {
    echo "## $exp"
    echo
    sed -n '/^## Claim/,/^## /p' "experiments/$exp/README.md" | sed '1d;$d'
    echo
    echo "Run: \`$BUILD/bin/$exp --out $dir $flags\` after its cases — exit code $rc; its cases' run time (one thread each) and this step: $seconds s."
    echo
    if [ -f "$dir/check.md" ]; then cat "$dir/check.md"; else echo "(no comparison table: $(tail -1 "$dir/check.log" 2>/dev/null))"; fi
    echo
    if [ -f "$dir/regression.md" ]; then
      echo "The quick case's own numbers against its committed regression record (reference-data/regression/):"
      echo; cat "$dir/regression.md"; echo
    fi
    if [ "$mode" = evidence ]; then
      [ -f "$dir/validation/check.md" ] && { echo "### Our rigid disk against published data"; echo; echo "One disk at the parameters of Pan & Glowinski (2002), J. Comput. Phys. 181, 260-279 (reference-data/disk_validation.csv; the experiment's README):"; echo; cat "$dir/validation/check.md"; echo; }
      [ -f "$dir/spread.md" ] && { echo "### The ensemble, the Δt sequences and the study's differences"; echo; cat "$dir/spread.md"; echo; }
      [ -f "$dir/ensemble.md" ] && { echo "### The ensemble of initial arrangements"; echo; cat "$dir/ensemble.md"; echo; }
      [ -f "$dir/re_evidence.md" ] && { echo "### What could explain the Reynolds numbers with the cell"; echo; cat "$dir/re_evidence.md"; echo; }
      [ -f "$dir/units_evidence.md" ] && { echo "### Which reading of the 2D constants"; echo; sed -n '/^## Units/,/^## /p' "experiments/$exp/README.md" | sed '1d;$d'; echo; cat "$dir/units_evidence.md"; echo; }
    fi
    [ -f "$dir/convergence.md" ] && { echo "### Error against run time"; echo; cat "$dir/convergence.md"; echo; }
    if [ -f "$dir/cases.csv" ]; then
      echo "Every run (wall time per run, one thread each; columns as defined in the experiment's README):"
      echo
      awk -F, 'NR==1{h="|"; s="|"; for(i=1;i<=NF;i++){h=h" "$i" |"; s=s"---|"}; print h; print s; next}
               {r="|"; for(i=1;i<=NF;i++){r=r" "$i" |"}; print r}' "$dir/cases.csv"
      echo
    fi
    if [ "$mode" = reproduce ] && grep -q '^## Deviations' "experiments/$exp/README.md" 2>/dev/null; then
      echo "### Deviations and choices"; echo
      sed -n '/^## Deviations/,/^## /p' "experiments/$exp/README.md" | sed '1d;$d'; echo
    fi
    for fig in "$figdir/${exp}"_*.png; do
      [ -f "$fig" ] || continue
      echo "![$(basename "$fig" .png)](figures/$(basename "$fig"))"; echo
    done
    for movie in "$figdir/${exp}"_*.gif; do
      [ -f "$movie" ] || continue
      echo "The run as a movie ($(( $(stat -c %s "$movie") / 1024 )) kB, animated GIF; the frames: the run's frames.dat, experiments/common/movie.gp):"
      echo; echo "![$(basename "$movie" .gif)](figures/$(basename "$movie"))"; echo
    done
  } > "$sections/$exp.md"
  echo "$seconds" > "$sections/$exp.wall"
  return $status
}
export -f collect_one log
export report tables kept sections movie_experiments jobs_file COLLECT
status=0
[ "${#run_list[@]}" -gt 0 ] && { printf '%s\n' "${run_list[@]}" | parallel --will-cite -j "$JOBS" --line-buffer collect_one || status=1; }
declare -A exp_wall
for exp in "${run_list[@]}"; do exp_wall[$exp]=$(cat "$sections/$exp.wall" 2>/dev/null); done

# make evidence: the record of u_num, with this commit and code (reference-data/uncertainty/).
# Not of an experiment that read kept cases of other code: its rows would carry this commit for
# runs it did not make (those rows' records: paper/record_kept_uncertainty.sh); they stay in
# results/<experiment>/uncertainty.csv.
# (A kept case carries its code in its folder's code_id; the cases this code ran have none. So an
# experiment that always reads some kept case, e.g. four_cells_vs_disks its kept pg2002 runs when
# they are not among its cases, keeps the record of paper/record_kept_uncertainty.sh.)
other_code=" "
for exp in "${run_list[@]}"; do
  for f in "$results/$exp"/*/code_id; do
    [ -f "$f" ] && [ "$(head -1 "$f")" != "$code" ] && { other_code="$other_code$exp "; break; }
  done
done
if [ "$mode" = evidence ] && [ "$COLLECT" != "1" -o -n "$(ls "$results"/*/uncertainty.csv 2>/dev/null)" ]; then
  mkdir -p reference-data/uncertainty
  for exp in "${run_list[@]}"; do
    if [[ "$other_code" == *" $exp "* ]]; then
      log "u_num of $exp not recorded: it read kept cases of other code than $code (paper/evidence/data/); its rows as measured: $results/$exp/uncertainty.csv"
      continue
    fi
    for pair in "$exp:$results/$exp/uncertainty.csv" "disk_validation:$results/$exp/validation/uncertainty.csv"; do
      table=${pair%%:*}; file=${pair#*:}
      [ -f "$file" ] || continue
      [ "$table" = disk_validation ] && [ "$exp" != four_cells_vs_disks ] && continue
      record=reference-data/uncertainty/$table.csv
      # Rows the previous record had and this run could not measure (evidence runs missing) are
      # dropped, not carried over from other code: said here.
      # With COLLECT=1 (the cases finished so far) they stay as they were, each with its own commit.
      dropped=$( [ -f "$record" ] && comm -23 <(cut -d, -f1 "$record" | tail -n +2 | sort) <(cut -d, -f1 "$file" | tail -n +2 | sort) | tr '\n' ' ')
      kept_rows="" said=""
      if [ -n "$dropped" ] && [ "$COLLECT" = "1" ] && [ "$(head -1 "$record")" = "$(head -1 "$file")" ]; then
        kept_rows=$(awk -F, -v keep=" $dropped" 'FNR > 1 && index(keep, " " $1 " ")' "$record")
        said="; not measured, kept as recorded before: $dropped"
      elif [ -n "$dropped" ]; then
        said="; not measured, dropped from the record: $dropped"
      fi
      awk -F, -v c="$commit" -v k="$code" 'NR == 1 {print; next} {sub(/,,$/, "," c "," k); print}' "$file" > "$record"
      [ -n "$kept_rows" ] && printf '%s\n' "$kept_rows" >> "$record"
      log "u_num of $(( $(wc -l < "$file") - 1 )) rows recorded in $record (commit $commit, code $code)$said"
    done
  done
fi

# The report, whole, from this run.
wall_all=$(( $(date +%s) - start_all ))
# Every invocation at this code counts (results/wall_<mode>.txt): an interrupted command and the
# ones that continued it, or a later one that read the finished runs back, are one reproduction.
echo "$code $wall_all" >> "$results/wall_$mode.txt"
earlier=$(awk -v c="$code" '$1 == c {s += $2; n++} END {print s + 0, n + 0}' "$results/wall_$mode.txt")
wall_total=${earlier%% *}; invocations=${earlier##* }
cpu=$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ *//')
out="$report/README.md.tmp"
{
  if [ "$mode" = reproduce ]; then
    echo "# rbcflow reproduction report"
    echo
    echo "Reproduction of L. Shi, T.-W. Pan, R. Glowinski, *Numerical simulation of lateral migration of red"
    echo "blood cells in Poiseuille flows*, Int. J. Numer. Meth. Fluids 68 (2012), DOI 10.1002/fld.2455: the study's"
    echo "own runs, from one commit. The evidence behind each u_num (ensembles, Δt/h refinement, error against"
    echo "run time, the stability map down to h = 0.125 µm) is [paper/evidence/](../evidence/README.md), written by \`make evidence\`;"
    echo "each row's u_num as recorded from it: reference-data/uncertainty/ (the table below)."
  else
    echo "# rbcflow evidence report"
    echo
    echo "Every run behind the u_num of [the reproduction report](../report/README.md): the start ensembles, the"
    echo "Δt and h refinements, the error against run time, the rigid disk against published data and the"
    echo "stability map. \`make evidence\` wrote it and recorded each row's u_num in reference-data/uncertainty/."
  fi
  echo
  echo "| | |"
  echo "|---|---|"
  echo "| command | \`$command\` |"
  echo "| commit | $commit$dirty |"
  echo "| code (its sources in lib/, experiments/, CMakeLists.txt) | $code |"
  echo "| date | $(date -u '+%Y-%m-%d %H:%M UTC') |"
  echo "| machine | $(nproc) cores, $cpu, $(free -g | awk '/Mem:/{print $2}') GiB; $JOBS cases side by side |"
  echo "| parameters | $([ "$QUICK" = "1" ] && echo 'quick (CI)' || echo "full length (each row's scheme, Δt and departures: column 'how run')") |"
  echo "| wall time | $wall_total s |"
  [ "$invocations" -gt 1 ] && echo "| invocations | $invocations at this code (interrupted and continued, or read back; this one $wall_all s) |"
  [ "$COLLECT" != "1" ] && [ "$read_back" -gt 0 ] && echo "| cases read back | $read_back of $total, finished at this code before this invocation: by an earlier invocation of this command (their time then in the wall time above) or by another command such as make evidence (then only in their experiment's row) |"
  [ "$COLLECT" = "1" ] && echo "| runs | collected (COLLECT=1: none run by this command; rows of missing cases say \"not run\") |"
  [ "$restored" -gt 0 ] && echo "| kept runs | $restored case(s) read from paper/evidence/data/ (paper/keep_evidence.sh), each made by the code its table names |"
  [ "$mode" = evidence ] && [ -n "${other_code// /}" ] && echo "| u_num records | not written for${other_code% } (read kept runs of other code; reference-data/uncertainty/ keeps their records) |"
  for exp in "${run_list[@]}"; do echo "| $exp | ${exp_wall[$exp]} s (its cases' run time, one thread each, and its collect step) |"; done
  if [ "$mode" = reproduce ] && [ "$QUICK" != "1" ]; then
    echo
    echo "The u_num records (reference-data/uncertainty/, written by \`make evidence\`), read for the rows whose"
    echo "u_num this run does not measure; each record's rows by the commit and code that recorded them:"
    echo
    echo "| record | evidence commit (rows) | its code | this run's code |"
    echo "|---|---|---|---|"
    for exp in "${run_list[@]}" disk_validation; do
      f=reference-data/uncertainty/$exp.csv
      [ -f "$f" ] || { echo "| $exp | (none: u_num not measured) | | |"; continue; }
      commits="" codes="" same=""
      while read -r ec ek n; do
        commits+="${commits:+; }$ec ($n)"
        codes+="${codes:+; }$ek"
        same+="${same:+; }$([ "$ek" = "$code" ] && echo "the same" || echo "differs: $(git diff --shortstat "$ec" "$commit" -- "${numeric[@]}" 2>/dev/null | sed 's/^ *//')")"
      done < <(awk -F, 'NR > 1 {n[$(NF - 1) " " $NF]++} END {for (k in n) print k, n[k]}' "$f" | sort)
      echo "| [$exp]($(realpath --relative-to="$report" "$f")) | $commits | $codes | $same |"
    done
  fi
  echo
  if [ "$mode" = reproduce ]; then
    echo "Every number is printed as ours ± u_num, our numerical uncertainty at 95 % (Δt refinement by Eça &"
    echo "Hoekstra's least squares, start ensemble and averaging window at twice their spread; the mesh apart, in"
    echo "the column 'converged in h'), against a tolerance from the study alone: its digits and the differences"
    echo "it draws conclusions from (reference-data/README.md). Where the study's words allow several readings"
    echo "(U in Re), every reading is measured and shown below, and one chosen for the whole study."
    echo "Verdicts: **PASS** within the tolerance with u_num no larger than it;"
    echo "**UNRESOLVED** u_num larger than the tolerance (or not measured) and ours ± u_num reaching it: our"
    echo "numerics cannot decide, counted as not reproduced; **DEVIATION** outside it, recorded in"
    echo "reference-data/deviations/ with our expected band, and its cause shown by a named run or exact"
    echo "arithmetic (column shown_by); **UNEXPLAINED** outside it, recorded with our band, its cause not shown"
    echo "(what we believe is beside the row), counted as not reproduced; **FAIL** outside the tolerance and not"
    echo "recorded, or a recorded difference that left its band. Each experiment's section below has its full"
    echo "table (u_num's parts, how each row was run, the cause of every difference), its runs and the figures."
    echo
    echo "## All the study's numbers"
    echo
    "$BUILD/bin/rbcflow" summary --results "$tables" || { echo "(the summary table failed)"; status=1; }
    echo
  fi
  for exp in "${run_list[@]}"; do cat "$sections/$exp.md"; done
} > "$out"
mv "$out" "$report/README.md"
# The case times of a full run, for the next run's order and progress estimates.
if [ "$QUICK" != "1" ] && [ -z "$ONLY" ] && [ "$COLLECT" != "1" ]; then
  { echo "experiment,case,seconds"; cat "$results"/*/case_times.csv 2>/dev/null; } > "$tables/case_times.csv.new"
  [ -f "$times_record" ] && awk -F, 'NR == FNR {k[$1 "," $2] = 1; print; next} !(($1 "," $2) in k) && FNR > 1' "$tables/case_times.csv.new" "$times_record" > "$tables/case_times.csv.merged" \
    && mv "$tables/case_times.csv.merged" "$tables/case_times.csv.new"
  mkdir -p "$(dirname "$times_record")"; mv "$tables/case_times.csv.new" "$times_record"
fi
log "report written to $report/README.md in $wall_total s"
exit $status
