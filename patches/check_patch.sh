#!/usr/bin/env bash
# Checks that mp-mvs's COLMAP patch still applies to a COLMAP source tree, without changing
# the tree. Fails loudly (exit 1, git's message naming the file and hunk) when COLMAP's code
# around the two edits has drifted, so the patch needs refreshing.
#
#   patches/check_patch.sh COLMAP_SRC        # a COLMAP checkout (git or plain source tree)
#   patches/check_patch.sh COLMAP_SRC TAG... # a COLMAP git clone: check each tag/commit
#                                            # (read from git, the work tree is not touched)
#
# The patch is picked per tree from COLMAP's own colmap.cc (see README.md):
#   colmap.cc uses COLMAP_MVS_ENABLED (4.1.x, development head)
#                                   -> colmap-4.1.x-head/colmap-mp_patch_match_stereo.patch
#   otherwise (3.12.x - 4.0.x)      -> colmap-mp_patch_match_stereo.patch
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
patch_old="colmap-mp_patch_match_stereo.patch"
patch_mvs_guard="colmap-4.1.x-head/colmap-mp_patch_match_stereo.patch"
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

# Every variant must touch exactly the two expected files. (Parsed from an empty folder:
# inside a git work tree's subfolder, git apply would skip paths outside that folder.)
for rel in "$patch_old" "$patch_mvs_guard"; do
  files="$(cd "$tmp" && git apply --numstat "$here/$rel" | cut -f3 | sort)"
  if [ "$files" != "$expected_files" ]; then
    echo "check_patch.sh: FAILED: $rel touches unexpected files:" >&2
    echo "$files" >&2
    exit 1
  fi
done

# 4.1 put COLMAP's MVS commands under `#if defined(COLMAP_MVS_ENABLED)`, which changed the
# context of both colmap.cc hunks; the marker says which variant fits.
pick_patch() {  # $1 = colmap.cc; prints the variant's path relative to patches/
  if grep -q 'COLMAP_MVS_ENABLED' "$1"; then
    echo "$patch_mvs_guard"
  else
    echo "$patch_old"
  fi
}

check_tree() {  # $1 = directory holding src/colmap/exe, $2 = label
  for f in src/colmap/exe/colmap.cc src/colmap/exe/CMakeLists.txt; do
    if [ ! -f "$1/$f" ]; then
      echo "check_patch.sh: FAILED for $2: $f does not exist (not a COLMAP >= 3.9 tree?)" >&2
      return 1
    fi
  done
  local rel patch
  rel="$(pick_patch "$1/src/colmap/exe/colmap.cc")"
  patch="$here/$rel"
  if grep -q 'mp_patch_match_stereo' "$1/src/colmap/exe/colmap.cc"; then
    echo "check_patch.sh: $2: the patch is already applied ($rel)"
    (cd "$1" && git apply --check --reverse "$patch") || {
      echo "check_patch.sh: FAILED for $2: mp_patch_match_stereo is registered but not by $rel" >&2
      return 1
    }
    return 0
  fi
  if ! (cd "$1" && git apply --check "$patch"); then
    echo "check_patch.sh: FAILED for $2: $rel does not apply; COLMAP's context has drifted." >&2
    echo "  Refresh patches/$rel against this version (see patches/README.md)." >&2
    return 1
  fi
  echo "check_patch.sh: OK for $2 with $rel (git apply --check)"
}

status=0
if [ $# -eq 0 ]; then
  label="$src"
  if git -C "$src" rev-parse --git-dir >/dev/null 2>&1; then
    label="$src ($(git -C "$src" describe --tags --always 2>/dev/null || echo unknown))"
  fi
  if check_tree "$src" "$label"; then
    if ! grep -q 'mp_patch_match_stereo' "$src/src/colmap/exe/colmap.cc"; then
      echo "  apply with: git -C \"$src\" apply \"$here/$(pick_patch "$src/src/colmap/exe/colmap.cc")\""
    fi
  else
    status=1
  fi
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
