#!/usr/bin/env bash
# Sets up (packages + build) and runs the whole test suite through CTest.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build_dir=${GLASSMAP_BUILD_DIR:-$here/build}
"$here/tools/setup.sh" "$@"
cd "$build_dir"
# Sanitizer builds: third-party process-lifetime caches are not leaks of ours.
export LSAN_OPTIONS="${LSAN_OPTIONS:-suppressions=$here/tests/lsan.supp}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
ctest --output-on-failure -j "$(nproc 2>/dev/null || echo 2)"
