"""map_log against `glassmap map` on the same log: the same labels, grid, segments and figures."""

import filecmp
import json

import numpy as np
import pytest

import glassmap
from conftest import SOURCE_DIR, run_cli

# Figures of stats.json that differ between two runs of the same map (times, memory, paths).
RUN_DEPENDENT = {"seconds", "peak_memory_bytes", "log", "files"}


def comparable(stats):
    return {k: v for k, v in stats.items() if k not in RUN_DEPENDENT}


def test_labels_match_the_labels_geotiff(py_map, cli_map):
    out, stats = cli_map
    labels = py_map.labels
    assert labels.dtype == np.uint8 and labels.ndim == 2
    assert labels.shape == (stats["grid"]["height"], stats["grid"]["width"])
    # Glass was found, with codes 10 + k, and everything is a valid code.
    codes = set(np.unique(labels).tolist())
    assert codes <= {0, 1, 2} | set(range(10, 46)), codes
    assert any(c >= 10 for c in codes)
    gdal = pytest.importorskip("osgeo.gdal", reason="python3-gdal absent: labels checked through write() below")
    ds = gdal.Open(str(out / "labels.tif"))
    assert np.array_equal(ds.GetRasterBand(1).ReadAsArray(), labels)
    assert ds.GetGeoTransform() == pytest.approx(py_map.geotransform, abs=1e-9)


def test_geotransform_is_the_grid(py_map, cli_map):
    _, stats = cli_map
    x0, cell, r1, top, r2, neg = py_map.geotransform
    grid = stats["grid"]
    assert (r1, r2) == (0.0, 0.0) and cell == grid["resolution"] == -neg == py_map.resolution
    assert x0 == pytest.approx(grid["origin"][0]) and top == pytest.approx(grid["origin"][1] + grid["height"] * cell)


def test_stats_are_those_of_the_command(py_map, cli_map):
    _, stats = cli_map
    mine = py_map.stats
    assert set(mine) | {"files"} == set(stats)
    assert comparable(mine) == comparable(stats)
    assert mine["glass_segments"] > 0 and mine["calibrated"] is True


def test_segments_match_the_floorplan_written(py_map, cli_map):
    out, stats = cli_map
    segments = py_map.segments
    assert len(segments) == stats["glass_segments"] + stats["wall_segments"]
    assert sum(s.material == "glass" for s in segments) == stats["glass_segments"]
    plan = glassmap.read_floorplan(out / "floorplan.gpkg", clutter=False)  # the walls and panes: .segments
    assert len(plan) == len(segments)
    for mine, theirs in zip(segments, plan.segments):
        assert mine.material == theirs.material
        assert np.allclose(mine.a + mine.b, theirs.a + theirs.b, atol=1e-6)
        assert mine.thickness == pytest.approx(theirs.thickness)


def test_write_gives_the_same_files(py_map, cli_map, tmp_path):
    out, stats = cli_map
    written = py_map.write(tmp_path / "py")
    names = sorted(p.rsplit("/", 1)[-1] for p in written)
    assert names == sorted(stats["files"] + ["stats.json"])
    for name in ["labels.tif", "map.pgm", "map.yaml", "sensor.yaml", "floorplan.geojson"]:
        assert filecmp.cmp(out / name, tmp_path / "py" / name, shallow=False), name
    mine = json.loads((tmp_path / "py" / "stats.json").read_text())
    assert comparable(mine) == comparable(stats) and mine["files"] == stats["files"]


def test_options_are_the_command_line_options(log, scene, tmp_path):
    # A cheaper run with several options, against the command with the same options.
    options = dict(method="direct", resolution=0.1, no_calibrate=True, keep_phantoms=True, no_vector=True,
                   no_return_range=8.0, min_glass_hits=3, sparse_panes=True, keep_opaque_glass=True,
                   no_scan_fit=True, p_hit_empty_from_log=True)
    mine = glassmap.map_log(scene / "log.clf", **options)
    from conftest import run_cli

    run_cli("map", scene / "log.clf", "-o", tmp_path, "-q", "--method", "direct", "--resolution", 0.1,
            "--no-calibrate", "--keep-phantoms", "--no-vector", "--no-return-range", 8, "--min-glass-hits", 3,
            "--sparse-panes", "--keep-opaque-glass", "--no-scan-fit", "--p-hit-empty-from-log")
    theirs = json.loads((tmp_path / "stats.json").read_text())
    assert comparable(mine.stats) == comparable(theirs)
    # The classifier took the hit rate of the log's empty space (Laplace's rule), not the fixed 0.02.
    empty = theirs["empty_space"]
    assert empty["cells"] > 0 and empty["p_hit_emp"] == pytest.approx(
        (empty["hits"] + 1) / (empty["hits"] + empty["misses"] + 2), rel=1e-12)
    assert empty["p_hit_emp"] < 0.01 and theirs["options"]["direct"]["p_hit_emp"] == 0.02
    assert mine.stats["options"]["scan_fit"]["enabled"] is False
    assert mine.stats["log"] == str(scene / "log.clf")
    assert mine.labels.shape == (theirs["grid"]["height"], theirs["grid"]["width"])


def test_unknown_and_bad_options(log):
    with pytest.raises(TypeError, match="resolutoin"):
        glassmap.map_log(log, resolutoin=0.1)
    with pytest.raises(TypeError, match="resolution"):
        glassmap.map_log(log, resolution="fine")
    with pytest.raises(ValueError, match="resolution"):
        glassmap.map_log(log, resolution=-1.0)
    with pytest.raises(glassmap.Error, match="unknown mapping method 'best'"):
        glassmap.map_log(log, method="best")


def test_memory_budget_is_refused_with_the_figure(log):
    with pytest.raises(glassmap.Error, match="MB"):
        glassmap.map_log(log, max_memory=1.0, no_calibrate=True)


def test_errors_name_the_file(tmp_path):
    missing = tmp_path / "missing.clf"
    with pytest.raises(glassmap.Error, match="missing.clf") as info:
        glassmap.map_log(missing)
    assert isinstance(info.value, RuntimeError) and info.value.file == str(missing)


def test_a_log_over_a_quarter_of_max_memory_is_kept_on_disk(tmp_path):
    # 60 s of glass-corridor: about 2.6 MB of scans; its grid needs about 4 MB. In 6.3 MB the log
    # held in memory leaves too little for the grid; kept on disk (two 1 MB blocks) it fits.
    run_cli("simulate", SOURCE_DIR / "maps" / "glass-corridor" / "scene.yaml", "-o", tmp_path / "sim", "--seed", 3,
            "--duration", 60, "-q")
    spool = tmp_path / "spool"
    spool.mkdir()
    in_memory = glassmap.map_log(tmp_path / "sim" / "log.clf")
    on_disk = glassmap.map_log(tmp_path / "sim" / "log.clf", max_memory=6.3, spool_dir=spool)
    assert in_memory.stats["log_on_disk_bytes"] == 0
    assert on_disk.stats["log_on_disk_bytes"] > 2_000_000
    assert np.array_equal(in_memory.labels, on_disk.labels)
    assert comparable(on_disk.stats)["glass_cells"] == comparable(in_memory.stats)["glass_cells"]
    assert not any(spool.iterdir())  # an unnamed file: nothing left
