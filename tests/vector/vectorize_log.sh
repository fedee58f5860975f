#!/usr/bin/env bash
# glassmap vectorize MAP.yaml --log LOG on a real log: the ROS map `map` wrote, vectorized with and
# without the log it was made from; with it the walls move onto the returns and the plan explains
# more of them (eval rays), with as many segments; the clutter lines chosen from the returns
# explain more again; a file that is no log fails and leaves no output.
# Usage: vectorize_log.sh GLASSMAP LOG
set -euo pipefail
glassmap=$1 log=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
"$glassmap" map "$log" -o "$work/map" -q
"$glassmap" vectorize "$work/map/map.yaml" -o "$work/plain/" --formats gpkg -q
"$glassmap" vectorize "$work/map/map.yaml" -o "$work/fitted/" --formats gpkg --log "$log" --json "$work/v.json" \
  --no-scan-clutter > "$work/stdout"
grep -q "walls onto returns" "$work/stdout" || fail "summary does not report the fit"
"$glassmap" vectorize "$work/map/map.yaml" -o "$work/full/" --formats gpkg --log "$log" --json "$work/full_v.json" -q
for p in plain fitted full; do
  "$glassmap" eval rays --plan "$work/$p/floorplan.gpkg" "$log" --json "$work/$p.json" -q
done
python3 - "$work" <<'PY' || fail "the fitted plan does not explain more returns"
import json, sys
d = sys.argv[1]
v = json.load(open(d + "/v.json"))["scan_fit"]
c = json.load(open(d + "/full_v.json"))["scan_clutter"]
plain, fitted, full = (json.load(open(f"{d}/{p}.json")) for p in ("plain", "fitted", "full"))
print(f"moved {v['moved']} of {v['segments']}; explained {plain['explained_share']:.3f} -> "
      f"{fitted['explained_share']:.3f}; clutter from the returns: {c['added']} lines for {c['replaced']}, "
      f"explained {full['explained_share']:.3f}, {fitted['segments']} -> {full['segments']} segments")
assert v["moved"] > 0 and v["explained_after"] > v["explained_before"], v
assert fitted["explained_share"] > plain["explained_share"] + 0.005, (plain["explained_share"], fitted["explained_share"])
assert fitted["segments"] == plain["segments"]
assert c["added"] > 0 and c["explained_after"] > c["explained_before"], c
assert full["explained_share"] > fitted["explained_share"] + 0.02, (fitted["explained_share"], full["explained_share"])
PY
echo "not a log" > "$work/bad.clf"
if "$glassmap" vectorize "$work/map/map.yaml" -o "$work/bad/" --log "$work/bad.clf" -q 2> "$work/err"; then
  fail "a file that is no log was accepted"
fi
test ! -e "$work/bad" || fail "a failed run left output behind"
echo "vectorize --log checks passed"
