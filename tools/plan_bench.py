#!/usr/bin/env python3
"""Floorplans from occupancy maps other programs leave: wall F1 against the true structure.

For every test plan (the bundled scenes' true plans, tests/data/vector's non-Manhattan buildings,
optionally the 100 m bench floor), every map convention (solid, slam, drawn) and every furniture
setting, `glassmap bench plan-map` draws the test map, `glassmap vectorize` makes the plan, and
`glassmap eval segments --tol 0.15` scores its WALL layer against the structure (glass as wall;
the scenes' desk outlines are furniture). It scores the plan a second time against the truth
with each wall that the map shows free beside on one side only moved onto that face (half its
thickness over): a wall seen from one side lies on its face. Prints a Markdown table and writes
CSV/JSON.

  python3 tools/plan_bench.py [--build build] [--out out/plan_bench] [--seeds 1 2] [--big]
                              [--extra "--no-structure"] [--map-extra "--resolution 0.1"]
                              [--plans office-floor,pentagon] [--blur 0.8] [--wall-thickness 0.5]
"""
import argparse
import csv
import json
import os
import statistics
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PLANS = {
    "office-floor": "maps/office-floor/floorplan.geojson",
    "no-glass": "maps/no-glass/floorplan.geojson",
    "paper-corridor": "maps/paper-corridor/floorplan.geojson",
    "glass-corridor": "maps/glass-corridor/floorplan.geojson",
    "pentagon": "tests/data/vector/pentagon.geojson",
    "angled-office": "tests/data/vector/angled-office.geojson",
}
BIG = {"office-100m": "../shared/data/bench/office-100m.geojson"}
FURNITURE = {"empty": ["--furniture-cover", "0", "--bins", "0", "--no-plan-furniture"],
             "furnished": []}


def run(cmd):
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"failed ({r.returncode}): {' '.join(cmd)}\n{r.stderr}")
    return r.stdout


def thickened(plan, thickness, out):
    """The plan with every wall of 0.1 m or more redrawn `thickness` thick (glass and thinner lines kept)."""
    d = json.load(open(plan))
    for f in d["features"]:
        p = f.get("properties") or {}
        if p.get("material") == "wall" and float(p.get("thickness", 0)) >= 0.1:
            p["thickness"] = thickness
    json.dump(d, open(out, "w"))
    return out


def read_map(stem):
    """The test map as (pixels, width, height, resolution, origin): the PGM's rows top down."""
    meta = {}
    for line in open(stem + ".yaml"):
        if ":" in line:
            k, v = line.split(":", 1)
            meta[k.strip()] = v.strip()
    res = float(meta["resolution"])
    origin = [float(x) for x in meta["origin"].strip("[]").split(",")[:2]]
    data = open(stem + ".pgm", "rb").read()
    fields, i = [], 0
    while len(fields) < 4:  # magic, width, height, maxval; comments skipped
        while data[i:i + 1].isspace():
            i += 1
        if data[i:i + 1] == b"#":
            i = data.index(b"\n", i)
            continue
        j = i
        while not data[j:j + 1].isspace():
            j += 1
        fields.append(data[i:j])
        i = j
    if fields[0] != b"P5":
        raise ValueError(f"{stem}.pgm: not a binary PGM")
    w, h = int(fields[1]), int(fields[2])
    return data[i + 1:i + 1 + w * h], w, h, res, origin


