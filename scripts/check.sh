#!/usr/bin/env bash
# What to run before committing (a minute or two, not CI's hour): on the C++ files changed since
# BASE (default HEAD, i.e. what is not committed yet, untracked files included)
#   1. the format check (scripts/format.sh --check; scripts/format.sh FILE... fixes it),
#   2. clang-tidy with the root .clang-tidy (a .h is checked through the .cpp beside it),
# then builds ./build and runs the unit tests of the fast layers and of the layers touched (see
# `layers` below). CI (.ci/run) runs everything, under the sanitizers too.
# Usage: scripts/check.sh [BASE]      e.g. scripts/check.sh main  (everything on this branch)
set -uo pipefail
cd "$(dirname "$0")/.."
base=${1:-HEAD}
status=0
export OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1

mapfile -t changed < <({ git diff --name-only --diff-filter=d "$base" -- '*.h' '*.cpp'
                         git ls-files --others --exclude-standard -- '*.h' '*.cpp'; } | sort -u)
echo "check: ${#changed[@]} changed C++ file(s) since $base"

if ((${#changed[@]})); then
  scripts/format.sh --check "${changed[@]}" || status=1
fi

[ -f build/compile_commands.json ] || cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
# clang-tidy reads a translation unit: a changed .cpp, or for a changed header the .cpp that
# implements it (<layer>/include/podium/<layer>/x.h -> <layer>/src/x.cpp).
units=()
for f in "${changed[@]}"; do
  case "$f" in
    *.cpp) units+=("$f") ;;
    *.h) for c in "${f%.h}.cpp" "$(echo "${f%.h}.cpp" | sed -E 's#/include/podium/[^/]+/#/src/#')"; do
           [ -f "$c" ] && units+=("$c") && break
         done ;;
  esac
done
if ((${#units[@]})); then
  mapfile -t units < <(printf '%s\n' "${units[@]}" | sort -u)
  # -Wno-unknown-warning-option: clang reads GCC's compile commands (-Wno-restrict is GCC's).
  tidy=$(printf '%s\n' "${units[@]}" |
    xargs -P "$(nproc)" -I{} clang-tidy -p build --quiet --extra-arg=-Wno-unknown-warning-option {} 2>/dev/null)
  # Only findings in this repository's files count: clang 14 in C++20 mode reports errors inside
  # libtorch's own headers (std::vector<c10::IValue> of an incomplete type, which GCC accepts);
  # the analysis of our code in those units still runs.
  ours=$(grep -E "^$PWD/[^:]+:[0-9]+:[0-9]+: (warning|error):" <<<"$tidy")
  if [ -n "$ours" ]; then echo "$ours"; status=1; fi
fi

cmake --build build -j "$(nproc)" || exit 1
# Unit tests of the layers that are fast (under a minute together) and of every layer a changed
# file belongs to (<layer>/... or tests/<layer>/...); learn, character, tasks, orchestrator and
# web_dashboard take minutes (training smoke runs, whole campaigns, a browser), so they run
# here only when touched, and always in CI.
layers=(base store search plugins sim)
for f in "${changed[@]}" $(git diff --name-only "$base"); do
  l=${f#tests/}; l=${l%%/*}
  [ -d "tests/$l" ] && [ -f "tests/$l/CMakeLists.txt" ] && layers+=("$l")
done
pick=$(printf '%s\n' "${layers[@]}" | sort -u | paste -sd'|')
ctest --test-dir build -L '^unit$' -L "^dir:($pick)\$" -j "$(nproc)" --output-on-failure || status=1

((status)) && echo "check: FAILED (see above)" >&2 || echo "check: ok"
exit "$status"
