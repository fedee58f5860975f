#!/usr/bin/env python3
"""glassmap's exact segment caster against range_libc's grid casters: speed and accuracy.

range_libc (https://github.com/kctess5/range_libc) is not packaged in Debian and is not vendored
here: build its Python wrapper yourself (its pywrapper/setup.py) so that `import range_libc`
works, then run

    tools/bench/compare_range_libc.py --build build --out out/range_libc [--resolution 0.05]

What it does, all on the shared office-100m floor (../shared/data/bench/office-100m.geojson, or
--plan):
  1. the query set of bench_raycast: poses uniformly in free space (not within 0.2 m of a
     segment, enclosed in the four axis directions), 61 beams over 270 degrees, 25 m max range
     (same rule, its own random draw; --poses, default 2,500);
  2. exact ranges of those rays against the segments (numpy, double precision): the reference;
  3. the floor rasterized at --resolution (every segment drawn into the cells it crosses), the
     grid range_libc casts in; Bresenham, ray marching, CDDT (pruned) and the giant lookup table
     are timed on the same rays (calc_range_many, one thread) and their errors against the
     reference summarised (median, p95, p99, max), build times included;
  4. glassmap's own figures from build/tools/bench_raycast (the same kind of query set): one ray
     at a time (BM_GridRange) and the SIMD batch on every instruction set the CPU has
     (BM_BatchRange); exact: tests hold them to brute force within 1e-12 m.
Writes OUT/range_libc.csv, OUT/range_libc.json and OUT/speed_accuracy.png (rays/s against p99
error). Without range_libc installed it still writes the reference and glassmap's row and says
what is missing. The machine's load average is recorded with the figures.
"""
import argparse
import json
import math
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent.parent
MAX_RANGE = 25.0
BEAMS = 61
FOV = 1.5 * math.pi
CLEARANCE = 0.2


def read_segments(path):
    data = json.loads(Path(path).read_text())
    segs = []
    for f in data["features"]:
        g = f["geometry"]
        lines = [g["coordinates"]] if g["type"] == "LineString" else g["coordinates"]
        for line in lines:
            for a, b in zip(line[:-1], line[1:]):
                segs.append((a[0], a[1], b[0], b[1]))
    return np.array(segs, dtype=np.float64)


