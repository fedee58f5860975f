#!/usr/bin/env python3
"""glassmap bench: speed against accuracy, and where each method breaks (issue 8).

Drives the `glassmap` command line (simulate, map, localize, eval) over seeds and writes CSV files
plus charts (PNG and SVG). Every figure comes from running the binaries; nothing is hard-coded.

  python3 tools/bench/sweep --quick --out build-bench-quick      # CI-sized, a few minutes
  python3 tools/bench/sweep --out docs/results                   # full mode

Seeds are derived from --base-seed with a hash of (purpose, scene, trial index), so the same
command gives the same CSV rows (timing columns aside). The same simulated logs are used for every
method and every value of a swept quantity (paired comparison).
"""

import argparse
import sys
import time
from pathlib import Path

if __package__ in (None, ""):  # run as `python3 tools/bench/sweep`: import the package by name
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
    __package__ = "sweep"  # noqa: A001

from sweep.charts import chart_names, charts  # noqa: E402
from sweep.report import recommendations, report  # noqa: E402
from sweep.runner import Runner, config, read_csv_typed  # noqa: E402
from sweep.sections import (section_fig8, section_kidnap, section_loc, section_map,  # noqa: E402
                            section_stability)
from sweep.stats import REPO  # noqa: E402


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
