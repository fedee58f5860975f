#!/usr/bin/env bash
# A DXF written with GDAL's default header ($INSUNITS 1 = inches) of a plan drawn in metres: read
# as declared, the 29 x 19 m corridor becomes 0.7 x 0.5 m. `export` warns and names --units;
# `localize` refuses (a run against it would be a confident wrong answer) until --units is given,
# and refuses an initial pose outside the plan. Usage: plan_units.sh GLASSMAP SCENE WORK
set -uo pipefail
glassmap=$1 scene=$2 work=$3
rm -rf "$work"
mkdir -p "$work"
fail=0
check() {
  local name=$1
  shift
  if "$@"; then echo "ok   $name"; else echo "FAIL $name"; fail=1; fi
}
"$glassmap" simulate "$scene" -o "$work/sim" --seed 4 > /dev/null 2>&1
ogr2ogr -f DXF "$work/inches.dxf" "$work/sim/floorplan.geojson" 2> /dev/null
check "GDAL's default DXF header declares inches" bash -c "grep -A2 INSUNITS '$work/inches.dxf' | tail -1 | grep -q '^ *1 *\$'"
init=$(grep -v '^#' "$work/sim/groundtruth.tum" | awk 'NR == 1 { printf "%s,%s,%s", $2, $3, 2 * atan2($7, $8) }')

"$glassmap" export "$work/inches.dxf" "$work/plan.geojson" > "$work/export.log" 2>&1
check "export warns about the implausible extent" grep -q "implausible for a building floor.*inches.*--units" "$work/export.log"

"$glassmap" localize --map "$work/inches.dxf" "$work/sim/log.clf" -o "$work/a.tum" --init="$init" > "$work/a.log" 2>&1
check "localize refuses a plan of implausible scale" [ $? -ne 0 ]
check "... saying why" grep -q "refusing to localize.*--units" "$work/a.log"
check "... and writes nothing" [ ! -e "$work/a.tum" ]

"$glassmap" localize --map "$work/inches.dxf" "$work/sim/log.clf" -o "$work/b.tum" --init="$init" --units in > "$work/b.log" 2>&1
check "with --units in, an initial pose outside the plan is refused" [ $? -ne 0 ]
check "... naming the extent" grep -q "initial pose.*outside the map's extent" "$work/b.log"

"$glassmap" localize --map "$work/inches.dxf" "$work/sim/log.clf" -o "$work/c.tum" --init="$init" --units m -q
check "with --units m it localizes" [ $? -eq 0 ]
"$glassmap" eval traj --truth "$work/sim/groundtruth.tum" "$work/c.tum" --json "$work/c.json" > /dev/null
check "... and tracks" python3 -c "import json, sys; sys.exit(0 if json.load(open('$work/c.json'))['rmse'] < 0.05 else 1)"

if [ $fail -eq 0 ]; then echo "all plan-units checks passed"; fi
exit $fail
