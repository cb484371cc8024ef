#!/usr/bin/env bash
# Every experiment README lists exactly the options its program takes: the long options of the
# fenced block under "## How to run" against those of the program's --help. Every experiment also
# takes the options a pool needs (--only, --list-cases, --threads, --version).
#   tests/readme_flags.sh SOURCE_DIR BUILD_DIR
set -euo pipefail
src=$1; build=$2
status=0; checked=0
for readme in "$src"/experiments/*/README.md; do
  exp=$(basename "$(dirname "$readme")")
  prog="$build/bin/$exp"
  [ -x "$prog" ] || { echo "$exp: no program $prog (build first)"; status=1; continue; }
  checked=$((checked + 1))
  documented=$(awk '/^## How to run/ {on = 1; next} on && /^## / {exit} on && /^```/ {block = !block; next}
                    on && block && /^ *--[a-z]/ {print $1}' "$readme" | sort -u)
  taken=$("$prog" --help | grep -oE '(^|[ ,])--[a-z][a-z0-9-]*' | sed 's/^[ ,]*//' | sort -u)
  if [ "$documented" != "$taken" ]; then
    echo "$exp: README.md's options differ from $exp --help:"
    diff <(echo "$documented") <(echo "$taken") | sed -n 's/^</  only in README:/p; s/^>/  only in --help:/p'  || true
    status=1
  fi
  for needed in --only --list-cases --threads --version; do
    grep -qx -- "$needed" <<< "$taken" || { echo "$exp: takes no $needed"; status=1; }
  done
done
[ "$checked" -ge 6 ] || { echo "only $checked experiments checked (six expected)"; status=1; }
[ "$status" = 0 ] && echo "every experiment README lists its program's options ($checked programs)"
exit "$status"
