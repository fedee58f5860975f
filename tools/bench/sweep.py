#!/usr/bin/env python3
"""glassmap bench: speed against accuracy, and where each method breaks (issue 8).

Drives the `glassmap` command line (simulate, map, localize, eval) over seeds and writes CSV files
plus charts (PNG and SVG). Every figure comes from running the binaries; nothing is hard-coded.

  tools/bench/sweep.py --quick --out build-bench-quick      # CI-sized, a few minutes
  tools/bench/sweep.py --out docs/results                   # full mode

Seeds are derived from --base-seed with a hash of (purpose, scene, trial index), so the same
command gives the same CSV rows (timing columns aside). The same simulated logs are used for every
method and every value of a swept quantity (paired comparison).
"""
from __future__ import annotations

import argparse
import copy
import csv
import hashlib
import json
import math
import os
import shutil
import subprocess
import sys
import threading
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
SUCCESS_ATE_M = 0.2      # localization succeeds when the ATE RMSE is under this [m]
SUCCESS_F1 = 0.8         # mapping succeeds when the glass F1 (cells, 2-cell tolerance) is over this
BREAK_RATE = 0.5         # a method "breaks" at the first swept value whose success rate is below this
WITHIN = 0.10            # "cheapest setting within 10% of the best accuracy"
LOC_ABS_TOL_M = 0.01     # ... or, for localization, within 1 cm of the best ATE
RECOVER_HOLD_S = 10.0    # a kidnapped filter recovered when its error stays under SUCCESS_ATE_M from some
                         # time on to the end of the run, and the run goes on this long after that [s]

# localization model variants: label -> (--model, --glass-as)
LOC_MODELS = {
    "beam-opaque": ("beam", "opaque"),
    "beam-invisible": ("beam", "invisible"),
    "field": ("field", "opaque"),
    "glass-paper": ("glass-paper", "opaque"),
    "glass": ("glass", "opaque"),
}
MAP_METHODS = ["heuristic", "direct", "mrf"]
COLORS = {"beam-opaque": "tab:red", "beam-invisible": "tab:orange", "field": "tab:purple",
          "glass-paper": "tab:blue", "glass": "tab:green",
          "heuristic": "tab:orange", "direct": "tab:blue", "mrf": "tab:green"}


# ----------------------------------------------------------------------------------------------
# pure logic (unit-tested in tests/bench/test_sweep.py)

def derive_seed(base: int, *keys) -> int:
    """Deterministic seed in [1, 2^31) from a base seed and any keys (stable across runs/platforms)."""
    text = "|".join([str(int(base))] + [str(k) for k in keys])
    return int(hashlib.sha256(text.encode()).hexdigest()[:8], 16) % (2**31 - 1) + 1


def trial_seeds(base: int, scene: str, n: int) -> list[tuple[int, int, int]]:
    """(trial index, simulation seed, localizer seed) for n trials of a scene; independent of
    the method and the swept value, so every method sees the same logs."""
    return [(i, derive_seed(base, "sim", scene, i), derive_seed(base, "loc", scene, i))
            for i in range(n)]


def _finite(x) -> bool:
    try:
        return x is not None and math.isfinite(float(x))
    except (TypeError, ValueError):
        return False


def loc_success(ate_rmse) -> bool:
    return _finite(ate_rmse) and float(ate_rmse) < SUCCESS_ATE_M


def map_success(f1) -> bool:
    return _finite(f1) and float(f1) > SUCCESS_F1


def success_rate(flags) -> float:
    flags = list(flags)
    return float("nan") if not flags else sum(1 for f in flags if f) / len(flags)


def break_value(values, rates, threshold: float = BREAK_RATE):
    """First swept value (in sweep order) whose success rate is below threshold; None if none."""
    for v, r in zip(values, rates):
        if not _finite(r) or r < threshold:
            return v
    return None


def cheapest_within(rows, acc_key: str, cost_key: str, higher_is_better: bool, tol: float = WITHIN,
                    abs_tol: float = 0.0):
    """(best row, cheapest row whose accuracy is within tol (relative) of the best, or within abs_tol
    of it). Rows lacking a finite accuracy or cost are ignored; (None, None) if nothing is left."""
    rows = [r for r in rows if _finite(r.get(acc_key)) and _finite(r.get(cost_key))]
    if not rows:
        return None, None
    if higher_is_better:
        best = max(rows, key=lambda r: float(r[acc_key]))
        ok = [r for r in rows if float(r[acc_key]) >= min((1 - tol) * float(best[acc_key]),
                                                          float(best[acc_key]) - abs_tol)]
    else:
        best = min(rows, key=lambda r: float(r[acc_key]))
        ok = [r for r in rows if float(r[acc_key]) <= max((1 + tol) * float(best[acc_key]),
                                                          float(best[acc_key]) + abs_tol)]
    return best, min(ok, key=lambda r: float(r[cost_key]))


def mean(xs):
    xs = [float(x) for x in xs if _finite(x)]
    return sum(xs) / len(xs) if xs else float("nan")


