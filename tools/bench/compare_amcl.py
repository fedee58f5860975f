#!/usr/bin/env python3
"""glassmap's localization update against nav2 AMCL's, on the same map, scans and particle counts.

nav2's AMCL (https://github.com/ros-navigation/navigation2, package nav2_amcl) is not packaged
in Debian and is not vendored here. Clone it yourself (no ROS installation is needed: only its
particle filter, map and laser-model sources are compiled, with g++), then run

    git clone --depth 1 https://github.com/ros-navigation/navigation2 /path/to/navigation2
    tools/bench/compare_amcl.py --nav2 /path/to/navigation2 --build build --out out/amcl

What it does:
  1. `glassmap simulate maps/office-floor/scene.yaml --duration 20 --seed 1`: the 200-scan log of
     build/tools/bench_localize (hokuyo-utm30lx, 1,081 beams, glass along the corridor);
  2. the true floorplan drawn into a 0.05 m occupancy grid (every segment into the cells it
     crosses, glass as walls: AMCL has no notion of glass), AMCL's map;
  3. a driver (written to a temporary folder, compiled against nav2_amcl/src/pf/*.c,
     src/map/map.c, map_range.c, map_cspace.cpp, src/sensors/laser/laser.cpp,
     likelihood_field_model.cpp and beam_model.cpp) runs AMCL's update on every scan: the differential odometry motion model
     (nav2's DifferentialMotionModel::odometryUpdate, copied into the driver because its file
     needs pluginlib; it draws with nav2's pf_ran_gaussian), the laser model's sensorUpdate
     (pf_update_sensor) and pf_update_resample, nav2's default parameters (alpha1-4 0.2,
     z_hit 0.5, z_rand 0.5, sigma_hit 0.2, laser_likelihood_max_dist 2.0; beam model: z_hit 0.5,
     z_short 0.05, z_max 0.05, z_rand 0.5, lambda_short 0.1), a fixed particle count
     (min = max), recovery off (alpha_slow = alpha_fast = 0, nav2's default), the filter started
     at the first true pose (0.1 m, 3 deg) like bench_localize; time per update over the whole log
     (CPU time of the driver's thread), and the final and largest position error of AMCL's
     estimate (its heaviest cluster's mean) against the truth;
  4. build/tools/bench_localize for glassmap's models at the same sizes (CPU time per update too).
Writes OUT/amcl.json and OUT/amcl.csv and prints the table. The load average is recorded with the
figures; run it on an idle machine.
"""
import argparse
import csv
import json
import math
import os
import struct
import subprocess
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent.parent
SIZES = [(2500, 61), (500, 15)]

