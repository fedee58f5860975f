#!/usr/bin/env python3
"""The README's speed table from one command.

Runs the Google Benchmark programs (ray casting one at a time and in SIMD batches, on one and two
threads; localization updates of every model on one and two threads; grid traversal; vectorizer;
MRF) and the end-to-end jobs (the 1M-cell MRF instance, mapping Freiburg 079 on one and on two
CPUs, simulating and mapping the 100 m office floor, simulating paper-corridor), each after reading
the load average, and writes what it measured to OUT/speed.json and OUT/speed.csv and the table
(Markdown) to stdout. A row measured while the 1-minute load average was above half a core is
flagged: such a figure is not an idle machine's. CPU time is reported beside wall time where the
two differ in meaning (end-to-end jobs, MRF).

    tools/bench/speed_table.py --build build --out out/speed
    tools/bench/speed_table.py --only raycast,localize      # a part
    tools/bench/speed_table.py --amcl /path/to/navigation2  # with nav2 AMCL's rows (compare_amcl.py)
    tools/bench/speed_table.py --range-libc                 # with range_libc's rows (compare_range_libc.py)

Sections: raycast, localize, grid, vector, mrf, map, floor100, simulate (and amcl, range_libc when
asked for). The end-to-end jobs need the shared data (../shared/data next to the checkout, or
GLASSMAP_DATA_DIR) for Freiburg 079 and the office-100m floor. One CPU is `taskset -c 0`; the
machine must have two for the two-CPU rows.
"""
import argparse
import csv
import json
import os
import platform
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent.parent

# The 100 m floor: the shared plan driven along its four corridors (the floor has no corridor
# between them, so the legs from one to the next cross walls: the simulator does not collide).
FLOOR100_SCENE = """name: office-100m
floorplan: {plan}
laser: {{preset: hokuyo-utm30lx, rate: 10}}
trajectory:
  waypoints: [[2.5, 13], [97.5, 13], [97.5, 38], [2.5, 38], [2.5, 63], [97.5, 63], [97.5, 87], [2.5, 87]]
  speed: 0.8
  turn_rate_deg: 45
glass: {{n_glass: 1.5, direct_sigma_deg: 2.0, direct_peak: 0.9, reflection_gain: 1.0}}
motion: {{odom_trans_sigma: 0.01, odom_rot_sigma: 0.01, odom_rot_per_m: 0.005, slam_sigma_xy: 0.01, slam_sigma_theta_deg: 0.2}}
people: {{density: 0}}
"""


def load_average():
    return os.getloadavg()[0]


def run_bench(exe, bench_filter, min_time):
    """Runs one Google Benchmark program; returns {name: entry} from its JSON output."""
    with tempfile.NamedTemporaryFile(suffix=".json") as out:
        cmd = [str(exe), f"--benchmark_filter={bench_filter}", f"--benchmark_min_time={min_time}",
               f"--benchmark_out={out.name}", "--benchmark_out_format=json"]
        subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        data = json.load(open(out.name))
    return {b["name"]: b for b in data["benchmarks"] if not b.get("error_occurred")}, f"{shown(exe)} {cmd[1]}"


def shown(path):
    try:
        return str(Path(path).resolve().relative_to(ROOT))
    except ValueError:
        return Path(path).name


def timed(cmd, cpus=None):
    """Runs cmd (pinned to `cpus` CPUs with taskset); returns (wall s, CPU s, peak RSS MB) of the child."""
    if cpus is not None and shutil.which("taskset"):
        cmd = ["taskset", "-c", ",".join(str(c) for c in range(cpus))] + list(cmd)
    # The child's own resource use (os.wait4): RUSAGE_CHILDREN's peak is the largest of every child
    # so far, which gave each row the peak of the biggest job run before it.
    t0 = time.perf_counter()
    proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    _, status, usage = os.wait4(proc.pid, 0)
    wall = time.perf_counter() - t0
    proc.returncode = os.waitstatus_to_exitcode(status)
    if proc.returncode != 0:
        raise subprocess.CalledProcessError(proc.returncode, cmd)
    return wall, usage.ru_utime + usage.ru_stime, usage.ru_maxrss / 1024.0


