"""Macro-block model of Argiento, Maione & Casapulla (2018).

The in-plane rocking-sliding mechanism of a multi-storey dry-joint wall with
frictional resistances reduced by the crack angle (Eqs. 1-12 of the paper),
minimised globally over the crack angle and the hinge storey. The model as
implemented and where it departs from the paper: ``docs/macro.md``.

Example:
    >>> import macro
    >>> wall = macro.MacroWall(length=60, block_length=3, block_height=1,
    ...                        rows=(20, 20, 20), thickness=(1, 1, 1),
    ...                        overload=(0, 0, 0), friction=0.6)
    >>> round(macro.solve(wall).load_factor, 3)
    0.583
"""

from macro.paper import PaperWalls, paper_walls
from macro.search import SearchSettings
from macro.solve import HingeResult, MacroResult, MacroWall, StoreyTerms, load_factor_curve, solve
from macro.sweep import MECHANISMS, SweepResult, sweep

__all__ = [
    "MECHANISMS",
    "HingeResult",
    "MacroResult",
    "MacroWall",
    "PaperWalls",
    "SearchSettings",
    "StoreyTerms",
    "SweepResult",
    "load_factor_curve",
    "paper_walls",
    "solve",
    "sweep",
]
