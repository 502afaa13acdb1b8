"""The validation report: the paper's cases through both models, set beside the published values.

* :mod:`~comparison.report.plan`: the explicit run plan (every wall and method);
* :mod:`~comparison.report.computed`: the plan computed;
* :mod:`~comparison.report.tables`, :mod:`~comparison.report.speed_accuracy`, :mod:`~comparison.report.findings`,
  :mod:`~comparison.report.figures`, :mod:`~comparison.report.text`: what the
  report shows, read from the results;
* :mod:`~comparison.report.build`: :func:`build_report`, plan -> compute -> render.

The macro model runs on every case; the associative micro LP and the iterated
non-associative LP (on walls of at most
:data:`~comparison.report.plan.NONASSOC_MAX_BLOCKS` blocks) on the walls the
micro model can build; ``quick`` keeps the small walls only (Sets 11-14 and
12-row variants) for the micro model.
"""

from comparison.report.build import build_report
from comparison.report.computed import Results
from comparison.report.plan import NONASSOC_MAX_BLOCKS, Plan, build_plan
from comparison.report.tables import Table, lam_cell, pct

__all__ = ["NONASSOC_MAX_BLOCKS", "Plan", "Results", "Table", "build_plan", "build_report", "lam_cell", "pct"]
