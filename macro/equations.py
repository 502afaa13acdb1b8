"""Eqs. (1)-(12) of Argiento, Maione & Casapulla (2018), vectorised.

Notation follows the paper: storeys are numbered from the top (1) to the
bottom (N); the hinge O is the base corner of the lowest storey ``k`` taking
part in the mechanism, so a hinge at storey ``k`` moves storeys ``1..k``.
Lengths are measured from O: ``B_i`` is the number of rows of the mechanism
below storey ``i`` and ``T_i = B_i + n_i`` the rows up to its top.

For a crack of slope ``tau = tan(alpha_c)`` (measured from the vertical) the
conventional crack line through O leaves the wall's far side at ``e = L/(b tau)``
rows above O (Eq. 2): storeys with ``T_i <= e`` are crossed over their whole
height, the storey holding ``e`` over ``e - B_i`` rows, the storeys above not
at all, so ``n_ci = clip(e - B_i, 0, n_i)`` (Eqs. 2-3).  The part of the wall
that moves is cut by the real, stepped crack ``x = v + tau* y`` with
``tau* = tau - v/(n b)`` (Eq. 9), ``n`` the rows of the mechanism.  Table 2
gives the parts A (half-block column over the hinge), B (full-length rows
above the crack), C (rectangle between column A and the crack in the crossed
rows) and D (triangle under the crack); the floor loads ``Q_i`` act at floor
level over the length the crack leaves on the moving side.  The frictional
resistances ``F_gi`` (self-weight of the half-block columns, Eq. 5) and
``F_qi`` (loads above the crossed rows, Eq. 6) act at 1/3 and 1/2 of the
crossed height and enter Eq. (10) reduced by ``1 - alpha_c/alpha_b`` (Eq. 8).

Readings of the OCR text of the paper: in ``W_Ai`` the
printed ``h`` is the block height ``b``; ``n_ai`` and ``n_ci`` are the same
quantity; Eq. (10) uses the reduced resultant ``F_W`` of Eq. (8); ``n`` in
Eqs. (9) and (11) counts the rows of the storeys in the mechanism; ``n_ci``
is continuous (the paper minimises over a continuous ``tan(alpha_c)``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

Array = NDArray[np.float64]

#: Names of the per-storey quantities :func:`evaluate` can return, in Table 2 order.
TERM_NAMES = (
    "H_c", "n_c",
    "W_A", "x_WA", "y_WA",
    "W_B", "x_WB", "y_WB",
    "W_C", "x_WC", "y_WC",
    "W_D", "x_WD", "y_WD",
    "Q", "x_Q", "y_Q",
    "F_g", "y_Fg",
    "F_q", "y_Fq",
)  # fmt: skip


@dataclass(frozen=True)
class HingeProblems:
    """A batch of (wall, hinge storey) problems, storey axis last.

    Every array has shape ``(P, 1, N)`` (per storey) or ``(P, 1)`` (per
    problem), so that it broadcasts against crack slopes of shape ``(P, G)``.
    Storeys below the hinge carry zero rows and zero load, which makes them
    drop out of every sum.
    """

    length: Array  # L
    overlap: Array  # v
    block_height: Array  # b
    unit_weight: Array  # gamma
    friction: Array  # f
    rows: Array  # n_i (0 below the hinge)
    thickness: Array  # b_i
    overload: Array  # q_i (0 below the hinge)
    below: Array  # B_i, rows of the mechanism below storey i
    load_above: Array  # sum_{j<=i} q_j + sum_{j<i} n_j b_j b gamma
    tau_low: Array  # v/(n b), lower end of Eq. (11)
    tau_high: Array  # v/b = tan(alpha_b), upper end of Eq. (11)
    alpha_b: Array  # atan(v/b)
    breakpoints: Array  # tan(alpha_pi) = L/(T_i b), shape (P, N); NaN below the hinge
    # crack-independent coefficients of the fused Eq. (10) in :func:`load_factor`
    row_weight: Array  # b b_i gamma, weight of one row per unit length
    coef_B: Array  # moment of W_B per uncrossed row about O: row_weight (L^2 - v^2)/2
    coef_By: Array  # row_weight (L - v) b
    coef_C: Array  # W_C = tan(alpha*) n_c coef_C, coef_C = row_weight b B_i
    coef_D: Array  # W_D = tan(alpha*) n_c^2 coef_D, coef_D = row_weight b / 2
    coef_g: Array  # F_g y_Fg = coef_g n_c (n_c + 1)(n_c/3 + B_i), coef_g = v row_weight f b / 2
    coef_q: Array  # v f b
    moment_A: Array  # sum_i W_Ai x_WAi, shape (P, 1)
    overturn_A: Array  # sum_i W_Ai y_WAi, shape (P, 1)
    floor_x: Array  # Q_i x_Qi when the floor moves whole: q_i L^2 / 2
    floor_y: Array  # Q_i y_Qi when the floor moves whole: q_i L T_i b
    floor_t: Array  # q_i (T_i b)^2 / 2: Q_i x_Qi = floor_t tau^2, Q_i y_Qi = 2 floor_t tau otherwise

    @property
    def size(self) -> int:
        """Number of problems ``P``."""
        return int(self.length.shape[0])

    def select(self, index: slice | NDArray[np.int_]) -> HingeProblems:
        """The sub-batch of the problems at ``index``."""
        return HingeProblems(**{name: getattr(self, name)[index] for name in self.__dataclass_fields__})


def hinge_problems(
    length: Array,
    overlap: Array,
    block_height: Array,
    unit_weight: Array,
    friction: Array,
    rows: Array,
    thickness: Array,
    overload: Array,
    hinge: NDArray[np.int_],
) -> HingeProblems:
    """Assemble the per-problem constants of a batch.

    Args:
        length, overlap, block_height, unit_weight, friction: shape ``(P,)``.
        rows, thickness, overload: shape ``(P, N)``, storey 1 first.
        hinge: shape ``(P,)``, the hinge storey ``k`` (1-based) of each problem.
    """
    rows = np.asarray(rows, dtype=float)
    n_storeys = rows.shape[1]
    in_mech = np.arange(1, n_storeys + 1)[None, :] <= np.asarray(hinge)[:, None]
    n = np.where(in_mech, rows, 0.0)
    q = np.where(in_mech, np.asarray(overload, dtype=float), 0.0)
    thk = np.asarray(thickness, dtype=float)
    b = np.asarray(block_height, dtype=float)[:, None]
    gam = np.asarray(unit_weight, dtype=float)[:, None]
    top = np.cumsum(n[:, ::-1], axis=1)[:, ::-1]  # T_i
    below = top - n  # B_i
    K = b * thk * gam  # weight of one row per unit length
    weight_row = n * K  # storey self weight per unit length
    load_above = np.cumsum(q, axis=1) + np.cumsum(weight_row, axis=1) - weight_row
    n_tot = n.sum(axis=1)
    v = np.asarray(overlap, dtype=float)
    L = np.asarray(length, dtype=float)
    with np.errstate(divide="ignore"):
        bp = np.where(in_mech, L[:, None] / (top * b), np.nan)
    f = np.asarray(friction, dtype=float)[:, None]
    Lc, vc = L[:, None], v[:, None]
    wa = weight_row * vc  # W_Ai
    per_storey = dict(
        rows=n,
        thickness=thk,
        overload=q,
        below=below,
        load_above=load_above,
        row_weight=K,
        coef_B=0.5 * K * (Lc**2 - vc**2),
        coef_By=K * (Lc - vc) * b,
        coef_C=K * b * below,
        coef_D=0.5 * K * b,
        coef_g=0.5 * vc * K * f * b,
        coef_q=np.broadcast_to(vc * f * b, n.shape),
        floor_x=0.5 * q * Lc**2,
        floor_y=q * Lc * top * b,
        floor_t=0.5 * q * (top * b) ** 2,
    )
    extra = {k: a[:, None, :] for k, a in per_storey.items()}
    col = lambda a: np.asarray(a, dtype=float)[:, None]  # noqa: E731
    return HingeProblems(
        length=col(L),
        overlap=col(v),
        block_height=b,
        unit_weight=gam,
        friction=col(friction),
        moment_A=(0.5 * vc * wa).sum(axis=1, keepdims=True),
        overturn_A=(wa * (0.5 * n + below) * b).sum(axis=1, keepdims=True),
        **extra,
        tau_low=col(v / (n_tot * b[:, 0])),
        tau_high=col(v / b[:, 0]),
        alpha_b=col(np.arctan(v / b[:, 0])),
        breakpoints=bp,
    )


def load_factor(tau: Array, pb: HingeProblems) -> Array:
    """Eq. (10) at crack slopes ``tau`` (shape ``(P, G)``), fused for speed.

    The same sums as :func:`evaluate` (which keeps every Table 2 term apart for
    the audit trail), regrouped around the crack-independent coefficients of
    :class:`HingeProblems`; a test pins the two together.
    """
    t = tau[..., None]
    b, v, B, n = pb.block_height[..., None], pb.overlap[..., None], pb.below, pb.rows
    ts = t - pb.tau_low[..., None]
    e = pb.length[..., None] / (b * t)
    nc = np.clip(e - B, 0.0, n)
    up = n - nc  # rows above the crack
    whole = e <= B + n
    cd = ts * nc
    nc3 = nc / 3.0
    stab = up * pb.coef_B + cd * (pb.coef_C * (0.5 * b * ts * B + v) + nc * pb.coef_D * (ts * b * (nc3 + B) + v))
    stab += np.where(whole, pb.floor_x, pb.floor_t * t * t)
    over = up * pb.coef_By * (0.5 * (n + nc) + B)
    over += cd * b * (pb.coef_C * (0.5 * nc + B) + nc * pb.coef_D * (2.0 * nc3 + B))
    over += np.where(whole, pb.floor_y, 2.0 * pb.floor_t * t)
    fric = nc * (pb.coef_g * (nc + 1.0) * (nc3 + B) + (up * pb.row_weight + pb.load_above) * (0.5 * nc + B) * pb.coef_q)
    reduction = 1.0 - np.arctan(tau) / pb.alpha_b
    return (pb.moment_A + stab.sum(axis=-1) + reduction * fric.sum(axis=-1)) / (pb.overturn_A + over.sum(axis=-1))


def evaluate(tau: Array, pb: HingeProblems, detail: bool = False, sliding: bool = True) -> dict[str, Array]:
    """Eq. (10) and Eq. (12) at crack slopes ``tau`` (shape ``(P, G)``).

    Returns:
        ``lambda_r`` (Eq. 10) and, with ``sliding``, ``lambda_s`` (Eq. 12),
        shape ``(P, G)``; with ``detail`` also ``stabilising``, ``overturning``,
        ``friction_moment`` (unreduced), ``reduction`` (``1 - alpha_c/alpha_b``)
        and every per-storey term of :data:`TERM_NAMES`, shape ``(P, G, N)``.
    """
    L, v, b = pb.length[..., None], pb.overlap[..., None], pb.block_height[..., None]
    gam, f = pb.unit_weight[..., None], pb.friction[..., None]
    n, thk, q, B = pb.rows, pb.thickness, pb.overload, pb.below
    t = tau[..., None]
    ts = t - pb.tau_low[..., None]  # tan(alpha_c*), Eq. (9)
    e = L / (b * t)  # rows from O to where the crack leaves the wall
    nc = np.clip(e - B, 0.0, n)  # Eqs. (2)-(3)
    top = B + n
    gt = gam * thk

    W_A = n * b * thk * v * gam
    x_A = 0.5 * v
    y_A = (0.5 * n + B) * b
    W_B = (n - nc) * (L - v) * b * gt
    x_B = 0.5 * (L + v)
    y_B = (0.5 * (n + nc) + B) * b
    W_C = ts * nc * b * b * gt * B
    x_C = 0.5 * b * ts * B + v
    y_C = (0.5 * nc + B) * b
    W_D = 0.5 * ts * (nc * b) ** 2 * gt
    x_D = ts * nc * b / 3.0 + b * ts * B + v
    y_D = (2.0 * nc / 3.0 + B) * b
    whole_floor = e <= top  # alpha_c >= alpha_pi: the floor moves over its whole length
    reach = top * b * t  # floor length on the moving side otherwise
    Q = np.where(whole_floor, L * q, reach * q)
    x_Q = np.where(whole_floor, 0.5 * L, 0.5 * reach)
    y_Q = top * b
    F_g = v * b * thk * 0.5 * nc * (nc + 1.0) * gam * f  # Eq. (5)
    y_g = (nc / 3.0 + B) * b
    F_q = ((n - nc) * b * gt + pb.load_above) * nc * v * f  # Eq. (6)
    y_q = (0.5 * nc + B) * b

    stab = (W_A * x_A + W_B * x_B + W_C * x_C + W_D * x_D + Q * x_Q).sum(axis=-1)
    over = (W_A * y_A + W_B * y_B + W_C * y_C + W_D * y_D + Q * y_Q).sum(axis=-1)
    fric = (F_g * y_g + F_q * y_q).sum(axis=-1)
    reduction = 1.0 - np.arctan(tau) / pb.alpha_b  # Eq. (8)
    out = {"lambda_r": (stab + reduction * fric) / over}
    if sliding or detail:
        out["lambda_s"] = (F_g + F_q).sum(axis=-1) / (W_A + W_B + W_C + W_D + Q).sum(axis=-1)
    if detail:
        shape = np.broadcast_shapes(nc.shape, n.shape)
        full = lambda a: np.broadcast_to(a, shape).copy()  # noqa: E731
        terms = dict(
            H_c=nc * b, n_c=nc,
            W_A=W_A, x_WA=x_A, y_WA=y_A, W_B=W_B, x_WB=x_B, y_WB=y_B,
            W_C=W_C, x_WC=x_C, y_WC=y_C, W_D=W_D, x_WD=x_D, y_WD=y_D,
            Q=Q, x_Q=x_Q, y_Q=y_Q, F_g=F_g, y_Fg=y_g, F_q=F_q, y_Fq=y_q,
        )  # fmt: skip
        out.update({k: full(a) for k, a in terms.items()})
        out.update(stabilising=stab, overturning=over, friction_moment=fric, reduction=reduction)
    return out
