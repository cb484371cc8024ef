#!/usr/bin/env sh
# The code id of the source tree, "<code> <commit>": the one definition of "the code that made a
# result" (the build bakes it into every program, build/bin/rbcflow --version; paper/make_report.sh
# names results by it). code: the first 12 hex digits of the hash of the committed sources that
# make the numbers (the .cpp, .hpp and .toml files of lib/ and experiments/, and CMakeLists.txt;
# not the documents, plot scripts or tests), followed by "-" and 8 digits of the hash of their
# uncommitted changes where there are any. commit: the short commit. Outside a git checkout:
# "unknown unknown".
cd "$(dirname "$0")/.." || exit 1
if ! git rev-parse --git-dir >/dev/null 2>&1; then echo "unknown unknown"; exit 0; fi
code=$(git ls-tree -r HEAD -- lib experiments CMakeLists.txt 2>/dev/null | grep -E "$(printf '(\\.[ch]pp|\\.toml|\tCMakeLists\\.txt)$')" | git hash-object --stdin | cut -c1-12)
numeric=':(glob)lib/**/*.[ch]pp :(glob)experiments/**/*.[ch]pp :(glob)experiments/**/*.toml CMakeLists.txt'
# shellcheck disable=SC2086
if [ -n "$(git status --porcelain -- $numeric 2>/dev/null)" ]; then
  # shellcheck disable=SC2086
  code="$code-$( (git diff HEAD -- $numeric; git ls-files --others --exclude-standard -- $numeric | xargs -r cat) | git hash-object --stdin | cut -c1-8)"
fi
echo "$code $(git rev-parse --short HEAD 2>/dev/null || echo unknown)"
