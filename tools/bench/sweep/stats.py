"""Seeds, success criteria, break points, "cheapest within", recovery time: the bench's arithmetic."""
from __future__ import annotations

import hashlib
import math
from pathlib import Path

REPO = Path(__file__).resolve().parents[3]
SUCCESS_ATE_M = 0.2      # localization succeeds when the ATE RMSE is under this [m]
SUCCESS_F1 = 0.8         # mapping succeeds when the glass F1 (cells, 2-cell tolerance) is over this
BREAK_RATE = 0.5         # a method "breaks" at the first swept value whose success rate is below this
WITHIN = 0.10            # "cheapest setting within 10% of the best accuracy"
LOC_ABS_TOL_M = 0.01     # ... or, for localization, within 1 cm of the best ATE
RECOVER_HOLD_S = 10.0    # a kidnapped filter recovered when its error stays under SUCCESS_ATE_M from some
                         # time on to the end of the run, and the run goes on this long after that [s]

# localization model variants: label -> (--model, --glass-as)
LOC_MODELS = {
    "beam-opaque": ("beam", "opaque"),
    "beam-invisible": ("beam", "invisible"),
    "field": ("field", "opaque"),
    "glass-paper": ("glass-paper", "opaque"),
    "glass": ("glass", "opaque"),
}
MAP_METHODS = ["heuristic", "direct", "mrf"]
COLORS = {"beam-opaque": "tab:red", "beam-invisible": "tab:orange", "field": "tab:purple",
          "glass-paper": "tab:blue", "glass": "tab:green",
          "heuristic": "tab:orange", "direct": "tab:blue", "mrf": "tab:green"}


# ----------------------------------------------------------------------------------------------
# pure logic (unit-tested in tests/bench/test_sweep.py)

def derive_seed(base: int, *keys) -> int:
    """Deterministic seed in [1, 2^31) from a base seed and any keys (stable across runs/platforms)."""
    text = "|".join([str(int(base))] + [str(k) for k in keys])
    return int(hashlib.sha256(text.encode()).hexdigest()[:8], 16) % (2**31 - 1) + 1


def trial_seeds(base: int, scene: str, n: int) -> list[tuple[int, int, int]]:
    """(trial index, simulation seed, localizer seed) for n trials of a scene; independent of
    the method and the swept value, so every method sees the same logs."""
    return [(i, derive_seed(base, "sim", scene, i), derive_seed(base, "loc", scene, i))
            for i in range(n)]


def finite(x) -> bool:
    try:
        return x is not None and math.isfinite(float(x))
    except (TypeError, ValueError):
        return False


def loc_success(ate_rmse) -> bool:
    return finite(ate_rmse) and float(ate_rmse) < SUCCESS_ATE_M


def map_success(f1) -> bool:
    return finite(f1) and float(f1) > SUCCESS_F1


def success_rate(flags) -> float:
    flags = list(flags)
    return float("nan") if not flags else sum(1 for f in flags if f) / len(flags)


def break_value(values, rates, threshold: float = BREAK_RATE):
    """First swept value (in sweep order) whose success rate is below threshold; None if none."""
    for v, r in zip(values, rates):
        if not finite(r) or r < threshold:
            return v
    return None


def cheapest_within(rows, acc_key: str, cost_key: str, higher_is_better: bool, tol: float = WITHIN,
                    abs_tol: float = 0.0):
    """(best row, cheapest row whose accuracy is within tol (relative) of the best, or within abs_tol
    of it). Rows lacking a finite accuracy or cost are ignored; (None, None) if nothing is left."""
    rows = [r for r in rows if finite(r.get(acc_key)) and finite(r.get(cost_key))]
    if not rows:
        return None, None
    if higher_is_better:
        best = max(rows, key=lambda r: float(r[acc_key]))
        ok = [r for r in rows if float(r[acc_key]) >= min((1 - tol) * float(best[acc_key]),
                                                          float(best[acc_key]) - abs_tol)]
    else:
        best = min(rows, key=lambda r: float(r[acc_key]))
        ok = [r for r in rows if float(r[acc_key]) <= max((1 + tol) * float(best[acc_key]),
                                                          float(best[acc_key]) + abs_tol)]
    return best, min(ok, key=lambda r: float(r[cost_key]))


def mean(xs):
    xs = [float(x) for x in xs if finite(x)]
    return sum(xs) / len(xs) if xs else float("nan")


def median(xs):
    xs = sorted(float(x) for x in xs if finite(x))
    if not xs:
        return float("nan")
    n = len(xs)
    return xs[n // 2] if n % 2 else 0.5 * (xs[n // 2 - 1] + xs[n // 2])



def time_to_recover(errors, t_kidnap: float, threshold: float = SUCCESS_ATE_M,
                    hold: float = RECOVER_HOLD_S):
    """Seconds from a kidnapping at t_kidnap to the first estimate at or after it from which on
    the position error stays under threshold to the end of the run (0 if it never left it); None
    when the last error is not under it, or the run ends less than `hold` seconds after the
    recovery (one lucky estimate at the end is no recovery). errors: (t, position error) pairs."""
    after = sorted((t, e) for t, e in errors if t >= t_kidnap - 1e-9)
    t_rec = None
    for t, e in reversed(after):
        if not (finite(e) and e < threshold):
            break
        t_rec = t
    if t_rec is None or after[-1][0] - t_rec < hold:
        return None
    return t_rec - t_kidnap
