"""The sections of the bench: localization grid, mapping grid, stability sweeps, kidnapping, Fig. 8."""
from __future__ import annotations

import csv
import json
import math
from pathlib import Path

from .runner import Runner, merge_rows, read_csv_typed, write_csv
from .scenes import *  # noqa: F401,F403
from .stats import *  # noqa: F401,F403

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
        for m in ("beam-opaque", "glass"):
            R.localize(sim, m, c["stab_particles"], c["stab_beams"], lseed)
            d = sim / f"loc-{m}-p{c['stab_particles']}-b{c['stab_beams']}-s{lseed}-fixed"
            spread = read_spread(d / "spread.csv")
            for t, e in R.errors(sim, d / "est.tum"):
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
        errs = R.errors(sim, d / "est.tum")
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
