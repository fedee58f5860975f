#!/usr/bin/env python3
"""The README's speed table from one command.

Runs the Google Benchmark programs (ray casting, localization update, grid traversal, vectorizer,
MRF) and two end-to-end jobs (mapping Freiburg 079, simulating paper-corridor), each after reading
the load average, and writes what it measured to OUT/speed.json and OUT/speed.csv and the table
(Markdown) to stdout. A row measured while the 1-minute load average was above half a core is
flagged: such a figure is not an idle machine's.

    tools/bench/speed_table.py --build build --out out/speed
    tools/bench/speed_table.py --only raycast,localize   # a part

The end-to-end jobs need the shared data (../shared/data next to the checkout, or
GLASSMAP_DATA_DIR) for Freiburg 079 and the office-100m floor.
"""
import argparse
import csv
import json
import os
import platform
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent.parent


def load_average():
    return os.getloadavg()[0]


def run_bench(exe, bench_filter, min_time):
    """Runs one Google Benchmark program; returns {name: entry} from its JSON output."""
    with tempfile.NamedTemporaryFile(suffix=".json") as out:
        cmd = [str(exe), f"--benchmark_filter={bench_filter}", f"--benchmark_min_time={min_time}",
               f"--benchmark_out={out.name}", "--benchmark_out_format=json"]
        subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        data = json.load(open(out.name))
    try:
        shown = str(Path(exe).resolve().relative_to(ROOT))
    except ValueError:
        shown = Path(exe).name
    return {b["name"]: b for b in data["benchmarks"]}, f"{shown} {cmd[1]}"


