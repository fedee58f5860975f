"""Unit tests of the bench driver's logic: seed handling, success criteria, break points,
'cheapest within 10%', trajectory errors through `glassmap eval traj`, scene variants. Only the
trajectory test needs the binary (GLASSMAP_BIN, set by CTest; skipped without it)."""
import json
import math
import os
import sys
import tempfile
import unittest
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "tools" / "bench"))
import sweep  # noqa: E402


class Seeds(unittest.TestCase):
    def test_known_values(self):
        # pinned: a change of the derivation changes every committed CSV, and must be noticed
        self.assertEqual(sweep.derive_seed(1, "sim", "paper-corridor", 0), 1190212131)
        self.assertEqual(sweep.trial_seeds(7, "x", 3),
                         [(0, 1194966317, 296338966), (1, 9519624, 532388144), (2, 627626507, 1122771760)])

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
        self.assertNotEqual(sweep.trial_seeds(1, "s", 5)[2:4], sweep.trial_seeds(1, "s", 2))


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
    @unittest.skipUnless(os.environ.get("GLASSMAP_BIN"), "GLASSMAP_BIN not set")
    def test_errors_come_from_glassmap_eval_traj(self):
        def tum(rows):
            return "".join(f"{t} {x} {y} 0 0 0 0 1\n" for t, x, y in rows)
        with tempfile.TemporaryDirectory() as d:
            sim = Path(d)
            (sim / "groundtruth.tum").write_text(tum([(0.0, 0, 0), (0.1, 1, 0), (0.2, 2, 0)]))
            (sim / "est.tum").write_text(tum([(0.0, 0, 0.5), (0.1, 1, 0), (0.2, 2, 2), (9.0, 0, 0)]))
            r = sweep.Runner(Path(os.environ["GLASSMAP_BIN"]), sim / "work", 1)
            e = r.errors(sim, sim / "est.tum")
        self.assertEqual([t for t, _ in e], [0.0, 0.1, 0.2])        # t=9 unmatched
        self.assertAlmostEqual(e[0][1], 0.5, places=5)
        self.assertAlmostEqual(e[1][1], 0.0, places=5)
        self.assertAlmostEqual(e[2][1], 2.0, places=5)


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

    def test_spread_slots(self):
        for k in range(sweep.PANE_SLOTS + 1):
            sl = sweep.spread_slots(k)
            self.assertEqual(len(sl), k)
            self.assertTrue(all(0 <= i < sweep.PANE_SLOTS for i in sl))
        self.assertEqual(sweep.spread_slots(2), [0, sweep.PANE_SLOTS - 1])   # both ends
        with self.assertRaises(ValueError):
            sweep.spread_slots(sweep.PANE_SLOTS + 1)

    def test_panes_corridor(self):
        def side(g, y):
            segs = sorted((min(a[0], b[0]), max(a[0], b[0]), f["properties"]["material"])
                          for f in g["features"]
                          for a, b in [f["geometry"]["coordinates"]] if a[1] == y and b[1] == y)
            return segs
        for n in (0, 1, 5, 18):
            g = sweep.panes_corridor_geojson(n, 0.02)
            glass = [f for f in g["features"] if f["properties"]["material"] == "glass"]
            self.assertEqual(len(glass), n)
            self.assertTrue(all(f["properties"]["thickness"] == 0.02 for f in glass))
            for y, k in ((3, (n + 1) // 2), (0, n // 2)):
                segs = side(g, y)
                # each corridor wall is covered from x = 0 to 20 without gaps or overlaps
                self.assertEqual(segs[0][0], 0)
                self.assertEqual(segs[-1][1], 20)
                self.assertTrue(all(a[1] == b[0] for a, b in zip(segs, segs[1:])), segs)
                panes = [s for s in segs if s[2] == "glass"]
                self.assertEqual(len(panes), k)
                self.assertTrue(all(b - a == 2 for a, b, _ in panes))
            json.dumps(g)
        with self.assertRaises(ValueError):
            sweep.panes_corridor_geojson(19)

    def test_config_modes(self):
        q, f = sweep.config(True, None), sweep.config(False, None)
        self.assertLessEqual(q["seeds"], 2)
        self.assertTrue(all(len(v) <= 2 for v in q["axes"].values()))
        self.assertEqual(f["beams"], [5, 15, 60, 100])
        self.assertEqual(f["particles"], [100, 500, 2500, 10000])
        self.assertEqual(set(f["models"]), set(sweep.LOC_MODELS))
        self.assertEqual(sweep.config(False, 4)["loc_seeds"], 4)
        # the new sweeps are in both modes, small in quick mode
        self.assertIn("panes", q["axes"]); self.assertIn("panes", f["axes"])
        self.assertEqual(f["axes"]["panes"][0], 0)
        self.assertLessEqual(len(q["kidnap"]["distances"]) * q["kidnap"]["seeds"], 2)
        self.assertEqual(f["kidnap"]["distances"], sorted(f["kidnap"]["distances"]))
        for mode in (q, f):
            k = mode["kidnap"]
            self.assertGreaterEqual(k["duration"] - k["at"], sweep.RECOVER_HOLD_S + 5)
        self.assertEqual(set(sweep.chart_names(f)) >= {"stability_panes", "stability_kidnap",
                                                        "fig8_paper_corridor"}, True)


class Recovery(unittest.TestCase):
    def errs(self, values, dt=1.0):
        return [(i * dt, e) for i, e in enumerate(values)]

    def test_recovers_when_the_error_stays_under(self):
        # kidnapped at t = 2: error jumps, comes back under 0.2 m at t = 5 and stays (to t = 20)
        e = self.errs([0.01, 0.01, 3.0, 2.0, 0.5, 0.1, 0.3, 0.1] + [0.05] * 13)
        self.assertAlmostEqual(sweep.time_to_recover(e, 2.0), 5.0)   # first under-0.2 after the last excursion (t = 7)

    def test_never_left(self):
        e = self.errs([0.01] * 20)
        self.assertEqual(sweep.time_to_recover(e, 3.0), 0.0)

    def test_not_recovered(self):
        self.assertIsNone(sweep.time_to_recover(self.errs([0.01, 5.0, 5.0, 5.0]), 1.0))
        # the last estimate is off: no recovery, even if it was under before
        self.assertIsNone(sweep.time_to_recover(self.errs([0.01] * 20 + [0.4]), 1.0))

    def test_hold(self):
        # under again for only the last 3 s of the run: too short to count
        e = self.errs([0.01, 5.0] + [5.0] * 15 + [0.01] * 4)
        self.assertIsNone(sweep.time_to_recover(e, 1.0))
        self.assertAlmostEqual(sweep.time_to_recover(e, 1.0, hold=3.0), 16.0)

    def test_threshold_is_strict_and_nan_is_failure(self):
        e = self.errs([0.0] + [0.2] * 20)
        self.assertIsNone(sweep.time_to_recover(e, 0.5))
        e = self.errs([0.0] * 5 + [float("nan")] + [0.0] * 15)
        self.assertAlmostEqual(sweep.time_to_recover(e, 1.0), 5.0)

    def test_before_the_kidnapping_does_not_count(self):
        # errors before t_kidnap are ignored; unsorted input is fine
        e = list(reversed(self.errs([9.0] * 3 + [0.01] * 18)))
        self.assertEqual(sweep.time_to_recover(e, 3.0), 0.0)
        self.assertIsNone(sweep.time_to_recover([], 3.0))


class PartialRuns(unittest.TestCase):
    def test_merge_rows(self):
        old = [{"axis": "a", "v": 1}, {"axis": "b", "v": 2}, {"axis": "a", "v": 3}]
        new = [{"axis": "a", "v": 9}]
        self.assertEqual(sweep.merge_rows(old, new, lambda r: r["axis"] == "a"),
                         [{"axis": "b", "v": 2}, {"axis": "a", "v": 9}])

    def test_csv_round_trip(self):
        import tempfile
        with tempfile.TemporaryDirectory() as d:
            p = Path(d) / "x.csv"
            rows = [{"axis": "panes", "value": 4, "rate": 0.5, "breaks_at": "", "m": float("nan")}]
            sweep.write_csv(p, rows, ["axis", "value", "rate", "breaks_at", "m"])
            back = sweep.read_csv_typed(p)
            self.assertEqual(back[0]["axis"], "panes")
            self.assertEqual(back[0]["value"], 4); self.assertIsInstance(back[0]["value"], int)
            self.assertEqual(back[0]["rate"], 0.5)
            self.assertEqual(back[0]["breaks_at"], "")
            self.assertTrue(math.isnan(back[0]["m"]))
            self.assertEqual(sweep.read_csv_typed(Path(d) / "missing.csv"), [])

    def test_read_spread(self):
        import tempfile
        with tempfile.TemporaryDirectory() as d:
            p = Path(d) / "spread.csv"
            p.write_text("t,spread_m,particles,corrected,relocalizations\n0.000000,0.5,10,1,0\n0.100000,0.25,10,0,0\n")
            self.assertEqual(sweep.read_spread(p), {0.0: 0.5, 0.1: 0.25})


if __name__ == "__main__":
    unittest.main()
