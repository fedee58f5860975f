#!/usr/bin/env bash
# Config files of the verbs through the glassmap binary: `--write-config` of a run, read back with
# `-c`, writes the same configuration and gives byte-identical outputs (info, simulate, map,
# localize, export, eval cells); the command line overrides the file; required options may come
# from the file; unknown keys, wrong types, YAML syntax errors and missing files are refused with
# file and line.
# Usage: config_cli.sh GLASSMAP SOURCE_DIR WORK_DIR
set -uo pipefail
glassmap=$(realpath "$1") src=$(realpath "$2") work=$3
rm -rf "$work"
mkdir -p "$work"
cd "$work" || exit 1
fail=0
check() {  # check NAME CONDITION...
  local name=$1
  shift
  if "$@"; then echo "ok   $name"; else echo "FAIL $name"; fail=1; fi
}
same() { cmp -s "$1" "$2"; }
# Each verb: the direct run's --write-config, then the same read back through -c.
roundtrip() {  # roundtrip NAME VERB... -- ARGS...
  local name=$1
  shift
  local verb=()
  while [ "$1" != "--" ]; do verb+=("$1"); shift; done
  shift
  "$glassmap" "${verb[@]}" "$@" --write-config >"$name.yaml" 2>"$name.err"
  check "$name: --write-config exits 0" test $? -eq 0
  "$glassmap" "${verb[@]}" -c "$name.yaml" --write-config >"$name.again.yaml" 2>>"$name.err"
  check "$name: -c then --write-config gives the same file" same "$name.yaml" "$name.again.yaml"
}

scene=$src/maps/no-glass/scene.yaml

# simulate: the written configuration holds the options given; the run via -c is the same run.
roundtrip simulate simulate -- "$scene" -o sim --duration 6 --seed 3 -q
check "simulate: given options written" grep -qx "seed: 3" simulate.yaml
check "simulate: defaults commented out" grep -qx "# people: -1" simulate.yaml
"$glassmap" simulate "$scene" -o sim --duration 6 --seed 3 -q
"$glassmap" simulate -c simulate.yaml -o sim-c  # -o on the command line overrides the file
for f in log.clf groundtruth.tum outcomes.bin floorplan.geojson; do
  check "simulate: $f identical through -c" same "sim/$f" "sim-c/$f"
done

# info: the same report (but for the time it took).
roundtrip info info -- sim/log.clf --json
"$glassmap" info sim/log.clf --json | grep -v read_seconds >info.direct
"$glassmap" info -c info.yaml | grep -v read_seconds >info.c
check "info: same report through -c" same info.direct info.c

# map: flags (negated ones too) and numbers; the same maps.
roundtrip map map -- sim/log.clf -o map --resolution 0.1 --keep-phantoms -q
check "map: a negated flag written true" grep -qx "keep-phantoms: true" map.yaml
check "map: unset flags commented out" grep -qx "# no-vector: false" map.yaml
"$glassmap" map sim/log.clf -o map --resolution 0.1 --keep-phantoms -q
"$glassmap" map -c map.yaml -o map-c
for f in labels.tif map.pgm map.yaml floorplan.geojson sensor.yaml; do
  check "map: $f identical through -c" same "map/$f" "map-c/$f"
done

# localize: the same trajectory estimate.
roundtrip localize localize -- --map sim/floorplan.geojson sim/log.clf -o est.tum --particles 300 --seed 5 -q
"$glassmap" localize --map sim/floorplan.geojson sim/log.clf -o est.tum --particles 300 --seed 5 -q
"$glassmap" localize -c localize.yaml -o est-c.tum
check "localize: same estimate through -c" same est.tum est-c.tum

# export: both positional arguments (required) given only by the file.
roundtrip export export -- sim/floorplan.geojson plan.geojson -q
"$glassmap" export sim/floorplan.geojson plan.geojson -q
rm -f plan-direct.geojson && mv plan.geojson plan-direct.geojson
"$glassmap" export -c export.yaml
check "export: required positionals from the file" same plan-direct.geojson plan.geojson

# eval cells, a nested verb.
roundtrip eval-cells eval cells -- --truth sim/floorplan.geojson --labels map/labels.tif --tolerance 1 -q --json cells.json
"$glassmap" eval cells -c eval-cells.yaml
mv cells.json cells-c.json
"$glassmap" eval cells --truth sim/floorplan.geojson --labels map/labels.tif --tolerance 1 -q --json cells.json
check "eval cells: same scores through -c" same cells.json cells-c.json

# The command line overrides the file, flags included.
"$glassmap" simulate -c simulate.yaml --seed 9 --quiet=false --write-config >override.yaml
check "override: option" grep -qx "seed: 9" override.yaml
check "override: flag" grep -qx "quiet: false" override.yaml
check "override: the rest from the file" grep -qx "duration: 6" override.yaml

# Errors name the file and the line; nothing runs.
printf 'scene: %s\noutput: bad-out\nsed: 4\n' "$scene" >unknown.yaml
"$glassmap" simulate -c unknown.yaml 2>err.txt
check "unknown key: refused" test $? -ne 0
check "unknown key: file:line and key" grep -q "unknown.yaml:3: sed: unknown key" err.txt
check "unknown key: nothing written" test ! -e bad-out
printf 'scene: %s\noutput: bad-out\n\nduration: long\n' "$scene" >type.yaml
"$glassmap" simulate -c type.yaml 2>err.txt
check "wrong type: refused" test $? -ne 0
check "wrong type: file:line and what was expected" grep -q "type.yaml:4: duration: expected a number, got 'long'" err.txt
printf 'quiet: true\nseed: [1, 2]\n' >list.yaml
"$glassmap" simulate "$scene" -o bad-out -c list.yaml 2>err.txt
check "list for a single value: file:line" grep -q "list.yaml:2: seed: expected a single value" err.txt
printf 'scene: %s\noutput: [bad-out\n' "$scene" >syntax.yaml
"$glassmap" simulate -c syntax.yaml 2>err.txt
check "YAML syntax error: refused" test $? -ne 0
check "YAML syntax error: file and line" grep -Eq "syntax.yaml:[23]: YAML syntax" err.txt
"$glassmap" simulate -c missing.yaml 2>err.txt
check "missing file: refused" test $? -ne 0
check "missing file: named" grep -q "missing.yaml" err.txt
check "no failed run wrote output" test ! -e bad-out
printf 'scene: %s\n' "$scene" >partial.yaml
"$glassmap" simulate -c partial.yaml 2>err.txt
check "required option missing from file and command line" grep -q "output is required" err.txt

if [ $fail -eq 0 ]; then echo "all config cli checks passed"; else exit 1; fi
