#!/usr/bin/env bash
# Records rows' u_num measured from kept evidence runs (paper/evidence/data/, paper/keep_evidence.sh)
# in reference-data/uncertainty/, beside the rows make evidence recorded:
#
#   paper/record_kept_uncertainty.sh EXPERIMENT ROW... -- CASE...
#
# puts the kept cases CASE... (names or shell patterns under paper/evidence/data/EXPERIMENT/) in a
# scratch folder, reads them back ($BUILD/bin/EXPERIMENT --collect --check, BUILD default build:
# the rows whose u_num is complete go to its uncertainty.csv) and replaces each ROW of
# reference-data/uncertainty/EXPERIMENT.csv by the measured one, with the commit and the code that
# the kept cases name (one code: a row does not mix the runs of two codes). A row that the kept
# cases leave incomplete is an error, and the record stays as it was. Where the kept cases have no
# 2h run, the h column is carried over from the row replaced, and the row's source says so; a row
# the record does not hold yet is added at its end.
# Exit status: 0; 2 on bad use, an incomplete row, or cases of more than one code.
set -euo pipefail
cd "$(dirname "$0")/.."
usage() { echo "usage: $0 EXPERIMENT ROW... -- CASE..." >&2; exit 2; }
[ $# -ge 4 ] || usage
exp=$1; shift
rows=()
while [ $# -gt 0 ] && [ "$1" != -- ]; do rows+=("$1"); shift; done
[ $# -ge 2 ] && [ ${#rows[@]} -ge 1 ] || usage
shift
kept=paper/evidence/data/$exp
bin=${BUILD:-build}/bin/$exp
record=reference-data/uncertainty/$exp.csv
[ -d "$kept" ] || { echo "record_kept_uncertainty: no kept runs in $kept" >&2; exit 2; }
[ -x "$bin" ] || { echo "record_kept_uncertainty: $bin missing: build it first (make build-runs)" >&2; exit 2; }
[ -f "$record" ] || { echo "record_kept_uncertainty: $record missing" >&2; exit 2; }

scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
mkdir -p "$scratch/$exp"
cases=()
for pattern in "$@"; do
  matched=0
  for dir in "$kept"/$pattern/; do
    [ -f "$dir/summary.json" ] || continue
    [ -f "$dir/code_id" ] || { echo "record_kept_uncertainty: $dir has no code_id: which code made it?" >&2; exit 2; }
    cp -r "$dir" "$scratch/$exp/"
    cases+=("$(basename "$dir")")
    matched=1
  done
  [ "$matched" = 1 ] || { echo "record_kept_uncertainty: no kept case matches $kept/$pattern" >&2; exit 2; }
done
codes=$(for c in "${cases[@]}"; do head -n 2 "$kept/$c/code_id" | paste -sd' '; done | sort -u)
if [ "$(wc -l <<< "$codes")" -ne 1 ]; then
  echo "record_kept_uncertainty: the cases were made by more than one code (code commit):" >&2
  echo "$codes" >&2; exit 2
fi
code=${codes%% *} commit=${codes#* }
[ "$commit" != "$code" ] || commit=unknown

rc=0
"$bin" --out "$scratch/$exp" --collect --check > "$scratch/collect.log" 2>&1 || rc=$?
if [ "$rc" -gt 1 ]; then
  cat "$scratch/collect.log" >&2; echo "record_kept_uncertainty: $bin --collect exited $rc" >&2; exit 2
fi
measured=$scratch/$exp/uncertainty.csv
[ -f "$measured" ] || { echo "record_kept_uncertainty: $bin wrote no $measured" >&2; exit 2; }

source_text="measured from the kept runs $(printf '%s ' "${cases[@]}" | sed 's/ $//') (paper/evidence/data/$exp, paper/record_kept_uncertainty.sh)"
python3 - "$record" "$measured" "$commit" "$code" "$source_text" "${rows[@]}" <<'EOF'
import csv, sys
record_path, measured_path, commit, code, source = sys.argv[1:6]
wanted = sys.argv[6:]
with open(record_path, newline='', encoding='utf-8') as f:
    record = list(csv.DictReader(f))
    header = list(record[0].keys()) if record else None
with open(measured_path, newline='', encoding='utf-8') as f:
    measured = {r['id']: r for r in csv.DictReader(f)}
header = header or list(next(iter(measured.values())).keys())
old = {r['id']: r for r in record}
for row in wanted:
    if row not in measured:
        print(f"record_kept_uncertainty: row {row}: its u_num is not complete from these kept runs "
              f"(the rows that are: {' '.join(sorted(measured)) or 'none'})", file=sys.stderr)
        sys.exit(2)
for row in wanted:
    new = dict(measured[row])
    new['source'], new['commit'], new['code'] = source, commit, code
    if not new['converged_in_h'] and row in old and old[row]['converged_in_h']:
        new['converged_in_h'] = old[row]['converged_in_h']
        new['source'] += (f"; the h column carried over from the record of commit {old[row]['commit']} "
                          f"(code {old[row]['code']}): these runs have no 2h run")
    if row in old:
        record[[r['id'] for r in record].index(row)] = new
    else:
        record.append(new)
    print(f"record_kept_uncertainty: {row} recorded in {record_path} (commit {commit}, code {code})")
with open(record_path, 'w', newline='', encoding='utf-8') as f:
    w = csv.DictWriter(f, fieldnames=header, lineterminator='\n')
    w.writeheader()
    w.writerows(record)
EOF
