#!/usr/bin/env python3
"""Sensor sweep (issue 13): simulated lasers x scenes, each log mapped several ways, scored
against the true floorplan. Prints Markdown tables (glass cell F1@2, glass segment F1, false glass
on glass-free floors, the MRF against the direct classifier, and the calibration of the fitted
range noise and lobe against the simulated numbers) and writes OUT/results.json.

Lasers (--profiles): the five named scanner profiles of `glassmap simulate --sensor`, `random:SEED`
profiles, `scene` (the scene's own laser: no --sensor), and the custom lasers of CUSTOM below (`noisy-fine`: the finer, noisier laser of issue 13:
0.25 deg beams, 3 cm noise, 3% max readings, a 4 deg / 0.55 lobe).
Scenes (positional): bundled scene names (maps/<name>), `glass-room@ANGLE` (the glass meeting
room of maps/glass-room turned ANGLE degrees, drawn by maps/make_floorplans.py), or scene files.
Modes (--modes): default (`glassmap map` as is: calibrated, MRF), direct (`--method direct`),
uncalibrated (`--no-calibrate`), oracle (`--sensor truth.yaml`: the simulated laser's own numbers),
no-lobe (`--no-profile-lobe`: the fitted range noise but the default 2 deg / 0.9 lobe, the default
before stop 33), lobe (`--profile-lobe`, the default since stop 33), search / no-search (`--lobe-search`: a second look with a broad lobe for a lobe the first pass could not fit, the default at stop 33; `--no-lobe-search`: none, the default since stop 34), raw (the default without the phantom test and the pane fit of the cells), sparse
(`--sparse-panes`: the search for panes too faint for the classifiers, on by default since it rejects
people walking by), no-sparse (`--no-sparse-panes`: the default without it), direct-sparse (both),
rounds1 / rounds2 / rounds3 (`--calibration-rounds 1` / `2` / `3`: fit and map at most once / twice / three times; rounds1-search: one round with `--lobe-search`; 1 was the default before stop 34, 2 since), mrf-w1 / mrf-w4 (the default with `--mrf-weight 1` / `4`: the MRF weight before stop 28, and a
stronger one), emp-log (`--p-hit-empty-from-log`: the direct classifier's P(hit | empty cell) from
the log's own empty space instead of 0.02; results.json also records each run's `empty_hit_rate`
and the `p_hit_emp` used).

With --people D every log is simulated with D people per 100 m^2 walking (`simulate --people`).

Usage: tools/sensor_sweep.py [--build build] [--seed 1] [--rate 10] [--people 0] [--out out/sensor_sweep]
         [--profiles a,b] [--modes default,direct] [-j 2] [scene ...]
       tools/sensor_sweep.py --from-results out/sensor_sweep/results.json [--modes default,direct]
"""
import argparse
import concurrent.futures as cf
import json
import os
import re
import shutil
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
PROFILES = ["sick-lms200", "hokuyo-urg04lx", "hokuyo-utm30lx", "rplidar-a2", "sick-tim571"]
SCENES = ["paper-corridor", "glass-corridor", "office-floor", "no-glass", "glass-room"]
MODES = ["default", "direct", "uncalibrated", "oracle"]
MODE_ARGS = {"default": [], "direct": ["--method", "direct"], "uncalibrated": ["--no-calibrate"],
             "oracle": ["--profile-lobe"], "lobe": ["--profile-lobe"], "no-lobe": ["--no-profile-lobe"], "no-search": ["--no-lobe-search"], "search": ["--lobe-search"], "rounds1": ["--calibration-rounds", "1"], "rounds1-search": ["--calibration-rounds", "1", "--lobe-search"], "rounds2": ["--calibration-rounds", "2"], "rounds3": ["--calibration-rounds", "3"], "raw": ["--keep-phantoms", "--keep-unfitted-glass"],
             "direct-raw": ["--method", "direct", "--keep-phantoms", "--keep-unfitted-glass"],
             "sparse": ["--sparse-panes"], "no-sparse": ["--no-sparse-panes"], "mrf-w1": ["--mrf-weight", "1"], "mrf-w4": ["--mrf-weight", "4"], "direct-sparse": ["--method", "direct", "--sparse-panes"],
             "emp-log": ["--p-hit-empty-from-log"]}
