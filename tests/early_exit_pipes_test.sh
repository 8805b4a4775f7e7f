#!/usr/bin/env bash
# ctest Scripts.NoEarlyExitReaderUnderPipefail: the project's shell scripts (most set
# pipefail, and the ones they source run under it) pipe into no reader that may exit before
# its input ends (grep -q / -m / -l, head, sed ...q). When the reader exits first, the writer
# dies of SIGPIPE (status 141) and pipefail turns a match into a failure, depending on timing:
# CI's HIP check failed so on a loaded machine. Capture the output in a variable and match that.
set -u
cd "$(dirname "${BASH_SOURCE[0]}")/.." || exit 1
self=tests/early_exit_pipes_test.sh
# The repository's own list when this is its work tree; else (a tarball) every script here.
if [ "$(git rev-parse --show-toplevel 2> /dev/null)" = "$PWD" ]; then
  mapfile -t files < <(git ls-files '*.sh' '.ci/run')
else
  mapfile -t files < <(find . -path './build*' -prune -o \( -name '*.sh' -o -path './.ci/run' \) -type f -print)
fi
[ ${#files[@]} -gt 0 ] || { echo "FAIL: no shell scripts found"; exit 1; }
# A pipe (not ||), optional VAR=value or `command` prefixes, then grep with -q/-m/-l/-L or
# their long forms among its options, head, or a sed script that quits.
reader='(^|[^|])\|&?[[:space:]]*(([A-Za-z_]+=[^[:space:]]*|command|env)[[:space:]]+)*'
reader+='(grep([[:space:]]+-[^[:space:]]*)*[[:space:]]+(-[A-Za-z]*[qmlL]|--quiet|--silent|--max-count|--files-with)'
reader+='|head\b|sed[[:space:]].*[0-9/$]q\b)'
bad=0 checked=0
for f in "${files[@]}"; do
  f=${f#./}
  [ "$f" = "$self" ] && continue  # its own pattern would match
  checked=$((checked + 1))
  # A pipe at a line's end continues on the next line: join them; comment lines are skipped.
  if hits=$(sed -e ':a' -e '/|[[:space:]]*$/{N;s/\n[[:space:]]*/ /;ba' -e '}' "$f" |
    grep -v '^[[:space:]]*#' | grep -E "$reader"); then
    echo "FAIL: $f pipes into an early-exit reader:"
    while IFS= read -r hit; do echo "  $hit"; done <<< "$hits"
    bad=1
  fi
done
echo "checked $checked scripts"
exit $bad
