#!/usr/bin/env bash
# Builds the libFuzzer targets of the readers (tests/fuzz) with clang + ASan + UBSan in build-fuzz
# and runs each for a number of executions on its seed corpus (tests/data/fuzz/<target>/).
#
#   tools/fuzz.sh [-n RUNS] [-t MAX_SECONDS] [-j JOBS] [target ...]
#
# RUNS defaults to 1000000 executions per target, MAX_SECONDS (a safety bound per target) to 600.
# Targets: fuzz_carmen fuzz_tum fuzz_rosmap fuzz_floorplan_geojson fuzz_floorplan_dxf fuzz_mcap fuzz_ros2_log
# (default: all).
# New coverage-increasing inputs go to build-fuzz/corpus/<target>/ (the committed seeds stay as
# they are); crashes, leaks, timeouts and out-of-memory inputs to build-fuzz/artifacts/<target>/.
# Exit status: 0 when every target finished clean, 1 when any found something.
set -euo pipefail

runs=1000000
max_time=600
jobs=2
while getopts "n:t:j:h" opt; do
  case $opt in
    n) runs=$OPTARG ;;
    t) max_time=$OPTARG ;;
    j) jobs=$OPTARG ;;
    *) sed -n '2,14p' "$0"; exit 2 ;;
  esac
done
shift $((OPTIND - 1))
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
  targets=(fuzz_carmen fuzz_tum fuzz_rosmap fuzz_floorplan_geojson fuzz_floorplan_dxf fuzz_mcap fuzz_ros2_log)
fi

root=$(cd "$(dirname "$0")/.." && pwd)
build=$root/build-fuzz
flags="-fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer -g"

CC=clang CXX=clang++ cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DGLASSMAP_BUILD_FUZZERS=ON -DGLASSMAP_BUILD_BENCHMARKS=OFF -DGLASSMAP_WERROR=OFF \
  -DCMAKE_C_FLAGS="$flags" -DCMAKE_CXX_FLAGS="$flags" >/dev/null
cmake --build "$build" -j "$jobs" --target "${targets[@]}"

# Leak checking stays on (libFuzzer's -detect_leaks=1 default); UBSan reports abort the run.
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1}

status=0
summary=()
for t in "${targets[@]}"; do
  seeds=$root/tests/data/fuzz/$t
  corpus=$build/corpus/$t
  artifacts=$build/artifacts/$t
  mkdir -p "$corpus" "$artifacts"
  log=$build/$t.log
  echo "== $t: up to $runs executions, at most ${max_time}s"
  set +e
  "$build/tests/fuzz/$t" -runs="$runs" -max_total_time="$max_time" -timeout=10 -rss_limit_mb=2048 \
    -max_len=65536 -print_final_stats=1 -artifact_prefix="$artifacts/" "$corpus" "$seeds" >"$log" 2>&1
  rc=$?
  set -e
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  secs=$(sed -n 's/^stat::.*//; s/^Done \([0-9]*\) runs in \([0-9]*\) second.*/\2/p' "$log" | tail -1)
  found=$(ls -A "$artifacts" | wc -l)
  if [ "$rc" -ne 0 ] || [ "$found" -ne 0 ]; then
    status=1
    echo "   FOUND: exit $rc, artifacts in $artifacts:"; ls "$artifacts" | sed 's/^/     /'
    grep -m3 -E "ERROR: |runtime error|SUMMARY" "$log" | sed 's/^/     /' || true
  fi
  summary+=("$(printf '%-24s %12s executions %6ss  exit %s  artifacts %s' "$t" "${execs:-?}" "${secs:-?}" "$rc" "$found")")
done
echo
echo "fuzz summary (log per target in $build/<target>.log):"
printf '%s\n' "${summary[@]}"
exit $status
