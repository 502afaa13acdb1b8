"""A researcher's own macro model, as a sweep's grid names it (``wedge:load_factor``).

The corner wedge beyond a crack that climbs the running bond's stair (slope ``1/(2m)``
from the toe) tips over its toe, friction along the crack ignored: the wedge is a
triangle of height H and base ``H/(2m)``, its centroid a third of the base from the
crack and two thirds up, so it tips at ``λ = (H/(6m)) / (2H/3) = 1/(4m)``; capped by
the whole wall tipping (``L/H = 1/t``) and sliding (``f``). Rows, overload and storeys
do not enter: a deliberately simple model, to be checked against the micro reference.
"""


def load_factor(t: float, m: float, rows: int, f: float, p: float, storeys: int) -> float:
    """λ of a wall of shape ratio ``t = H/L`` and units ``m = b/l`` with friction ``f``."""
    return min(1.0 / (4.0 * m), 1.0 / t, f)
