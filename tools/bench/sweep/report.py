"""Recommendations (cheapest setting within 10% of the best) and RESULTS.md."""
from __future__ import annotations

import math
from pathlib import Path

from .runner import write_csv
from .sections import AXIS_LABEL
from .stats import *  # noqa: F401,F403

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


def _f(x, nd=3):
    return "n/a" if not finite(x) else f"{float(x):.{nd}f}"


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
