#!/usr/bin/env bash
# Builds the fuzz targets (tests/fuzz/) with clang-14: libFuzzer, AddressSanitizer and UndefinedBehaviorSanitizer, in
# build/fuzz, and runs each target for a time or a number of runs, one after the other. Prints the executions and
# the crashes of each target and writes build/fuzz/report.json; exits 1 when any target crashed.
#   bash scripts/fuzz.sh [--seconds S | --runs N] [TARGET...]     (default: 60 s each, every target)
# The seed corpus (tests/fuzz/corpus/TARGET) is only read; what the fuzzer adds goes to build/fuzz/corpus/TARGET and
# is kept between runs. A crashing input is saved to build/fuzz/crashes/TARGET/ (cleared at the next run): copy it to
# tests/fuzz/regressions/TARGET/ so that the tests replay it, and fix the code (tests/fuzz/README.md).
set -euo pipefail
cd "$(dirname "$0")/.."
limit=(-max_total_time=60)
targets=()
while (($#)); do
  case "$1" in
    --seconds) limit=(-max_total_time="$2"); shift 2 ;;
    --runs) limit=(-runs="$2"); shift 2 ;;
    -h|--help) sed -n 2,9p "$0"; exit 0 ;;
    -*) echo "fuzz.sh: unknown option $1" >&2; exit 2 ;;
    *) targets+=("$1"); shift ;;
  esac
done
all=(placement experiment_config plugin_config csv_import host_protocol device_protocol)
if ((${#targets[@]} == 0)); then targets=("${all[@]}"); fi
for target in "${targets[@]}"; do
  [[ " ${all[*]} " == *" $target "* ]] || { echo "fuzz.sh: no target '$target' (targets: ${all[*]})" >&2; exit 2; }
done

bash scripts/setup.sh --tests
build=build/fuzz
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSOFTWRIST_FUZZ=ON \
  -DCMAKE_C_COMPILER=clang-14 -DCMAKE_CXX_COMPILER=clang++-14 >/dev/null
cmake --build "$build" -j2 --target $(printf '%s_fuzz ' "${targets[@]}")

export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:intercept_tls_get_addr=0
export LSAN_OPTIONS="suppressions=$PWD/tests/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
failed=0
report="["
printf '%-18s %12s %10s %8s %s\n' target executions exec/s crashes seconds
for target in "${targets[@]}"; do
  corpus="$build/corpus/$target" crashes="$build/crashes/$target" log="$build/logs/$target.log"
  rm -rf "$crashes"  # the last run's; the ones worth keeping are in tests/fuzz/regressions
  mkdir -p "$corpus" "$crashes" "$(dirname "$log")"
  start=$(date +%s.%N)
  status=0
  "$build/tests/fuzz/${target}_fuzz" "${limit[@]}" -print_final_stats=1 -max_len=4096 -timeout=20 -rss_limit_mb=4096 \
    -artifact_prefix="$crashes/" "$corpus" "tests/fuzz/corpus/$target" >"$log" 2>&1 || status=$?
  seconds=$(echo "$(date +%s.%N) - $start" | bc)
  executions=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -1)
  crash_count=$(find "$crashes" -type f | wc -l)
  if ((status != 0)) || ((crash_count > 0)); then
    failed=1
    echo "fuzz.sh: $target failed (exit $status); its log: $log" >&2
    grep -m 20 -E "ERROR|invariant broken|SUMMARY|Test unit written" "$log" >&2 || true
  fi
  printf '%-18s %12s %10s %8s %.0f\n' "$target" "${executions:-?}" "${rate:-?}" "$crash_count" "$seconds"
  report+=$(printf '%s{"target": "%s", "executions": %s, "exec_per_s": %s, "crashes": %s, "exit": %s, "seconds": %.1f}' \
    "$([ "$report" = "[" ] || echo ", ")" "$target" "${executions:-null}" "${rate:-null}" "$crash_count" "$status" "$seconds")
done
echo "$report]" > "$build/report.json"
exit $failed