DRIVER = r"""
// AMCL's update on a log, timed. Built by tools/bench/compare_amcl.py against nav2_amcl's sources.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <string>
#include <vector>
#include "nav2_amcl/angleutils.hpp"
#include "nav2_amcl/map/map.hpp"
#include "nav2_amcl/pf/pf.hpp"
#include "nav2_amcl/pf/pf_pdf.hpp"
#include "nav2_amcl/sensors/laser/laser.hpp"

using namespace nav2_amcl;

static double cpu() { timespec t; clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t); return t.tv_sec + 1e-9 * t.tv_nsec; }
static pf_vector_t randomPose(void*) { pf_vector_t p = pf_vector_zero(); return p; }  // recovery is off

// nav2_amcl DifferentialMotionModel::odometryUpdate (motion_model/differential_motion_model.cpp).
static void odometryUpdate(pf_t* pf, const pf_vector_t& pose, const pf_vector_t& delta, const double* a) {
  pf_sample_set_t* set = pf->sets + pf->current_set;
  pf_vector_t old_pose = pf_vector_sub(pose, delta);
  double delta_rot1, delta_trans, delta_rot2, delta_rot1_noise, delta_rot2_noise;
  if (sqrt(delta.v[1] * delta.v[1] + delta.v[0] * delta.v[0]) < 0.01)
    delta_rot1 = 0.0;
  else
    delta_rot1 = angleutils::angle_diff(atan2(delta.v[1], delta.v[0]), old_pose.v[2]);
  delta_trans = sqrt(delta.v[0] * delta.v[0] + delta.v[1] * delta.v[1]);
  delta_rot2 = angleutils::angle_diff(delta.v[2], delta_rot1);
  delta_rot1_noise = std::min(fabs(angleutils::angle_diff(delta_rot1, 0.0)), fabs(angleutils::angle_diff(delta_rot1, M_PI)));
  delta_rot2_noise = std::min(fabs(angleutils::angle_diff(delta_rot2, 0.0)), fabs(angleutils::angle_diff(delta_rot2, M_PI)));
  for (int i = 0; i < set->sample_count; i++) {
    pf_sample_t* s = set->samples + i;
    double r1 = angleutils::angle_diff(delta_rot1, pf_ran_gaussian(sqrt(a[0] * delta_rot1_noise * delta_rot1_noise + a[1] * delta_trans * delta_trans)));
    double tr = delta_trans - pf_ran_gaussian(sqrt(a[2] * delta_trans * delta_trans + a[3] * delta_rot1_noise * delta_rot1_noise + a[3] * delta_rot2_noise * delta_rot2_noise));
    double r2 = angleutils::angle_diff(delta_rot2, pf_ran_gaussian(sqrt(a[0] * delta_rot2_noise * delta_rot2_noise + a[1] * delta_trans * delta_trans)));
    s->pose.v[0] += tr * cos(s->pose.v[2] + r1);
    s->pose.v[1] += tr * sin(s->pose.v[2] + r1);
    s->pose.v[2] += r1 + r2;
  }
}

int main(int argc, char** argv) {
  if (argc < 5) { std::fprintf(stderr, "usage: driver DATA PARTICLES BEAMS MODEL(field|beam)\n"); return 2; }
  FILE* f = std::fopen(argv[1], "rb");
  int32_t w, h, n_scans, n_ranges;
  double res, ox, oy, start, step, range_max;
  if (!f || std::fread(&w, 4, 1, f) != 1 || std::fread(&h, 4, 1, f) != 1 || std::fread(&res, 8, 1, f) != 1 ||
      std::fread(&ox, 8, 1, f) != 1 || std::fread(&oy, 8, 1, f) != 1 || std::fread(&n_scans, 4, 1, f) != 1 ||
      std::fread(&n_ranges, 4, 1, f) != 1 || std::fread(&start, 8, 1, f) != 1 || std::fread(&step, 8, 1, f) != 1 ||
      std::fread(&range_max, 8, 1, f) != 1) { std::fprintf(stderr, "bad data file\n"); return 1; }
  std::vector<unsigned char> grid(size_t(w) * h);
  std::vector<double> poses(size_t(n_scans) * 6);
  std::vector<float> ranges(size_t(n_scans) * n_ranges);
  if (std::fread(grid.data(), 1, grid.size(), f) != grid.size() ||
      std::fread(poses.data(), 8, poses.size(), f) != poses.size() ||
      std::fread(ranges.data(), 4, ranges.size(), f) != ranges.size()) { std::fprintf(stderr, "short data file\n"); return 1; }
  std::fclose(f);
  const int particles = std::atoi(argv[2]), beams = std::atoi(argv[3]);
  const bool beam_model = std::string(argv[4]) == "beam";
  map_t* map = map_alloc();
  map->size_x = w;
  map->size_y = h;
  map->scale = res;
  map->origin_x = ox + (w / 2) * res;  // as amcl_node's convertMap: the map centre
  map->origin_y = oy + (h / 2) * res;
  map->cells = (map_cell_t*)std::malloc(sizeof(map_cell_t) * w * h);
  for (size_t i = 0; i < grid.size(); ++i) map->cells[i].occ_state = grid[i] ? +1 : -1;
  Laser* laser = beam_model ? (Laser*)new BeamModel(0.5, 0.05, 0.05, 0.5, 0.2, 0.1, 0.0, beams, map)
                            : (Laser*)new LikelihoodFieldModel(0.5, 0.5, 0.2, 2.0, beams, map);
  pf_vector_t laser_pose = pf_vector_zero();
  laser->SetLaserPose(laser_pose);
  const double alpha[4] = {0.2, 0.2, 0.2, 0.2};
  srand48(1);
  pf_t* pf = pf_alloc(particles, particles, 0.0, 0.0, randomPose);
  pf_vector_t mean = {{poses[3], poses[4], poses[5]}};
  pf_matrix_t cov = pf_matrix_zero();
  cov.m[0][0] = cov.m[1][1] = 0.1 * 0.1;
  cov.m[2][2] = std::pow(3.0 * M_PI / 180.0, 2);
  pf_init(pf, mean, cov);
  LaserData data;
  data.laser = laser;
  data.range_count = n_ranges;
  data.range_max = range_max;
  data.ranges = new double[n_ranges][2];
  double final_error = 0, max_error = 0;
  const double t0 = cpu();
  for (int k = 1; k < n_scans; ++k) {
    const double* o0 = &poses[size_t(k - 1) * 6];
    const double* o1 = &poses[size_t(k) * 6];
    pf_vector_t pose = {{o1[0], o1[1], o1[2]}};
    pf_vector_t delta = {{o1[0] - o0[0], o1[1] - o0[1], angleutils::angle_diff(o1[2], o0[2])}};
    odometryUpdate(pf, pose, delta, alpha);
    for (int i = 0; i < n_ranges; ++i) {
      data.ranges[i][0] = ranges[size_t(k) * n_ranges + i];
      data.ranges[i][1] = start + i * step;
    }
    laser->sensorUpdate(pf, &data);
    pf_update_resample(pf, nullptr);
    // The estimate: the heaviest cluster's mean (amcl_node's choice); not timed.
    double best_w = -1;
    pf_vector_t best = pf_vector_zero();
    for (int c = 0; c < pf->sets[pf->current_set].cluster_count; ++c) {
      double wc;
      pf_vector_t m;
      pf_matrix_t cv;
      if (pf_get_cluster_stats(pf, c, &wc, &m, &cv) && wc > best_w) { best_w = wc; best = m; }
    }
    const double* truth = &poses[size_t(k) * 6 + 3];
    final_error = std::hypot(best.v[0] - truth[0], best.v[1] - truth[1]);
    if (final_error > max_error) max_error = final_error;
  }
  const double secs = cpu() - t0;
  std::printf("{\"updates\": %d, \"seconds\": %.6f, \"ms_per_update\": %.4f, \"final_error_m\": %.4f, \"max_error_m\": %.4f}\n",
              n_scans - 1, secs, 1e3 * secs / (n_scans - 1), final_error, max_error);
  return 0;
}
"""


