"""read_log: scans, poses and odometry as numpy arrays, through glassmap's own reader."""

import math

import numpy as np
import pytest

import glassmap
from conftest import run_cli


def test_scans_ranges_angles_poses(log, scene):
    info = __import__("json").loads(run_cli("info", scene / "log.clf", "--json").stdout)
    assert len(log) == info["scans"] == len(log.scans)
    scan = log[0]
    assert scan.ranges.dtype == np.float32 and scan.ranges.shape == (len(scan),)
    assert np.allclose(scan.angles, scan.angle_min + scan.angle_increment * np.arange(len(scan)))
    assert scan.max_range > 0 and np.nanmax(scan.ranges[np.isfinite(scan.ranges)]) <= scan.max_range + 1e-6
    x, y, theta = scan.pose
    assert (x, y, theta) == tuple(log.poses[0])
    assert scan.odom is not None and len(scan.odom) == 3
    assert np.all(np.diff(log.times) > 0)
    assert log[-1].time == log.times[-1] and log.path == str(scene / "log.clf")
    assert log.poses.shape == (len(log), 3) and log.odom_poses.shape == (len(log), 3)
    assert log.stats["scans"] == len(log)


def test_scans_keep_their_log_alive(scene):
    ranges = glassmap.read_log(scene / "log.clf")[5].ranges  # the log itself is dropped at once
    again = glassmap.read_log(scene / "log.clf")[5].ranges
    assert np.array_equal(ranges, again)


def test_iteration_and_indexing(log):
    times = [s.time for s in log]
    assert times == list(log.times)
    with pytest.raises(IndexError):
        log[len(log)]
    assert log[-1].time == times[-1]


def test_errors_name_file_and_line(tmp_path):
    bad = tmp_path / "bad.clf"
    bad.write_text("ODOM 0 0 0 0 0 0 1.0 host 1.0\nROBOTLASER1 0 -1.5 3.0 0.01 80 0.01 0 3 1.0 abc 1.0\n")
    with pytest.raises(glassmap.Error) as info:
        glassmap.read_log(bad)
    assert "bad.clf:2" in str(info.value) and info.value.line == 2 and info.value.file == str(bad)
    with pytest.raises(glassmap.Error, match="nothing.clf"):
        glassmap.read_log(tmp_path / "nothing.clf")


def test_options(scene):
    with pytest.raises(TypeError, match="laserid"):
        glassmap.read_log(scene / "log.clf", laserid=1)
    assert len(glassmap.read_log(scene / "log.clf", laser_id=1)) == len(glassmap.read_log(scene / "log.clf"))
    # A log over a quarter of max_memory is kept on disk; a grid that does not fit is refused.
    with pytest.raises(glassmap.Error, match="max_memory: the grid .* over the limit"):
        glassmap.map_log(scene / "log.clf", max_memory=0.2)
    with pytest.raises(TypeError):
        glassmap.read_log(42)
    assert math.isfinite(glassmap.read_log(scene / "log.clf", max_memory=100.0)[0].time)
