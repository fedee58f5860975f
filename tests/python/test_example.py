"""tools/examples/map_and_localize.py runs end to end on a short simulation."""

import os
import subprocess
import sys

from conftest import SOURCE_DIR, glassmap_bin


def test_example_script(tmp_path):
    env = dict(os.environ, GLASSMAP_BIN=glassmap_bin())
    proc = subprocess.run([sys.executable, str(SOURCE_DIR / "tools" / "examples" / "map_and_localize.py"), "-o",
                           str(tmp_path), "--duration", "25"], capture_output=True, text=True, env=env)
    assert proc.returncode == 0, proc.stderr
    assert "position error against ground truth" in proc.stdout
    assert (tmp_path / "map" / "stats.json").exists() and (tmp_path / "estimate.tum").exists()
    mean = float(proc.stdout.split("position error against ground truth: mean ")[1].split(" m")[0])
    assert mean < 0.1, proc.stdout
