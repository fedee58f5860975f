"""Floorplans: Segment, read_floorplan / write_floorplan round trips in every format the command
writes, errors naming the file."""

import numpy as np
import pytest

import glassmap


def square_with_glass():
    return [
        glassmap.Segment((0, 0), (10, 0)),
        glassmap.Segment((10, 0), (10, 8), "glass", thickness=0.012),
        glassmap.Segment((10, 8), (0, 8), material="wall", thickness=0.2),
        glassmap.Segment((0, 8), (0, 0), "glass", 0.01),
    ]


@pytest.mark.parametrize("ext", ["gpkg", "geojson", "dxf", "shp", "fgb"])
def test_round_trip(tmp_path, ext):
    segments = square_with_glass()
    path = tmp_path / f"plan.{ext}"
    glassmap.write_floorplan(segments, path)
    plan = glassmap.read_floorplan(path)
    assert len(plan) == 4 and plan.count("glass") == 2 and plan.path == str(path)
    for a, b in zip(segments, plan.segments):
        assert b.material == a.material
        assert np.allclose(a.a, b.a, atol=1e-6) and np.allclose(a.b, b.b, atol=1e-6)
        assert b.thickness == pytest.approx(a.thickness, abs=1e-9)
    assert plan.bounds == pytest.approx((0, 0, 10, 8))
    # A Floorplan writes as its segments do.
    glassmap.write_floorplan(plan, tmp_path / f"again.{ext}")
    assert glassmap.read_floorplan(tmp_path / f"again.{ext}").segments == plan.segments


def test_pictures(tmp_path):
    for ext in ["svg", "png", "pdf"]:
        glassmap.write_floorplan(glassmap.Floorplan(square_with_glass()), tmp_path / f"plan.{ext}")
        assert (tmp_path / f"plan.{ext}").stat().st_size > 100


def test_units_and_scale_warning(tmp_path):
    path = tmp_path / "plan.geojson"
    glassmap.write_floorplan(square_with_glass(), path)
    with pytest.warns(UserWarning, match="implausible"):
        plan = glassmap.read_floorplan(path, units="cm")
    assert plan.bounds == pytest.approx((0, 0, 0.1, 0.08)) and plan.scale_warning
    with pytest.warns(UserWarning, match="plan.geojson"):
        small = glassmap.read_floorplan(path, units="mm")
    assert small.scale_warning


def test_segment_api():
    s = glassmap.Segment((0, 0), (3, 4), "glass")
    assert s.length == 5 and s.material == "glass" and s.thickness == 0.1
    s.b = (6, 8)
    s.material = "wall"
    assert s.length == 10 and s.material == "wall"
    with pytest.raises(glassmap.Error, match="brick"):
        s.material = "brick"
    with pytest.raises(TypeError):
        glassmap.Segment((0, 0, 0), (1, 1))


def test_errors_name_the_file(tmp_path):
    with pytest.raises(glassmap.Error, match="none.gpkg"):
        glassmap.read_floorplan(tmp_path / "none.gpkg")
    with pytest.raises(glassmap.Error, match="plan.xyz"):
        glassmap.write_floorplan(square_with_glass(), tmp_path / "plan.xyz")
    with pytest.raises(TypeError):
        glassmap.write_floorplan([1, 2], tmp_path / "plan.gpkg")
    with pytest.raises(glassmap.Error, match="units"):
        glassmap.read_floorplan(tmp_path / "none.gpkg", units="furlongs")
