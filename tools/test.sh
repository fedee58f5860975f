#!/usr/bin/env bash
# Sets up (packages + build) and runs the whole test suite through CTest.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build_dir=${GLASSMAP_BUILD_DIR:-$here/build}
"$here/tools/setup.sh" "$@"
cd "$build_dir"
ctest --output-on-failure -j "$(nproc 2>/dev/null || echo 2)"
