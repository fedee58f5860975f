#!/usr/bin/env bash
# glassmap calibrate end to end: a simulated log with a known laser, against its plan and alone;
# the profile drives `map --sensor`; bad profiles are refused with file, line and key.
set -euo pipefail
glassmap=$1
src=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

"$glassmap" simulate "$src/maps/glass-corridor/scene.yaml" -o "$work/sim" --duration 40 -q
"$glassmap" calibrate "$work/sim/log.clf" --map "$work/sim/floorplan.geojson" -o "$work/sensor.yaml" \
  --json "$work/cal.json" --chart "$work/cal.png" -q
[ -s "$work/sensor.yaml" ] && [ -s "$work/cal.png" ] || fail "calibrate wrote no profile or chart"
python3 - "$work/cal.json" <<'PY' || fail "calibrated values off"
import json, sys
j = json.load(open(sys.argv[1]))
for k in ["range_sigma_m", "direct_peak", "direct_sigma_deg", "normal_lambda_per_deg", "w_hit", "w_short", "w_max", "w_rand"]:
    assert k in j and k + "_se" in j, k
# The bundled scene's laser: 1 cm noise, a 2 deg lobe of peak 0.9.
assert abs(j["range_sigma_m"] - 0.01) < 0.0025, j["range_sigma_m"]
assert abs(j["direct_sigma_deg"] - 2.0) < 0.5, j["direct_sigma_deg"]
assert abs(j["direct_peak"] - 0.9) < 0.08, j["direct_peak"]
assert len(j["angle_bins"]) > 10
PY
# Without a plan: against the log's own map.
"$glassmap" calibrate "$work/sim/log.clf" -o "$work/own.yaml" --json "$work/own.json" -q
python3 -c "import json,sys; j=json.load(open(sys.argv[1])); assert j['own_floorplan'] and abs(j['range_sigma_m']-0.01)<0.0025, j" "$work/own.json" \
  || fail "own-map calibration off"
# map uses a given profile in one pass and records it.
"$glassmap" map "$work/sim/log.clf" -o "$work/map" --sensor "$work/sensor.yaml" -q
python3 -c "import json,sys; j=json.load(open(sys.argv[1])); assert not j['calibrated'] and abs(j['sensor']['direct_sigma_deg']-2.0)<0.5, j['sensor']" "$work/map/stats.json" \
  || fail "map --sensor did not use the profile"
[ -s "$work/map/sensor.yaml" ] || fail "map wrote no sensor.yaml"
# A bad profile is refused, naming the key, and nothing is written.
printf 'range_sigma_m: 0.02\ndirect_sigma_deg: -3\n' > "$work/bad.yaml"
if "$glassmap" map "$work/sim/log.clf" -o "$work/map-bad" --sensor "$work/bad.yaml" -q 2> "$work/err"; then
  fail "a negative lobe width was accepted"
fi
grep -q "bad.yaml:2" "$work/err" && grep -q "direct_sigma_deg" "$work/err" || { cat "$work/err"; fail "error does not name file:line and key"; }
[ ! -e "$work/map-bad/stats.json" ] || fail "a refused run wrote a map"
echo "calibrate CLI: ok"
