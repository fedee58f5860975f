"""calibrate: the sensor profile of the simulated laser, as `glassmap calibrate --json`."""

import json

import pytest

import glassmap
from conftest import run_cli


@pytest.fixture(scope="module")
def fit(scene, log):
    return glassmap.calibrate(log, glassmap.read_floorplan(scene / "floorplan.geojson"))


def test_fits_the_simulated_laser(fit):
    # The bundled scene's laser: 1 cm noise, a 2 deg glass lobe of peak 0.9.
    assert fit["range_sigma_m"] == pytest.approx(0.01, abs=0.0025)
    assert fit["direct_sigma_deg"] == pytest.approx(2.0, abs=0.5)
    assert "range_sigma_m" in fit["fitted"] and len(fit["angle_bins"]) > 5


def test_same_as_the_command(fit, scene, tmp_path):
    run_cli("calibrate", scene / "log.clf", "--map", scene / "floorplan.geojson", "-o", tmp_path / "s.yaml",
            "--json", tmp_path / "c.json", "-q")
    theirs = json.loads((tmp_path / "c.json").read_text())
    differ = {"seconds", "log", "floorplan", "source"}
    assert {k: v for k, v in fit.items() if k not in differ} == {k: v for k, v in theirs.items() if k not in differ}
    assert glassmap.read_sensor_profile(tmp_path / "s.yaml")["range_sigma_m"] == pytest.approx(fit["range_sigma_m"])


def test_profile_round_trip_and_use(fit, log, tmp_path):
    glassmap.write_sensor_profile(fit, tmp_path / "sensor.yaml")
    back = glassmap.read_sensor_profile(tmp_path / "sensor.yaml")
    for key in ["range_sigma_m", "direct_peak", "direct_sigma_deg", "w_hit", "glass_offset_m"]:
        assert back[key] == pytest.approx(fit[key], rel=1e-9)
    assert back["fitted"] == fit["fitted"]
    # map_log takes the profile as a file or a dict: one pass, not calibrated.
    for sensor in [tmp_path / "sensor.yaml", back]:
        stats = glassmap.map_log(log, sensor=sensor, resolution=0.1, no_vector=True).stats
        assert stats["calibrated"] is False
        assert stats["sensor"]["range_sigma_m"] == pytest.approx(fit["range_sigma_m"])


def test_bad_profiles(tmp_path, log):
    with pytest.raises(glassmap.Error, match="range_sgima_m"):
        glassmap.write_sensor_profile({"range_sgima_m": 0.01}, tmp_path / "p.yaml")
    bad = tmp_path / "bad.yaml"
    bad.write_text("range_sigma_m: 0.02\ndirect_sigma_deg: -3\n")
    with pytest.raises(glassmap.Error, match="bad.yaml:2") as info:
        glassmap.map_log(log, sensor=bad)
    assert "direct_sigma_deg" in str(info.value)
    with pytest.raises(TypeError, match="roundz"):
        glassmap.calibrate(log, roundz=2)
