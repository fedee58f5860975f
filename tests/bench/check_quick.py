"""Checks the CSV files of `tools/bench/sweep.py --quick`: expected columns, finite figures,
success flags consistent with the criteria, seeds derived from the base seed."""
import csv
import math
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "tools" / "bench"))
import sweep  # noqa: E402

FINITE = {
    "loc_grid.csv": ["ate_rmse", "ate_max", "fraction_under", "ms_per_update", "mean_particles"],
    "loc_summary.csv": ["ate_rmse_mean", "success_rate", "ms_per_update_median"],
    "map_grid.csv": ["f1_cells", "f1_cells_exact", "f1_segments", "seconds_map"],
    "map_summary.csv": ["f1_cells_mean", "success_rate", "seconds_median"],
    "stability.csv": ["value", "metric"],
    "stability_summary.csv": ["value", "metric_mean", "success_rate"],
    "fig8.csv": ["t", "position_error", "spread_m"],
    "kidnap.csv": ["distance", "kidnap_time", "jump_m", "error_before_max", "ate_rmse"],
    "kidnap_summary.csv": ["distance", "success_rate"],
    "recommendations.csv": ["best_accuracy", "best_cost", "cheapest_accuracy", "cheapest_cost"],
}
COLUMNS = {"loc_grid.csv": sweep.LOC_COLS, "loc_summary.csv": sweep.LOC_SUM_COLS,
           "map_grid.csv": sweep.MAP_COLS, "map_summary.csv": sweep.MAP_SUM_COLS,
           "stability.csv": sweep.STAB_COLS, "stability_summary.csv": sweep.STAB_SUM_COLS,
           "fig8.csv": sweep.FIG8_COLS, "kidnap.csv": sweep.KID_COLS,
           "kidnap_summary.csv": sweep.KID_SUM_COLS}


def main(out):
    out, bad = Path(out), []
    for name, cols in FINITE.items():
        p = out / name
        if not p.exists():
            bad.append(f"{name}: missing"); continue
        rows = list(csv.DictReader(open(p)))
        header = list(rows[0].keys()) if rows else []
        if not rows:
            bad.append(f"{name}: no rows")
        if name in COLUMNS and header != COLUMNS[name]:
            bad.append(f"{name}: columns {header} != {COLUMNS[name]}")
        for i, r in enumerate(rows):
            for c in cols:
                try:
                    ok = math.isfinite(float(r[c]))
                except (KeyError, ValueError):
                    ok = False
                if not ok:
                    bad.append(f"{name} row {i}: {c}={r.get(c)!r} not finite")
    for r in csv.DictReader(open(out / "loc_grid.csv")):
        if int(r["success"]) != int(sweep.loc_success(float(r["ate_rmse"]))):
            bad.append(f"loc_grid: success flag wrong in {r}")
        if int(r["sim_seed"]) != sweep.derive_seed(1, "sim", r["scene"], int(r["trial"])):
            bad.append(f"loc_grid: seed not derived from base seed 1: {r}")
    for r in csv.DictReader(open(out / "map_grid.csv")):
        if int(r["success"]) != int(sweep.map_success(float(r["f1_cells"]))):
            bad.append(f"map_grid: success flag wrong in {r}")
    for r in csv.DictReader(open(out / "stability.csv")):
        crit = sweep.loc_success if r["task"] == "loc" else sweep.map_success
        if int(r["success"]) != int(crit(float(r["metric"]))):
            bad.append(f"stability: success flag wrong in {r}")
    axes = {r["axis"] for r in csv.DictReader(open(out / "stability_summary.csv"))}
    if axes != set(sweep.config(True, None)["axes"]):
        bad.append(f"stability_summary: axes {sorted(axes)} != the quick config's")
    panes = [r for r in csv.DictReader(open(out / "stability.csv")) if r["axis"] == "panes"]
    if not {"loc", "map"} <= {r["task"] for r in panes}:
        bad.append("stability: the panes sweep needs localization and mapping rows")
    quick_k = sweep.config(True, None)["kidnap"]
    for r in csv.DictReader(open(out / "kidnap.csv")):
        # recovered <=> a time to recover; the event happened when asked, and as far as asked
        if int(r["recovered"]) != (r["time_to_recover"] != ""):
            bad.append(f"kidnap: recovered flag and time to recover disagree in {r}")
        if r["time_to_recover"] != "" and not 0 <= float(r["time_to_recover"]) < 1e4:
            bad.append(f"kidnap: time to recover out of range in {r}")
        if abs(float(r["kidnap_time"]) - quick_k["at"]) > 0.11:
            bad.append(f"kidnap: kidnap time {r['kidnap_time']} != {quick_k['at']}")
        if float(r["jump_m"]) > float(r["distance"]) + 1e-6:
            bad.append(f"kidnap: jumped {r['jump_m']} m, further than {r['distance']} m along the path")
        if float(r["error_before_max"]) >= sweep.SUCCESS_ATE_M:
            bad.append(f"kidnap: lost before the kidnapping in {r}")
    # The report's kidnapping table is the CSV's: every success rate appears in its model's row.
    results = (out / "RESULTS.md").read_text().split("## Kidnapping", 1)
    kid_rows = results[1].split("\n## ", 1)[0].splitlines() if len(results) == 2 else []
    for r in csv.DictReader(open(out / "kidnap_summary.csv")):
        row = next((line for line in kid_rows if line.startswith(f"| {r['model']} |")), None)
        cell = f"{float(r['success_rate']):.2f}"
        if row is None or cell not in row:
            bad.append(f"RESULTS.md kidnapping row of {r['model']} lacks {cell} at {r['distance']} m: {row}")
    spread = [float(r["spread_m"]) for r in csv.DictReader(open(out / "fig8.csv"))]
    if spread and not all(s >= 0 for s in spread):
        bad.append("fig8: negative particle spread")
    for b in bad[:30]:
        print("FAIL", b)
    print(f"{'FAILED' if bad else 'OK'}: {len(bad)} problems in {out}")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