# Lasers that are no named profile: scene keys laid over the scene's laser and glass.
CUSTOM = {
    "noisy-fine": {"laser": "{preset: hokuyo-utm30lx, rate: 10, resolution_deg: 0.25, range_sigma: 0.03, "
                            "dropout_rate: 0.03}",
                   "glass": "{n_glass: 1.5, direct_sigma_deg: 4.0, direct_peak: 0.55, reflection_gain: 1.0}"},
    # The scene's default laser with 6 cm range noise and the same weak lobe: where mapping breaks.
    "noisy-6cm": {"laser": "{range_sigma: 0.06}",
                  "glass": "{n_glass: 1.5, direct_sigma_deg: 4.0, direct_peak: 0.55, reflection_gain: 1.0}"},
}


def run(cmd):
    r = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    if r.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)}: {r.stderr.strip()}")


def scene_file(scene, work):
    """A scene.yaml path for a scene argument (bundled name, glass-room@ANGLE or a file)."""
    if scene.endswith(".yaml"):
        return os.path.abspath(scene)
    m = re.fullmatch(r"glass-room@(-?[0-9.]+)", scene)
    if not m:
        return os.path.join(ROOT, "maps", scene, "scene.yaml")
    angle = float(m.group(1))
    folder = os.path.join(work, "scenes", scene)
    os.makedirs(folder, exist_ok=True)
    sys.path.insert(0, os.path.join(ROOT, "maps"))
    import make_floorplans as mf
    mf.glass_room(angle, folder)
    text = open(os.path.join(ROOT, "maps", "glass-room", "scene.yaml")).read()
    text = re.sub(r"waypoints: \[\[.*?\]\]\n", "waypoints: " + json.dumps(mf.glass_room_waypoints(angle) * 2) + "\n",
                  text, flags=re.S)
    path = os.path.join(folder, "scene.yaml")
    with open(path, "w") as f:
        f.write(text)
    return path


def custom_scene(base_yaml, laser, work_dir):
    """The scene with a custom laser's keys laid over its laser and glass lines."""
    text = open(base_yaml).read()
    for key, value in CUSTOM[laser].items():
        text, n = re.subn(rf"^{key}:.*$", f"{key}: {value}", text, flags=re.M)
        if n == 0:
            text += f"\n{key}: {value}\n"
    os.makedirs(work_dir, exist_ok=True)
    src_dir = os.path.dirname(base_yaml)
    plan = re.search(r"^floorplan:\s*(\S+)", text, flags=re.M).group(1)
    shutil.copy(os.path.join(src_dir, plan), os.path.join(work_dir, os.path.basename(plan)))
    text = re.sub(r"^floorplan:.*$", f"floorplan: {os.path.basename(plan)}", text, flags=re.M)
    path = os.path.join(work_dir, "scene.yaml")
    with open(path, "w") as f:
        f.write(text)
    return path


def truth_profile(meta, path):
    """The simulated laser as a sensor profile (what a perfect calibration would find)."""
    s = meta["sensor"] if "sensor" in meta else meta["scene"]
    laser, glass = s["laser"], s["glass"]
    with open(path, "w") as f:
        f.write("source: simulated truth\n")
        f.write(f"range_sigma_m: {max(laser['range_sigma'], 1e-4)}\n")
        f.write(f"range_sigma_rel: {laser.get('range_sigma_rel', 0.0)}\n")
        f.write(f"direct_peak: {glass['direct_peak']}\n")
        f.write(f"direct_sigma_deg: {glass['direct_sigma_deg']}\n")
        f.write(f"direct_floor: {glass.get('direct_floor', 0.0)}\n")


