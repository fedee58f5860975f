#!/usr/bin/env python3
"""Reproduces the tracking table of docs/localization.md: for each scene and seed, simulate, then localize
against the true floorplan with every model (the command's defaults: 2,000 particles at most, KLD
down to 500; 15 beams; started at the first true pose) and score with `glassmap eval traj`; prints the Markdown table of mean ATE RMSE over the
seeds / worst maximum error [m].

Usage: tools/loc_table.py [--glassmap build/tools/glassmap] [--seeds 1,2,3] [--particles N] [--out out/loc_table]
                         [scene ...]
"""
import argparse
import json
import os
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
# column -> (--model, --glass-as)
COLUMNS = {"glass": ("glass", "opaque"), "glass-paper": ("glass-paper", "opaque"),
           "beam, glass opaque": ("beam", "opaque"), "beam, glass invisible": ("beam", "invisible"),
           "field opaque": ("field", "opaque"), "field invisible": ("field", "invisible")}
LOST_M = 0.5  # a mean ATE over this is marked "(lost)"


def run(cmd):
    subprocess.run([str(c) for c in cmd], check=True, stdout=subprocess.DEVNULL)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--glassmap", default=os.path.join(ROOT, "build", "tools", "glassmap"))
    ap.add_argument("--seeds", default="1,2,3")
    ap.add_argument("--particles", type=int, default=0, help="--particles of localize (0: its default)")
    ap.add_argument("--beams", type=int, default=15)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "loc_table"))
    ap.add_argument("scenes", nargs="*", default=["paper-corridor", "glass-corridor", "no-glass", "office-floor"])
    a = ap.parse_args()
    seeds = [int(s) for s in a.seeds.split(",")]
    gm = a.glassmap

    def simulate(job):
        scene, seed = job
        sim = os.path.join(a.out, scene, f"seed{seed}")
        if not os.path.exists(os.path.join(sim, "meta.json")):
            run([gm, "simulate", os.path.join(ROOT, "maps", scene, "scene.yaml"), "-o", sim, "--seed", seed, "-q"])
        return sim

    def localize(job):
        scene, seed, col = job
        sim = os.path.join(a.out, scene, f"seed{seed}")
        model, glass_as = COLUMNS[col]
        d = os.path.join(sim, col.replace(", ", "-").replace(" ", "-"))
        os.makedirs(d, exist_ok=True)
        init = json.load(open(os.path.join(sim, "meta.json")))["start_pose"]
        run([gm, "localize", "--map", os.path.join(sim, "floorplan.gpkg"), os.path.join(sim, "log.clf"),
             "-o", os.path.join(d, "est.tum"), "--model", model, "--glass-as", glass_as,
             "--beams", a.beams, "--seed", seed, "--init", "%.6f,%.6f,%.6f" % tuple(init), "-q"]
            + (["--particles", a.particles] if a.particles > 0 else []))
        run([gm, "eval", "traj", "--truth", os.path.join(sim, "groundtruth.tum"), os.path.join(d, "est.tum"),
             "--json", os.path.join(d, "ate.json"), "-q"])
        e = json.load(open(os.path.join(d, "ate.json")))
        return (scene, col), (e["rmse"], e["max"])

    with ThreadPoolExecutor(a.jobs) as ex:
        list(ex.map(simulate, [(s, k) for s in a.scenes for k in seeds]))
        results = {}
        for key, v in ex.map(localize, [(s, k, c) for s in a.scenes for k in seeds for c in COLUMNS]):
            results.setdefault(key, []).append(v)
            print(f"{key[0]} {key[1]}: {v[0]:.4f}", file=sys.stderr)
    print("| scene | " + " | ".join(COLUMNS) + " |")
    print("| --- | " + " | ".join(["---"] * len(COLUMNS)) + " |")
    for scene in a.scenes:
        cells = []
        for col in COLUMNS:
            v = results[(scene, col)]
            mean = sum(r for r, _ in v) / len(v)
            worst = max(m for _, m in v)
            cells.append(f"{mean:.2f} / {worst:.1f} (lost)" if mean > LOST_M else f"{mean:.4f} / {worst:.3f}")
        print(f"| {scene} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