def one(b, prefix):
    hits = [v for k, v in b.items() if k.startswith(prefix)]
    return hits[0] if hits else None


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default=str(ROOT / "build"), help="build directory (default: build/)")
    ap.add_argument("--out", default=str(ROOT / "out" / "speed"), help="where speed.json/.csv go")
    ap.add_argument("--min-time", type=float, default=1.0, help="Google Benchmark min time per figure [s]")
    ap.add_argument("--only", default="",
                    help="comma-separated sections: raycast,localize,grid,vector,mrf,map,floor100,simulate,amcl,range_libc")
    ap.add_argument("--busy-load", type=float, default=0.5,
                    help="1-minute load average above which a row is flagged as not idle (default 0.5)")
    ap.add_argument("--amcl", default="", help="a navigation2 checkout: add nav2 AMCL's rows (tools/bench/compare_amcl.py)")
    ap.add_argument("--range-libc", action="store_true",
                    help="add range_libc's rows (tools/bench/compare_range_libc.py; needs `import range_libc`)")
    args = ap.parse_args()
    build = Path(args.build)
    tools = build / "tools"
    data = Path(os.environ.get("GLASSMAP_DATA_DIR", ROOT.parent / "shared" / "data"))
    only = set(filter(None, args.only.split(",")))
    want = lambda s: (not only and s not in ("amcl", "range_libc")) or s in only
    rows = []
    two = (os.cpu_count() or 1) >= 2

    def add(section, what, figure, unit, command, load):
        rows.append({"section": section, "what": what, "figure": figure, "unit": unit, "command": command,
                     "load_avg_1min": round(load, 2), "idle": load <= args.busy_load})
        print(f"  {what}: {figure:.4g} {unit} (load {load:.2f})", file=sys.stderr)

    if want("raycast"):
        load = load_average()
        b, cmd = run_bench(tools / "bench_raycast", "BM_GridRange$|BM_GridCastDir|BM_BatchRange/|BM_BatchParallel/",
                           args.min_time)
        add("raycast", "exact ray casting, office-100m, one core, one ray at a time (range only)",
            b["BM_GridRange"]["items_per_second"] / 1e6, "M rays/s", cmd, load)
        add("raycast", "exact ray casting, one ray at a time (segment, material, incidence)",
            b["BM_GridCastDir"]["items_per_second"] / 1e6, "M rays/s", cmd, load)
        for name, e in b.items():
            if name.startswith("BM_BatchRange/"):
                add("raycast", f"exact ray casting, SIMD batch, one core ({e.get('label', '')})",
                    e["items_per_second"] / 1e6, "M rays/s", cmd, load)
        p1, p2 = one(b, "BM_BatchParallel/1/"), one(b, "BM_BatchParallel/2/")
        if p1 and p2 and two:
            add("raycast", "exact ray casting, SIMD batch, two cores / one core", p2["items_per_second"] /
                p1["items_per_second"], "x", cmd, load)
    if want("localize"):
        load = load_average()
        b, cmd = run_bench(tools / "bench_localize", ".", args.min_time)
        for model in ["glass", "field", "beam", "glass_paper"]:
            for size in ["2500/61", "500/15"]:
                e = b.get(f"BM_Update_{model}/{size}/1/real_time")
                if not e:
                    continue
                ms = 1e3 * e["s/update"]
                add("localize", f"MCL update {size.replace('/', ' x ')}, {model} model, one core", ms, "ms", cmd, load)
                if e.get("updates/iteration") and e.get("time_unit") == "ms":  # one thread: all on the main one
                    add("localize", f"MCL update {size.replace('/', ' x ')}, {model} model, one core, CPU",
                        e["cpu_time"] / e["updates/iteration"], "ms CPU", cmd, load)
                if e.get("max_error_m", 0.0) > 0.05:
                    print(f"  warning: {model} {size} strays {e['max_error_m']:.2f} m from the truth", file=sys.stderr)
            e1, e2 = b.get(f"BM_Update_{model}/2500/61/1/real_time"), b.get(f"BM_Update_{model}/2500/61/2/real_time")
            if e1 and e2 and two:
                add("localize", f"MCL update 2500 x 61, {model} model, two cores / one core",
                    e1["s/update"] / e2["s/update"], "x", cmd, load)
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
    glassmap = tools / "glassmap"
    with tempfile.TemporaryDirectory() as tmp:
        if want("mrf"):
            load = load_average()
            b, cmd = run_bench(tools / "bench_mrf", "/500", args.min_time)
            for name, e in b.items():
                add("mrf", name.replace("BM_Mrf", "MRF ") + " (500x500)", e["cpu_time"], e["time_unit"] + " CPU", cmd,
                    load)
            load = load_average()
            out = Path(tmp) / "mrf.json"
            subprocess.run([str(glassmap), "bench", "mrf", "--unary-scale", "1", "--solvers", "expansion", "--solvers",
                            "swap", "--json", str(out)], check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            shown_cmd = "glassmap bench mrf --unary-scale 1 --solvers expansion --solvers swap"
            for r in json.load(open(out)).get("results", []):
                if r.get("solver") in ("expansion", "swap"):
                    add("mrf", f"MRF {r['solver']}, 1M cells, 38 labels (unary scale 1)", r["seconds"], "s", shown_cmd, load)
                    add("mrf", f"MRF {r['solver']}, 1M cells, CPU", r["cpu_seconds"], "s CPU", shown_cmd, load)
        if want("map"):
            log = data / "real" / "freiburg-079-corrected.log.gz"
            if log.exists():
                for cpus in ([1, 2] if two else [1]):
                    load = load_average()
                    cmd = [str(glassmap), "map", str(log), "-o", f"{tmp}/fr079", "-q"]
                    wall, cpu, rss = timed(cmd, cpus)
                    shown_cmd = f"taskset -c {','.join(str(c) for c in range(cpus))} glassmap map freiburg-079-corrected.log.gz -o OUT"
                    label = "one CPU" if cpus == 1 else "two CPUs"
                    add("map", f"map Freiburg 079 (4,791 scans x 360 beams), {label}, wall", wall, "s", shown_cmd, load)
                    add("map", f"map Freiburg 079, {label}, CPU", cpu, "s CPU", shown_cmd, load)
                    add("map", f"map Freiburg 079, {label}, peak memory", rss, "MB", shown_cmd, load)
                    stages = json.load(open(f"{tmp}/fr079/stats.json")).get("seconds", {})
                    for stage in ["read", "calibration", "counts", "angles", "phantoms", "mrf", "vectorize"]:
                        if stage in stages:
                            add("map", f"map Freiburg 079, {label}: {stage}", stages[stage], "s", shown_cmd, load)
            else:
                print(f"  skipped map: {log} not found", file=sys.stderr)
        if want("floor100"):
            plan = data / "bench" / "office-100m.geojson"
            if plan.exists():
                scene = Path(tmp) / "office-100m.yaml"
                scene.write_text(FLOOR100_SCENE.format(plan=plan))
                load = load_average()
                wall, cpu, rss = timed([str(glassmap), "simulate", str(scene), "-o", f"{tmp}/o100"])
                shown_sim = "glassmap simulate office-100m.yaml -o SIM (scene: FLOOR100_SCENE in speed_table.py)"
                add("floor100", "simulate the 100 m floor (5,800 scans x 1,081 beams)", wall, "s", shown_sim, load)
                for cpus in ([1, 2] if two else [1]):
                    load = load_average()
                    wall, cpu, rss = timed([str(glassmap), "map", f"{tmp}/o100/log.clf", "-o", f"{tmp}/o100map", "-q"],
                                           cpus)
                    label = "one CPU" if cpus == 1 else "two CPUs"
                    shown_map = f"taskset -c {','.join(str(c) for c in range(cpus))} glassmap map SIM/log.clf -o OUT"
                    add("floor100", f"map the 100 m floor at 0.05 m, {label}, wall", wall, "s", shown_map, load)
                    add("floor100", f"map the 100 m floor, {label}, CPU", cpu, "s CPU", shown_map, load)
                    add("floor100", f"map the 100 m floor, {label}, peak memory", rss, "MB", shown_map, load)
            else:
                print(f"  skipped floor100: {plan} not found", file=sys.stderr)
        if want("simulate"):
            load = load_average()
            cmd = [str(glassmap), "simulate", str(ROOT / "maps" / "paper-corridor" / "scene.yaml"), "-o", f"{tmp}/pc"]
            wall, cpu, rss = timed(cmd)
            add("simulate", "simulate paper-corridor (1.5 M beams)", wall, "s",
                "glassmap simulate maps/paper-corridor/scene.yaml -o OUT", load)
        if want("amcl") and args.amcl:
            load = load_average()
            subprocess.run([sys.executable, str(HERE / "compare_amcl.py"), "--nav2", args.amcl, "--build", str(build),
                            "--out", f"{tmp}/amcl"], check=True, stdout=subprocess.DEVNULL)
            for r in json.load(open(f"{tmp}/amcl/amcl.json"))["rows"]:
                add("amcl", f"{r['who']} {r['model']}, {r['particles']} x {r['beams']}, per update", r["ms_per_update"],
                    "ms CPU", "tools/bench/compare_amcl.py --nav2 NAV2", load)
        if want("range_libc") and args.range_libc:
            load = load_average()
            subprocess.run([sys.executable, str(HERE / "compare_range_libc.py"), "--build", str(build), "--out",
                            f"{tmp}/rl"], check=True, stdout=subprocess.DEVNULL)
            for r in json.load(open(f"{tmp}/rl/range_libc.json"))["rows"]:
                add("range_libc", f"{r['caster']} (p99 error {r['p99_m']:.3f} m)", r["rays_per_s"] / 1e6, "M rays/s",
                    "tools/bench/compare_range_libc.py", load)

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
