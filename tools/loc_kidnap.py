#!/usr/bin/env python3
"""Kidnap recovery on paper-corridor (issue 14), one or more glassmap builds side by side: the robot
is carried D metres ahead along its path at --at seconds while the odometry records no motion
(`glassmap simulate --kidnap-at --kidnap-along`), then `glassmap localize --init <true start>`
with a fixed particle count. Recovered = the position error falls under 0.2 m and stays there to
the end with at least 10 s left (the definition of tools/bench.sh --sections kidnap); time to
recover from the kidnap. Prints success / median time per distance and build as Markdown, and the
breaks the filter counted (scans that contradict the one before them); CSV in OUT/kidnap.csv.

Usage: tools/loc_kidnap.py [--glassmap build/tools/glassmap[,other/glassmap]] [--out out/loc_kidnap]
    [--distances 0.5,1,2,4,8,12] [--seeds 1,...,8] [--model glass] [--particles 500] [--beams 15]
"""
import argparse
import csv
import json
import math
import os
import statistics
import subprocess

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
THRESHOLD_M, HOLD_S = 0.2, 10.0


def run(cmd):
    subprocess.run([str(c) for c in cmd], check=True, stdout=subprocess.DEVNULL)


def read_tum(path):
    out = {}
    for line in open(path):
        if line.strip() and not line.startswith("#"):
            v = line.split()
            out[round(float(v[0]), 6)] = (float(v[1]), float(v[2]))
    return out


def time_to_recover(errors, t_kidnap):
    """Seconds from t_kidnap to the first estimate from which on the error stays under THRESHOLD_M
    to the end, with at least HOLD_S left; None when it does not."""
    after = sorted((t, e) for t, e in errors if t >= t_kidnap - 1e-9)
    t_rec = None
    for t, e in reversed(after):
        if not e < THRESHOLD_M:
            break
        t_rec = t
    if t_rec is None or after[-1][0] - t_rec < HOLD_S:
        return None
    return t_rec - t_kidnap


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--glassmap", default=os.path.join(ROOT, "build", "tools", "glassmap"),
                    help="one build or several, comma-separated (the first one simulates)")
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "loc_kidnap"))
    ap.add_argument("--scene", default="paper-corridor")
    ap.add_argument("--distances", default="0.5,1,2,4,8,12")
    ap.add_argument("--seeds", default="1,2,3,4,5,6,7,8")
    ap.add_argument("--at", type=float, default=15.0)
    ap.add_argument("--duration", type=float, default=75.0)
    ap.add_argument("--model", default="glass")
    ap.add_argument("--particles", type=int, default=500)
    ap.add_argument("--beams", type=int, default=15)
    a = ap.parse_args()
    builds = a.glassmap.split(",")
    scene = os.path.join(ROOT, "maps", a.scene, "scene.yaml")
    rows = []
    for dist in a.distances.split(","):
        for seed in a.seeds.split(","):
            sim = os.path.join(a.out, f"{a.scene}-d{dist}-s{seed}")
            if not os.path.exists(os.path.join(sim, "meta.json")):
                run([builds[0], "simulate", scene, "-o", sim, "--seed", seed, "--duration", a.duration,
                     "--kidnap-at", a.at, "--kidnap-along", dist, "-q"])
            meta = json.load(open(os.path.join(sim, "meta.json")))
            x0, y0, th0 = meta["start_pose"]
            truth = read_tum(os.path.join(sim, "groundtruth.tum"))
            for b, gm in enumerate(builds):
                est, js = os.path.join(sim, f"est{b}.tum"), os.path.join(sim, f"loc{b}.json")
                run([gm, "localize", "--map", os.path.join(sim, "floorplan.gpkg"), os.path.join(sim, "log.clf"),
                     "-o", est, "--model", a.model, "--particles", a.particles, "--fixed-count", "--beams", a.beams,
                     "--init", f"{x0:.6f},{y0:.6f},{th0:.6f}", "--seed", seed, "--json", js, "-q"])
                e = read_tum(est)
                errors = [(t, math.dist(truth[t], p)) for t, p in e.items() if t in truth]
                ttr = time_to_recover(errors, meta["kidnap"]["time"])
                summary = json.load(open(js))
                rows.append(dict(build=b, distance=float(dist), seed=int(seed), recovered=int(ttr is not None),
                                 time_to_recover="" if ttr is None else round(ttr, 2),
                                 breaks=summary.get("breaks", ""), relocalizations=summary["relocalizations"]))
                print(f"build {b} d {dist:>4} m seed {seed}: " +
                      (f"recovered after {ttr:.1f} s" if ttr is not None else "not recovered") +
                      f", breaks {rows[-1]['breaks']}", flush=True)
    os.makedirs(a.out, exist_ok=True)
    with open(os.path.join(a.out, "kidnap.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    dists = sorted({r["distance"] for r in rows})
    print()
    print("| build | " + " | ".join(f"{d:g} m" for d in dists) + " |")
    print("|---|" + "---|" * len(dists))
    for b, gm in enumerate(builds):
        cells = []
        for d in dists:
            rs = [r for r in rows if r["build"] == b and r["distance"] == d]
            ok = [r["time_to_recover"] for r in rs if r["recovered"]]
            med = f"{statistics.median(ok):.1f} s" if ok else "-"
            cells.append(f"{len(ok)}/{len(rs)} / {med}")
        print(f"| {os.path.relpath(gm, ROOT)} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
