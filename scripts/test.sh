#!/usr/bin/env bash
# Set-up, the style checks (clang-format, no function over 80 lines), build with warnings as errors, and run every
# test through CTest.
#   bash scripts/test.sh             the normal build (build/test)
#   bash scripts/test.sh --sanitize  the same tests under AddressSanitizer + UndefinedBehaviorSanitizer (build/asan)
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh --tests

build_dir=build/test
# Line tables only (-g1), as the instrumented builds: a failure's stack trace still names file and line, and the
# build is shorter (CI's time, docs/ci.md).
options=(-DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O2 -g1 -DNDEBUG" -DSOFTWRIST_WERROR=ON)
if [ "${1:-}" = "--sanitize" ]; then
  build_dir=build/asan
  # Clang 14, where the normal build is GCC 12: a second compiler's warnings, as errors, over the same code, and
  # clang's UBSan caught what GCC's did not (a member named in a delegating constructor, bridge_plant.cc). It builds
  # this tree in about three quarters of GCC's time (docs/ci.md).
  options+=(-DSOFTWRIST_SANITIZE=ON -DCMAKE_C_COMPILER=clang-14 -DCMAKE_CXX_COMPILER=clang++-14)
  # A tree configured with another compiler is configured afresh (CMake cannot switch a cache's compiler).
  cache=$build_dir/CMakeCache.txt
  if [ -f "$cache" ] && ! grep -q "^CMAKE_CXX_COMPILER:.*clang++-14" "$cache"; then rm -rf "$build_dir"; fi
  # intercept_tls_get_addr=0: the sanitizer runtime (seen with GCC 12's, before this build was clang's) can take a
  # malloc'd dynamic-TLS block for a pre-glibc-2.25 header by its address alone, and LeakSanitizer's tracer then
  # segfaults at exit ("Tracer caught signal 11") after a passing test: seen once in CI on a test that ran worker
  # threads. The flag only stops that interception; leaks are still checked.
  export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:intercept_tls_get_addr=0
  export LSAN_OPTIONS="suppressions=$PWD/tests/lsan.supp:print_suppressions=0"  # Mesa's own leaks only
  export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
elif [ -n "${1:-}" ]; then
  echo "usage: $0 [--sanitize]" >&2
  exit 2
fi

bash scripts/check_format.sh
python3 scripts/check_function_length.py --max 80 src plugins firmware

cmake -S . -B "$build_dir" "${options[@]}" >/dev/null
cmake --build "$build_dir" -j2
ctest --test-dir "$build_dir" -j2 --output-on-failure
