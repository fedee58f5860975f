"""glassmap bench: speed against accuracy, and where each method breaks. Run it with
`tools/bench.sh` (or `python3 tools/bench/sweep`); the modules:

  stats     seeds, success criteria, break points, cheapest-within, recovery time
  scenes    scene variants of the sweeps
  runner    the glassmap binary with caching; the two modes' settings; CSV files
  sections  loc, map, stability, kidnap, fig8
  charts    PNG/SVG charts
  report    recommendations and RESULTS.md
"""
from .charts import *  # noqa: F401,F403
from .report import *  # noqa: F401,F403
from .runner import *  # noqa: F401,F403
from .scenes import *  # noqa: F401,F403
from .sections import *  # noqa: F401,F403
from .stats import *  # noqa: F401,F403