def read_log(path):
    """ROBOTLASER1 records of a glassmap CARMEN log: (start, step, max_range, ranges, odometry pose)."""
    scans = []
    for line in open(path):
        if not line.startswith("ROBOTLASER1"):
            continue
        f = line.split()
        start, fov, step, max_range = float(f[2]), float(f[3]), float(f[4]), float(f[5])
        n = int(f[8])
        ranges = [float(v) for v in f[9:9 + n]]
        m = int(f[9 + n])
        k = 10 + n + m
        robot = (float(f[k + 3]), float(f[k + 4]), float(f[k + 5]))  # robot_pose: the odometry
        scans.append((start, step, max_range, ranges, robot))
    return scans


def read_truth(path):
    out = []
    for line in open(path):
        if line.startswith("#") or not line.strip():
            continue
        t, x, y, z, qx, qy, qz, qw = map(float, line.split())
        out.append((x, y, 2.0 * math.atan2(qz, qw)))
    return out


def rasterize(plan, res, margin=1.0):
    data = json.loads(Path(plan).read_text())
    segs = []
    for feat in data["features"]:
        g = feat["geometry"]
        lines = [g["coordinates"]] if g["type"] == "LineString" else g["coordinates"]
        for line in lines:
            segs += [(a[0], a[1], b[0], b[1]) for a, b in zip(line[:-1], line[1:])]
    lo_x = min(min(s[0], s[2]) for s in segs) - margin
    lo_y = min(min(s[1], s[3]) for s in segs) - margin
    hi_x = max(max(s[0], s[2]) for s in segs) + margin
    hi_y = max(max(s[1], s[3]) for s in segs) + margin
    w, h = int(math.ceil((hi_x - lo_x) / res)), int(math.ceil((hi_y - lo_y) / res))
    grid = bytearray(w * h)
    for ax, ay, bx, by in segs:
        steps = max(2, int(math.ceil(math.hypot(bx - ax, by - ay) / (res / 4))) + 1)
        for i in range(steps):
            t = i / (steps - 1)
            cx, cy = int((ax + t * (bx - ax) - lo_x) / res), int((ay + t * (by - ay) - lo_y) / res)
            grid[cy * w + cx] = 1
    return w, h, lo_x, lo_y, bytes(grid)


def write_data(path, grid, res, scans, truth):
    w, h, lo_x, lo_y, cells = grid
    start, step, max_range = scans[0][0], scans[0][1], scans[0][2]
    n = len(scans[0][3])
    with open(path, "wb") as f:
        f.write(struct.pack("<iiddd", w, h, res, lo_x, lo_y))
        f.write(struct.pack("<iiddd", len(scans), n, start, step, max_range))
        f.write(cells)
        for s, t in zip(scans, truth):
            f.write(struct.pack("<6d", *s[4], *t))
        for s in scans:
            f.write(struct.pack(f"<{n}f", *s[3]))