def one_case(gm, profile, scene, a):
    base = os.path.join(a.out, profile.replace(":", "-"), scene)
    sim = os.path.join(base, "sim")
    yaml = scene_file(scene, a.out)
    sim_args = ["--seed", str(a.seed), "--rate", str(a.rate), "-q"] + (["--people", str(a.people)] if a.people else [])
    if profile in CUSTOM:
        yaml = custom_scene(yaml, profile, os.path.join(base, "scene"))
    elif profile != "scene":
        sim_args += ["--sensor", profile]
    run([gm, "simulate", yaml, "-o", sim] + sim_args)
    meta = json.load(open(os.path.join(sim, "meta.json")))
    truth_yaml = os.path.join(base, "truth.yaml")
    truth_profile(meta, truth_yaml)
    truth = os.path.join(sim, "floorplan.gpkg")
    row = {"profile": profile, "scene": scene}
    for mode in a.modes:
        out = os.path.join(base, mode)
        extra = MODE_ARGS[mode] + (["--sensor", truth_yaml] if mode == "oracle" else [])
        run([gm, "map", os.path.join(sim, "log.clf"), "-o", out, "-q"] + extra)
        stats = json.load(open(os.path.join(out, "stats.json")))
        cj, sj = os.path.join(out, "cells.json"), os.path.join(out, "segments.json")
        run([gm, "eval", "cells", "--truth", truth, "--labels", os.path.join(out, "labels.tif"), "--json", cj, "-q"])
        run([gm, "eval", "segments", "--truth", truth, "--pred", os.path.join(out, "floorplan.gpkg"), "--json", sj,
             "-q"])
        c, s = json.load(open(cj)), json.load(open(sj))
        row[mode] = {"cell_f1": c["tolerant"]["f1"], "cell_p": c["tolerant"]["precision"],
                     "cell_r": c["tolerant"]["recall"], "segment_f1": s["glass"]["f1"],
                     "glass_m": s["glass"]["pred_length_m"], "wall_f1": s["wall"]["f1"]}
        if "empty_space" in stats:
            row[mode]["empty_hit_rate"] = stats["empty_space"]["hit_rate"]
            row[mode]["p_hit_emp"] = stats["empty_space"]["p_hit_emp"]
        if mode == "default" and "sensor" in stats:
            s_meta = meta["sensor"] if "sensor" in meta else meta["scene"]
            laser, glass = s_meta["laser"], s_meta["glass"]
            p = stats["sensor"]
            row["calibration"] = {
                "range_sigma_m": [p["range_sigma_m"], laser["range_sigma"]],
                "range_sigma_rel": [p.get("range_sigma_rel", 0.0), laser.get("range_sigma_rel", 0.0)],
                "direct_sigma_deg": [p["direct_sigma_deg"], glass["direct_sigma_deg"]],
                "direct_peak": [p["direct_peak"], glass["direct_peak"]],
                "direct_floor": [p["direct_floor"], glass.get("direct_floor", 0.0)],
                "fitted": p["fitted"]}
    return row


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--rate", type=float, default=10.0, help="scan rate [Hz] (the bundled scenes use 10)")
    ap.add_argument("--people", type=float, default=0.0, help="people walking per 100 m^2 (0: the scene's own)")
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "sensor_sweep"))
    ap.add_argument("--profiles", default=",".join(PROFILES))
    ap.add_argument("--modes", default=",".join(MODES))
    ap.add_argument("-j", "--jobs", type=int, default=2)
    ap.add_argument("--from-results", metavar="RESULTS_JSON",
                    help="run nothing: print the tables and the summary of an earlier run's results.json")
    ap.add_argument("scenes", nargs="*", default=SCENES)
    a = ap.parse_args()
    a.out = os.path.abspath(a.out)
    a.modes = a.modes.split(",")
    if a.from_results:
        with open(a.from_results) as f:
            rows = json.load(f)
        modes = [m for m in a.modes if rows and m in rows[0]] or [m for m in MODES if rows and m in rows[0]]
        print_tables(rows, modes)
        print_summary(rows, modes)
        return 0
    gm = os.path.join(os.path.abspath(a.build), "tools", "glassmap")
    cases = [(p, s) for p in a.profiles.split(",") for s in a.scenes]
    for s in a.scenes:  # draw generated scenes once, before the parallel runs
        scene_file(s, a.out)
    results = {}
    with cf.ThreadPoolExecutor(max_workers=a.jobs) as pool:
        futures = {pool.submit(one_case, gm, p, s, a): (p, s) for p, s in cases}
        for f in cf.as_completed(futures):
            p, s = futures[f]
            try:
                row = f.result()
            except Exception as e:  # a failed run is a result too
                print(f"FAILED {p} {s}: {e}", file=sys.stderr, flush=True)
                continue
            results[(p, s)] = row
            print(p, s, {m: round(row[m]["cell_f1"], 3) for m in a.modes}, flush=True)
    rows = [results[c] for c in cases if c in results]
    os.makedirs(a.out, exist_ok=True)
    with open(os.path.join(a.out, "results.json"), "w") as f:
        json.dump(rows, f, indent=1)
    print_tables(rows, a.modes)
    print_summary(rows, a.modes)
    return 0 if len(rows) == len(cases) else 1


