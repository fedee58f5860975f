#!/usr/bin/env python3
"""Localization defaults against the sensor profiles (issue 14): each bundled scene is simulated
with each scanner profile (`glassmap simulate --sensor NAME|random:SEED`), then localized against
the true floorplan from the first true pose with several option sets ("settings"); ATE RMSE from
`glassmap eval traj`. Prints per setting the mean / worst ATE over the runs and a Markdown table
of the chosen settings per profile; writes every run to OUT/results.csv and a chart OUT/ate.png.

Settings are "name=extra localize arguments", separated by ';'. "default" (no extra argument) is
always run. "oracle" is a setting made per run: the simulator's own numbers (meta.json) as a
sensor profile (`--sensor`): the range noise, spurious-reading weights and glass lobe that made
the log. "calibrated" is also made per run: the profile `glassmap calibrate LOG --map PLAN` fits to
the log against the plan, given with `--sensor` (the default fits the model inside the filter).

Usage: tools/loc_sweep.py [--glassmap build/tools/glassmap] [--out out/loc_sweep]
    [--scenes paper-corridor,glass-corridor,no-glass,office-floor]
    [--sensors sick-lms200,...,random:1] [--seeds 1] [--settings "p500=--min-particles 500;..."]
    [--models glass] [--oracle] [--calibrated] [--jobs 2]
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
SENSORS = ["sick-lms200", "hokuyo-urg04lx", "hokuyo-utm30lx", "rplidar-a2", "sick-tim571",
           "random:1", "random:2", "random:3"]


def run(cmd, **kw):
    subprocess.run([str(c) for c in cmd], check=True, stdout=subprocess.DEVNULL, **kw)


def oracle_profile(meta, path):
    """The simulator's numbers as a sensor profile (YAML keys of `glassmap calibrate`)."""
    laser, glass = meta["sensor"]["laser"], meta["sensor"]["glass"]
    short, rand, drop = laser.get("short_rate", 0), laser.get("random_rate", 0), laser.get("dropout_rate", 0)
    # Range noise grows with range: the typical sigma at half of a 10 m reach.
    sigma = math.hypot(laser["range_sigma"], laser.get("range_sigma_rel", 0) * 5.0)
    hit = max(1e-3, 1.0 - short - rand - drop)
    keys = {"range_sigma_m": sigma, "w_hit": hit, "w_short": max(short, 1e-3), "w_max": max(drop, 1e-3),
            "w_rand": max(rand, 1e-3), "lambda_short": laser.get("short_lambda", 1.0),
            "direct_peak": glass["direct_peak"], "direct_sigma_deg": glass["direct_sigma_deg"],
            "direct_floor": glass.get("direct_floor", 0.0), "normal_floor": glass.get("reflection_floor", 0.0)}
    with open(path, "w") as f:
        for k, v in keys.items():
            f.write(f"{k}: {v:.6g}\n")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--glassmap", default=os.path.join(ROOT, "build", "tools", "glassmap"))
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "loc_sweep"))
    ap.add_argument("--scenes", default=",".join(SCENES))
    ap.add_argument("--sensors", default=",".join(SENSORS))
    ap.add_argument("--seeds", default="1")
    ap.add_argument("--models", default="glass")
    ap.add_argument("--beams", type=int, default=15)
    ap.add_argument("--settings", default="", help="name=extra localize arguments, separated by ';'")
    ap.add_argument("--oracle", action="store_true", help="also run the 'oracle' setting (the simulator's numbers)")
    ap.add_argument("--calibrated", action="store_true",
                    help="also run the 'calibrated' setting (`glassmap calibrate LOG --map PLAN` as --sensor)")
    ap.add_argument("--sim-args", default="", help="extra `glassmap simulate` arguments (e.g. --rate 10)")
    ap.add_argument("--motion", default="",
                    help="scene motion keys to override, as YAML (e.g. '{odom_trans_sigma: 0.05}'): the scene is "
                         "copied under OUT/scenes with them")
    ap.add_argument("--jobs", type=int, default=2)
    a = ap.parse_args()
    gm = a.glassmap
    scenes, sensors = a.scenes.split(","), a.sensors.split(",")
    seeds = [int(s) for s in a.seeds.split(",")]
    models = a.models.split(",")
    settings = [("default", "")] + [tuple(s.split("=", 1)) for s in a.settings.split(";") if s]
    if a.calibrated:
        settings.append(("calibrated", "@calibrated"))
    if a.oracle:
        settings.append(("oracle", None))
    sim_tag = (a.sim_args + a.motion).replace("--", "").replace(" ", "").replace(":", "=") or "plain"
    sim_tag = "".join(c for c in sim_tag if c.isalnum() or c in "=._,-")

    def scene_file(scene):
        src = os.path.join(ROOT, "maps", scene, "scene.yaml")
        if not a.motion:
            return src
        import yaml
        d = os.path.join(a.out, "scenes", sim_tag, scene)
        os.makedirs(d, exist_ok=True)
        y = yaml.safe_load(open(src))
        y["floorplan"] = os.path.abspath(os.path.join(ROOT, "maps", scene, y["floorplan"]))
        y.setdefault("motion", {}).update(yaml.safe_load(a.motion))
        with open(os.path.join(d, "scene.yaml"), "w") as f:
            yaml.safe_dump(y, f)
        return os.path.join(d, "scene.yaml")

    def sim_dir(scene, sensor, seed):
        return os.path.join(a.out, "sim", sim_tag, scene, sensor.replace(":", "-"), f"seed{seed}")

    def simulate(job):
        d = sim_dir(*job)
        if not os.path.exists(os.path.join(d, "meta.json")):
            scene, sensor, seed = job
            run([gm, "simulate", scene_file(scene), "-o", d, "--seed", seed,
                 "--sensor", sensor, "-q"] + a.sim_args.split())
        if a.oracle and not os.path.exists(os.path.join(d, "oracle.yaml")):
            oracle_profile(json.load(open(os.path.join(d, "meta.json"))), os.path.join(d, "oracle.yaml"))
        if a.calibrated and not os.path.exists(os.path.join(d, "calibrated.yaml")):
            run([gm, "calibrate", os.path.join(d, "log.clf"), "--map", os.path.join(d, "floorplan.gpkg"),
                 "-o", os.path.join(d, "calibrated.yaml"), "-q"])

    def localize(job):
        scene, sensor, seed, model, (name, extra) = job
        d = sim_dir(scene, sensor, seed)
        r = os.path.join(d, f"{model}-{name}")
        os.makedirs(r, exist_ok=True)
        init = json.load(open(os.path.join(d, "meta.json")))["start_pose"]
        if extra is None:
            args = ["--sensor", os.path.join(d, "oracle.yaml")]
        elif extra == "@calibrated":
            args = ["--sensor", os.path.join(d, "calibrated.yaml")]
        else:
            args = extra.split()
        run([gm, "localize", "--map", os.path.join(d, "floorplan.gpkg"), os.path.join(d, "log.clf"),
             "-o", os.path.join(r, "est.tum"), "--model", model, "--beams", a.beams, "--seed", seed,
             "--init", "%.6f,%.6f,%.6f" % tuple(init), "-q", "--json", os.path.join(r, "loc.json")] + args)
        run([gm, "eval", "traj", "--truth", os.path.join(d, "groundtruth.tum"), os.path.join(r, "est.tum"),
             "--json", os.path.join(r, "ate.json"), "-q"])
        e = json.load(open(os.path.join(r, "ate.json")))
        s = json.load(open(os.path.join(r, "loc.json")))
        row = {"scene": scene, "sensor": sensor, "seed": seed, "model": model, "setting": name,
               "rmse": e["rmse"], "max": e["max"], "particles": s["mean_particles"],
               "ms_per_update": s["ms_per_update"], "sigma_hit": s.get("sigma_hit", "")}
        print(f"{scene:15s} {sensor:15s} {seed} {model:6s} {name:12s} ATE {row['rmse']:.4f} max {row['max']:.3f} "
              f"particles {row['particles']:.0f}", file=sys.stderr, flush=True)
        return row

    with ThreadPoolExecutor(a.jobs) as ex:
        list(ex.map(simulate, [(sc, se, k) for sc in scenes for se in sensors for k in seeds]))
        jobs = [(sc, se, k, m, st) for sc in scenes for se in sensors for k in seeds for m in models for st in settings]
        rows = list(ex.map(localize, jobs))
    os.makedirs(a.out, exist_ok=True)
    with open(os.path.join(a.out, "results.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)

    # Per setting and model: mean and worst ATE over every run.
    print("| model | setting | mean ATE [m] | worst ATE [m] | runs over 0.025 m | mean particles |")
    print("| --- | --- | ---: | ---: | ---: | ---: |")
    for m in models:
        for name, _ in settings:
            v = [r for r in rows if r["model"] == m and r["setting"] == name]
            print(f"| {m} | {name} | {sum(r['rmse'] for r in v) / len(v):.4f} | {max(r['rmse'] for r in v):.4f} | "
                  f"{sum(r['rmse'] > 0.025 for r in v)} of {len(v)} | "
                  f"{sum(r['particles'] for r in v) / len(v):.0f} |")
    # Per profile: each setting's mean ATE over scenes and seeds.
    print()
    print("| model | sensor | " + " | ".join(n for n, _ in settings) + " |")
    print("| --- | --- | " + " | ".join("---:" for _ in settings) + " |")
    for m in models:
        for se in sensors:
            cells = []
            for name, _ in settings:
                v = [r["rmse"] for r in rows if r["model"] == m and r["sensor"] == se and r["setting"] == name]
                cells.append(f"{sum(v) / len(v):.4f} / {max(v):.3f}")
            print(f"| {m} | {se} | " + " | ".join(cells) + " |")
    chart(rows, models, sensors, scenes, [n for n, _ in settings], a.out)


def chart(rows, models, sensors, scenes, names, out):
    """OUT/ate.png: ATE RMSE per laser and scene, a bar per setting, a panel per model."""
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib missing: no chart", file=sys.stderr)
        return
    fig, axes = plt.subplots(len(models), 1, figsize=(max(8, 0.5 * len(sensors) * len(scenes)), 3.2 * len(models)),
                             squeeze=False)
    groups = [(se, sc) for se in sensors for sc in scenes]
    width = 0.8 / max(len(names), 1)
    for ax, m in zip(axes[:, 0], models):
        for j, name in enumerate(names):
            ys = []
            for se, sc in groups:
                v = [r["rmse"] for r in rows if r["model"] == m and r["sensor"] == se and r["scene"] == sc
                     and r["setting"] == name]
                ys.append(1000 * sum(v) / len(v) if v else 0.0)
            ax.bar([i + j * width for i in range(len(groups))], ys, width, label=name)
        ax.axhline(25, color="k", lw=0.8, ls="--")  # the 25 mm
        ax.set_xticks([i + 0.4 - width / 2 for i in range(len(groups))])
        ax.set_xticklabels([f"{se}\n{sc}" for se, sc in groups], rotation=90, fontsize=6)
        ax.set_ylabel("ATE RMSE [mm]")
        ax.set_title(f"model {m}")
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "ate.png"), dpi=110)
    print(f"chart: {os.path.join(out, 'ate.png')}", file=sys.stderr)


if __name__ == "__main__":
    main()