def build_driver(nav2, tmp):
    amcl = Path(nav2) / "nav2_amcl"
    if not (amcl / "src" / "pf" / "pf.c").exists():
        sys.exit(f"compare_amcl: {amcl}/src/pf/pf.c not found: --nav2 must name a navigation2 checkout")
    inc = ["-I", str(amcl / "include"), "-I", str(amcl / "src" / "include")]
    objs = []
    for c in ["pf/pf.c", "pf/pf_kdtree.c", "pf/pf_pdf.c", "pf/pf_vector.c", "pf/eig3.c", "map/map.c", "map/map_range.c"]:
        o = Path(tmp) / (Path(c).stem + ".o")
        subprocess.run(["gcc", "-O2", "-c", str(amcl / "src" / c), "-o", str(o)] + inc, check=True)
        objs.append(str(o))
    cxx = ["map/map_cspace.cpp", "sensors/laser/laser.cpp", "sensors/laser/likelihood_field_model.cpp",
           "sensors/laser/beam_model.cpp"]
    (Path(tmp) / "driver.cpp").write_text(DRIVER)
    exe = Path(tmp) / "amcl_driver"
    subprocess.run(["g++", "-O2", "-std=c++17", str(Path(tmp) / "driver.cpp")] + [str(amcl / "src" / c) for c in cxx] +
                   objs + inc + ["-o", str(exe), "-lm"], check=True)
    return exe


def bench_localize(build):
    exe = Path(build) / "tools" / "bench_localize"
    with tempfile.NamedTemporaryFile(suffix=".json") as out:
        subprocess.run([str(exe), "--benchmark_filter=/1/", f"--benchmark_out={out.name}", "--benchmark_out_format=json"],
                       check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        data = json.load(open(out.name))
    rows = []
    for b in data["benchmarks"]:
        name = b["name"]  # BM_Update_<model>/<particles>/<beams>/1/real_time
        model, p, n = name.split("/")[0].replace("BM_Update_", ""), int(name.split("/")[1]), int(name.split("/")[2])
        # CPU time per update, as the driver's: the benchmark's wall time per update scaled by its
        # CPU / wall ratio (one thread: the whole update runs on the benchmark's thread).
        cpu_share = b["cpu_time"] / b["real_time"] if b["real_time"] > 0 else 1.0
        rows.append({"who": "glassmap", "model": model, "particles": p, "beams": n,
                     "ms_per_update": 1e3 * b["s/update"] * cpu_share, "final_error_m": b["final_error_m"],
                     "max_error_m": b["max_error_m"]})
    return rows


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--nav2", required=True, help="a navigation2 checkout (holds nav2_amcl/)")
    ap.add_argument("--build", default=str(ROOT / "build"))
    ap.add_argument("--out", default=str(ROOT / "out" / "amcl"))
    ap.add_argument("--resolution", type=float, default=0.05, help="AMCL's map cell [m] (default 0.05)")
    args = ap.parse_args()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    load_before = os.getloadavg()[0]
    glassmap = Path(args.build) / "tools" / "glassmap"
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        sim = Path(tmp) / "sim"
        subprocess.run([str(glassmap), "simulate", str(ROOT / "maps" / "office-floor" / "scene.yaml"), "-o", str(sim),
                        "--duration", "20", "--seed", "1", "-q"], check=True)
        scans, truth = read_log(sim / "log.clf"), read_truth(sim / "groundtruth.tum")
        if len(scans) != len(truth):
            sys.exit(f"compare_amcl: {len(scans)} scans but {len(truth)} true poses")
        data = Path(tmp) / "amcl.bin"
        write_data(data, rasterize(sim / "floorplan.geojson", args.resolution), args.resolution, scans, truth)
        driver = build_driver(args.nav2, tmp)
        for model in ["field", "beam"]:
            for p, n in SIZES:
                r = json.loads(subprocess.run([str(driver), str(data), str(p), str(n), model], check=True,
                                              capture_output=True, text=True).stdout)
                rows.append({"who": "nav2 AMCL", "model": "likelihood field" if model == "field" else "beam",
                             "particles": p, "beams": n, "ms_per_update": r["ms_per_update"],
                             "final_error_m": r["final_error_m"], "max_error_m": r["max_error_m"]})
                print(f"  AMCL {model} {p} x {n}: {r['ms_per_update']:.2f} ms/update", file=sys.stderr)
    rows += bench_localize(args.build)
    result = {"scene": "office-floor, 20 s, seed 1", "load_avg_1min_before": load_before,
              "load_avg_1min_after": os.getloadavg()[0], "rows": rows}
    (out / "amcl.json").write_text(json.dumps(result, indent=2) + "\n")
    with open(out / "amcl.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    print("| who | model | particles x beams | ms per update | final / max error [m] |")
    print("| --- | --- | --- | --- | --- |")
    for r in rows:
        print(f"| {r['who']} | {r['model']} | {r['particles']} x {r['beams']} | {r['ms_per_update']:.2f} | "
              f"{r['final_error_m']:.3f} / {r['max_error_m']:.3f} |")
    print(f"\nload average (1 min) {load_before:.2f} before, {result['load_avg_1min_after']:.2f} after")


if __name__ == "__main__":
    main()
