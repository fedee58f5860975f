#!/usr/bin/env bash
# Speed-against-accuracy bench (issue 8): drives build/tools/glassmap over seeds, writes CSV + charts.
#   tools/bench.sh --quick                 # CI-sized, a few minutes -> build-bench-quick/
#   tools/bench.sh                         # full mode -> docs/results/ (logs cached in docs/results/work, not committed)
#   tools/bench.sh --sections loc --seeds 3 --out out/r --glassmap build-rel/tools/glassmap
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
py=python3
# Charts need matplotlib (Debian python3-matplotlib); a pyenv python3 on PATH may lack it.
if ! "$py" -c 'import matplotlib, yaml' 2>/dev/null && [ -x /usr/bin/python3 ]; then py=/usr/bin/python3; fi
exec "$py" "$here/bench/sweep" "$@"
