"""localize: tracks the simulated robot against the scene's floorplan, as `glassmap localize`."""

import json

import numpy as np
import pytest

import glassmap
from conftest import read_tum, run_cli


@pytest.fixture(scope="module")
def truth(scene):
    return read_tum(scene / "groundtruth.tum")


@pytest.fixture(scope="module")
def track(scene, log, truth):
    plan = glassmap.read_floorplan(scene / "floorplan.geojson")
    return glassmap.localize(plan, log, init=tuple(truth[1][0]))


def test_tracks_within_10_cm(track, truth, log):
    t_true, p_true = truth
    assert track.poses.shape == (len(log), 3) and len(track) == len(log)
    idx = np.searchsorted(t_true, track.times)
    assert np.allclose(t_true[idx], track.times, atol=1e-6), "truth has a pose per scan"
    err = np.linalg.norm(track.poses[:, :2] - p_true[idx, :2], axis=1)
    assert err.max() < 0.1, err.max()
    assert track.converged and track.summary["converged"] is True
    assert track.spread.shape == (len(log),) and track.spread[-1] < 0.1


def test_same_as_the_command(track, truth, scene, tmp_path):
    x, y, theta = truth[1][0]
    run_cli("localize", "--map", scene / "floorplan.geojson", scene / "log.clf", "-o", tmp_path / "est.tum",
            "--init", f"{x!r},{y!r},{theta!r}", "--json", tmp_path / "summary.json", "-q")
    t, poses = read_tum(tmp_path / "est.tum")
    assert np.allclose(t, track.times) and np.allclose(poses[:, :2], track.poses[:, :2], atol=1e-4)
    theirs = json.loads((tmp_path / "summary.json").read_text())
    timing = {"seconds", "ms_per_update", "real_time_factor"}
    assert {k: v for k, v in theirs.items() if k not in timing} == {
        k: v for k, v in track.summary.items() if k not in timing
    }
    track.write_tum(tmp_path / "mine.tum")
    assert np.allclose(read_tum(tmp_path / "mine.tum")[1], poses)


def test_options_and_paths(scene, truth):
    # Paths work as well as objects; options are the command's.
    r = glassmap.localize(scene / "floorplan.geojson", scene / "log.clf", init=truth[1][0], model="field",
                          beams=8, particles=300, fixed_count=True, seed=2)
    assert r.summary["model"] == "field" and r.summary["beams"] == 8 and r.summary["seed"] == 2
    with pytest.raises(TypeError, match="partcles"):
        glassmap.localize(scene / "floorplan.geojson", scene / "log.clf", partcles=10)
    with pytest.raises(glassmap.Error, match="glass_as|opaque"):
        glassmap.localize(scene / "floorplan.geojson", scene / "log.clf", glass_as="tinted")


def test_initial_pose_outside_the_plan(scene, log):
    with pytest.raises(glassmap.Error, match="initial pose") as info:
        glassmap.localize(scene / "floorplan.geojson", log, init=(500.0, 0.0, 0.0))
    assert "floorplan.geojson" in str(info.value) and info.value.field == "init"


def test_empty_and_implausible_plans(scene, log, tmp_path):
    with pytest.raises(glassmap.Error, match="no segments"):
        glassmap.localize(glassmap.Floorplan(), log)
    with pytest.warns(UserWarning):
        with pytest.raises(glassmap.Error, match="refusing to localize"):
            tiny = tmp_path / "tiny.geojson"
            glassmap.write_floorplan([glassmap.Segment((0, 0), (0.5, 0)), glassmap.Segment((0.5, 0), (0.5, 0.4))], tiny)
            glassmap.localize(tiny, log)
