"""The polish of an interior point's static forces onto exact equilibrium.

Why: an interior point meets the equilibrium rows only to its tolerance
relative to the size of the data. The kinematic back end
(:mod:`micro.backends.clarabel_kinematic`) reads the static forces from
Clarabel's cone duals, whose equilibrium residual is Clarabel's dual residual
(``1e-10`` relative) times the largest force. On Set 17 (p = 8, 7,575 blocks)
the generators reach 1.7e5 block weights: the residual was 4.1e-6 block
weights, beyond :data:`micro.backends.base.MAX_RESIDUAL`, although Clarabel
had solved to its tolerances.

What: the smallest correction ``(dg, dlam)`` of the generators ``g`` and the
load factor that closes the residual ``r0 = A_g g + lam f_L - r``, in the
metric ``sum_j dg_j^2 / g_j + dlam^2 / W`` (``W`` =
:data:`LOAD_FACTOR_WEIGHT`)::

    dg = G A_g^T y,   dlam = W f_L . y,   (A_g G A_g^T + W f_L f_L^T) y = -r0,   G = diag(g).

Weighting by ``g`` makes the correction relative, ``g_j -> g_j (1 + a_j . y)``:
the generators that carry force take it, those that carry none (the interior
point's ~1e-6) hardly move, and none changes sign while ``|a_j . y| < 1``.
The load factor must be free to move: the generators that carry force leave
the mechanism ``u`` in the null space (``a_j . u = 0`` for them, complementary
slackness), so the part of ``r0`` along ``u`` can only be closed by the load
factor (``f_L . u = 1``) or by generators that carry none. Held fixed, the
load factor made those change by up to 17 times their size, and their sign,
on 443 small walls. Free, on 581 small walls (9-294 blocks, floors up to
p = 64) ``lam`` moved by at most 1.4e-9 relative (on Set 17, 7,575 blocks:
3.5e-9), always down, towards the lower bound it now certifies; on 569 of
them the residual fell to at most 8e-16 times the largest force. On the
other 12 (9-42 blocks, residuals 4e-11 to 7e-10, which pass the re-check
anyway) the correction would have turned generators negative, and the
polish keeps the state it was given. The polished state is exactly
admissible, so its ``lam`` is a lower bound; the kinematic objective is the
upper one.

How: the dense term ``W f_L f_L^T`` is kept out of the factorisation by
bordering, ``[[A_g G A_g^T, f_L], [f_L^T, -1/W]] [y; dlam] = [-r0; 0]``,
factorised once by SuperLU (minimum degree on ``A + A^T``, symmetric mode,
:data:`PIVOT_THRESHOLD`); up to :data:`POLISH_MAX_STEPS` corrections reuse
the factors (iterative refinement, each in the first one's metric ``G``), as
long as each lowers the residual and leaves every generator ``>= 0``.
Nothing here decides whether the result is good enough: the independent
re-check (:func:`micro.backends.base.recheck`) does.
"""

from __future__ import annotations

import dataclasses
import time
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from numpy.typing import NDArray

from micro.backends.base import FloatArray, Outcome, recheck
from micro.lp import LimitLP

#: ``W``, the weight of the load-factor column against the generators'
#: (whose weights are their own values, in block weights). The result did not
#: change between ``W = 1`` and ``W = lam`` (Set 17, a 666-block wall);
#: ``W = 1e3`` made the first correction 1e3 times less accurate.
LOAD_FACTOR_WEIGHT = 1.0
#: SuperLU's threshold for a diagonal pivot. The bordered matrix is indefinite
#: and its leading block nearly singular along the mechanism: without pivoting
#: (0) one correction left 6e-8 block weights on a 300-block wall (p = 64) and
#: took 4 more to reach 1e-11; 0.01 reaches 2e-11 in one. Partial pivoting
#: (1, unsymmetric mode) is as accurate with 4x the fill (Set 17: 22.5 M
#: against 5.6 M non-zeros; its CPU seconds: docs/speed.md).
PIVOT_THRESHOLD = 0.01
#: Largest change of the load factor the polish may make, relative to
#: ``max(|lambda|, 1)``; a larger one is not a rounding correction and the
#: solve stays ``inaccurate`` (``info["polish_rejected"]``). Measured: 3.5e-9 at
#: most, always down (Set 17; 581 small walls: 1.4e-9), 30 times below this
#: and 300 times below the 1e-6 the references ask.
POLISH_MAX_LOAD_FACTOR_CHANGE = 1e-7
#: Corrections at most (the first and two steps of iterative refinement
#: reusing its factors); measured, the first reaches the rounding floor
#: (~1e-16 times the largest force) or within 10x of it.
POLISH_MAX_STEPS = 3


@dataclass(frozen=True, eq=False)
class Polished:
    """A static state after the polish.

    Attributes:
        g: the generators (the columns of ``A_g``), block weights.
        load_factor: the value of the load-factor column.
        residual_before: largest equilibrium residual before the polish.
        residual: the same after it.
        steps: corrections kept (0: the factorisation failed, or the first
            correction did not lower the residual or would have turned a
            generator negative; the state is then the one given).
        seconds: wall time of the polish.
    """

    g: FloatArray = field(repr=False)
    load_factor: float
    residual_before: float
    residual: float
    steps: int
    seconds: float