def timed(cmd):
    """Runs cmd; returns (wall s, CPU s of the child, peak RSS MB of the child)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu, after.ru_maxrss / 1024.0


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default=str(ROOT / "build"), help="build directory (default: build/)")
    ap.add_argument("--out", default=str(ROOT / "out" / "speed"), help="where speed.json/.csv go")
    ap.add_argument("--min-time", type=float, default=1.0, help="Google Benchmark min time per figure [s]")
    ap.add_argument("--only", default="", help="comma-separated sections: raycast,localize,grid,vector,mrf,map,simulate")
    ap.add_argument("--busy-load", type=float, default=0.5,
                    help="1-minute load average above which a row is flagged as not idle (default 0.5)")
    args = ap.parse_args()
    build = Path(args.build)
    tools = build / "tools"
    data = Path(os.environ.get("GLASSMAP_DATA_DIR", ROOT.parent / "shared" / "data"))
    only = set(filter(None, args.only.split(",")))
    want = lambda s: not only or s in only
    rows = []

    def add(section, what, figure, unit, command, load):
        rows.append({"section": section, "what": what, "figure": figure, "unit": unit, "command": command,
                     "load_avg_1min": round(load, 2), "idle": load <= args.busy_load})
        print(f"  {what}: {figure:.4g} {unit} (load {load:.2f})", file=sys.stderr)

    if want("raycast"):
        load = load_average()
        b, cmd = run_bench(tools / "bench_raycast", "BM_GridRange|BM_GridCastDir|BM_GridParallel/[12]/", args.min_time)
        add("raycast", "exact ray casting, office-100m, one core (range only)",
            b["BM_GridRange"]["items_per_second"] / 1e6, "M rays/s", cmd, load)
        add("raycast", "exact ray casting, office-100m, one core (segment, material, incidence)",
            b["BM_GridCastDir"]["items_per_second"] / 1e6, "M rays/s", cmd, load)
        one = [v for k, v in b.items() if k.startswith("BM_GridParallel/1/")][0]["items_per_second"]
        two = [v for k, v in b.items() if k.startswith("BM_GridParallel/2/")][0]["items_per_second"]
        add("raycast", "exact ray casting, two cores / one core", two / one, "x", cmd, load)
    if want("localize"):
        load = load_average()
        b, cmd = run_bench(tools / "bench_localize", ".", args.min_time)
        for name, what in [("BM_Update_glass/2500/61/1/real_time", "MCL update 2,500 x 61, glass model, one core"),
                           ("BM_Update_glass/2500/61/2/real_time", "MCL update 2,500 x 61, glass model, two cores"),
                           ("BM_Update_field/2500/61/1/real_time", "MCL update 2,500 x 61, likelihood field, one core"),
                           ("BM_Update_beam/2500/61/1/real_time", "MCL update 2,500 x 61, beam model, one core"),
                           ("BM_Update_glass/500/15/1/real_time", "MCL update 500 x 15, glass model"),
                           ("BM_Update_field/500/15/1/real_time", "MCL update 500 x 15, likelihood field"),
                           ("BM_Update_beam/500/15/1/real_time", "MCL update 500 x 15, beam model")]:
            e = b[name]
            add("localize", what, e["real_time"], e["time_unit"], cmd, load)
            if e.get("final_error_m", 0.0) > 0.05:
                print(f"  warning: {name} ends {e['final_error_m']:.2f} m from the truth", file=sys.stderr)
    if want("grid"):
        load = load_average()
        b, cmd = run_bench(tools / "bench_grid", "BM_TraverseOnly", args.min_time)
        add("grid", "grid traversal (Amanatides-Woo), pure walk", b["BM_TraverseOnly"]["cells/s"] / 1e6, "M cells/s",
            cmd, load)
    if want("vector"):
        load = load_average()
        b, cmd = run_bench(tools / "bench_vector", ".", args.min_time)
        for name, e in b.items():
            add("vector", name.replace("BM_Vectorize", "vectorize "), e["cpu_time"], e["time_unit"] + " CPU", cmd, load)
    if want("mrf"):
        load = load_average()
        b, cmd = run_bench(tools / "bench_mrf", "/500", args.min_time)
        for name, e in b.items():
            add("mrf", name.replace("BM_Mrf", "MRF ") + " (500x500)", e["cpu_time"], e["time_unit"] + " CPU", cmd, load)
    glassmap = tools / "glassmap"
    with tempfile.TemporaryDirectory() as tmp:
        if want("map"):
            log = data / "real" / "freiburg-079-corrected.log.gz"
            if log.exists():
                for extra, label in [([], ""), (["--no-calibrate"], ", --no-calibrate")]:
                    load = load_average()
                    cmd = [str(glassmap), "map", str(log), "-o", f"{tmp}/fr079", "--no-return-range", "8", "-q"] + extra
                    wall, cpu, rss = timed(cmd)
                    shown = f"glassmap map freiburg-079-corrected.log.gz -o OUT --no-return-range 8 {' '.join(extra)}"
                    add("map", f"map Freiburg 079 wall time{label}", wall, "s", shown, load)
                    add("map", f"map Freiburg 079 CPU time{label}", cpu, "s CPU", shown, load)
                    add("map", f"map Freiburg 079 peak memory{label}", rss, "MB", shown, load)
            else:
                print(f"  skipped map: {log} not found", file=sys.stderr)
        if want("simulate"):
            load = load_average()
            cmd = [str(glassmap), "simulate", str(ROOT / "maps" / "paper-corridor" / "scene.yaml"), "-o", f"{tmp}/pc"]
            wall, cpu, rss = timed(cmd)
            add("simulate", "simulate paper-corridor (1.5 M beams)", wall, "s",
                "glassmap simulate maps/paper-corridor/scene.yaml -o OUT", load)

    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    meta = {"machine": platform.machine(), "cpus": os.cpu_count(), "python": platform.python_version(),
            "when": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()), "build": str(build.name), "rows": rows}
    (out / "speed.json").write_text(json.dumps(meta, indent=2) + "\n")
    with open(out / "speed.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()) if rows else ["section"])
        w.writeheader()
        w.writerows(rows)
    print("| what | figure | load avg (1 min) | command |")
    print("| --- | --- | --- | --- |")
    for r in rows:
        flag = "" if r["idle"] else " (busy)"
        print(f"| {r['what']} | {r['figure']:.3g} {r['unit']} | {r['load_avg_1min']:.2f}{flag} | `{r['command']}` |")
    busy = [r for r in rows if not r["idle"]]
    if busy:
        print(f"\nwarning: {len(busy)} of {len(rows)} figures measured with a load average above {args.busy_load}",
              file=sys.stderr)


if __name__ == "__main__":
    main()
