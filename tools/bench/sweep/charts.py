"""Charts (PNG and SVG) of the bench's summaries."""
from __future__ import annotations

import math
import sys
from pathlib import Path

from .sections import AXIS_LABEL
from .stats import *  # noqa: F401,F403

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
                if finite(r[key]):
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
                    if r["model"] == m and finite(r[key]):
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
