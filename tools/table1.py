#!/usr/bin/env python3
"""Reproduces the mapping tables (README.md: glass cells; docs/mapping.md: floorplans): for each
scene, simulate with a fixed seed, map with every method, score the cells (paper Table I + F1) and
the vector floorplan (segments), and print Markdown tables.

Usage: tools/table1.py [--build build] [--seed 1] [--out out/table1] [scene ...]
"""
import argparse
import json
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
# Ablations: the classifier alone, without the mirror-phantom test and the pane fit of the cells
# ("direct, raw" against "mrf, raw" is what the MRF changes), and the MRF with the paper's Psi.
RAW = {"heuristic, raw": "heuristic", "direct, raw": "direct", "mrf, raw": "mrf"}
EXTRA = {"mrf, paper psi": ["--method", "mrf", "--mrf-psi", "paper"]}
METHODS = ["heuristic", "direct", "mrf", "heuristic, raw", "direct, raw", "mrf, raw", "mrf, paper psi"]


def run(cmd):
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "table1"))
    ap.add_argument("scenes", nargs="*", default=["paper-corridor", "glass-corridor", "office-floor", "no-glass"])
    a = ap.parse_args()
    gm = os.path.join(a.build, "tools", "glassmap")
    cells_rows, seg_rows = [], []
    for scene in a.scenes:
        sim = os.path.join(a.out, scene, "sim")
        run([gm, "simulate", os.path.join(ROOT, "maps", scene, "scene.yaml"), "-o", sim, "--seed", str(a.seed), "-q"])
        truth = os.path.join(sim, "floorplan.gpkg")
        for method in METHODS:
            d = os.path.join(a.out, scene, method.replace(", ", "_").replace(" ", "_"))
            flags = (["--method", RAW[method], "--keep-phantoms", "--keep-unfitted-glass"] if method in RAW
                     else EXTRA[method] if method in EXTRA else ["--method", method])
            run([gm, "map", os.path.join(sim, "log.clf"), "-o", d, "-q"] + flags)
            cj = os.path.join(d, "cells.json")
            run([gm, "eval", "cells", "--truth", truth, "--labels", os.path.join(d, "labels.tif"), "--json", cj])
            c = json.load(open(cj))
            stats = json.load(open(os.path.join(d, "stats.json")))
            t = c["table_i"]
            cells_rows.append((scene, method, t["ground_truth"], c["predicted_glass_cells"], t["found"],
                               t["false_positives"], t["exact_found"], t["found_with_displacement"], t["not_found"],
                               c["exact"]["f1"], c["tolerant"]["precision"], c["tolerant"]["recall"],
                               c["tolerant"]["f1"], stats["seconds"]["total"]))
            sj = os.path.join(d, "segments.json")
            run([gm, "eval", "segments", "--truth", truth, "--pred", os.path.join(d, "floorplan.gpkg"),
                 "--visible-from", os.path.join(sim, "log.clf"), "--json", sj, "-q"])
            seg_rows.append((scene, method, json.load(open(sj))))
        print(f"{scene} done", file=sys.stderr)

    print("| scene | method | ground truth | predicted | found | false + | exact | displaced ≤2 | not found "
          "| F1@0 | P@2 | R@2 | F1@2 | seconds |")
    print("| --- | --- | " + " | ".join(["---:"] * 12) + " |")
    for r in cells_rows:
        print("| %s | %s | %d | %d | %d | %d | %d | %d | %d | %.3f | %.3f | %.3f | **%.3f** | %.1f |" % r)
    print()
    print("| scene | method | glass P | glass R | glass F1 | glass segments pred/true | segments per found pane "
          "| angle err [deg] | longest false glass [m] | wall P | wall R | wall F1 | wall R seen | wall F1 seen |")
    print("| --- | --- | " + " | ".join(["---:"] * 12) + " |")
    for scene, method, s in seg_rows:
        g, w = s["glass"], s["wall"]
        print(f"| {scene} | {method} | {g['precision']:.3f} | {g['recall']:.3f} | **{g['f1']:.3f}** | "
              f"{g['pred_segments']}/{g['truth_segments']} | {s['segments_per_found_pane']:.2f} | "
              f"{s['glass_angle_error_deg']:.2f} | {s['longest_false_glass_m']:.2f} | "
              f"{w['precision']:.3f} | {w['recall']:.3f} | {w['f1']:.3f} | "
              f"{s['seen_from_log']['wall']['recall']:.3f} | **{s['seen_from_log']['wall']['f1']:.3f}** |")


if __name__ == "__main__":
    main()
