#!/usr/bin/env python3
"""Sensor sweep (issue 13): every simulated sensor profile x scene, mapped four ways: with the
default thresholds (`--no-calibrate`), calibrated from the log (the default: range-noise
thresholds), calibrated with the fitted glass lobe in the classifier (`--profile-lobe`), and with
the true (oracle) profile and its lobe (`--sensor truth.yaml --profile-lobe`). Prints Markdown tables of glass cell F1@2, glass segment F1
and false glass on the glass-free floor, and the calibration error of the fitted range noise and
lobe width against the simulated ones. Writes out/sensor_sweep/results.json.

Usage: tools/sensor_sweep.py [--build build] [--seed 1] [--rate 10] [--out out/sensor_sweep]
                             [--profiles a,b] [scene ...]
"""
import argparse
import json
import os
import subprocess

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
PROFILES = ["sick-lms200", "hokuyo-urg04lx", "hokuyo-utm30lx", "rplidar-a2", "sick-tim571"]
MODES = ["default", "calibrated", "calibrated+lobe", "oracle+lobe"]


def run(cmd):
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)


def truth_profile(meta, path):
    """The simulated laser as a sensor profile (what a perfect calibration would find)."""
    s = meta["sensor"]
    laser, glass = s["laser"], s["glass"]
    with open(path, "w") as f:
        f.write("source: simulated truth\n")
        f.write(f"range_sigma_m: {laser['range_sigma']}\n")
        f.write(f"direct_peak: {glass['direct_peak']}\n")
        f.write(f"direct_sigma_deg: {glass['direct_sigma_deg']}\n")
        f.write(f"direct_floor: {glass.get('direct_floor', 0.0)}\n")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--rate", type=float, default=10.0, help="scan rate [Hz] (the bundled scenes use 10)")
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "sensor_sweep"))
    ap.add_argument("--profiles", default=",".join(PROFILES))
    ap.add_argument("scenes", nargs="*", default=["paper-corridor", "glass-corridor", "office-floor", "no-glass"])
    a = ap.parse_args()
    gm = os.path.join(a.build, "tools", "glassmap")
    results = []
    for profile in a.profiles.split(","):
        for scene in a.scenes:
            base = os.path.join(a.out, profile, scene)
            sim = os.path.join(base, "sim")
            run([gm, "simulate", os.path.join(ROOT, "maps", scene, "scene.yaml"), "-o", sim, "--seed", str(a.seed),
                 "--sensor", profile, "--rate", str(a.rate), "-q"])
            meta = json.load(open(os.path.join(sim, "meta.json")))
            truth_yaml = os.path.join(base, "truth.yaml")
            truth_profile(meta, truth_yaml)
            truth = os.path.join(sim, "floorplan.gpkg")
            row = {"profile": profile, "scene": scene}
            for mode in MODES:
                out = os.path.join(base, mode)
                extra = {"default": ["--no-calibrate"], "calibrated": [], "calibrated+lobe": ["--profile-lobe"],
                         "oracle+lobe": ["--sensor", truth_yaml, "--profile-lobe"]}[mode]
                run([gm, "map", os.path.join(sim, "log.clf"), "-o", out, "-q"] + extra)
                stats = json.load(open(os.path.join(out, "stats.json")))
                cj, sj = os.path.join(out, "cells.json"), os.path.join(out, "segments.json")
                run([gm, "eval", "cells", "--truth", truth, "--labels", os.path.join(out, "labels.tif"), "--json", cj,
                     "-q"])
                run([gm, "eval", "segments", "--truth", truth, "--pred", os.path.join(out, "floorplan.gpkg"),
                     "--json", sj, "-q"])
                c, s = json.load(open(cj)), json.load(open(sj))
                row[mode] = {"cell_f1": c["tolerant"]["f1"], "segment_f1": s["glass"]["f1"],
                             "glass_m": s["glass"]["pred_length_m"], "wall_f1": s["wall"]["f1"]}
                if mode == "calibrated":
                    laser, glass = meta["sensor"]["laser"], meta["sensor"]["glass"]
                    p = stats["sensor"]
                    row["calibration"] = {
                        "range_sigma_m": [p["range_sigma_m"], laser["range_sigma"]],
                        "direct_sigma_deg": [p["direct_sigma_deg"], glass["direct_sigma_deg"]],
                        "direct_peak": [p["direct_peak"], glass["direct_peak"]],
                        "direct_floor": [p["direct_floor"], glass.get("direct_floor", 0.0)],
                        "fitted": p["fitted"]}
            results.append(row)
            print(profile, scene, {m: round(row[m]["cell_f1"], 3) for m in MODES}, flush=True)
    os.makedirs(a.out, exist_ok=True)
    with open(os.path.join(a.out, "results.json"), "w") as f:
        json.dump(results, f, indent=1)

    def fmt(x):
        return "–" if x is None else f"{x:.3f}"
    print("\n| profile | scene | cell F1@2 default / calibrated / +lobe / oracle+lobe | glass segment F1 (same four) | glass drawn on no-glass [m] |")
    print("| --- | --- | --- | --- | --- |")
    for r in results:
        glass_free = r["scene"] == "no-glass"
        cells = " / ".join("–" if glass_free else fmt(r[m]["cell_f1"]) for m in MODES)
        segs = " / ".join("–" if glass_free else fmt(r[m]["segment_f1"]) for m in MODES)
        false_m = " / ".join(f"{r[m]['glass_m']:.1f}" for m in MODES) if glass_free else ""
        print(f"| {r['profile']} | {r['scene']} | {cells} | {segs} | {false_m} |")
    print("\n| profile | scene | range sigma fitted / true [m] | lobe sigma fitted / true [deg] | peak fitted / true | floor fitted / true |")
    print("| --- | --- | --- | --- | --- | --- |")
    for r in results:
        c = r["calibration"]
        lobe = "not fitted" if "direct_sigma_deg" not in c["fitted"] else \
            f"{c['direct_sigma_deg'][0]:.1f} / {c['direct_sigma_deg'][1]:.1f}"
        peak = "" if "direct_peak" not in c["fitted"] else f"{c['direct_peak'][0]:.2f} / {c['direct_peak'][1]:.2f}"
        floor = "" if "direct_floor" not in c["fitted"] else f"{c['direct_floor'][0]:.3f} / {c['direct_floor'][1]:.3f}"
        print(f"| {r['profile']} | {r['scene']} | {c['range_sigma_m'][0]:.4f} / {c['range_sigma_m'][1]:.4f} | "
              f"{lobe} | {peak} | {floor} |")


if __name__ == "__main__":
    main()
