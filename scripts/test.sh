#!/usr/bin/env bash
# Set-up, build with warnings as errors, and run every test through CTest.
#   bash scripts/test.sh             the normal build (build/test)
#   bash scripts/test.sh --sanitize  the same tests under AddressSanitizer + UndefinedBehaviorSanitizer (build/asan)
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh

build_dir=build/test
options=(-DCMAKE_BUILD_TYPE=RelWithDebInfo -DSOFTWRIST_WERROR=ON)
if [ "${1:-}" = "--sanitize" ]; then
  build_dir=build/asan
  options+=(-DSOFTWRIST_SANITIZE=ON)
  export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1
  export LSAN_OPTIONS="suppressions=$PWD/tests/lsan.supp:print_suppressions=0"  # Mesa's own leaks only
  export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
elif [ -n "${1:-}" ]; then
  echo "usage: $0 [--sanitize]" >&2
  exit 2
fi

cmake -S . -B "$build_dir" "${options[@]}" >/dev/null
cmake --build "$build_dir" -j2
ctest --test-dir "$build_dir" -j2 --output-on-failure