def median(xs):
    xs = sorted(float(x) for x in xs if _finite(x))
    if not xs:
        return float("nan")
    n = len(xs)
    return xs[n // 2] if n % 2 else 0.5 * (xs[n // 2 - 1] + xs[n // 2])


def yaw_from_quat(qx, qy, qz, qw) -> float:
    return math.atan2(2 * (qw * qz + qx * qy), 1 - 2 * (qy * qy + qz * qz))


def read_tum(path):
    out = []
    for line in Path(path).read_text().splitlines():
        if not line.strip() or line.startswith("#"):
            continue
        t, x, y, _z, qx, qy, qz, qw = map(float, line.split()[:8])
        out.append((t, x, y, yaw_from_quat(qx, qy, qz, qw)))
    return out


def errors_along(truth, est, max_dt: float = 0.01):
    """(t, position error) for every estimate with a ground-truth pose within max_dt."""
    out, j = [], 0
    truth = sorted(truth)
    for t, x, y, _ in sorted(est):
        while j + 1 < len(truth) and abs(truth[j + 1][0] - t) <= abs(truth[j][0] - t):
            j += 1
        if truth and abs(truth[j][0] - t) <= max_dt:
            out.append((t, math.hypot(x - truth[j][1], y - truth[j][2])))
    return out


def pane_corridor_geojson(angle_deg: float, thickness: float = 0.01) -> dict:
    """A 20 m x 3 m corridor with a 2 m gap in its upper wall into a 6 m x 4 m room; one 2 m glass
    pane hinged at the gap's left end, rotated by angle_deg from the corridor axis into the room."""
    def line(a, b, mat, th):
        return {"type": "Feature", "properties": {"material": mat, "thickness": th},
                "geometry": {"type": "LineString", "coordinates": [list(a), list(b)]}}
    a = math.radians(angle_deg)
    walls = [((0, 0), (20, 0)), ((0, 3), (9, 3)), ((11, 3), (20, 3)), ((0, 0), (0, 3)),
             ((20, 0), (20, 3)), ((7, 3), (7, 7)), ((7, 7), (13, 7)), ((13, 7), (13, 3))]
    feats = [line(p, q, "wall", 0.15) for p, q in walls]
    feats.append(line((9, 3), (round(9 + 2 * math.cos(a), 6), round(3 + 2 * math.sin(a), 6)),
                      "glass", thickness))
    return {"type": "FeatureCollection", "name": f"pane-{angle_deg:g}deg", "features": feats}


def set_glass_thickness(geojson: dict, thickness: float) -> dict:
    g = copy.deepcopy(geojson)
    for f in g["features"]:
        if f.get("properties", {}).get("material") == "glass":
            f["properties"]["thickness"] = thickness
    return g


PANE_SLOTS = 9   # 2 m slots per corridor side between x = 1 and x = 19


def spread_slots(k: int, slots: int = PANE_SLOTS) -> list[int]:
    """k distinct slot indices out of `slots`, spread evenly (0 -> [], slots -> all)."""
    if not 0 <= k <= slots:
        raise ValueError(f"{k} panes do not fit in {slots} slots")
    if k == 0:
        return []
    if k == 1:
        return [slots // 2]
    return sorted({round(i * (slots - 1) / (k - 1)) for i in range(k)})


def panes_corridor_geojson(n: int, thickness: float = 0.01) -> dict:
    """A 20 m x 3 m corridor (y 0..3) between two 20 m x 4 m rooms (y 3..7 and -4..0), its two
    walls made of 2 m slots between x = 1 and x = 19 (walls at both ends): n of the 18 slots are glass
    panes, ceil(n/2) in the upper wall and floor(n/2) in the lower one, spread evenly along each; the
    others are wall. The rooms behind give transmitted beams something to return from."""
    if not 0 <= n <= 2 * PANE_SLOTS:
        raise ValueError(f"0..{2 * PANE_SLOTS} panes, not {n}")
    def line(a, b, mat, th):
        return {"type": "Feature", "properties": {"material": mat, "thickness": th},
                "geometry": {"type": "LineString", "coordinates": [list(a), list(b)]}}
    feats = [line(p, q, "wall", 0.15) for p, q in
             [((0, -4), (20, -4)), ((0, 7), (20, 7)), ((0, -4), (0, 7)), ((20, -4), (20, 7)),
              ((0, 0), (1, 0)), ((19, 0), (20, 0)), ((0, 3), (1, 3)), ((19, 3), (20, 3))]]
    for y, k in ((3, (n + 1) // 2), (0, n // 2)):
        glass = set(spread_slots(k))
        x0 = 1
        for i in range(PANE_SLOTS + 1):      # merge neighbouring wall slots into one segment
            if i == PANE_SLOTS or i in glass:
                if 1 + 2 * i > x0:
                    feats.append(line((x0, y), (1 + 2 * i, y), "wall", 0.15))
                if i < PANE_SLOTS:
                    feats.append(line((1 + 2 * i, y), (3 + 2 * i, y), "glass", thickness))
                x0 = 3 + 2 * i
    return {"type": "FeatureCollection", "name": f"panes-{n}", "features": feats}


def time_to_recover(errors, t_kidnap: float, threshold: float = SUCCESS_ATE_M,
                    hold: float = RECOVER_HOLD_S):
    """Seconds from a kidnapping at t_kidnap to the first estimate at or after it from which on
    the position error stays under threshold to the end of the run (0 if it never left it); None
    when the last error is not under it, or the run ends less than `hold` seconds after the
    recovery (one lucky estimate at the end is no recovery). errors: (t, position error) pairs."""
    after = sorted((t, e) for t, e in errors if t >= t_kidnap - 1e-9)
    t_rec = None
    for t, e in reversed(after):
        if not (_finite(e) and e < threshold):
            break
        t_rec = t
    if t_rec is None or after[-1][0] - t_rec < hold:
        return None
    return t_rec - t_kidnap


def merge_rows(old_rows, new_rows, replaced):
    """old_rows without those for which replaced(row) is true, then new_rows: a partial re-run
    replaces its part of a CSV and keeps the rest."""
    return [r for r in old_rows if not replaced(r)] + list(new_rows)


def _typed(v: str):
    for cast in (int, float):
        try:
            return cast(v)
        except ValueError:
            pass
    return v


def read_csv_typed(path: Path) -> list[dict]:
    """Rows of a CSV written by write_csv, numbers back as int/float ("" stays a string)."""
    if not Path(path).exists():
        return []
    with open(path, newline="") as f:
        return [{k: _typed(v) for k, v in r.items()} for r in csv.DictReader(f)]


# ----------------------------------------------------------------------------------------------
# running the command line

class Runner:
    def __init__(self, glassmap: Path, work: Path, jobs: int, verbose: bool = True):
        self.g = str(glassmap)
        self.work = work
        self.jobs = max(1, jobs)
        self.verbose = verbose
        self._locks: dict[str, threading.Lock] = {}
        self._lock = threading.Lock()
        self.nruns = 0
        work.mkdir(parents=True, exist_ok=True)

    def _key_lock(self, key):
        with self._lock:
            return self._locks.setdefault(key, threading.Lock())

    def run(self, args):
        with self._lock:
            self.nruns += 1
        for attempt in range(5):   # the binary may be mid-rebuild (ETXTBSY, EACCES): retry
            try:
                r = subprocess.run([self.g] + [str(a) for a in args], capture_output=True, text=True)
                break
            except OSError:
                if attempt == 4:
                    raise
                time.sleep(3)
        if r.returncode != 0:
            raise RuntimeError(f"glassmap {' '.join(map(str, args))} failed ({r.returncode}): "
                               f"{r.stderr.strip()[-500:]}")
        return r

    def pmap(self, fn, items):
        items = list(items)
        if self.jobs == 1:
            return [fn(i) for i in items]
        with ThreadPoolExecutor(self.jobs) as ex:
            return list(ex.map(fn, items))

    # scene variants: a scene YAML (dict) plus an optional floorplan GeoJSON (dict)
    def scene(self, base_yaml: Path, mods: dict | None = None, floorplan: dict | None = None):
        import yaml
        scene = yaml.safe_load(Path(base_yaml).read_text())
        for k, v in (mods or {}).items():
            if isinstance(v, dict):
                scene.setdefault(k, {})
                scene[k].update(v)
            else:
                scene[k] = v
        if floorplan is None:
            scene["floorplan"] = str((Path(base_yaml).parent / scene["floorplan"]).resolve())
        key = hashlib.sha256(json.dumps([scene, floorplan], sort_keys=True).encode()).hexdigest()[:16]
        d = self.work / "scenes" / key
        d.mkdir(parents=True, exist_ok=True)
        if floorplan is not None:
            (d / "floorplan.geojson").write_text(json.dumps(floorplan))
            scene["floorplan"] = "floorplan.geojson"
        (d / "scene.yaml").write_text(json.dumps(scene, indent=1))   # JSON is YAML
        return d / "scene.yaml"

    def simulate(self, scene_yaml: Path, seed: int, duration: float = 0.0,
                 people=None, range_sigma=None, kidnap_at=None, kidnap_along=None) -> Path:
        extra = [] if kidnap_at is None else [kidnap_at, kidnap_along]
        key = hashlib.sha256(json.dumps([Path(scene_yaml).read_text(), seed, duration, people,
                                         range_sigma] + extra).encode()).hexdigest()[:16]
        d = self.work / "sims" / key
        with self._key_lock(str(d)):
            if not (d / "meta.json").exists():
                args = ["simulate", scene_yaml, "-o", d, "--seed", seed, "--duration", duration, "-q"]
                if people is not None:
                    args += ["--people", people]
                if range_sigma is not None:
                    args += ["--range-sigma", range_sigma]
                if kidnap_at is not None:
                    args += ["--kidnap-at", kidnap_at, "--kidnap-along", kidnap_along]
                self.run(args)
        return d

    def localize(self, sim: Path, variant: str, particles: int, beams: int, seed: int,
                 fixed_count: bool = True) -> dict:
        model, glass_as = LOC_MODELS[variant]
        d = sim / f"loc-{variant}-p{particles}-b{beams}-s{seed}{'-fixed' if fixed_count else ''}"
        res = d / "result.json"
        if res.exists() and (d / "spread.csv").exists():
            return json.loads(res.read_text())
        d.mkdir(parents=True, exist_ok=True)
        t0, x0, y0, th0 = read_tum(sim / "groundtruth.tum")[0]
        args = ["localize", "--map", sim / "floorplan.gpkg", sim / "log.clf", "-o", d / "est.tum",
                "--model", model, "--glass-as", glass_as, "--particles", particles,
                "--beams", beams, "--init", f"{x0:.6f},{y0:.6f},{th0:.6f}", "--seed", seed,
                "--json", d / "loc.json", "--spread", d / "spread.csv", "-q"]
        if fixed_count:
            args.append("--fixed-count")
        w0 = time.perf_counter()
        self.run(args)
        wall = time.perf_counter() - w0
        self.run(["eval", "traj", "--truth", sim / "groundtruth.tum", d / "est.tum",
                  "--json", d / "ate.json", "-q"])
        loc, ate = json.loads((d / "loc.json").read_text()), json.loads((d / "ate.json").read_text())
        out = {"ate_rmse": ate.get("rmse"), "ate_max": ate.get("max"),
               "fraction_under": ate.get("fraction_under"),
               "ms_per_update": loc.get("ms_per_update"), "mean_particles": loc.get("mean_particles"),
               "updates": loc.get("updates"), "relocalizations": loc.get("relocalizations"),
               "seconds_wall": wall}
        res.write_text(json.dumps(out))
        return out

    def map(self, sim: Path, method: str, resolution: float, vector: bool = True) -> dict:
        d = sim / f"map-{method}-r{resolution:g}{'' if vector else '-novec'}"
        res = d / "result.json"
        if res.exists():
            return json.loads(res.read_text())
        args = ["map", sim / "log.clf", "-o", d, "--method", method, "--resolution", resolution, "-q"]
        if not vector:
            args.append("--no-vector")
        w0 = time.perf_counter()
        self.run(args)
        wall = time.perf_counter() - w0
        self.run(["eval", "cells", "--truth", sim / "floorplan.gpkg", "--labels", d / "labels.tif",
                  "--json", d / "cells.json", "-q"])
        cells = json.loads((d / "cells.json").read_text())
        stats = json.loads((d / "stats.json").read_text())
        secs = stats.get("seconds", {})
        out = {"f1_cells": cells.get("tolerant", {}).get("f1"),
               "f1_cells_exact": cells.get("exact", {}).get("f1"),
               "precision_cells": cells.get("tolerant", {}).get("precision"),
               "recall_cells": cells.get("tolerant", {}).get("recall"),
               "f1_segments": float("nan"), "panes_found": float("nan"),
               "seconds_map": secs.get("total") if isinstance(secs, dict) else float("nan"),
               "seconds_wall": wall}
        if vector and (d / "floorplan.gpkg").exists():
            self.run(["eval", "segments", "--truth", sim / "floorplan.gpkg", "--pred",
                      d / "floorplan.gpkg", "--json", d / "seg.json", "-q"])
            seg = json.loads((d / "seg.json").read_text())
            out["f1_segments"] = seg.get("glass", {}).get("f1")
            out["panes_found"] = seg.get("panes_found")
        res.write_text(json.dumps(out))
        return out


# ----------------------------------------------------------------------------------------------
# configuration of the two modes

def config(quick: bool, seeds: int | None):
    if quick:
        c = dict(seeds=1, loc_seeds=1, map_seeds=1, loc_scenes=["paper-corridor"], map_scenes=["paper-corridor"],
                 loc_duration=20.0, map_duration=40.0, models=list(LOC_MODELS),
                 beams=[5, 60], particles=[100, 500], max_cost=None,
                 methods=MAP_METHODS, resolutions=[0.1], stab_resolution=0.1,
                 stab_particles=300, stab_beams=15, fig8_seeds=1, fig8_duration=30.0,
                 axes=dict(range_sigma=[0.01, 0.1], pane_angle=[0, 60], thickness=[0.01, 0.05],
                           people=[0, 10], odom_noise=[1, 20], odom_bias=[0.0, 0.1], panes=[0, 6]),
                 kidnap=dict(seeds=1, at=10.0, duration=35.0, distances=[1, 4], particles=300, beams=15))
    else:
        c = dict(seeds=3, loc_seeds=1, map_seeds=2, loc_scenes=["paper-corridor", "glass-corridor"],
                 map_scenes=["paper-corridor", "glass-corridor"],
                 loc_duration=30.0, map_duration=0.0, models=list(LOC_MODELS),
                 beams=[5, 15, 60, 100], particles=[100, 500, 2500, 10000],
                 max_cost=150_000,  # skip particles x beams above this (2500x100, 10000x{60,100}): time budget
                 methods=MAP_METHODS, resolutions=[0.025, 0.05, 0.1], stab_resolution=0.05,
                 stab_particles=500, stab_beams=15, fig8_seeds=3, fig8_duration=0.0,
                 axes=dict(range_sigma=[0.01, 0.03, 0.1, 0.3],
                           pane_angle=[0, 20, 40, 60, 80],
                           thickness=[0.005, 0.02, 0.05, 0.1],
                           people=[0, 5, 10, 20],
                           odom_noise=[1, 10, 30, 100],
                           odom_bias=[0.0, 0.05, 0.1, 0.2],
                           panes=[0, 1, 2, 4, 8, 12, 18]),
                 # kidnapped at 15 s on the first leg of paper-corridor (x = 8.5 m, heading +x), carried
                 # ahead along the path; 60 s to recover
                 kidnap=dict(seeds=8, at=15.0, duration=75.0, distances=[0.5, 1, 2, 4, 8, 12],
                             particles=500, beams=15))
    if seeds:
        c["seeds"] = c["loc_seeds"] = c["map_seeds"] = seeds
    return c


def write_csv(path: Path, rows: list[dict], columns: list[str]):
    path.parent.mkdir(parents=True, exist_ok=True)
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=columns, extrasaction="ignore")
        w.writeheader()
        for r in rows:
            w.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in r.items()})


def scene_yaml(name):
    return REPO / "maps" / name / "scene.yaml"


# ----------------------------------------------------------------------------------------------
# sections

LOC_COLS = ["scene", "trial", "sim_seed", "loc_seed", "model", "beams", "particles", "ate_rmse",
            "ate_max", "fraction_under", "success", "ms_per_update", "mean_particles", "seconds_wall"]
LOC_SUM_COLS = ["scene", "model", "beams", "particles", "n", "ate_rmse_mean", "success_rate",
                "ms_per_update_median"]


def section_loc(R: Runner, c, base, out: Path):
    jobs = []
    for scene in c["loc_scenes"]:
        for trial, sseed, lseed in trial_seeds(base, scene, c["loc_seeds"]):
            for m in c["models"]:
                for b in c["beams"]:
                    for p in c["particles"]:
                        if c["max_cost"] and p * b > c["max_cost"]:
                            continue
                        jobs.append((scene, trial, sseed, lseed, m, b, p))
    sims = {(s, ss): None for s, _, ss, *_ in jobs}
    for k, v in zip(sims, R.pmap(lambda k: R.simulate(scene_yaml(k[0]), k[1], c["loc_duration"]), sims)):
        sims[k] = v

    def one(j):
        scene, trial, sseed, lseed, m, b, p = j
        r = R.localize(sims[(scene, sseed)], m, p, b, lseed)
        return dict(scene=scene, trial=trial, sim_seed=sseed, loc_seed=lseed, model=m, beams=b,
                    particles=p, success=int(loc_success(r["ate_rmse"])), **r)
    rows = R.pmap(one, jobs)
    write_csv(out / "loc_grid.csv", rows, LOC_COLS)
    summ = []
    keys = sorted({(r["scene"], r["model"], r["beams"], r["particles"]) for r in rows},
                  key=lambda k: (k[0], list(LOC_MODELS).index(k[1]), k[2], k[3]))
    for k in keys:
        rs = [r for r in rows if (r["scene"], r["model"], r["beams"], r["particles"]) == k]
        summ.append(dict(scene=k[0], model=k[1], beams=k[2], particles=k[3], n=len(rs),
                         ate_rmse_mean=mean(r["ate_rmse"] for r in rs),
                         success_rate=success_rate(r["success"] for r in rs),
                         ms_per_update_median=median(r["ms_per_update"] for r in rs)))
    write_csv(out / "loc_summary.csv", summ, LOC_SUM_COLS)
    return summ


MAP_COLS = ["scene", "trial", "sim_seed", "method", "resolution", "f1_cells", "f1_cells_exact",
            "precision_cells", "recall_cells", "f1_segments", "panes_found", "success",
            "seconds_map", "seconds_wall"]
MAP_SUM_COLS = ["scene", "method", "resolution", "n", "f1_cells_mean", "f1_segments_mean",
                "success_rate", "seconds_median"]


def section_map(R: Runner, c, base, out: Path):
    jobs = []
    for scene in c["map_scenes"]:
        for trial, sseed, _ in trial_seeds(base, scene, c["map_seeds"]):
            for m in c["methods"]:
                for res in c["resolutions"]:
                    jobs.append((scene, trial, sseed, m, res))
    sims = {(s, ss): None for s, _, ss, *_ in jobs}
    for k, v in zip(sims, R.pmap(lambda k: R.simulate(scene_yaml(k[0]), k[1], c["map_duration"]), sims)):
        sims[k] = v

    def one(j):
        scene, trial, sseed, m, res = j
        r = R.map(sims[(scene, sseed)], m, res)
        return dict(scene=scene, trial=trial, sim_seed=sseed, method=m, resolution=res,
                    success=int(map_success(r["f1_cells"])), **r)
    rows = R.pmap(one, jobs)
    write_csv(out / "map_grid.csv", rows, MAP_COLS)
    summ = []
    for scene in c["map_scenes"]:
        for m in c["methods"]:
            for res in c["resolutions"]:
                rs = [r for r in rows if (r["scene"], r["method"], r["resolution"]) == (scene, m, res)]
                summ.append(dict(scene=scene, method=m, resolution=res, n=len(rs),
                                 f1_cells_mean=mean(r["f1_cells"] for r in rs),
                                 f1_segments_mean=mean(r["f1_segments"] for r in rs),
                                 success_rate=success_rate(r["success"] for r in rs),
                                 seconds_median=median(r["seconds_map"] for r in rs)))
    write_csv(out / "map_summary.csv", summ, MAP_SUM_COLS)
    return summ


STAB_COLS = ["axis", "value", "task", "method", "trial", "sim_seed", "metric", "success"]
STAB_SUM_COLS = ["axis", "value", "task", "method", "n", "metric_mean", "success_rate", "breaks_at"]
AXIS_LABEL = {"range_sigma": "laser range noise sigma [m]", "pane_angle": "pane angle to corridor [deg]",
              "thickness": "glass pane thickness [m]", "people": "people density [per 100 m^2]",
              "odom_noise": "odometry noise (x scene default)", "odom_bias": "odometry scale bias",
              "panes": "glass panes along the corridor (2 m each, of 18 slots)",
              "kidnap": "kidnap distance along the trajectory [m]"}


def _variant(R: Runner, axis, value):
    """(scene yaml, simulate kwargs, tasks) of one value of one swept quantity."""
    base = scene_yaml("paper-corridor")
    if axis == "range_sigma":
        return base, dict(range_sigma=value), ("loc", "map")
    if axis == "people":
        return base, dict(people=value), ("loc", "map")
    if axis == "thickness":
        # the paper-corridor's panes have nothing behind them (transmitted beams return max range,
        # so thickness never shows): use the pane-in-a-doorway corridor with a room behind the pane
        mods = {"name": f"pane-t{value}", "trajectory": {"waypoints": [[1, 1.5], [19, 1.5]],
                                                        "round_trip": True}}
        return R.scene(base, mods, floorplan=pane_corridor_geojson(0, value)), {}, ("loc", "map")
    if axis == "pane_angle":
        mods = {"name": f"pane-{value}", "trajectory": {"waypoints": [[1, 1.5], [19, 1.5]],
                                                      "round_trip": True}}
        return R.scene(base, mods, floorplan=pane_corridor_geojson(value)), {}, ("loc", "map")
    if axis == "odom_noise":
        m = {"odom_trans_sigma": 0.01 * value, "odom_rot_sigma": 0.01 * value,
             "odom_rot_per_m": 0.005 * value}
        return R.scene(base, {"motion": m}), {}, ("loc",)
    if axis == "odom_bias":
        return R.scene(base, {"motion": {"odom_scale_bias": value,
                                         "odom_drift_deg_per_m": 10 * value}}), {}, ("loc",)
    if axis == "panes":
        # a corridor whose two walls are 2 m slots, `value` of them glass; no glass, no glass F1
        mods = {"name": f"panes-{value}", "trajectory": {"waypoints": [[1, 1.5], [19, 1.5]],
                                                       "round_trip": True}}
        return (R.scene(base, mods, floorplan=panes_corridor_geojson(value)), {},
                ("loc", "map") if value > 0 else ("loc",))
    raise ValueError(axis)


def section_stability(R: Runner, c, base, out: Path, only=None):
    """Runs the axes in `only` (default all); the other axes' rows are kept from OUT's CSVs."""
    run_axes = [a for a in c["axes"] if only is None or a in only]
    jobs, sims = [], {}
    for axis in run_axes:
        values = c["axes"][axis]
        for v in values:
            yml, kw, tasks = _variant(R, axis, v)
            for trial, sseed, lseed in trial_seeds(base, "stability", c["seeds"]):
                for task in tasks:
                    dur = c["loc_duration"] if task == "loc" else c["map_duration"]
                    sk = (str(yml), sseed, dur, json.dumps(kw))
                    sims[sk] = None
                    methods = c["models"] if task == "loc" else c["methods"]
                    for m in methods:
                        jobs.append((axis, v, task, m, trial, sseed, lseed, sk))
    for k, d in zip(list(sims), R.pmap(lambda k: R.simulate(Path(k[0]), k[1], k[2], **json.loads(k[3])),
                                       list(sims))):
        sims[k] = d

    def one(j):
        axis, v, task, m, trial, sseed, lseed, sk = j
        if task == "loc":
            r = R.localize(sims[sk], m, c["stab_particles"], c["stab_beams"], lseed)
            metric, ok = r["ate_rmse"], loc_success(r["ate_rmse"])
        else:
            r = R.map(sims[sk], m, c["stab_resolution"], vector=False)
            metric, ok = r["f1_cells"], map_success(r["f1_cells"])
        return dict(axis=axis, value=v, task=task, method=m, trial=trial, sim_seed=sseed,
                    metric=metric, success=int(ok))
    rows = R.pmap(one, jobs)
    replaced = lambda r: r["axis"] in run_axes or r["axis"] not in c["axes"]   # noqa: E731
    write_csv(out / "stability.csv",
              merge_rows(read_csv_typed(out / "stability.csv") if only else [], rows, replaced), STAB_COLS)
    summ = []
    for axis in run_axes:
        values = c["axes"][axis]
        for task in ("loc", "map"):
            for m in (c["models"] if task == "loc" else c["methods"]):
                rates, block = [], []
                for v in values:
                    rs = [r for r in rows if (r["axis"], r["value"], r["task"], r["method"]) == (axis, v, task, m)]
                    if not rs:
                        continue
                    rates.append(success_rate(r["success"] for r in rs))
                    block.append(dict(axis=axis, value=v, task=task, method=m, n=len(rs),
                                      metric_mean=mean(r["metric"] for r in rs), success_rate=rates[-1]))
                if not block:
                    continue
                bv = break_value([b["value"] for b in block], rates)
                for b in block:
                    b["breaks_at"] = "" if bv is None else bv
                summ += block
    if only:
        summ = merge_rows(read_csv_typed(out / "stability_summary.csv"), summ, replaced)
        order = list(c["axes"])
        summ.sort(key=lambda r: order.index(r["axis"]) if r["axis"] in order else len(order))
    write_csv(out / "stability_summary.csv", summ, STAB_SUM_COLS)
    return summ


FIG8_COLS = ["model", "trial", "sim_seed", "t", "position_error", "spread_m"]


def read_spread(path: Path) -> dict:
    """t (rounded to ms) -> particle spread [m] from `glassmap localize --spread`."""
    out = {}
    with open(path, newline="") as f:
        for r in csv.DictReader(f):
            out[round(float(r["t"]), 3)] = float(r["spread_m"])
    return out


def section_fig8(R: Runner, c, base, out: Path):
    rows = []
    for trial, sseed, lseed in trial_seeds(base, "paper-corridor-fig8", c["fig8_seeds"]):
        sim = R.simulate(scene_yaml("paper-corridor"), sseed, c["fig8_duration"])
        truth = read_tum(sim / "groundtruth.tum")
        for m in ("beam-opaque", "glass"):
            R.localize(sim, m, c["stab_particles"], c["stab_beams"], lseed)
            d = sim / f"loc-{m}-p{c['stab_particles']}-b{c['stab_beams']}-s{lseed}-fixed"
            spread = read_spread(d / "spread.csv")
            for t, e in errors_along(truth, read_tum(d / "est.tum")):
                if round(t * 10) % 5:          # every 0.5 s keeps the CSV and SVG small
                    continue
                rows.append(dict(model=m, trial=trial, sim_seed=sseed, t=t, position_error=e,
                                 spread_m=spread.get(round(t, 3), float("nan"))))
    write_csv(out / "fig8.csv", rows, FIG8_COLS)
    return rows


KID_COLS = ["distance", "model", "trial", "sim_seed", "loc_seed", "kidnap_time", "jump_m",
            "error_before_max", "recovered", "time_to_recover", "relocalizations", "ate_rmse"]
KID_SUM_COLS = ["distance", "model", "n", "success_rate", "median_time_to_recover", "breaks_at"]


def section_kidnap(R: Runner, c, base, out: Path):
    """Kidnapping on paper-corridor: the robot is carried `distance` metres ahead along its path
    at k["at"] seconds without odometry; success = recovered (time_to_recover) within the run."""
    k = c["kidnap"]
    jobs, sims = [], {}
    for dist in k["distances"]:
        for trial, sseed, lseed in trial_seeds(base, "kidnap", k["seeds"]):
            sims[(dist, sseed)] = None
            for m in c["models"]:
                jobs.append((dist, m, trial, sseed, lseed))
    for key, d in zip(list(sims), R.pmap(lambda key: R.simulate(
            scene_yaml("paper-corridor"), key[1], k["duration"], kidnap_at=k["at"], kidnap_along=key[0]),
            list(sims))):
        sims[key] = d

    def one(j):
        dist, m, trial, sseed, lseed = j
        sim = sims[(dist, sseed)]
        r = R.localize(sim, m, k["particles"], k["beams"], lseed)
        ev = json.loads((sim / "meta.json").read_text())["kidnap"]
        d = sim / f"loc-{m}-p{k['particles']}-b{k['beams']}-s{lseed}-fixed"
        errs = errors_along(read_tum(sim / "groundtruth.tum"), read_tum(d / "est.tum"))
        ttr = time_to_recover(errs, ev["time"])
        return dict(distance=dist, model=m, trial=trial, sim_seed=sseed, loc_seed=lseed,
                    kidnap_time=ev["time"], jump_m=ev["distance_m"],
                    error_before_max=max((e for t, e in errs if t < ev["time"]), default=float("nan")),
                    recovered=int(ttr is not None), time_to_recover="" if ttr is None else ttr,
                    relocalizations=r.get("relocalizations"), ate_rmse=r["ate_rmse"])
    rows = R.pmap(one, jobs)
    write_csv(out / "kidnap.csv", rows, KID_COLS)
    summ = []
    for m in c["models"]:
        block = []
        for dist in k["distances"]:
            rs = [r for r in rows if (r["distance"], r["model"]) == (dist, m)]
            block.append(dict(distance=dist, model=m, n=len(rs),
                              success_rate=success_rate(r["recovered"] for r in rs),
                              median_time_to_recover=median(r["time_to_recover"] for r in rs
                                                            if r["recovered"])))
        bv = break_value([b["distance"] for b in block], [b["success_rate"] for b in block])
        for b in block:
            b["breaks_at"] = "" if bv is None else bv
        summ += block
    write_csv(out / "kidnap_summary.csv", summ, KID_SUM_COLS)
    return summ


def recommendations(loc_summ, map_summ, out: Path):
    rows = []
    for scene in sorted({r["scene"] for r in loc_summ}):
        rs = [dict(r, cost=r["ms_per_update_median"]) for r in loc_summ if r["scene"] == scene]
        # ATEs of a few mm differ by more than 10 % from seed to seed: 1 cm absolute counts as close
        best, cheap = cheapest_within(rs, "ate_rmse_mean", "cost", higher_is_better=False,
                                      abs_tol=LOC_ABS_TOL_M)
        if best:
            rows.append(dict(scene=scene, task="localization", accuracy="ATE RMSE [m] (10% or 1 cm)",
                             best=f"{best['model']} b{best['beams']} p{best['particles']}",
                             best_accuracy=best["ate_rmse_mean"], best_cost=best["cost"],
                             cheapest=f"{cheap['model']} b{cheap['beams']} p{cheap['particles']}",
                             cheapest_accuracy=cheap["ate_rmse_mean"], cheapest_cost=cheap["cost"],
                             cost="ms per update"))
    for scene in sorted({r["scene"] for r in map_summ}):
        rs = [r for r in map_summ if r["scene"] == scene]
        best, cheap = cheapest_within(rs, "f1_cells_mean", "seconds_median", higher_is_better=True)
        if best:
            rows.append(dict(scene=scene, task="mapping", accuracy="glass F1 (cells, 2-cell tol.)",
                             best=f"{best['method']} r{best['resolution']}",
                             best_accuracy=best["f1_cells_mean"], best_cost=best["seconds_median"],
                             cheapest=f"{cheap['method']} r{cheap['resolution']}",
                             cheapest_accuracy=cheap["f1_cells_mean"],
                             cheapest_cost=cheap["seconds_median"], cost="seconds"))
    write_csv(out / "recommendations.csv", rows,
              ["scene", "task", "accuracy", "best", "best_accuracy", "best_cost", "cheapest",
               "cheapest_accuracy", "cheapest_cost", "cost"])
    return rows


# ----------------------------------------------------------------------------------------------
# charts

def _plt():
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        plt.rcParams.update({"font.size": 8, "svg.hashsalt": "glassmap", "svg.fonttype": "none"})
        return plt
    except ImportError:
        print("matplotlib missing: CSV only (Debian: python3-matplotlib, run with /usr/bin/python3)",
              file=sys.stderr)
        return None


def _save(plt, fig, out: Path, name: str):
    fig.tight_layout()
    fig.savefig(out / f"{name}.png", dpi=80)
    fig.savefig(out / f"{name}.svg", metadata={"Date": None})
    plt.close(fig)


def chart_names(c) -> list[str]:
    """Every chart the driver can draw, in the order of the results page."""
    return (["loc_tradeoff", "map_tradeoff"] + [f"stability_{a}" for a in c["axes"]]
            + ["stability_kidnap", "fig8_paper_corridor"])


def _break_marks(ax, xs, bv, color, off):
    if bv != "":
        ax.axvline(bv, color=color, ls="--", lw=0.8)
        ax.plot([bv], [BREAK_RATE + off], marker="x", color=color, ms=8)


def charts(out: Path, loc_summ, map_summ, stab_summ, fig8_rows, c, kid_summ=(), stab_axes=None):
    """Draws the charts of the summaries given; stability charts for stab_axes (default all)."""
    plt = _plt()
    if plt is None:
        return []
    made = []
    if loc_summ:
        scenes = sorted({r["scene"] for r in loc_summ})
        fig, axs = plt.subplots(1, len(scenes), figsize=(5 * len(scenes), 3.6), squeeze=False)
        marks = {5: "v", 15: "o", 60: "s", 100: "D"}
        for ax, scene in zip(axs[0], scenes):
            for r in loc_summ:
                if r["scene"] != scene:
                    continue
                ax.scatter(r["ms_per_update_median"], max(r["ate_rmse_mean"], 1e-4),
                           c=COLORS[r["model"]], marker=marks.get(r["beams"], "o"),
                           s=8 + 4 * math.log2(r["particles"] / 50), alpha=0.75)
            ax.set_xscale("log"); ax.set_yscale("log")
            ax.axhline(SUCCESS_ATE_M, color="grey", ls=":", lw=0.8)
            ax.set_xlabel("time per update [ms] (median)"); ax.set_ylabel("ATE RMSE [m] (mean over seeds)")
            ax.set_title(f"localization, {scene}")
        for m in c["models"]:
            axs[0][0].scatter([], [], c=COLORS[m], label=m)
        for b, mk in marks.items():
            if b in c["beams"]:
                axs[0][0].scatter([], [], c="k", marker=mk, label=f"{b} beams")
        axs[0][0].legend(fontsize=6, ncol=2, title="size: particles", title_fontsize=6)
        _save(plt, fig, out, "loc_tradeoff"); made.append("loc_tradeoff")
    if map_summ:
        scenes = sorted({r["scene"] for r in map_summ})
        fig, axs = plt.subplots(1, 2, figsize=(9, 3.6))
        marks = {0.025: "s", 0.05: "o", 0.1: "v"}
        fills = {s: f for s, f in zip(scenes, ["full", "none", "left"])}
        for r in map_summ:
            for ax, key in zip(axs, ("f1_cells_mean", "f1_segments_mean")):
                if _finite(r[key]):
                    ax.plot(r["seconds_median"], r[key], ls="", color=COLORS[r["method"]],
                            marker=marks.get(r["resolution"], "o"), fillstyle=fills[r["scene"]], ms=6)
        for ax, t in zip(axs, ("glass F1, cells (2-cell tolerance)", "glass F1, segments (0.1 m)")):
            ax.set_xscale("log"); ax.set_xlabel("map wall-clock time [s] (median)"); ax.set_ylabel(t)
            ax.axhline(SUCCESS_F1, color="grey", ls=":", lw=0.8); ax.set_ylim(0, 1.02)
        for m in c["methods"]:
            axs[0].plot([], [], ls="", marker="o", color=COLORS[m], label=m)
        for res, mk in marks.items():
            if res in c["resolutions"]:
                axs[0].plot([], [], ls="", marker=mk, color="k", label=f"{res} m")
        for s, f in fills.items():
            axs[0].plot([], [], ls="", marker="o", color="grey", fillstyle=f, label=s)
        axs[0].legend(fontsize=6); fig.suptitle("mapping: accuracy against time")
        _save(plt, fig, out, "map_tradeoff"); made.append("map_tradeoff")
    for axis in c["axes"]:
        if stab_axes is not None and axis not in stab_axes:
            continue
        rs = [r for r in stab_summ if r["axis"] == axis]
        if not rs:
            continue
        tasks = [t for t in ("loc", "map") if any(r["task"] == t for r in rs)]
        fig, axs = plt.subplots(1, len(tasks), figsize=(4.6 * len(tasks), 3.3), squeeze=False)
        for ax, task in zip(axs[0], tasks):
            methods = []
            for r in rs:
                if r["task"] == task and r["method"] not in methods:
                    methods.append(r["method"])
            for i, m in enumerate(methods):
                mr = [r for r in rs if r["task"] == task and r["method"] == m]
                xs, ys = [r["value"] for r in mr], [r["success_rate"] for r in mr]
                off = (i - (len(methods) - 1) / 2) * 0.012
                ax.plot(xs, [y + off for y in ys], marker="o", ms=3, color=COLORS[m], label=m)
                _break_marks(ax, xs, mr[0]["breaks_at"], COLORS[m], off)
            ax.set_ylim(-0.05, 1.05); ax.set_xlabel(AXIS_LABEL[axis])
            ax.set_ylabel("success rate (ATE < 0.2 m)" if task == "loc" else "success rate (glass F1 > 0.8)")
            ax.set_title(("localization" if task == "loc" else "mapping") + ": dashed = breaks")
            ax.legend(fontsize=6)
        _save(plt, fig, out, f"stability_{axis}"); made.append(f"stability_{axis}")
    if kid_summ:
        fig, axs = plt.subplots(1, 2, figsize=(9.2, 3.3))
        models = [m for m in c["models"] if any(r["model"] == m for r in kid_summ)]
        for i, m in enumerate(models):
            mr = [r for r in kid_summ if r["model"] == m]
            xs = [r["distance"] for r in mr]
            off = (i - (len(models) - 1) / 2) * 0.012
            axs[0].plot(xs, [r["success_rate"] + off for r in mr], marker="o", ms=3, color=COLORS[m], label=m)
            _break_marks(axs[0], xs, mr[0]["breaks_at"], COLORS[m], off)
            axs[1].plot(xs, [r["median_time_to_recover"] for r in mr], marker="o", ms=3, color=COLORS[m],
                        label=m)
        k = c["kidnap"]
        for ax in axs:
            ax.set_xscale("log"); ax.set_xlabel(AXIS_LABEL["kidnap"])
            ax.set_xticks(k["distances"]); ax.set_xticklabels([f"{d:g}" for d in k["distances"]])
            ax.minorticks_off()
        axs[0].set_ylim(-0.05, 1.05)
        axs[0].set_ylabel(f"recovered (error < {SUCCESS_ATE_M} m for good, >= {RECOVER_HOLD_S:g} s left)")
        axs[0].set_title("kidnapping: success rate, dashed = breaks")
        axs[1].set_ylabel("time to recover [s] (median of recovered runs)")
        axs[1].set_title(f"paper-corridor, kidnapped at {k['at']:g} s, {k['particles']} particles")
        axs[0].legend(fontsize=6)
        _save(plt, fig, out, "stability_kidnap"); made.append("stability_kidnap")
    if fig8_rows:
        fig, axs = plt.subplots(2, 1, figsize=(7, 4.6), sharex=True)
        n = len({r["trial"] for r in fig8_rows})
        for m, col, lab in (("beam-opaque", "red", "without glass model (beam, glass opaque)"),
                            ("glass", "green", "with glass model")):
            for ax, key in zip(axs, ("position_error", "spread_m")):
                pts = {}
                for r in fig8_rows:
                    if r["model"] == m and _finite(r[key]):
                        pts.setdefault(round(r["t"], 3), []).append(r[key])
                ts = sorted(pts)
                ax.plot(ts, [max(mean(pts[t]), 1e-4) for t in ts], color=col, lw=0.9, label=lab)
        axs[0].set_ylabel("position error [m]"); axs[1].set_ylabel("particle spread [m]")
        for ax in axs:
            ax.set_yscale("log")
        axs[1].set_xlabel("time [s]")
        axs[0].set_title(f"paper Fig. 8 redrawn on paper-corridor ({c['stab_particles']} particles, "
                         f"{c['stab_beams']} beams; mean over {n} seed(s))")
        axs[0].axhline(SUCCESS_ATE_M, color="grey", ls=":", lw=0.8)
        axs[0].legend(fontsize=7)
        _save(plt, fig, out, "fig8_paper_corridor"); made.append("fig8_paper_corridor")
    return made


# ----------------------------------------------------------------------------------------------
# report: markdown tables from the summaries (docs/results/RESULTS.md)

def _f(x, nd=3):
    return "n/a" if not _finite(x) else f"{float(x):.{nd}f}"


def report(out: Path, loc_summ, map_summ, stab_summ, recs, made, c, cmdline, kid_summ=()):
    L = [f"<!-- written by tools/bench/sweep.py; last command: {cmdline} (sections it did not run: read back from the CSVs) -->", "# Bench results", ""]
    if loc_summ:
        L += ["## Localization (ATE RMSE [m] / time per update [ms], tracking from the true start pose, "
              "fixed particle count)", ""]
        for scene in sorted({r["scene"] for r in loc_summ}):
            rs = [r for r in loc_summ if r["scene"] == scene]
            L += [f"**{scene}** (n = {rs[0]['n']} seed(s) per cell)", "",
                  "| model | " + " | ".join(f"b{b} p{p}" for b in c["beams"] for p in c["particles"]
                                           if not c["max_cost"] or b * p <= c["max_cost"]) + " | share of settings with all seeds < 0.2 m |",
                  "|---" * (1 + sum(1 for b in c["beams"] for p in c["particles"]
                                    if not c["max_cost"] or b * p <= c["max_cost"])) + "|---|"]
            for m in c["models"]:
                mr = {(r["beams"], r["particles"]): r for r in rs if r["model"] == m}
                if not mr:
                    continue
                cells = [f"{_f(mr[k]['ate_rmse_mean'])} / {_f(mr[k]['ms_per_update_median'], 2)}"
                         if k in mr else "-" for k in [(b, p) for b in c["beams"] for p in c["particles"]
                                                      if not c["max_cost"] or b * p <= c["max_cost"]]]
                L.append(f"| {m} | " + " | ".join(cells) +
                         f" | {_f(success_rate(r['success_rate'] == 1 for r in mr.values()), 2)} |")
            L.append("")
    if map_summ:
        L += ["## Mapping (glass, per scene; F1 over cells with 2-cell tolerance, exact cells in the CSV)", "",
              "| scene | method | resolution [m] | F1 cells | F1 segments | success | seconds |",
              "|---|---|---|---|---|---|---|"]
        for r in map_summ:
            L.append(f"| {r['scene']} | {r['method']} | {r['resolution']} | {_f(r['f1_cells_mean'])} | "
                     f"{_f(r['f1_segments_mean'])} | {_f(r['success_rate'], 2)} | {_f(r['seconds_median'], 2)} |")
        L.append("")
    if stab_summ:
        L += ["## Where each method breaks (first swept value with success rate < 0.5; "
              "success: ATE < 0.2 m, glass F1 > 0.8)", "",
              "| quantity | task | " + " | ".join(["method: breaks at (success rates along the sweep)"]) + " |",
              "|---|---|---|"]
        for axis, values in c["axes"].items():
            for task in ("loc", "map"):
                parts = []
                for m in (c["models"] if task == "loc" else c["methods"]):
                    mr = [r for r in stab_summ if (r["axis"], r["task"], r["method"]) == (axis, task, m)]
                    if not mr:
                        continue
                    bv = mr[0]["breaks_at"]
                    rates = "/".join(_f(r["success_rate"], 2) for r in mr)
                    parts.append(f"{m}: {'no break' if bv == '' else bv} ({rates})")
                if parts:
                    L.append(f"| {AXIS_LABEL[axis]} = {', '.join(str(v) for v in values)} | {task} | "
                             + "; ".join(parts) + " |")
        L.append("")
    if kid_summ:
        k = c["kidnap"]
        L += [f"## Kidnapping (paper-corridor, carried ahead along the path at {k['at']:g} s without "
              f"odometry; {k['particles']} particles, {k['beams']} beams; recovered: the position error "
              f"stays under {SUCCESS_ATE_M} m to the end of the run, >= {RECOVER_HOLD_S:g} s after)", "",
              "| model | " + " | ".join(f"{d:g} m" for d in k["distances"]) + " | breaks at |",
              "|---" * (2 + len(k["distances"])) + "|"]
        for m in c["models"]:
            mr = {r["distance"]: r for r in kid_summ if r["model"] == m}
            if not mr:
                continue
            cells = [f"{_f(mr[d]['success_rate'], 2)} / {_f(mr[d]['median_time_to_recover'], 1)} s"
                     if d in mr else "-" for d in k["distances"]]
            bv = next(iter(mr.values()))["breaks_at"]
            L.append(f"| {m} | " + " | ".join(cells) + f" | {'no break' if bv == '' else f'{bv} m'} |")
        L += ["", f"Cells: success rate / median time to recover (n = {kid_summ[0]['n']} seeds per cell).", ""]
    if recs:
        L += ["## Cheapest setting within 10% of the best accuracy", "",
              "| scene | task | best | best accuracy | cheapest within 10% | its accuracy | cost (best -> cheapest) |",
              "|---|---|---|---|---|---|---|"]
        for r in recs:
            L.append(f"| {r['scene']} | {r['task']} | {r['best']} | {_f(r['best_accuracy'], 4)} | "
                     f"{r['cheapest']} | {_f(r['cheapest_accuracy'], 4)} | "
                     f"{_f(r['best_cost'], 2)} -> {_f(r['cheapest_cost'], 2)} {r['cost']} |")
        L.append("")
    if made:
        L += ["## Charts", ""] + [f"![{m}]({m}.png)" for m in made] + [""]
    (out / "RESULTS.md").write_text("\n".join(L))


# ----------------------------------------------------------------------------------------------

def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--quick", action="store_true", help="CI-sized run: 1 seed, 2 values per axis, short logs")
    ap.add_argument("--out", type=Path, default=None, help="CSV and charts (default: docs/results, quick: build-bench-quick)")
    ap.add_argument("--work", type=Path, default=None, help="logs and per-run outputs, reused across runs (default OUT/work)")
    ap.add_argument("--glassmap", type=Path, default=REPO / "build/tools/glassmap")
    ap.add_argument("--base-seed", type=int, default=1)
    ap.add_argument("--seeds", type=int, default=None, help="override the number of seeds")
    ap.add_argument("--stability-seeds", type=int, default=None,
                    help="override the number of seeds of the stability sweeps and Fig. 8 only")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--sections", default="loc,map,stability,kidnap,fig8",
                    help="comma list of loc,map,stability,kidnap,fig8; the CSVs of the sections not run "
                         "are read back from OUT for RESULTS.md (their charts are left alone)")
    ap.add_argument("--axes", default=None,
                    help="stability: run only these comma-separated quantities (of "
                         "range_sigma,pane_angle,thickness,people,odom_noise,odom_bias,panes); the other "
                         "quantities' rows are kept from OUT's stability CSVs")
    ap.add_argument("--no-charts", action="store_true")
    a = ap.parse_args(argv)
    out = a.out or (REPO / ("build-bench-quick" if a.quick else "docs/results"))
    out.mkdir(parents=True, exist_ok=True)
    work = a.work or out / "work"
    c = config(a.quick, a.seeds)
    if a.stability_seeds:
        c["seeds"] = c["fig8_seeds"] = a.stability_seeds
    secs = set(a.sections.split(","))
    unknown = secs - {"loc", "map", "stability", "kidnap", "fig8"}
    axes = None if a.axes is None else a.axes.split(",")
    if unknown or (axes and set(axes) - set(c["axes"])):
        ap.error(f"unknown section or axis: {', '.join(sorted(unknown | set(axes or []) - set(c['axes'])))}")
    R = Runner(a.glassmap, work, a.jobs)
    t0 = time.time()
    typed = lambda name: read_csv_typed(out / name)   # noqa: E731  (sections not run)
    loc_summ = section_loc(R, c, a.base_seed, out) if "loc" in secs else typed("loc_summary.csv")
    print(f"[bench] loc {'done' if 'loc' in secs else 'read back'} {time.time()-t0:.0f}s", flush=True)
    map_summ = section_map(R, c, a.base_seed, out) if "map" in secs else typed("map_summary.csv")
    print(f"[bench] map {'done' if 'map' in secs else 'read back'} {time.time()-t0:.0f}s", flush=True)
    stab_summ = (section_stability(R, c, a.base_seed, out, axes) if "stability" in secs
                 else typed("stability_summary.csv"))
    print(f"[bench] stability {'done' if 'stability' in secs else 'read back'} {time.time()-t0:.0f}s", flush=True)
    kid_summ = section_kidnap(R, c, a.base_seed, out) if "kidnap" in secs else typed("kidnap_summary.csv")
    print(f"[bench] kidnap {'done' if 'kidnap' in secs else 'read back'} {time.time()-t0:.0f}s", flush=True)
    fig8 = section_fig8(R, c, a.base_seed, out) if "fig8" in secs else typed("fig8.csv")
    print(f"[bench] fig8 {'done' if 'fig8' in secs else 'read back'} {time.time()-t0:.0f}s", flush=True)
    if "loc" in secs or "map" in secs:
        recs = recommendations(loc_summ, map_summ, out)
    else:
        recs = typed("recommendations.csv")
    made = [] if a.no_charts else charts(
        out, loc_summ if "loc" in secs else [], map_summ if "map" in secs else [],
        stab_summ if "stability" in secs else [], fig8 if "fig8" in secs else [], c,
        kid_summ if "kidnap" in secs else [], axes)
    shown = [n for n in chart_names(c) if (out / f"{n}.png").exists()]
    report(out, loc_summ, map_summ, stab_summ, recs, shown, c,
           "tools/bench.sh " + " ".join(x for x in (argv if argv is not None else sys.argv[1:])), kid_summ)
    print(f"[bench] {R.nruns} glassmap runs, {time.time()-t0:.0f}s; wrote {out} (charts: {', '.join(made) or 'none'})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
