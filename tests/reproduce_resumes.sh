#!/usr/bin/env bash
# make reproduce, interrupted as by Ctrl-C and run again, gives the numbers of a straight run
# (paper/make_report.sh; the cases' own checkpoints: the Checkpoint.* tests). On the quick
# cell_free_layer (two cases of some 10-20 s, side by side): a straight run; then a run stopped by
# SIGINT to its whole process group once a case has printed progress (10 s into it), and the same
# command again; the rows of the two reports and the cases' summaries must agree. A third run,
# whose GNU parallel alone gets the SIGINT, must stop the same way.
#   tests/reproduce_resumes.sh SOURCE_DIR BUILD_DIR
set -euo pipefail
src=$1; build=$2
work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
run() {  # results folder
  RESULTS="$work/$1" QUICK=1 ONLY=cell_free_layer BUILD="$build" JOBS=2 \
    bash "$src/paper/make_report.sh" reproduce channel_flow cell_free_layer
}
run straight > "$work/straight.log" 2>&1 || { cat "$work/straight.log"; exit 1; }

set -m  # job control: the interrupted run gets its own process group, as a terminal's foreground job
run stopped > "$work/stopped.log" 2>&1 &
pid=$!
for _ in $(seq 1200); do  # until a case is under way (its first progress line), at most 120 s
  grep -q 'steps/s' "$work"/stopped/cell_free_layer/n*.log 2>/dev/null && break
  sleep 0.1
done
kill -INT -- -"$pid"
rc=0; wait "$pid" || rc=$?
set +m
[ "$rc" = 130 ] || { echo "the interrupted run exited with $rc, not 130"; cat "$work/stopped.log"; exit 1; }
grep -q 'checkpoint' "$work"/stopped/cell_free_layer/n*.log || { echo "no case wrote a checkpoint on the interrupt"; exit 1; }
run stopped > "$work/again.log" 2>&1 || { cat "$work/again.log"; exit 1; }
grep -q 'resuming' "$work"/stopped/cell_free_layer/n*.log || { echo "no case resumed"; cat "$work"/stopped/cell_free_layer/n*.log; exit 1; }

# SIGINT to GNU parallel alone (its pid, as a batch system may send it) stops the command as well:
# exit 130 and no report of missing cases; the report already there (the straight run's) stays
# whole, its figures and data included.
mkdir -p "$work/parallel_stopped" && cp -r "$work/straight/report" "$work/parallel_stopped/report"
run parallel_stopped > "$work/parallel_stopped.log" 2>&1 &
pid=$!
for _ in $(seq 1200); do
  grep -q 'steps/s' "$work"/parallel_stopped/cell_free_layer/n*.log 2>/dev/null && break
  sleep 0.1
done
pkill -INT -f "parallel .*$work/parallel_stopped/joblog_reproduce"
rc=0; wait "$pid" || rc=$?
[ "$rc" = 130 ] || { echo "the run whose GNU parallel was interrupted exited with $rc, not 130"; cat "$work/parallel_stopped.log"; exit 1; }
cmp -s "$work/straight/report/README.md" "$work/parallel_stopped/report/README.md" || { echo "a report was written after GNU parallel was interrupted"; exit 1; }
diff -r "$work/straight/report" "$work/parallel_stopped/report" > /dev/null || { echo "the interrupted run changed the earlier report's figures or data"; exit 1; }

# The rows (id, ours, verdict) of both reports, and every case's summary but what the clock and the command line (its folder) write.
rows() { [ -s "$work/$1/report/data/cell_free_layer/check.csv" ] || { echo "no table in $work/$1/report/data/cell_free_layer" >&2; return 1; }
  cut -d, -f1-3 "$work/$1/report/data/cell_free_layer/check.csv"; }
rows straight > "$work/rows_straight"
rows stopped > "$work/rows_stopped"
diff "$work/rows_straight" "$work/rows_stopped"
for c in n50 n100; do
  diff <(grep -Ev '"(wall_seconds|started|ended|command)"' "$work/straight/cell_free_layer/$c/summary.json") <(grep -Ev '"(wall_seconds|started|ended|command)"' "$work/stopped/cell_free_layer/$c/summary.json")
done
echo "interrupted and resumed: the same rows and summaries as the straight run"

# The report written again from the same runs keeps its movie's bytes (gnuplot places a few colours
# at other table slots from run to run: experiments/common/gif_same_frames.py), and that
# comparison tells other frames apart.
movie="$work/straight/report/figures/cell_free_layer_movie.gif"
[ -s "$movie" ] || { echo "no movie in the quick report"; exit 1; }
cp "$movie" "$work/movie.gif"
COLLECT=1 run straight > "$work/collect.log" 2>&1 || { cat "$work/collect.log"; exit 1; }
cmp -s "$movie" "$work/movie.gif" || { echo "the movie of the same runs was written as other bytes"; exit 1; }
gnuplot -e "set terminal gif animate size 200,100; set output '$work/other.gif'; plot x; plot x**2" 2> /dev/null
rc=0; python3 "$src/experiments/common/gif_same_frames.py" "$movie" "$work/other.gif" || rc=$?
[ "$rc" = 1 ] || { echo "gif_same_frames.py found other frames the same (exit $rc)"; exit 1; }
echo "the same runs' movie kept its bytes; other frames told apart"