def faces_truth(stem, out):
    """The truth with each wall that the map shows free space beside on one side only moved onto that
    face (half its thickness towards the free side): a wall seen from one side lies on its face, as
    the vectorizer puts it (nothing in the map says how thick it is). Returns how many moved."""
    pix, w, h, res, (ox, oy) = read_map(stem)

    def free(x, y):
        cx, cy = int((x - ox) // res), int((y - oy) // res)
        return 0 <= cx < w and 0 <= cy < h and pix[(h - 1 - cy) * w + cx] >= 250

    d = json.load(open(stem + "-truth.geojson"))
    moved = 0
    for f in d["features"]:
        p, g = f.get("properties") or {}, f["geometry"]
        if p.get("material") != "wall" or g["type"] != "LineString" or len(g["coordinates"]) != 2:
            continue
        (ax, ay), (bx, by) = g["coordinates"][0][:2], g["coordinates"][1][:2]
        length = ((bx - ax) ** 2 + (by - ay) ** 2) ** 0.5
        half = 0.5 * float(p.get("thickness", 0))
        if length == 0 or half < res:
            continue
        nx, ny = -(by - ay) / length, (bx - ax) / length
        # Free space beside the wall: from two cells off its face out to 0.7 m (furniture against it).
        steps = [half + k * res for k in range(2, max(3, int(0.7 / res) + 1))]
        left = right = 0
        samples = [(k + 0.5) / 20 for k in range(20)]
        for t in samples:
            x, y = ax + t * (bx - ax), ay + t * (by - ay)
            fl = any(free(x + r * nx, y + r * ny) for r in steps)
            fr = any(free(x - r * nx, y - r * ny) for r in steps)
            left += fl and not fr
            right += fr and not fl
        side = 1 if left >= 0.7 * len(samples) else -1 if right >= 0.7 * len(samples) else 0
        if side:
            g["coordinates"] = [[ax + side * half * nx, ay + side * half * ny], [bx + side * half * nx, by + side * half * ny]]
            moved += 1
    json.dump(d, open(out, "w"))
    return moved


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "plan_bench"))
    ap.add_argument("--seeds", type=int, nargs="+", default=[1, 2])
    ap.add_argument("--conventions", default="solid,slam,drawn")
    ap.add_argument("--furniture", default="empty,furnished")
    ap.add_argument("--plans", default=",".join(PLANS))
    ap.add_argument("--big", action="store_true", help="also the 100 m bench floor (minutes)")
    ap.add_argument("--extra", default="", help="more options for vectorize, e.g. --no-structure")
    ap.add_argument("--map-extra", default="",
                    help="more options for bench plan-map, e.g. \"--resolution 0.1 --range-sigma 0.03\"")
    ap.add_argument("--tol", default="0.15")
    ap.add_argument("--wall-thickness", type=float, default=0.0,
                    help="redraw every structural wall of the plans (0.1 m thick or more) this thick [m], e.g. 0.5 "
                         "for the thick walls of older buildings (0: as the plans have them)")
    ap.add_argument("--blur", type=float, default=0.0,
                    help="blur each test map with a Gaussian of this many pixels before vectorizing (the grey "
                         "rims anti-aliasing or resampling leave; needs Pillow: apt-get install python3-pil)")
    args = ap.parse_args()
    exe = os.path.join(args.build, "tools", "glassmap")
    if args.blur > 0:
        try:
            from PIL import Image, ImageFilter
        except ImportError:
            sys.exit("--blur needs Pillow (apt-get install python3-pil, then run with /usr/bin/python3)")

        def blur(pgm):
            Image.open(pgm).filter(ImageFilter.GaussianBlur(args.blur)).save(pgm)
    plans = {k: PLANS[k] for k in args.plans.split(",")}
    if args.big:
        plans.update(BIG)
    os.makedirs(args.out, exist_ok=True)
    rows = []
    for name, rel in plans.items():
        plan = os.path.join(ROOT, rel)
        if not os.path.exists(plan):
            print(f"skipping {name}: {plan} missing", file=sys.stderr)
            continue
        if args.wall_thickness > 0:
            plan = thickened(plan, args.wall_thickness, os.path.join(args.out, f"{name}-plan.geojson"))
        for conv in args.conventions.split(","):
            for furn in args.furniture.split(","):
                for seed in args.seeds:
                    stem = os.path.join(args.out, f"{name}-{conv}-{furn}-{seed}")
                    run([exe, "bench", "plan-map", plan, "-o", stem, "--convention", conv, "--seed", str(seed), "-q"]
                        + FURNITURE[furn] + args.map_extra.split())
                    if args.blur > 0:
                        blur(stem + ".pgm")
                    run([exe, "vectorize", stem + ".yaml", "-o", stem + "-plan", "-q", "--json", stem + "-vec.json"]
                        + args.extra.split())
                    run([exe, "eval", "segments", "--truth", stem + "-truth.geojson", "--pred", stem + "-plan.gpkg",
                         "--tol", args.tol, "-q", "--json", stem + "-eval.json"])
                    moved = faces_truth(stem, stem + "-truth-faces.geojson")
                    run([exe, "eval", "segments", "--truth", stem + "-truth-faces.geojson", "--pred",
                         stem + "-plan.gpkg", "--tol", args.tol, "-q", "--json", stem + "-eval-faces.json"])
                    ef = json.load(open(stem + "-eval-faces.json"))["wall"]
                    e = json.load(open(stem + "-eval.json"))
                    v = json.load(open(stem + "-vec.json"))
                    w = e["wall"]
                    rows.append({"plan": name, "convention": conv, "furniture": furn, "seed": seed,
                                 "precision": w["precision"], "recall": w["recall"], "f1": w["f1"],
                                 "truth_segments": w["truth_segments"], "segments": w["pred_segments"],
                                 "clutter": v.get("clutter_segments", 0), "doors": v.get("doors", 0),
                                 "rooms": v.get("rooms", 0), "f1_faces": ef["f1"], "one_sided": moved})
                    r = rows[-1]
                    print(f"{name:15s} {conv:6s} {furn:10s} {seed}: P {r['precision']:.3f} R {r['recall']:.3f} "
                          f"F1 {r['f1']:.3f} (faces {r['f1_faces']:.3f})  {r['segments']}/{r['truth_segments']} segments, "
                          f"{r['clutter']} clutter, {r['doors']} doors, {r['rooms']} rooms", file=sys.stderr)
    with open(os.path.join(args.out, "plan_bench.csv"), "w", newline="") as f:
        wr = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        wr.writeheader()
        wr.writerows(rows)
    json.dump(rows, open(os.path.join(args.out, "plan_bench.json"), "w"), indent=1)
    # Markdown: mean over seeds per plan x convention x furniture.
    print(f"| plan | convention | furniture | wall P | wall R | wall F1 (min) | F1, one-sided walls on their faces | "
          f"segments / truth | clutter | doors | rooms |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    keys = []
    for r in rows:
        k = (r["plan"], r["convention"], r["furniture"])
        if k not in keys:
            keys.append(k)
    f1s, faces = [], []
    for k in keys:
        g = [r for r in rows if (r["plan"], r["convention"], r["furniture"]) == k]
        m = lambda f: statistics.mean(r[f] for r in g)
        f1s += [r["f1"] for r in g]
        faces += [r["f1_faces"] for r in g]
        print(f"| {k[0]} | {k[1]} | {k[2]} | {m('precision'):.3f} | {m('recall'):.3f} | "
              f"**{m('f1'):.3f}** ({min(r['f1'] for r in g):.3f}) | {m('f1_faces'):.3f} ({m('one_sided'):.0f} moved) | "
              f"{m('segments'):.0f} / {g[0]['truth_segments']} | "
              f"{m('clutter'):.0f} | {m('doors'):.0f} | {m('rooms'):.0f} |")
    print(f"\n{len(f1s)} maps: wall F1 median {statistics.median(f1s):.3f}, min {min(f1s):.3f}, "
          f"{sum(f >= 0.9 for f in f1s)} at 0.9 or more; with one-sided walls on their faces: median "
          f"{statistics.median(faces):.3f}, min {min(faces):.3f}, {sum(f >= 0.9 for f in faces)} at 0.9 or more")


if __name__ == "__main__":
    main()