def print_summary(rows, modes):
    """Per scene with glass and mode: rows with cell F1@2 and glass segment F1 at least 0.9, mean
    cell F1@2; glass-free floors with glass drawn; rows where the default (MRF) is below the direct
    classifier by more than 0.005, and by how much in all."""
    print("\n| scene | mode | laser rows | cell F1@2 >= 0.9 | glass segment F1 >= 0.9 | mean cell F1@2 |")
    print("| --- | --- | --- | --- | --- | --- |")
    scenes = [s for s in dict.fromkeys(r["scene"] for r in rows) if s != "no-glass"]
    for scene in scenes:
        of = [r for r in rows if r["scene"] == scene]
        for m in modes:
            cells = [r[m]["cell_f1"] for r in of]
            segs = [r[m]["segment_f1"] for r in of]
            print(f"| {scene} | {m} | {len(of)} | {sum(c >= 0.9 for c in cells)} | {sum(x >= 0.9 for x in segs)} "
                  f"| {sum(cells) / len(cells):.3f} |")
    for m in modes:
        drawn = [(r["profile"], r[m]["glass_m"]) for r in rows if r["scene"] == "no-glass" and r[m]["glass_m"] > 0]
        floors = sum(r["scene"] == "no-glass" for r in rows)
        if floors:
            print(f"\n{m}: glass drawn on {len(drawn)} of {floors} glass-free floors"
                  + ("" if not drawn else ": " + ", ".join(f"{p} {g:.1f} m" for p, g in drawn)))
    if "default" in modes and "direct" in modes:
        glass = [r for r in rows if r["scene"] != "no-glass"]
        below = [r for r in glass if r["default"]["cell_f1"] < r["direct"]["cell_f1"] - 0.005]
        deficit = sum(r["direct"]["cell_f1"] - r["default"]["cell_f1"] for r in below)
        print(f"\nthe default below the direct classifier by more than 0.005 on {len(below)} of {len(glass)} rows "
              f"with glass (summed deficit {deficit:.2f})"
              + "".join(f"\n  {r['profile']} {r['scene']}: {r['default']['cell_f1']:.3f} against "
                        f"{r['direct']['cell_f1']:.3f}" for r in below))


def print_tables(rows, modes):
    def fmt(x):
        return "–" if x is None else f"{x:.3f}"
    print(f"\n| laser | scene | cell F1@2 ({' / '.join(modes)}) | glass segment F1 (same) | glass drawn on a "
          f"glass-free floor [m] |")
    print("| --- | --- | --- | --- | --- |")
    for r in rows:
        glass_free = r["scene"] == "no-glass"
        cells = " / ".join("–" if glass_free else fmt(r[m]["cell_f1"]) for m in modes)
        segs = " / ".join("–" if glass_free else fmt(r[m]["segment_f1"]) for m in modes)
        false_m = " / ".join(f"{r[m]['glass_m']:.1f}" for m in modes) if glass_free else ""
        print(f"| {r['profile']} | {r['scene']} | {cells} | {segs} | {false_m} |")
    cal = [r for r in rows if "calibration" in r]
    if not cal:
        return
    print("\n| laser | scene | range sigma fitted / true [m] | growth with range fitted / true [%] "
          "| lobe sigma fitted / true [deg] | peak fitted / true | floor fitted / true |")
    print("| --- | --- | --- | --- | --- | --- | --- |")
    for r in cal:
        c = r["calibration"]
        lobe = "not fitted" if "direct_sigma_deg" not in c["fitted"] else \
            f"{c['direct_sigma_deg'][0]:.1f} / {c['direct_sigma_deg'][1]:.1f}"
        peak = "" if "direct_peak" not in c["fitted"] else f"{c['direct_peak'][0]:.2f} / {c['direct_peak'][1]:.2f}"
        floor = "" if "direct_floor" not in c["fitted"] else f"{c['direct_floor'][0]:.3f} / {c['direct_floor'][1]:.3f}"
        rel = c.get("range_sigma_rel", [0.0, 0.0])
        print(f"| {r['profile']} | {r['scene']} | {c['range_sigma_m'][0]:.4f} / {c['range_sigma_m'][1]:.4f} | "
              f"{100 * rel[0]:.2f} / {100 * rel[1]:.2f} | {lobe} | {peak} | {floor} |")


if __name__ == "__main__":
    sys.exit(main())
