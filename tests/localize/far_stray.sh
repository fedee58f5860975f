#!/usr/bin/env bash
# A floorplan with one stray 1 m segment 20 km from the building (real CAD files have such
# strays): `localize` must run in bounded memory (here under a 3 GB address-space limit; a grid
# over the bounding box would need 8 GB) and still track.
# Usage: far_stray.sh GLASSMAP SCENE WORK [KB]  (KB: address-space limit; 0 = none, for sanitizer
# builds, whose shadow memory needs terabytes of address space)
set -euo pipefail
glassmap=$1 scene=$2 work=$3 limit_kb=${4:-3000000}
rm -rf "$work"
mkdir -p "$work"
"$glassmap" simulate "$scene" -o "$work/sim" --seed 2 > /dev/null 2>&1
# The stray goes first in the feature list.
awk '{ print } /"features": \[/ && !done { print "{ \"type\": \"Feature\", \"properties\": { \"material\": \"wall\", \"thickness\": 0.1 }, \"geometry\": { \"type\": \"LineString\", \"coordinates\": [ [ 20000.0, 20000.0 ], [ 20001.0, 20000.0 ] ] } },"; done = 1 }' \
  "$work/sim/floorplan.geojson" > "$work/plan-with-stray.geojson"
grep -q 20000.0 "$work/plan-with-stray.geojson"
init=$(grep -v '^#' "$work/sim/groundtruth.tum" | awk 'NR == 1 { printf "%s,%s,%s", $2, $3, 2 * atan2($7, $8) }')
for model in field glass; do
  (if [ "$limit_kb" -gt 0 ]; then ulimit -v "$limit_kb"; fi; "$glassmap" localize --map "$work/plan-with-stray.geojson" "$work/sim/log.clf" \
     -o "$work/est-$model.tum" --model "$model" --particles 300 --init="$init" -q)
  "$glassmap" eval traj --truth "$work/sim/groundtruth.tum" "$work/est-$model.tum" --json "$work/ate-$model.json" > /dev/null
  python3 - "$work/ate-$model.json" "$model" <<'PY'
import json, sys
e = json.load(open(sys.argv[1]))
rmse = e.get("rmse", e.get("ate", {}).get("rmse") if isinstance(e.get("ate"), dict) else None)
assert rmse is not None, e
assert rmse < 0.05, f"{sys.argv[2]}: ATE rmse {rmse} m with a stray segment"
print(f"{sys.argv[2]}: tracks with a stray 20 km away, ATE rmse {rmse:.4f} m")
PY
done
echo "far-stray checks passed"
