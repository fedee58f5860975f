"""Fixtures of the Python module's tests: one simulated scene, and the glassmap command's own
outputs on it (map, localize, calibrate), to compare the module with."""

import json
import os
import pathlib
import subprocess

import numpy as np
import pytest

import glassmap

SOURCE_DIR = pathlib.Path(os.environ.get("GLASSMAP_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))


def glassmap_bin():
    """The glassmap command of the same build as the module."""
    if "GLASSMAP_BIN" in os.environ:
        return os.environ["GLASSMAP_BIN"]
    # build/python/glassmap/__init__.py -> build/tools/glassmap
    return str(pathlib.Path(glassmap.__file__).resolve().parents[2] / "tools" / "glassmap")


def run_cli(*args):
    """Runs the glassmap command; fails the test with its stderr when it fails."""
    proc = subprocess.run([glassmap_bin(), *map(str, args)], capture_output=True, text=True)
    assert proc.returncode == 0, f"glassmap {' '.join(map(str, args))} failed:\n{proc.stderr}"
    return proc


def read_tum(path):
    """TUM trajectory as (times, N x 3 poses x, y, yaw)."""
    rows = np.loadtxt(path, ndmin=2)
    qz, qw = rows[:, 6], rows[:, 7]
    yaw = 2.0 * np.arctan2(qz, qw)
    return rows[:, 0], np.column_stack([rows[:, 1], rows[:, 2], yaw])


@pytest.fixture(scope="session")
def scene(tmp_path_factory):
    """glass-corridor simulated for 30 s with seed 3: log.clf, groundtruth.tum, floorplan.*."""
    out = tmp_path_factory.mktemp("sim")
    run_cli("simulate", SOURCE_DIR / "maps" / "glass-corridor" / "scene.yaml", "-o", out, "--seed", 3,
            "--duration", 30, "-q")
    return out


@pytest.fixture(scope="session")
def log(scene):
    return glassmap.read_log(scene / "log.clf")


@pytest.fixture(scope="session")
def cli_map(scene, tmp_path_factory):
    """`glassmap map` of the scene with its defaults: the folder and its stats.json."""
    out = tmp_path_factory.mktemp("cli-map")
    run_cli("map", scene / "log.clf", "-o", out, "-q")
    return out, json.loads((out / "stats.json").read_text())


@pytest.fixture(scope="session")
def py_map(log):
    """map_log of the same log with the defaults."""
    return glassmap.map_log(log)