def polish_equilibrium(
    A_g: sp.csc_matrix,
    live: FloatArray,
    rhs: FloatArray,
    g: FloatArray,
    load_factor: float,
    *,
    max_steps: int = POLISH_MAX_STEPS,
) -> Polished:
    """Correct a static state ``(g, load_factor)`` onto exact equilibrium (module docstring).

    Args:
        A_g: equilibrium columns of the generators (``n_eq`` rows).
        live: the live load ``f_L`` (the load-factor column).
        rhs: the right-hand side ``r = -f_D``.
        g: generators, ``>= 0`` (an interior point's are ``> 0``).
        load_factor: the value of the load-factor column.
        max_steps: corrections at most.

    Returns:
        The polished state, or the given one with ``steps = 0``.
    """
    t0 = time.perf_counter()

    def residual(gen: FloatArray, lam: float) -> FloatArray:
        return A_g @ gen + lam * live - rhs

    r = residual(g, load_factor)
    before = best = float(np.max(np.abs(r), initial=0.0))
    n = r.size
    K = A_g @ sp.diags(g) @ A_g.T
    bordered = sp.bmat([[K, live[:, None]], [live[None, :], [[-1.0 / LOAD_FACTOR_WEIGHT]]]], format="csc")
    try:
        lu = spla.splu(bordered, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=PIVOT_THRESHOLD,
                       options={"SymmetricMode": True})
    except RuntimeError:  # exactly singular: a block with nothing carrying it
        return Polished(g, load_factor, before, before, 0, time.perf_counter() - t0)
    steps = 0
    g0 = g
    for _ in range(max_steps):
        y = lu.solve(np.append(-r, 0.0))
        g_new = g + g0 * (A_g.T @ y[:n])  # G0 A_g^T y: the metric the factors were made with
        lam_new = load_factor + float(y[n])
        r_new = residual(g_new, lam_new)
        res = float(np.max(np.abs(r_new), initial=0.0))
        if not res < best or np.any(g_new < 0.0):  # no worse state, no generator's sign changed
            break
        g, load_factor, r, best = g_new, lam_new, r_new, res
        steps += 1
    return Polished(g, load_factor, before, best, steps, time.perf_counter() - t0)


def static_outcome(lp: LimitLP, active: NDArray[np.intp], direction: int, g_active: FloatArray, lam_column: float,
                   raw: Outcome) -> Outcome:
    """``raw`` (optimal, no forces yet) with the static state ``(g, lambda column)``.

    Args:
        lp: the LP.
        active: indices of the generator columns ``g_active`` stands for (the
            others are zero).
        direction: ``+1`` or ``-1``.
        g_active: their values.
        lam_column: the value of the load-factor column.
        raw: the outcome to complete.
    """
    g = np.zeros(2 * lp.n_points)
    g[active] = g_active
    n, s = lp.forces(g)
    return dataclasses.replace(raw, load_factor=float(direction) * lam_column, n=n, s=s)


def checked_outcome(lp: LimitLP, A_g: sp.csc_matrix, active: NDArray[np.intp], direction: int, g_active: FloatArray,
                    lam_column: float, raw: Outcome, *, polish: bool) -> Outcome:
    """An interior point's static state, re-checked (:func:`micro.backends.base.recheck`)
    and, if it fails and ``polish`` is set, polished onto equilibrium and re-checked again.

    A polish that moves the load factor by more than
    :data:`POLISH_MAX_LOAD_FACTOR_CHANGE` is rejected: the outcome stays
    ``inaccurate`` with ``info["polish_rejected"]``. A polished outcome's
    ``info`` keeps the load factor read from the solver
    (``unpolished_load_factor``), its residual (``unpolished_residual``), the
    polish's corrections (``polish_steps``) and time (``polish_seconds``, also
    in ``seconds``).

    Args:
        lp: the LP.
        A_g: its active generator columns (``lp.A[:, active]``).
        active, direction, g_active, lam_column, raw: as :func:`static_outcome`.
        polish: polish a state that fails the re-check.
    """
    out = recheck(lp, direction, static_outcome(lp, active, direction, g_active, lam_column, raw))
    if out.ok or not polish:
        return out
    p = polish_equilibrium(A_g, lp.live, lp.rhs, g_active, lam_column)
    facts = {"unpolished_load_factor": float(direction) * lam_column,
             "unpolished_residual": out.info["primal_residual"], "polish_steps": p.steps,
             "polish_seconds": p.seconds}
    if abs(p.load_factor - lam_column) > POLISH_MAX_LOAD_FACTOR_CHANGE * max(abs(lam_column), 1.0):
        facts["polish_rejected"] = f"the polish moved lambda from {lam_column!r} to {p.load_factor!r}"
        return dataclasses.replace(out, seconds=out.seconds + p.seconds, info={**out.info, **facts})
    polished = dataclasses.replace(raw, seconds=raw.seconds + p.seconds, info={**raw.info, **facts})
    return recheck(lp, direction, static_outcome(lp, active, direction, p.g, p.load_factor, polished))
