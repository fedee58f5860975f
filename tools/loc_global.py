#!/usr/bin/env python3
"""Global localization bench (issue 14): each bundled scene is simulated (with the scene's own
laser, or a sensor profile: `--sensors`), then `glassmap localize` runs WITHOUT --init against the
true floorplan. Per run: whether the filter says it converged (`converged`, `converged_at_s` of
the JSON summary), whether it is right (the position error stays under 0.5 m from the moment it
says so to the end), the time the estimate really settled (error under 0.5 m from then on), and
the error at the end. A confident wrong answer = converged but the error exceeds 0.5 m after
converged_at_s. Prints a per-scene Markdown table (success = converged, right and within --limit
seconds of driving) and writes OUT/global.csv and a chart OUT/global.png.

Usage: tools/loc_global.py [--glassmap build/tools/glassmap] [--out out/loc_global]
    [--scenes paper-corridor,glass-corridor,no-glass,office-floor] [--sensors scene,sick-lms200,...]
    [--seeds 1,2,3] [--limit 60] [--extra "localize arguments"] [--jobs 2]
"""
import argparse
import csv
import json
import math
import os
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCENES = ["paper-corridor", "glass-corridor", "no-glass", "office-floor"]
RIGHT_M = 0.5  # an estimate within this of the truth is "right"


def run(cmd):
    subprocess.run([str(c) for c in cmd], check=True, stdout=subprocess.DEVNULL)


def read_tum(path):
    out = []
    for line in open(path):
        if line.strip() and not line.startswith("#"):
            v = line.split()
            out.append((float(v[0]), float(v[1]), float(v[2])))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--glassmap", default=os.path.join(ROOT, "build", "tools", "glassmap"))
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "loc_global"))
    ap.add_argument("--scenes", default=",".join(SCENES))
    ap.add_argument("--sensors", default="scene", help="'scene' = the scene's own laser, else --sensor names")
    ap.add_argument("--seeds", default="1,2,3")
    ap.add_argument("--limit", type=float, default=60.0, help="success: converged within this many seconds")
    ap.add_argument("--extra", default="", help="extra localize arguments")
    ap.add_argument("--tag", default="default", help="name of this option set (output folder)")
    ap.add_argument("--jobs", type=int, default=2)
    a = ap.parse_args()
    gm = a.glassmap
    jobs = [(sc, se, int(k)) for sc in a.scenes.split(",") for se in a.sensors.split(",") for k in a.seeds.split(",")]

    def one(job):
        scene, sensor, seed = job
        sim = os.path.join(a.out, "sim", scene, sensor.replace(":", "-"), f"seed{seed}")
        if not os.path.exists(os.path.join(sim, "meta.json")):
            extra = [] if sensor == "scene" else ["--sensor", sensor]
            run([gm, "simulate", os.path.join(ROOT, "maps", scene, "scene.yaml"), "-o", sim, "--seed", seed, "-q"]
                + extra)
        d = os.path.join(sim, a.tag)
        os.makedirs(d, exist_ok=True)
        est, js = os.path.join(d, "est.tum"), os.path.join(d, "loc.json")
        run([gm, "localize", "--map", os.path.join(sim, "floorplan.gpkg"), os.path.join(sim, "log.clf"), "-o", est,
             "--seed", seed, "-q", "--json", js] + a.extra.split())
        s = json.load(open(js))
        truth = read_tum(os.path.join(sim, "groundtruth.tum"))
        estimate = read_tum(est)
        t0 = truth[0][0]
        err = [math.hypot(e[1] - g[1], e[2] - g[2]) for e, g in zip(estimate, truth)]
        times = [g[0] - t0 for g in truth]
        settled = None  # error under RIGHT_M from here to the end
        for i in range(len(err) - 1, -1, -1):
            if err[i] >= RIGHT_M:
                break
            settled = times[i]
        conv = bool(s["converged"])
        at = s["converged_at_s"] if conv else None
        right = conv and all(e < RIGHT_M for e, t in zip(err, times) if t >= at)
        row = {"scene": scene, "sensor": sensor, "seed": seed, "converged": conv,
               "converged_at_s": at, "right": right, "confident_wrong": conv and not right,
               "settled_s": settled, "final_error_m": err[-1], "duration_s": times[-1],
               "success": conv and right and at <= a.limit, "probes": s.get("probes", 0),
               "relocalizations": s["relocalizations"], "mean_particles": s["mean_particles"],
               "seconds": s["seconds"]}
        print(f"{scene:15s} {sensor:15s} {seed}: converged {conv} at {at} right {right} settled {settled} "
              f"final {err[-1]:.3f} m, {s['seconds']:.1f} s", file=sys.stderr, flush=True)
        return row

    with ThreadPoolExecutor(a.jobs) as ex:
        rows = list(ex.map(one, jobs))
    os.makedirs(a.out, exist_ok=True)
    with open(os.path.join(a.out, f"global-{a.tag}.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    print(f"| scene | sensor | runs | success (converged, right, within {a.limit:.0f} s) | converged | "
          "confident wrong | median time to converge [s] | median time the estimate settled [s] |")
    print("| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: |")

    def median(v):
        v = sorted(x for x in v if x is not None)
        return f"{v[len(v) // 2]:.1f}" if v else "n/a"

    for scene in a.scenes.split(","):
        for sensor in a.sensors.split(","):
            v = [r for r in rows if r["scene"] == scene and r["sensor"] == sensor]
            print(f"| {scene} | {sensor} | {len(v)} | {sum(r['success'] for r in v)} | "
                  f"{sum(r['converged'] for r in v)} | {sum(r['confident_wrong'] for r in v)} | "
                  f"{median(r['converged_at_s'] for r in v)} | {median(r['settled_s'] for r in v)} |")
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(7, 3.5))
        scenes = a.scenes.split(",")
        for i, scene in enumerate(scenes):
            v = [r for r in rows if r["scene"] == scene]
            for r in v:
                x = r["converged_at_s"] if r["converged"] else r["duration_s"]
                color = "tab:green" if r["right"] else ("tab:red" if r["converged"] else "tab:gray")
                ax.scatter(x, i, color=color, marker="o" if r["converged"] else "x")
        ax.axvline(a.limit, color="k", lw=0.8, ls="--")
        ax.set_yticks(range(len(scenes)), scenes)
        ax.set_xlabel("time to converge [s] (x: not converged by the end; red: converged to a wrong place)")
        ax.set_title("global localization (no --init): time until the filter says it converged")
        fig.tight_layout()
        fig.savefig(os.path.join(a.out, f"global-{a.tag}.png"), dpi=120)
    except ImportError:
        print("matplotlib missing: no chart", file=sys.stderr)


if __name__ == "__main__":
    main()
