#!/usr/bin/env bash
# A floorplan in a building's projected CRS through the command line, as a GIS sees it: GDAL's
# ogrinfo reads the GPKG's CRS (EPSG:25832) and the wall where --origin puts it, to a millimetre,
# at coordinates of 10^6 m; glassmap reads the GPKG and the GeoJSON back in the map frame (eval
# segments finds the plan again), a DXF needs --input-origin; a bare rotation is refused.
# Usage: georef_cli.sh GLASSMAP WORK_DIR   (skips when ogrinfo is missing)
set -uo pipefail
glassmap=$1 work=$2
if ! command -v ogrinfo >/dev/null; then
  echo "ogrinfo missing: skipped"
  exit 0
fi
rm -rf "$work"
mkdir -p "$work"
fail=0
check() {  # check NAME CONDITION...
  local name=$1
  shift
  if "$@"; then echo "ok   $name"; else echo "FAIL $name"; fail=1; fi
}
near() { awk -v a="$1" -v b="$2" -v t="$3" 'BEGIN { d = a - b; if (d < 0) d = -d; exit !(d <= t) }'; }

# A 12 m wall from (0, 0) along x and a 5 m glass pane from (12, 0) along y, in the map frame.
cat >"$work/plan.geojson" <<'JSON'
{"type": "FeatureCollection", "description": "glassmap floorplan: local metres", "features": [
{"type": "Feature", "properties": {"material": "wall", "thickness": 0.15},
 "geometry": {"type": "LineString", "coordinates": [[0, 0], [12, 0]]}},
{"type": "Feature", "properties": {"material": "glass", "thickness": 0.01},
 "geometry": {"type": "LineString", "coordinates": [[12, 0], [12, 5]]}}]}
JSON
E=691234.567 N=5334567.891
origin="$E,$N,30deg"
"$glassmap" export "$work/plan.geojson" "$work/plan.gpkg" --crs EPSG:25832 --origin "$origin" >"$work/out.txt" 2>&1
check "export --crs --origin exits 0" test $? -eq 0
check "summary names the origin" grep -q "map frame origin at E 691234.567 N 5334567.891, x axis 30.000000 deg" "$work/out.txt"
ogrinfo -ro -al "$work/plan.gpkg" floorplan >"$work/ogr.txt" 2>&1
check "ogrinfo: EPSG 25832" grep -q 'ID\["EPSG",25832\]' "$work/ogr.txt"
# The wall's far end (12, 0) lies at E + 12 cos 30, N + 12 sin 30.
read -r x1 y1 x2 y2 < <(grep -m1 -o 'LINESTRING ([^)]*)' "$work/ogr.txt" | tr -d 'LINESTRG()' | tr ',' ' ' | tr -s ' ' '\n' | grep . | tr '\n' ' ')
check "ogrinfo: wall starts at the origin (1 mm)" near "$x1" "$E" 0.001
check "ogrinfo: ... northing (1 mm)" near "$y1" "$N" 0.001
check "ogrinfo: wall ends 12 m at 30 deg (1 mm)" near "$x2" "$(awk -v e="$E" 'BEGIN { printf "%.6f", e + 12 * cos(atan2(1, 1) * 4 / 6) }')" 0.001
check "ogrinfo: ... northing (1 mm)" near "$y2" "$(awk -v n="$N" 'BEGIN { printf "%.6f", n + 6 }')" 0.001

"$glassmap" eval segments --truth "$work/plan.geojson" --pred "$work/plan.gpkg" --tol 0.001 -q --json "$work/e1.json"
check "the GPKG reads back in the map frame" grep -q '"f1": 1.0' "$work/e1.json"
"$glassmap" export "$work/plan.gpkg" "$work/again.geojson" --crs EPSG:25832 --origin "$origin" -q
"$glassmap" eval segments --truth "$work/plan.geojson" --pred "$work/again.geojson" --tol 0.001 -q --json "$work/e2.json"
check "GPKG -> georeferenced GeoJSON reads back in the map frame" grep -q '"f1": 1.0' "$work/e2.json"
check "GeoJSON names its CRS" grep -q 'EPSG::25832' "$work/again.geojson"
"$glassmap" export "$work/plan.gpkg" "$work/plan.dxf" --crs EPSG:25832 --origin "$origin" -q
"$glassmap" export "$work/plan.dxf" "$work/back.gpkg" --input-origin "$origin" -q
"$glassmap" eval segments --truth "$work/plan.geojson" --pred "$work/back.gpkg" --tol 0.001 -q --json "$work/e3.json"
check "DXF in building coordinates, back with --input-origin" grep -q '"f1": 1.0' "$work/e3.json"

"$glassmap" export "$work/plan.geojson" "$work/bad.gpkg" --crs EPSG:25832 --origin "$E,$N,30" >/dev/null 2>"$work/bad.txt"
check "a bare rotation is refused" test $? -ne 0
check "... naming both units" grep -q "needs its unit: 30deg or 30rad" "$work/bad.txt"
check "... and writes nothing" test ! -e "$work/bad.gpkg"
"$glassmap" export "$work/plan.geojson" "$work/bad.gpkg" --crs EPSG:25832 >/dev/null 2>&1
check "--crs without --origin is refused" test $? -ne 0

if [ $fail -eq 0 ]; then echo "all georef cli checks passed"; fi
exit $fail
