#!/usr/bin/env bash
# glassmap map on a real log with its defaults, then eval rays of the plan against the same log:
# the plan explains at least MIN_NEAR of the returns under 8 m within 0.10 m of a segment (walls,
# panes and clutter lines) with at most MAX_SEGMENTS segments (issue 15's goal: >= 0.85 with no
# more segments than the plans had before the clutter lines were chosen from the returns).
# Usage: real_log_plan.sh GLASSMAP LOG MIN_NEAR MAX_SEGMENTS
set -euo pipefail
glassmap=$1 log=$2 min_near=$3 max_segments=$4
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$glassmap" map "$log" -o "$work/map" -q
"$glassmap" eval rays --plan "$work/map/floorplan.gpkg" "$log" --json "$work/rays.json" -q
python3 - "$work/rays.json" "$min_near" "$max_segments" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
min_near, max_segments = float(sys.argv[2]), int(sys.argv[3])
print(f"near a segment {r['near_share']:.3f} (>= {min_near}), first surface {r['explained_share']:.3f}, "
      f"{r['segments']} segments (<= {max_segments})")
if r["near_share"] < min_near or r["segments"] > max_segments or r["returns"] == 0:
    sys.exit("FAIL: the plan does not explain enough of its log's returns, or has too many segments")
PY
echo "real log plan checks passed"