def cast_exact(segs, ox, oy, dx, dy, max_range):
    """Exact range of each ray (ox, oy) + t (dx, dy) to the nearest segment; max_range when none."""
    ax, ay, bx, by = segs[:, 0], segs[:, 1], segs[:, 2], segs[:, 3]
    ex, ey = bx - ax, by - ay
    out = np.full(ox.shape, float(max_range))
    chunk = max(1, 4_000_000 // len(segs))
    for s in range(0, len(ox), chunk):
        o_x, o_y = ox[s:s + chunk, None], oy[s:s + chunk, None]
        d_x, d_y = dx[s:s + chunk, None], dy[s:s + chunk, None]
        den = d_x * ey - d_y * ex
        wx, wy = ax - o_x, ay - o_y
        with np.errstate(divide="ignore", invalid="ignore"):
            t = (wx * ey - wy * ex) / den
            u = (wx * d_y - wy * d_x) / den
        ok = (np.abs(den) > 1e-15) & (t >= 0) & (u >= 0) & (u <= 1)
        t = np.where(ok, t, np.inf)
        out[s:s + chunk] = np.minimum(t.min(axis=1), max_range)
    return out


def point_segment_distance(segs, p):
    a, b = segs[:, :2], segs[:, 2:]
    e = b - a
    t = np.clip(((p - a) * e).sum(1) / np.maximum((e * e).sum(1), 1e-30), 0, 1)
    q = a + t[:, None] * e
    return np.sqrt(((p - q) ** 2).sum(1)).min()


def make_queries(segs, poses, seed):
    rng = np.random.default_rng(seed)
    lo = np.minimum(segs[:, :2], segs[:, 2:]).min(0)
    hi = np.maximum(segs[:, :2], segs[:, 2:]).max(0)
    out = []
    while len(out) < poses:
        p = rng.uniform(lo, hi)
        if point_segment_distance(segs, p) < CLEARANCE:
            continue
        axes = np.arange(4) * math.pi / 2
        r = cast_exact(segs, np.full(4, p[0]), np.full(4, p[1]), np.cos(axes), np.sin(axes), 1e9)
        if np.all(r < 1e9):
            out.append((p[0], p[1], rng.uniform(-math.pi, math.pi)))
    pose = np.array(out)
    beam = -FOV / 2 + np.arange(BEAMS) * FOV / (BEAMS - 1)
    ang = (pose[:, 2:3] + beam[None, :]).ravel()
    ox = np.repeat(pose[:, 0], BEAMS)
    oy = np.repeat(pose[:, 1], BEAMS)
    return ox, oy, ang


def rasterize(segs, res, margin=1.0):
    lo = np.minimum(segs[:, :2], segs[:, 2:]).min(0) - margin
    hi = np.maximum(segs[:, :2], segs[:, 2:]).max(0) + margin
    n = int(math.ceil(max(hi - lo) / res))  # square: older range_libc wrappers mix up width and height
    grid = np.zeros((n, n), dtype=bool)  # grid[row = y, col = x]
    for ax, ay, bx, by in segs:
        steps = max(2, int(math.ceil(math.hypot(bx - ax, by - ay) / (res / 4))) + 1)
        t = np.linspace(0, 1, steps)
        cx = ((ax + t * (bx - ax) - lo[0]) / res).astype(int)
        cy = ((ay + t * (by - ay) - lo[1]) / res).astype(int)
        grid[cy, cx] = True
    return grid, lo


def summarize(err):
    return {"median_m": float(np.median(err)), "p95_m": float(np.percentile(err, 95)),
            "p99_m": float(np.percentile(err, 99)), "max_m": float(err.max())}


def glassmap_rows(build):
    exe = Path(build) / "tools" / "bench_raycast"
    if not exe.exists():
        print(f"compare_range_libc: {exe} not built; glassmap's rows left out", file=sys.stderr)
        return []
    with tempfile.NamedTemporaryFile(suffix=".json") as out:
        subprocess.run([str(exe), "--benchmark_filter=BM_GridRange$|BM_BatchRange/", f"--benchmark_out={out.name}",
                        "--benchmark_out_format=json"], check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        runs = json.load(open(out.name))["benchmarks"]
    rows = []
    note = "exact (tests: brute force within 1e-12 m, the batch bit for bit); its own query draw of the same rule"
    for b in runs:
        if b.get("error_occurred"):
            continue  # an instruction set this CPU lacks
        label = b.get("label", "")
        name = ("glassmap exact, one ray at a time" if b["name"] == "BM_GridRange" else
                "glassmap exact, batch (scalar fallback)" if label == "scalar" else
                f"glassmap exact, SIMD batch ({label})")
        rows.append({"caster": name, "rays_per_s": b["items_per_second"], "build_s": None,
                     "median_m": 0.0, "p95_m": 0.0, "p99_m": 0.0, "max_m": 0.0, "note": note})
    return rows


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--plan", default=str(Path(os.environ.get("GLASSMAP_DATA_DIR", ROOT.parent / "shared" / "data"))
                                          / "bench" / "office-100m.geojson"))
    ap.add_argument("--build", default=str(ROOT / "build"))
    ap.add_argument("--out", default=str(ROOT / "out" / "range_libc"))
    ap.add_argument("--resolution", type=float, default=0.05, help="grid cell for range_libc [m] (default 0.05)")
    ap.add_argument("--poses", type=int, default=2500)
    ap.add_argument("--theta-bins", type=int, default=108, help="CDDT / LUT angle discretisation (range_libc's default 108)")
    ap.add_argument("--skip-lut", action="store_true", help="leave out the giant lookup table (about 1 GB, 30 s build)")
    ap.add_argument("--seed", type=int, default=42)
    args = ap.parse_args()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    load_before = os.getloadavg()[0]

    segs = read_segments(args.plan)
    print(f"{len(segs)} segments; drawing {args.poses} poses x {BEAMS} beams", file=sys.stderr)
    ox, oy, ang = make_queries(segs, args.poses, args.seed)
    ref = cast_exact(segs, ox, oy, np.cos(ang), np.sin(ang), MAX_RANGE)
    rows = []
    rows += glassmap_rows(args.build)
    try:
        import range_libc  # noqa: F401 (the user's build of https://github.com/kctess5/range_libc)
    except ImportError:
        range_libc = None
        print("compare_range_libc: `import range_libc` failed: build its pywrapper first; only glassmap's row written",
              file=sys.stderr)
    if range_libc is not None:
        grid, lo = rasterize(segs, args.resolution)
        with tempfile.TemporaryDirectory() as tmp:
            png = Path(tmp) / "office.png"
            import matplotlib
            matplotlib.use("Agg")
            import matplotlib.pyplot as plt
            plt.imsave(png, np.where(grid, 0, 255).astype(np.uint8), cmap="gray", vmin=0, vmax=255)
            omap = range_libc.PyOMap(str(png).encode(), 0.5)
        # Query frame: pixels, x = column, y = row (row 0 = lowest y, as drawn), angles unchanged.
        q = np.stack([(ox - lo[0]) / args.resolution, (oy - lo[1]) / args.resolution, ang], axis=1).astype(np.float32)
        q = np.ascontiguousarray(q)
        max_px = MAX_RANGE / args.resolution
        casters = [("range_libc Bresenham", lambda: range_libc.PyBresenhamsLine(omap, max_px)),
                   ("range_libc ray marching", lambda: range_libc.PyRayMarching(omap, max_px)),
                   ("range_libc CDDT (pruned)", lambda: _pruned(range_libc.PyCDDTCast(omap, max_px, args.theta_bins)))]
        if not args.skip_lut:
            casters.append(("range_libc giant LUT", lambda: range_libc.PyGiantLUTCast(omap, max_px, args.theta_bins)))
        for name, make in casters:
            t0 = time.perf_counter()
            caster = make()
            built = time.perf_counter() - t0
            ranges = np.zeros(len(q), dtype=np.float32)
            caster.calc_range_many(q, ranges)  # warm-up
            t0 = time.perf_counter()
            caster.calc_range_many(q, ranges)
            secs = time.perf_counter() - t0
            err = np.abs(np.minimum(ranges.astype(np.float64) * args.resolution, MAX_RANGE) - ref)
            row = {"caster": name, "rays_per_s": len(q) / secs, "build_s": built, **summarize(err),
                   "note": f"grid {args.resolution} m"}
            rows.append(row)
            print(f"  {name}: {row['rays_per_s'] / 1e6:.2f} M rays/s, p99 error {row['p99_m']:.3f} m", file=sys.stderr)
            del caster

    result = {"plan": Path(args.plan).name, "rays": int(len(ref)), "resolution_m": args.resolution,
              "load_avg_1min_before": load_before, "load_avg_1min_after": os.getloadavg()[0], "rows": rows}
    (out / "range_libc.json").write_text(json.dumps(result, indent=2) + "\n")
    import csv
    with open(out / "range_libc.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=["caster", "rays_per_s", "build_s", "median_m", "p95_m", "p99_m", "max_m", "note"])
        w.writeheader()
        w.writerows(rows)
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(6, 4))
        for r in rows:
            ax.scatter(r["rays_per_s"] / 1e6, max(r["p99_m"], 1e-4), label=r["caster"])
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("M rays/s (one core)")
        ax.set_ylabel("p99 range error [m] (exact drawn at 1e-4)")
        ax.legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(out / "speed_accuracy.png", dpi=120)
    except ImportError:
        pass
    for r in rows:
        print(f"{r['caster']:32s} {r['rays_per_s'] / 1e6:8.2f} M rays/s  p95 {r['p95_m']:.3f} m  p99 {r['p99_m']:.3f} m")


def _pruned(cddt):
    cddt.prune()
    return cddt


if __name__ == "__main__":
    main()
