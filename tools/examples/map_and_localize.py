#!/usr/bin/env python3
"""Map a laser log, then localize the same log against the map: the glassmap Python module.

Run it as a script, or cell by cell (`# %%`) in an editor that knows cells (VS Code, Spyder,
Jupyter through jupytext):

    PYTHONPATH=build/python python3 tools/examples/map_and_localize.py              # a simulated corridor
    PYTHONPATH=build/python python3 tools/examples/map_and_localize.py run.clf -o out/mine

Without a log it simulates the bundled `paper-corridor` scene with the `glassmap` command (from the
same build, or $GLASSMAP_BIN) and compares the localization with the simulator's ground truth.
"""

# %% Setup: where the log comes from.
import argparse
import os
import pathlib
import subprocess

import numpy as np

import glassmap

here = pathlib.Path(__file__).resolve().parent
source_dir = here.parents[1]
parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("log", nargs="?", help="CARMEN log or ROS 2 bag with SLAM-corrected poses (default: simulate)")
parser.add_argument("-o", "--out", default="out/example", help="output folder")
parser.add_argument("--scene", default="paper-corridor", help="bundled scene to simulate without a log")
parser.add_argument("--duration", type=float, default=60.0, help="simulated seconds")
args = parser.parse_args()
out = pathlib.Path(args.out)
out.mkdir(parents=True, exist_ok=True)

truth = None
if args.log is None:
    # The glassmap command of this build: build/python/glassmap/ -> build/tools/glassmap.
    exe = os.environ.get("GLASSMAP_BIN", str(pathlib.Path(glassmap.__file__).resolve().parents[2] / "tools" / "glassmap"))
    scene = source_dir / "maps" / args.scene / "scene.yaml"
    subprocess.run([exe, "simulate", str(scene), "-o", str(out / "sim"), "--seed", "1", "--duration",
                    str(args.duration), "-q"], check=True)
    log_path = out / "sim" / "log.clf"
    rows = np.loadtxt(out / "sim" / "groundtruth.tum", ndmin=2)  # t x y z qx qy qz qw
    truth = (rows[:, 0], rows[:, 1:3])
else:
    log_path = pathlib.Path(args.log)

# %% Read the log: scans with numpy ranges, laser poses, odometry.
log = glassmap.read_log(log_path)
scan = log[0]
print(f"{len(log)} scans of {len(scan)} beams, {np.degrees(scan.angles[-1] - scan.angles[0]):.0f} deg field of view, "
      f"{log.times[-1] - log.times[0]:.1f} s")

# %% Map it as `glassmap map` would (same defaults: calibration, direct classifier, MRF, pane fit).
result = glassmap.map_log(log)
labels = result.labels  # uint8 codes, row 0 = north: 0 unknown, 1 empty, 2 occupied, 10+k glass
print(f"grid {labels.shape[1]} x {labels.shape[0]} cells of {result.resolution} m, "
      f"{int((labels >= 10).sum())} glass cells, {result.stats['glass_segments']} glass and "
      f"{result.stats['wall_segments']} wall segments")
for seg in [s for s in result.segments if s.material == "glass"][:3]:
    print("  glass pane", seg)

# %% Write the same files as `glassmap map -o DIR` (ROS map, labels GeoTIFF, floorplans, stats.json).
written = result.write(out / "map")
print("wrote", len(written), "files into", out / "map")

# %% Localize the log against the fitted floorplan, starting at the first laser pose.
track = glassmap.localize(result.floorplan, log, init=log[0].pose)
print(f"localized {len(track)} scans: converged {track.converged}, "
      f"{track.summary['ms_per_update']:.2f} ms per update, final spread {track.spread[-1]:.3f} m")
track.write_tum(out / "estimate.tum")

# %% How far is the estimate from the truth (simulated logs) or from the log's own laser poses?
if truth is not None:
    t, xy = truth
    reference = xy[np.searchsorted(t, track.times).clip(0, len(t) - 1)]
    name = "ground truth"
else:
    reference = log.poses[:, :2]
    name = "the log's laser poses"
# The map was fitted in the frame of the log's laser poses, so both sit in one frame.
error = np.linalg.norm(track.poses[:, :2] - reference, axis=1)
print(f"position error against {name}: mean {error.mean():.3f} m, max {error.max():.3f} m")

# %% A picture, when matplotlib is there.
try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    plt = None
if plt is not None:
    x0, cell, _, top, _, _ = result.geotransform
    extent = (x0, x0 + labels.shape[1] * cell, top - labels.shape[0] * cell, top)
    shown = np.select([labels == 1, labels == 2, labels >= 10], [1, 2, 3], 0)
    fig, ax = plt.subplots(figsize=(10, 5))
    ax.imshow(shown, extent=extent, cmap=matplotlib.colors.ListedColormap(["#dddddd", "white", "black", "#1f77ff"]),
              vmin=0, vmax=3, interpolation="nearest")
    ax.plot(track.poses[:, 0], track.poses[:, 1], "r-", lw=1, label="localized")
    ax.set_aspect("equal")
    ax.legend()
    fig.savefig(out / "map_and_track.png", dpi=120, bbox_inches="tight")
    print("drew", out / "map_and_track.png")
