#!/usr/bin/env bash
# Checks that mp-mvs's COLMAP patch still applies to a COLMAP source tree, without changing
# the tree. Fails loudly (exit 1, git's message naming the file and hunk) when COLMAP's code
# around the two edits has drifted, so the patch needs refreshing.
#
#   patches/check_patch.sh COLMAP_SRC        # a COLMAP checkout (git or plain source tree)
#   patches/check_patch.sh COLMAP_SRC TAG... # a COLMAP git clone: check each tag/commit
#                                            # (read from git, the work tree is not touched)
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
patch="$here/colmap-mp_patch_match_stereo.patch"
expected_files=$'src/colmap/exe/CMakeLists.txt\nsrc/colmap/exe/colmap.cc'

if [ $# -lt 1 ] || [ ! -d "$1" ]; then
  echo "usage: $0 COLMAP_SRC [TAG_OR_COMMIT...]" >&2
  exit 2
fi
src="$(cd "$1" && pwd)"
shift
command -v git >/dev/null || { echo "check_patch.sh: git is required" >&2; exit 2; }

tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT

# The patch must touch exactly the two expected files. (Parsed from an empty folder: inside a
# git work tree's subfolder, git apply would skip paths outside that folder.)
files="$(cd "$tmp" && git apply --numstat "$patch" | cut -f3 | sort)"
if [ "$files" != "$expected_files" ]; then
  echo "check_patch.sh: FAILED: the patch touches unexpected files:" >&2
  echo "$files" >&2
  exit 1
fi

check_tree() {  # $1 = directory holding src/colmap/exe, $2 = label
  for f in src/colmap/exe/colmap.cc src/colmap/exe/CMakeLists.txt; do
    if [ ! -f "$1/$f" ]; then
      echo "check_patch.sh: FAILED for $2: $f does not exist (not a COLMAP >= 3.9 tree?)" >&2
      return 1
    fi
  done
  if grep -q 'mp_patch_match_stereo' "$1/src/colmap/exe/colmap.cc"; then
    echo "check_patch.sh: $2: the patch is already applied"
    (cd "$1" && git apply --check --reverse "$patch") || {
      echo "check_patch.sh: FAILED for $2: mp_patch_match_stereo is registered but not by this patch" >&2
      return 1
    }
    return 0
  fi
  if ! (cd "$1" && git apply --check "$patch"); then
    echo "check_patch.sh: FAILED for $2: the patch does not apply; COLMAP's context has drifted." >&2
    echo "  Refresh patches/colmap-mp_patch_match_stereo.patch against this version (see patches/README.md)." >&2
    return 1
  fi
  echo "check_patch.sh: OK for $2 (git apply --check)"
}

status=0
if [ $# -eq 0 ]; then
  label="$src"
  if git -C "$src" rev-parse --git-dir >/dev/null 2>&1; then
    label="$src ($(git -C "$src" describe --tags --always 2>/dev/null || echo unknown))"
  fi
  check_tree "$src" "$label" || status=1
else
  for rev in "$@"; do
    rm -rf "$tmp/tree" && mkdir -p "$tmp/tree/src/colmap/exe"
    ok=1
    for f in src/colmap/exe/colmap.cc src/colmap/exe/CMakeLists.txt; do
      git -C "$src" show "$rev:$f" > "$tmp/tree/$f" 2>/dev/null || ok=0
    done
    if [ $ok -eq 0 ]; then
      echo "check_patch.sh: FAILED for $rev: cannot read src/colmap/exe/{colmap.cc,CMakeLists.txt} at that revision" >&2
      status=1
      continue
    fi
    check_tree "$tmp/tree" "COLMAP $rev" || status=1
  done
fi
exit $status
