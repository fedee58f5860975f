#!/usr/bin/env bash
# ROS 2 bags through the real binary: a simulated CARMEN log converted to bags (MCAP zstd, SQLite),
# `map` on the bag gives the same labels and floorplan as on the CARMEN log, `info` lists the
# bag's topics, types, counts and frames, a bag converts back to a CARMEN log, and a bag without
# a scan topic fails naming the topics.
# Usage: bag_cli.sh GLASSMAP SCENE_YAML WORK_DIR
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

"$glassmap" simulate "$scene" -o "$work/sim" --seed 4 --duration 40 -q
check "simulate" test -s "$work/sim/log.clf"

"$glassmap" convert "$work/sim/log.clf" "$work/bag_mcap" >"$work/conv.txt" 2>&1
check "convert to mcap exits 0" test $? -eq 0
check "convert to mcap: summary" grep -q "wrote .*bag_mcap (ROS 2 bag, mcap, zstd)" "$work/conv.txt"
check "bag folder has metadata.yaml" test -f "$work/bag_mcap/metadata.yaml"
"$glassmap" convert "$work/sim/log.clf" "$work/bag_db3" --storage sqlite3 -q
check "convert to sqlite3 exits 0" test $? -eq 0
"$glassmap" convert "$work/sim/log.clf" "$work/bag_bad" --storage sqlite3 --compression zstd -q 2>"$work/bad.txt"
check "sqlite3 with zstd refused" test $? -ne 0
check "refused bag not left behind" test ! -e "$work/bag_bad"

"$glassmap" info "$work/bag_mcap" >"$work/info.txt" 2>"$work/info_err.txt"
check "info on a bag exits 0" test $? -eq 0
check "info: scan topic" grep -Eq "^  /scan +sensor_msgs/msg/LaserScan +[0-9]+" "$work/info.txt"
check "info: odometry topic" grep -Eq "^  /odom +nav_msgs/msg/Odometry" "$work/info.txt"
check "info: static laser frame" grep -Eq "^  base_link +-> laser +static" "$work/info.txt"
check "info: map -> odom" grep -Eq "^  map +-> odom +dynamic" "$work/info.txt"
check "info: scans read" grep -Eq "^scans +[0-9]+" "$work/info.txt"
"$glassmap" info --json "$work/bag_db3" >"$work/info.json" 2>/dev/null
check "info --json on sqlite3" grep -q '"storage": "sqlite3"' "$work/info.json"

"$glassmap" map "$work/sim/log.clf" -o "$work/map_clf" -q --method direct
"$glassmap" map "$work/bag_mcap" -o "$work/map_bag" --method direct >/dev/null 2>"$work/map_err.txt"
check "map on a bag exits 0" test $? -eq 0
check "map says which chain" grep -q "laser poses from map -> odom" "$work/map_err.txt"
"$glassmap" map "$work/bag_db3/bag_db3_0.db3" -o "$work/map_db3" -q --method direct
check "map on a .db3 file exits 0" test $? -eq 0
check "same labels.tif (mcap)" cmp -s "$work/map_clf/labels.tif" "$work/map_bag/labels.tif"
check "same labels.tif (db3)" cmp -s "$work/map_clf/labels.tif" "$work/map_db3/labels.tif"
# A bag over a quarter of --max-memory (its scans need about 1.7 MB) is kept on disk as it is read:
# the same labels.
"$glassmap" map "$work/bag_mcap" -o "$work/map_bag_spooled" --method direct --max-memory 6.5 >/dev/null 2>"$work/spool_err.txt"
check "map spools a bag over a quarter of --max-memory" grep -q "kept on disk" "$work/spool_err.txt"
check "same labels.tif (bag kept on disk)" cmp -s "$work/map_bag/labels.tif" "$work/map_bag_spooled/labels.tif"
# The bag's LaserScan holds its angles as float32: the walls and panes are the same, a segment's
# evidence (a mean over its cells' beams) may differ in the 7th digit, and a clutter line (fitted
# through returns rounded to the millimetre) by a few micrometres where a return lies on a
# rounding edge.
strip() { sed 's/"evidence": [-0-9.eE+]*/"evidence": E/g' "$1" | grep -v '"layer": "CLUTTER"'; }
evidence() { grep -o '"evidence": [-0-9.eE+]*' "$1" | cut -d' ' -f2; }
clutter() { grep '"layer": "CLUTTER"' "$1" | grep -o '\[ [-0-9.eE+]*, [-0-9.eE+]* \]' | tr -d '[],'; }
check "same walls and panes" cmp -s <(strip "$work/map_clf/floorplan.geojson") <(strip "$work/map_bag/floorplan.geojson")
check "clutter lines within 1e-4 m" awk 'BEGIN { bad = 0; n = 0 }
  { n++; if (NF != 4) bad = 1; for (i = 1; i <= 2; i++) { d = $i - $(i + 2); if (d < 0) d = -d; if (d > 1e-4) bad = 1 } }
  END { exit bad || n == 0 }' <(paste -d' ' <(clutter "$work/map_clf/floorplan.geojson") <(clutter "$work/map_bag/floorplan.geojson"))
check "floorplan evidence within 1e-5" awk 'BEGIN { bad = 0 } { d = $1 - $2; if (d < 0) d = -d; if (d > 1e-5) bad = 1 }
  END { exit bad }' <(paste <(evidence "$work/map_clf/floorplan.geojson") <(evidence "$work/map_bag/floorplan.geojson"))
check "evidence values compared" test "$(evidence "$work/map_clf/floorplan.geojson" | wc -l)" -gt 0

"$glassmap" localize --map "$work/sim/floorplan.geojson" "$work/bag_mcap" -o "$work/est.tum" --init 1,1.2,0 \
  --particles 200 --beams 10 --seed 1 >/dev/null 2>"$work/loc_err.txt"
check "localize on a bag exits 0" test $? -eq 0
check "localize takes odometry alone" grep -q "laser poses from odom -> base_link (/tf) -> laser" "$work/loc_err.txt"
check "localize says map -> odom is ignored" grep -q "map -> odom ignored" "$work/loc_err.txt"
check "localize wrote every pose" test "$(grep -vc '^#' "$work/est.tum")" -eq "$(grep -c '^ROBOTLASER1' "$work/sim/log.clf")"

"$glassmap" convert "$work/bag_mcap" "$work/back.clf" -q
check "bag -> CARMEN exits 0" test $? -eq 0
"$glassmap" map "$work/back.clf" -o "$work/map_back" -q --method direct
check "same labels.tif after the round trip" cmp -s "$work/map_clf/labels.tif" "$work/map_back/labels.tif"

"$glassmap" map "$work/bag_mcap" -o "$work/map_none" -q --scan-topic /nope 2>"$work/none.txt"
check "unknown --scan-topic fails" test $? -ne 0
check "unknown --scan-topic names the topics" grep -q "/scan (sensor_msgs/msg/LaserScan)" "$work/none.txt"

if [ $fail -eq 0 ]; then echo "all bag cli checks passed"; fi
exit $fail
