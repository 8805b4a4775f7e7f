#!/usr/bin/env bash
# ctest Scripts.NoEarlyExitReaderUnderPipefail: the project's shell scripts (most set
# pipefail, and the ones they source run under it) pipe into no reader that may exit before
# its input ends (grep -q, grep -m, head). When the reader exits first, the writer dies of
# SIGPIPE (status 141) and pipefail turns a match into a failure, depending on timing: CI's
# HIP check failed so on a loaded machine. Capture the output in a variable and match that.
set -u
cd "$(dirname "${BASH_SOURCE[0]}")/.." || exit 1
if git rev-parse --is-inside-work-tree > /dev/null 2>&1; then
  mapfile -t files < <(git ls-files '*.sh' '.ci/run')
else
  mapfile -t files < <(find . -path './build*' -prune -o \( -name '*.sh' -o -path './.ci/run' \) -type f -print)
fi
[ ${#files[@]} -gt 0 ] || { echo "FAIL: no shell scripts found"; exit 1; }
bad=0 checked=0
for f in "${files[@]}"; do
  [ "$f" = tests/early_exit_pipes_test.sh ] && continue  # its own pattern would match
  checked=$((checked + 1))
  # A pipe at a line's end continues on the next line: join them before matching.
  if hits=$(sed -e ':a' -e '/|[[:space:]]*$/{N;s/\n[[:space:]]*/ /;ba' -e '}' "$f" |
    grep -E '\|[[:space:]]*(grep[[:space:]]+(-[A-Za-z]*[qm]|--quiet|--max-count)|head\b)'); then
    echo "FAIL: $f pipes into an early-exit reader:"
    printf '  %s\n' "$hits"
    bad=1
  fi
done
echo "checked $checked scripts"
exit $bad
