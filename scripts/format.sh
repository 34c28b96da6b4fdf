#!/usr/bin/env bash
# Formats the C++ sources with the root .clang-format (clang-format 14, as Debian 12 ships it).
# Usage: scripts/format.sh [--check] [FILE...]
#   no FILE: every tracked *.h and *.cpp (except the paths `excluded` matches below)
#   --check: change nothing; list the files whose format differs and exit 1 if there is any
# CLANG_FORMAT names another binary (e.g. clang-format-14 beside a newer default).
set -euo pipefail
cd "$(dirname "$0")/.."

# Paths never formatted (an extended regex over repository paths): generated or vendored C++
# goes here. Nothing tracked is either today; test data is listed in case a fixture is a source file
# compared byte for byte.
excluded='(^|/)testdata/'

check=0
if [ "${1:-}" = "--check" ]; then check=1; shift; fi
cf=${CLANG_FORMAT:-clang-format}
command -v "$cf" >/dev/null || { echo "format.sh: $cf not found (scripts/setup.sh installs clang-format)" >&2; exit 2; }
# Another major version formats some constructs differently, so a check would flag files that are fine.
major=$("$cf" --version | sed -nE 's/.*version ([0-9]+)\..*/\1/p')
[ "$major" = 14 ] || { echo "format.sh: $cf is version ${major:-unknown}; the format is defined by clang-format 14 (set CLANG_FORMAT)" >&2; exit 2; }

if (($#)); then
  files=()
  for f in "$@"; do
    case "$f" in *.h|*.cpp) [ -f "$f" ] && ! [[ "$f" =~ $excluded ]] && files+=("$f") ;; esac
  done
else
  mapfile -t files < <(git ls-files -- '*.h' '*.cpp' | grep -Ev "$excluded")
fi
((${#files[@]})) || exit 0

if ((check)); then
  # Each differing file printed once; clang-format's own exit status says nothing about differences.
  differ=$(printf '%s\0' "${files[@]}" |
    xargs -0 -n 8 -P "$(nproc)" sh -c 'for f; do "$0" --style=file "$f" | cmp -s - "$f" || echo "$f"; done' "$cf" | sort)
  if [ -n "$differ" ]; then
    echo "$differ"
    echo "format.sh: $(echo "$differ" | wc -l) file(s) differ from .clang-format; run scripts/format.sh to fix" >&2
    exit 1
  fi
else
  printf '%s\0' "${files[@]}" | xargs -0 -n 8 -P "$(nproc)" "$cf" --style=file -i
fi
