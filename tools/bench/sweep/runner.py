"""Runs the glassmap binary (simulate, map, localize, eval) with caching, and the two modes' settings."""
from __future__ import annotations

import csv
import hashlib
import json
import math
import subprocess
import threading
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

from .stats import LOC_MODELS, MAP_METHODS

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
        x0, y0, th0 = json.loads((sim / "meta.json").read_text())["start_pose"]  # the true first pose
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

    def errors(self, sim: Path, est: Path) -> list[tuple[float, float]]:
        """(t, position error [m]) of every estimate matched to the simulated truth, from
        `glassmap eval traj --errors`."""
        out_csv = est.with_name(est.stem + "-errors.csv")
        if not out_csv.exists():
            self.run(["eval", "traj", "--truth", sim / "groundtruth.tum", est, "--errors", out_csv, "-q"])
        with open(out_csv, newline="") as f:
            return [(float(r["t"]), float(r["position_error_m"])) for r in csv.DictReader(f)]

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



def config(quick: bool, seeds: int | None):
    if quick:
        c = dict(seeds=1, loc_seeds=1, map_seeds=1, loc_scenes=["paper-corridor"], map_scenes=["paper-corridor"],
                 loc_duration=12.0, map_duration=25.0, models=list(LOC_MODELS),
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
