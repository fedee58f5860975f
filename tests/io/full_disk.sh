#!/usr/bin/env bash
# Full disk and unwritable outputs, through the command line as a user meets them. A file-size
# limit (ulimit -f, with SIGXFSZ ignored so that writes fail with EFBIG instead of killing the
# process) stands in for a full disk.
# Usage: full_disk.sh GLASSMAP SCENE_YAML WORK_DIR
set -uo pipefail
glassmap=$1 scene=$2 work=$3
rm -rf "$work"
mkdir -p "$work"
fail=0
check() {  # check NAME CONDITION...
  local name=$1
  shift
  if "$@"; then echo "ok   $name"; else echo "FAIL $name"; fail=1; fi
}
limited() {  # limited KIB CMD...: run CMD with files capped at KIB KiB
  local kib=$1
  shift
  bash -c 'trap "" XFSZ; ulimit -f "$0"; exec "$@"' "$kib" "$@"
}
no_hidden() { [ -z "$(ls -A "$1" | grep '^\.')" ]; }

# A floorplan of 3,000 segments (about 300 KB as GeoJSON).
plan=$work/plan.geojson
awk 'BEGIN {
  printf "{\"type\":\"FeatureCollection\",\"features\":[";
  for (i = 0; i < 3000; ++i) {
    if (i) printf ",";
    printf "{\"type\":\"Feature\",\"properties\":{\"material\":\"%s\",\"thickness\":0.1},", (i % 7 ? "wall" : "glass");
    printf "\"geometry\":{\"type\":\"LineString\",\"coordinates\":[[%d.5,%d.25],[%d.5,%d.75]]}}", i % 60, i / 60, i % 60, i / 60;
  }
  printf "]}\n" }' > "$plan"

for ext in geojson fgb gpkg shp dxf svg png pdf; do
  out=$work/export-$ext
  mkdir -p "$out"
  limited 16 "$glassmap" export "$plan" "$out/plan.$ext" > "$out/log" 2>&1
  rc=$?
  check "export .$ext on a full disk fails" [ $rc -ne 0 ]
  check "export .$ext on a full disk leaves no file" [ ! -e "$out/plan.$ext" ]
  check "export .$ext on a full disk leaves no temporary" no_hidden "$out"
  check "export .$ext error names the output" grep -q "$out/plan" "$out/log"
  "$glassmap" export "$plan" "$out/plan.$ext" > /dev/null 2>&1
  check "export .$ext without the limit succeeds" [ -s "$out/plan.$ext" ]
done

# map: a complete set, then a run on a full disk must leave that set (and its stats.json) alone.
"$glassmap" simulate "$scene" -o "$work/sim" --seed 3 > /dev/null 2>&1
"$glassmap" map "$work/sim/log.clf" -o "$work/map" -q --method heuristic
check "map writes a complete set" grep -q '"method": "heuristic"' "$work/map/stats.json"
before=$(cd "$work/map" && md5sum labels.tif stats.json)
limited 40 "$glassmap" map "$work/sim/log.clf" -o "$work/map" -q --method direct > "$work/map.log" 2>&1
rc=$?
check "map on a full disk fails" [ $rc -ne 0 ]
check "map on a full disk keeps the previous set" [ "$(cd "$work/map" && md5sum labels.tif stats.json)" = "$before" ]
check "map on a full disk leaves no staging folder" no_hidden "$work/map"
check "map's error names the user's folder" grep -q "$work/map/" "$work/map.log"

# A log over a quarter of --max-memory is kept on disk and read back in blocks: the same maps as a
# run with the log in memory; a budget the grid does not fit in stops before anything is written.
"$glassmap" map "$work/sim/log.clf" -o "$work/map-memory" -q --method heuristic
"$glassmap" map "$work/sim/log.clf" -o "$work/map-spooled" --method heuristic --max-memory 10 > "$work/spooled.log" 2>&1
check "map spools a log over a quarter of --max-memory" grep -q "kept on disk" "$work/spooled.log"
for f in labels.tif map.pgm floorplan.geojson sensor.yaml; do
  check "... and writes the same $f as in memory" cmp -s "$work/map-memory/$f" "$work/map-spooled/$f"
done
"$glassmap" map "$work/sim/log.clf" -o "$work/map-small" -q --max-memory 2 > "$work/memory.log" 2>&1
rc=$?
check "map stops when the grid does not fit in --max-memory" [ $rc -ne 0 ]
check "... naming the limit" grep -q "over the limit of .* MB: raise the limit (--max-memory)" "$work/memory.log"
check "... and writes nothing" [ ! -e "$work/map-small/stats.json" ]
# The folder the scans are spooled to fills up: an error naming it, nothing written, nothing left there.
mkdir -p "$work/spool"
limited 1024 "$glassmap" map "$work/sim/log.clf" -o "$work/map-spool-full" -q --max-memory 10 --spool-dir "$work/spool" \
  > "$work/spool.log" 2>&1
rc=$?
check "map fails when the spool folder is full" [ $rc -ne 0 ]
check "... naming the folder and the reason" grep -q "$work/spool: cannot keep the scans .*: File too large" "$work/spool.log"
check "... leaving the spool folder empty" [ -z "$(ls -A "$work/spool")" ]
check "... and writing no map" [ ! -e "$work/map-spool-full/stats.json" ]

# An output folder that cannot be created fails before the log is read.
touch "$work/a-file"
"$glassmap" map "$work/sim/log.clf" -o "$work/a-file/map" > "$work/unwritable.log" 2>&1
rc=$?
check "map into an impossible folder fails" [ $rc -ne 0 ]
check "map's error names the folder and the reason" grep -q "$work/a-file/map: cannot create the output folder: $work/a-file is not a folder" "$work/unwritable.log"

if [ $fail -eq 0 ]; then echo "all full-disk checks passed"; fi
exit $fail
