#!/usr/bin/env bash
# glassmap vectorize on a map editor's occupancy map (YAML + PGM, everything but free space
# black, origin with yaw): walls only on the faces of free space, placed by the origin.
set -euo pipefail
glassmap=$1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
python3 - "$work" <<'PY'
import sys
w, h, res = 160, 120, 0.05
rows = []
for y in range(h - 1, -1, -1):  # PGM: top row first
    row = bytearray()
    for x in range(w):
        cx, cy = (x + 0.5) * res, (y + 0.5) * res
        row.append(254 if 1.0 < cx < 7.0 and 1.0 < cy < 5.0 else 0)
    rows.append(bytes(row))
open(sys.argv[1] + "/room.pgm", "wb").write(b"P5\n%d %d\n255\n" % (w, h) + b"".join(rows))
open(sys.argv[1] + "/room.yaml", "w").write(
    "image: room.pgm\nresolution: 0.05\norigin: [100.0, 50.0, 1.5707963267948966]\n"
    "negate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\nmode: trinary\n")
PY
"$glassmap" vectorize "$work/room.yaml" -o "$work/out/" --formats geojson --json "$work/v.json" > "$work/stdout"
grep -q "ROS occupancy map" "$work/stdout" || fail "summary does not say what was read"
python3 - "$work" <<'PY' || fail "wrong floorplan"
import json, math, sys
d = sys.argv[1]
v = json.load(open(d + "/v.json"))
assert v["read_as"] == "ROS occupancy map", v["read_as"]
assert v["occupancy"]["solid_inside"] > 5000, v["occupancy"]
assert v["occupancy"]["ridges"] == 0, v["occupancy"]  # black, grey and white only: no ridge to read
fc = json.load(open(d + "/out/floorplan.geojson"))
length, xs, ys = 0.0, [], []
for f in fc["features"]:
    c = f["geometry"]["coordinates"]
    for a, b in zip(c[:-1], c[1:]):
        length += math.dist(a, b)
        xs += [a[0], b[0]]; ys += [a[1], b[1]]
# The 6 x 4 m room: 20 m of wall, no hatching; rotated 90 deg about (100, 50): x in [95, 99], y in [51, 57].
assert 18.0 < length < 22.0, length
assert abs(min(xs) - 95.0) < 0.15 and abs(max(xs) - 99.0) < 0.15, (min(xs), max(xs))
assert abs(min(ys) - 51.0) < 0.15 and abs(max(ys) - 57.0) < 0.15, (min(ys), max(ys))
PY
if "$glassmap" vectorize "$work/room.yaml" -o "$work/bad/" --input labels 2> "$work/err"; then
  fail "a map YAML was accepted as labels"
fi
echo "vectorize occupancy: ok"
