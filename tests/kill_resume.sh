#!/usr/bin/env bash
# A run killed with SIGKILL at random instants (inside a step, between a write and its sync,
# inside a checkpoint's write) and resumed each time ends with the bits of a straight run: its
# series.csv, snapshots.dat and summary.json (less the clock's fields) equal. As a user would: after
# each kill `rbcflow resume DIR` where the folder holds a checkpoint, else `rbcflow run --overwrite`.
#   tests/kill_resume.sh SOURCE_DIR BUILD_DIR [KILLS]
set -euo pipefail
src=$1; build=$2; kills=${3:-12}
rbcflow="$build/bin/rbcflow"
scene="$src/paper/method/scenes/single_cell_coarse.toml"
work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
# 25,000 steps of some 0.15 ms each (3-4 s), a checkpoint every 2e-5 s of flow (every 500 steps).
opts=(--threads 1 --checkpoint-sim 2e-5)
"$rbcflow" run "$scene" --out "$work/straight" "${opts[@]}" > /dev/null 2>&1

RANDOM=20261129  # the instants are random but the same at every run of the test
done_=0
for k in $(seq "$kills"); do
  if [ -e "$work/killed/checkpoint.bin" ] || [ -e "$work/killed/checkpoint.bin.prev" ]; then
    cmd=(resume "$work/killed")
  else
    cmd=(run "$scene" --out "$work/killed" --overwrite)
  fi
  { exec "$rbcflow" "${cmd[@]}" "${opts[@]}" > /dev/null 2>> "$work/stderr"; } &
  pid=$!
  sleep "0.$(printf '%03d' $((RANDOM % 1000)))"
  kill -KILL "$pid" 2>/dev/null || true
  rc=0; wait "$pid" || rc=$?
  if [ "$rc" = 0 ]; then done_=1; break; fi
  [ "$rc" = 137 ] || { echo "kill $k: rbcflow ${cmd[0]} exited with $rc, not 137 (SIGKILL)"; cat "$work/stderr"; exit 1; }
done
# Then to the end without a kill.
if [ "$done_" = 0 ]; then
  if [ -e "$work/killed/checkpoint.bin" ] || [ -e "$work/killed/checkpoint.bin.prev" ]; then
    "$rbcflow" resume "$work/killed" "${opts[@]}" > /dev/null 2>> "$work/stderr" || { cat "$work/stderr"; exit 1; }
  else
    "$rbcflow" run "$scene" --out "$work/killed" --overwrite "${opts[@]}" > /dev/null 2>> "$work/stderr" || { cat "$work/stderr"; exit 1; }
  fi
fi
resumed=$(grep -c 'resuming' "$work/stderr" || true)
echo "resumed $resumed times after SIGKILL"
[ "$resumed" -ge 2 ] || { echo "fewer than two kills fell after a checkpoint: the test tested little"; exit 1; }
grep 'warning' "$work/stderr" || true
for f in series.csv snapshots.dat membranes_final.dat profile.csv; do
  cmp "$work/straight/$f" "$work/killed/$f" || { echo "$f differs from the straight run's"; exit 1; }
done
python3 - "$work/straight/summary.json" "$work/killed/summary.json" <<'EOF'
import json, sys
a, b = (json.load(open(p)) for p in sys.argv[1:])
for clock in ("wall_seconds", "started", "ended", "command"):
    a.pop(clock, None); b.pop(clock, None)
if a != b:
    sys.exit("summary.json differs from the straight run's: " + str({k: (a.get(k), b.get(k)) for k in set(a) | set(b) if a.get(k) != b.get(k)}))
EOF
echo "killed and resumed: the same bits as the straight run"
