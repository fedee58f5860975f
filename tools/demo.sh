#!/usr/bin/env bash
# Sets up (packages + build) and runs the main job on a bundled scene:
# simulate a log in maps/<scene>, map the glass, vectorize, localize against the floorplan, evaluate.
# Usage: tools/demo.sh [scene] [outdir]   (defaults: paper-corridor, out/demo)
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
scene=${1:-paper-corridor}
out=${2:-$here/out/demo}
"$here/tools/setup.sh"
gm="${GLASSMAP_BUILD_DIR:-$here/build}/tools/glassmap"
has() { "$gm" "$1" --help >/dev/null 2>&1; }

echo "== simulate $scene" >&2
"$gm" simulate "$here/maps/$scene/scene.yaml" -o "$out/sim" --seed 1
"$gm" info "$out/sim/log.clf"
"$gm" render "$out/sim/floorplan.geojson" --log "$out/sim/log.clf" --outcomes "$out/sim/outcomes.bin" \
  -o "$out/sim/scene.png"
if has map; then
  echo "== map" >&2
  "$gm" map "$out/sim/log.clf" -o "$out/map"
  "$gm" eval cells --truth "$out/sim/floorplan.gpkg" --labels "$out/map/labels.tif"
  if [ -f "$out/map/floorplan.gpkg" ]; then
    "$gm" eval segments --truth "$out/sim/floorplan.gpkg" --pred "$out/map/floorplan.gpkg"
  fi
fi
if has localize; then
  echo "== localize" >&2
  "$gm" localize --map "$out/sim/floorplan.gpkg" "$out/sim/log.clf" -o "$out/loc/estimate.tum" \
    --init "$(python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["start_init"])' "$out/sim/meta.json")"
  "$gm" eval traj --truth "$out/sim/groundtruth.tum" "$out/loc/estimate.tum"
fi
echo "== converting the true floorplan to CAD/GIS formats" >&2
mkdir -p "$out/convert"
for ext in dxf gpkg shp fgb; do
  "$gm" convert "$out/sim/floorplan.geojson" "$out/convert/floorplan.$ext"
done
echo "outputs in $out" >&2
