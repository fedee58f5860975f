"""Unit tests of the bench driver's logic: seed handling, success criteria, break points,
'cheapest within 10%', trajectory error matching, scene variants. No binaries needed."""
import json
import math
import sys
import unittest
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "tools" / "bench"))
import sweep  # noqa: E402


class Seeds(unittest.TestCase):
    def test_deterministic(self):
        self.assertEqual(sweep.derive_seed(1, "sim", "paper-corridor", 0),
                         sweep.derive_seed(1, "sim", "paper-corridor", 0))
        self.assertEqual(sweep.trial_seeds(7, "x", 3), sweep.trial_seeds(7, "x", 3))

    def test_range_and_distinct(self):
        seeds = [sweep.derive_seed(b, k, i) for b in (1, 2) for k in ("sim", "loc") for i in range(50)]
        self.assertTrue(all(1 <= s < 2**31 for s in seeds))
        self.assertEqual(len(set(seeds)), len(seeds))

    def test_base_seed_changes_everything(self):
        a, b = sweep.trial_seeds(1, "s", 4), sweep.trial_seeds(2, "s", 4)
        self.assertTrue(all(x[1] != y[1] and x[2] != y[2] for x, y in zip(a, b)))

    def test_trials_are_prefixes(self):
        # more seeds only add trials: the first n rows of a larger run are the same runs
        self.assertEqual(sweep.trial_seeds(1, "s", 5)[:2], sweep.trial_seeds(1, "s", 2))

    def test_known_value(self):
        # pinned so a change of the derivation (and so of every committed CSV) is noticed
        self.assertEqual(sweep.derive_seed(1, "sim", "paper-corridor", 0),
                         int(__import__("hashlib").sha256(b"1|sim|paper-corridor|0").hexdigest()[:8], 16)
                         % (2**31 - 1) + 1)


class Success(unittest.TestCase):
    def test_loc(self):
        self.assertTrue(sweep.loc_success(0.05))
        self.assertFalse(sweep.loc_success(0.2))      # strictly under 0.2 m
        self.assertFalse(sweep.loc_success(3.0))
        self.assertFalse(sweep.loc_success(float("nan")))
        self.assertFalse(sweep.loc_success(None))

    def test_map(self):
        self.assertTrue(sweep.map_success(0.81))
        self.assertFalse(sweep.map_success(0.8))      # strictly over 0.8
        self.assertFalse(sweep.map_success(float("inf")))
        self.assertFalse(sweep.map_success("x"))

    def test_rate(self):
        self.assertEqual(sweep.success_rate([1, 0, 1, 1]), 0.75)
        self.assertTrue(math.isnan(sweep.success_rate([])))

    def test_break_value(self):
        self.assertEqual(sweep.break_value([0, 1, 2, 3], [1, 1, 0.4, 0]), 2)
        self.assertEqual(sweep.break_value([0, 1], [1, 0.5]), None)   # 0.5 is not below 0.5
        self.assertEqual(sweep.break_value([5, 6], [0.0, 1.0]), 5)
        self.assertIsNone(sweep.break_value([], []))


class Cheapest(unittest.TestCase):
    rows = [dict(n="a", acc=0.010, cost=10.0), dict(n="b", acc=0.0108, cost=2.0),
            dict(n="c", acc=0.0115, cost=1.0), dict(n="d", acc=float("nan"), cost=0.1)]

    def test_lower_is_better(self):
        best, cheap = sweep.cheapest_within(self.rows, "acc", "cost", higher_is_better=False)
        self.assertEqual((best["n"], cheap["n"]), ("a", "b"))

    def test_higher_is_better(self):
        rows = [dict(n="a", f1=0.95, t=9), dict(n="b", f1=0.86, t=1), dict(n="c", f1=0.85, t=0.5)]
        best, cheap = sweep.cheapest_within(rows, "f1", "t", higher_is_better=True)
        self.assertEqual((best["n"], cheap["n"]), ("a", "b"))   # 0.855 is the bar

    def test_absolute_tolerance(self):
        best, cheap = sweep.cheapest_within(self.rows, "acc", "cost", False, abs_tol=0.01)
        self.assertEqual((best["n"], cheap["n"]), ("a", "c"))   # 0.0115 <= 0.010 + 0.01

    def test_empty(self):
        self.assertEqual(sweep.cheapest_within([], "a", "b", True), (None, None))


class Trajectories(unittest.TestCase):
    def test_errors_along(self):
        truth = [(0.0, 0, 0, 0), (0.1, 1, 0, 0), (0.2, 2, 0, 0)]
        est = [(0.0, 0, 0.5, 0), (0.1, 1, 0, 0), (0.2, 2, 2, 0), (9.0, 0, 0, 0)]
        e = sweep.errors_along(truth, est)
        self.assertEqual([t for t, _ in e], [0.0, 0.1, 0.2])        # t=9 unmatched
        self.assertAlmostEqual(e[0][1], 0.5)
        self.assertAlmostEqual(e[2][1], 2.0)

    def test_yaw(self):
        self.assertAlmostEqual(sweep.yaw_from_quat(0, 0, math.sin(0.35), math.cos(0.35)), 0.7)


class Scenes(unittest.TestCase):
    def test_pane_corridor(self):
        g = sweep.pane_corridor_geojson(30, 0.02)
        glass = [f for f in g["features"] if f["properties"]["material"] == "glass"]
        self.assertEqual(len(glass), 1)
        (x0, y0), (x1, y1) = glass[0]["geometry"]["coordinates"]
        self.assertAlmostEqual(math.degrees(math.atan2(y1 - y0, x1 - x0)), 30, places=4)
        self.assertAlmostEqual(math.hypot(x1 - x0, y1 - y0), 2.0, places=4)
        self.assertEqual(glass[0]["properties"]["thickness"], 0.02)
        json.dumps(g)

    def test_thickness(self):
        g = sweep.pane_corridor_geojson(0)
        t = sweep.set_glass_thickness(g, 0.07)
        self.assertEqual({f["properties"]["thickness"] for f in t["features"]
                          if f["properties"]["material"] == "glass"}, {0.07})
        self.assertEqual(g["features"][-1]["properties"]["thickness"], 0.01)   # copy, not in place

    def test_config_modes(self):
        q, f = sweep.config(True, None), sweep.config(False, None)
        self.assertLessEqual(q["seeds"], 2)
        self.assertTrue(all(len(v) <= 2 for v in q["axes"].values()))
        self.assertEqual(f["beams"], [5, 15, 60, 100])
        self.assertEqual(f["particles"], [100, 500, 2500, 10000])
        self.assertEqual(set(f["models"]), set(sweep.LOC_MODELS))
        self.assertEqual(sweep.config(False, 4)["loc_seeds"], 4)


if __name__ == "__main__":
    unittest.main()
