#!/usr/bin/env bash
# Sets up (packages + build) and runs the whole test suite through CTest.
# GLASSMAP_SKIP_HEAVY=1 leaves out the long end-to-end tests listed in tests/heavy_tests.txt
# (for the whole suite run sanitized by hand, see .ci/run; the Release suite runs them all).
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build_dir=${GLASSMAP_BUILD_DIR:-$here/build}
"$here/tools/setup.sh" "$@"
cd "$build_dir"
# Sanitizer builds: third-party process-lifetime caches are not leaks of ours.
export LSAN_OPTIONS="${LSAN_OPTIONS:-suppressions=$here/tests/lsan.supp}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
exclude=()
if [ "${GLASSMAP_SKIP_HEAVY:-0}" = 1 ]; then
  regex=$(grep -v '^#' "$here/tests/heavy_tests.txt" | grep -v '^$' | paste -sd'|')
  exclude=(-E "$regex")
  echo "test.sh: leaving out the tests of tests/heavy_tests.txt" >&2
fi
ctest --output-on-failure -j "$(nproc 2>/dev/null || echo 2)" "${exclude[@]}"
