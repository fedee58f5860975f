#!/usr/bin/env bash
# A CAD floorplan through `glassmap convert`: materials and counts in the output, the per-layer
# report on stderr, --layers overriding the built-in table, and a plan whose every line is
# ignored failing with no output file.
# Usage: dxf_cli.sh GLASSMAP SEMANTICS_DXF WORK_DIR
set -uo pipefail
glassmap=$1 dxf=$2 work=$3
rm -rf "$work"
mkdir -p "$work"
fail=0
check() {  # check NAME CONDITION...
  local name=$1
  shift
  if "$@"; then echo "ok   $name"; else echo "FAIL $name"; fail=1; fi
}
count() { grep -o "\"material\": \"$1\"" "$2" | wc -l; }

"$glassmap" convert "$dxf" "$work/plan.geojson" >"$work/out.txt" 2>"$work/err.txt"
check "convert exits 0" test $? -eq 0
check "summary counts" grep -q "9 segments (7 wall, 2 glass)" "$work/out.txt"
check "7 wall features written" test "$(count wall "$work/plan.geojson")" -eq 7
check "2 glass features written" test "$(count glass "$work/plan.geojson")" -eq 2
check "report: A-WALL walls" grep -Eq "^  A-WALL +4 +6  wall +standard \*WALL\*" "$work/err.txt"
check "report: A-GLAZ glass" grep -Eq "^  A-GLAZ +2 +2  glass +standard \*GLAZ\*" "$work/err.txt"
check "report: dimensions ignored" grep -Eq "^  A-ANNO-DIMS +2 +0  ignored +dimension" "$work/err.txt"
check "report: frozen layer ignored" grep -Eq "^  A-WALL-OLD +1 +0  ignored +frozen layer" "$work/err.txt"
check "report: paper space ignored" grep -Eq "^  A-WALL +1 +0  ignored +paper space" "$work/err.txt"
check "report: spline note" grep -q "note: 1 spline(s) given only by fit points" "$work/err.txt"
check "report: unknown layer warning" grep -q "warning: layer(s) with no known name read as wall: MYSTERY (1)" "$work/err.txt"

"$glassmap" convert "$dxf" "$work/quiet.geojson" -q >"$work/q_out.txt" 2>"$work/q_err.txt"
check "quiet: silent" test ! -s "$work/q_out.txt" -a ! -s "$work/q_err.txt"

"$glassmap" convert "$dxf" "$work/rules.geojson" --layers "glass=MYSTERY;ignore=A-GLAZ" >/dev/null 2>"$work/r_err.txt"
check "--layers exits 0" test $? -eq 0
check "--layers: 1 glass" test "$(count glass "$work/rules.geojson")" -eq 1
check "--layers: 6 wall" test "$(count wall "$work/rules.geojson")" -eq 6
check "--layers: named in the report" grep -q "\-\-layers ignore=A-GLAZ" "$work/r_err.txt"

"$glassmap" convert "$dxf" "$work/none.geojson" --layers "ignore=*" >/dev/null 2>"$work/n_err.txt"
check "all ignored fails" test $? -ne 0
check "all ignored: no output" test ! -e "$work/none.geojson"
check "all ignored: says --layers" grep -q "every line of the floorplan was ignored" "$work/n_err.txt"

"$glassmap" convert "$dxf" "$work/bad.geojson" --layers "steel=X" >/dev/null 2>&1
check "bad --layers fails" test $? -ne 0

[ $fail -eq 0 ] && echo "all dxf cli checks passed"
exit $fail
