"""Assembly of the static (lower-bound) limit-analysis LP of a block wall.

Formulation (Livesley 1978; Gilbert, Casapulla & Ahmed 2006), in scaled units
(lengths in block heights, forces in full-block weights of the thickest
storey, see :attr:`micro.BlockWall.reference_weight`). At every contact point
``p`` the force on block ``b`` is ``n_p * normal + s_p * tangent`` with the
normal force ``n_p >= 0`` (no tension, unlimited compression) and associative
Coulomb friction ``|s_p| <= mu_p n_p``. Equilibrium, three rows per block
(``F_x``, ``F_y``, ``M`` about the centroid)::

    B_n n + B_s s + lambda f_L = -f_D          (i.e.  B x = -(f_D + lambda f_L))

with ``f_D`` the dead load and ``f_L`` the live load in ``+x`` per unit load
factor. Maximise ``lambda`` for the live load in ``+x`` (``d = +1``) or
``-x`` (``d = -1``): the LP is ``min -d * lambda``; the feasible load factors
form an interval ``[-lambda_minus, lambda_plus]`` so one model serves both
directions by a change of one cost coefficient.

Columns: the Coulomb cone at each point is written by its two edge
generators, ``n = g+ + g-``, ``s = mu (g+ - g-)``, ``g+/- >= 0``
(Livesley's form). The model then has only the ``3 n_blocks`` equilibrium
rows and ``2 P + 1`` columns (``g+`` for all points, ``g-`` for all points,
``lambda``). The same LP written with ``n``, ``s`` columns and two friction
rows per point (``s - mu n <= 0``, ``-s - mu n <= 0``; the cvxpy reference
back end uses it) has ``2P`` more rows; HiGHS IPM was slower on it than on the
generator form (docs/speed.md) and no more accurate.

Non-associative friction: the rebuilt condition ``|s_p| <= mu_p nbar_p`` is
a pair of columns per point, ``n_p >= 0`` along the normal and ``s_p`` along
the tangent with bounds ``[-mu nbar, mu nbar]``; its columns are
:meth:`LimitLP.equilibrium_matrix` (``B_n``, ``B_s``). The iterated LP builds
them once into a persistent HiGHS model and changes only the bounds of the
``s`` columns between iterations, so the simplex basis is kept (see
:class:`micro.nonassociative.model.IterationModel`).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from micro.geometry import BlockWall

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]


@dataclass(frozen=True, eq=False)
class LimitLP:
    """The assembled LP of a wall (scaled units; see the module docstring).

    Attributes:
        wall: the wall it was built from.
        A: ``(n_eq, 2P + 1)`` CSC matrix ``[B_n + mu B_s, B_n - mu B_s, f_L]``.
        Bn, Bs: ``(n_eq, P)`` CSC equilibrium matrices of the normal and
            shear point forces (their transposes map block velocities onto
            the normal and tangential relative velocities at the points).
        rhs: ``-f_D``, right-hand side of the equilibrium rows.
        col_lower, col_upper: column bounds (generators ``>= 0``,
            ``lambda`` free).
        n_eq: number of equilibrium rows (``3 * n_blocks``).
        n_points: number of contact points ``P``.
        mu: friction coefficient per point.
        dead, live: scaled load vectors ``f_D``, ``f_L`` (length ``n_eq``).
        length_scale, force_scale: units of the scaled problem (block height,
            reference block weight).
        build_seconds: wall time of the assembly.
        points: the wall's index of each point, for an LP of only some of the
            wall's points (a fused wall's, :mod:`micro.nonassociative.fusion`);
            ``None``: every point of the wall, in its order.
    """

    wall: BlockWall = field(repr=False)
    A: sp.csc_matrix = field(repr=False)
    Bn: sp.csc_matrix = field(repr=False)
    Bs: sp.csc_matrix = field(repr=False)
    rhs: FloatArray = field(repr=False)
    col_lower: FloatArray = field(repr=False)
    col_upper: FloatArray = field(repr=False)
    n_eq: int
    n_points: int
    mu: FloatArray = field(repr=False)
    dead: FloatArray = field(repr=False)
    live: FloatArray = field(repr=False)
    length_scale: float
    force_scale: float
    build_seconds: float
    points: IntArray | None = field(default=None, repr=False)

    @property
    def n_cols(self) -> int:
        """Number of variables."""
        return int(self.A.shape[1])

    @property
    def n_rows(self) -> int:
        """Number of rows."""
        return int(self.A.shape[0])

    @property
    def nnz(self) -> int:
        """Non-zeros of the constraint matrix."""
        return int(self.A.nnz)

    @property
    def lam_col(self) -> int:
        """Index of the load-factor column."""
        return 2 * self.n_points

    def point_kinds(self) -> IntArray:
        """The contact kind (:data:`~micro.geometry.BASE`, ``BED``, ``HEAD``) of each point."""
        kinds = np.repeat(self.wall.contact_kind, 2)
        return kinds if self.points is None else kinds[self.points]

    def active_generators(self) -> NDArray[np.intp]:
        """Indices of the generator columns that may carry force (upper bound ``> 0``;
        ``g-`` of a frictionless point is fixed at 0)."""
        return np.flatnonzero(self.col_upper[: self.lam_col] > 0.0)

    def cost(self, direction: int) -> FloatArray:
        """Objective of the minimisation for live load direction ``+1``/``-1``."""
        c = np.zeros(self.n_cols)
        c[self.lam_col] = -float(direction)
        return c

    def forces(self, x: FloatArray) -> tuple[FloatArray, FloatArray]:
        """Point forces ``(n, s)`` (scaled) from a solution in generator form."""
        P = self.n_points
        gp, gm = x[:P], x[P : 2 * P]
        return gp + gm, self.mu * (gp - gm)

    def equilibrium_matrix(self) -> tuple[sp.csc_matrix, sp.csc_matrix]:
        """``(B_n, B_s)``: equilibrium columns of the normal and shear forces."""
        return self.Bn, self.Bs

    def primal_residual(self, n: FloatArray, s: FloatArray, lam: float, *, coulomb: bool = True) -> float:
        """Largest violation of equilibrium, ``n >= 0`` and (unless
        ``coulomb=False``) associative Coulomb ``|s| <= mu n`` (scaled units)."""
        r = self.Bn @ n + self.Bs @ s + lam * self.live - self.rhs
        viol = max(float(np.max(np.abs(r), initial=0.0)), float(np.max(-n, initial=0.0)))
        if not coulomb:
            return viol
        return max(viol, float(np.max(np.abs(s) - self.mu * n, initial=0.0)))


def point_geometry(wall: BlockWall) -> tuple[IntArray, IntArray, FloatArray, FloatArray, FloatArray, FloatArray]:
    """Per-point data: blocks ``a``, ``b``, coordinates, normal and tangent.

    Returns:
        ``(a, b, px, py, normal, tangent)`` with one entry per contact point
        (point ``2c + k`` is end ``k`` of contact ``c``), dimensional units.
    """
    a = np.repeat(wall.contact_a, 2)
    b = np.repeat(wall.contact_b, 2)
    px = wall.px.ravel()
    py = wall.py.ravel()
    nrm = np.repeat(wall.normal, 2, axis=0)
    tan = np.column_stack([nrm[:, 1], -nrm[:, 0]])
    return a, b, px, py, nrm, tan


def point_columns(a: IntArray, b: IntArray, px: FloatArray, py: FloatArray, vec: FloatArray, xc: FloatArray,
                  yc: FloatArray, n_blocks: int) -> sp.csc_matrix:
    """Equilibrium columns of unit forces at contact points: the matrix ``B`` of the module docstring.

    Point ``p`` pushes block ``b[p]`` along ``vec[p]`` and block ``a[p]`` the opposite way (``-1``: the
    ground, which has no rows); each block has three rows ``(F_x, F_y, M)``, ``M`` counter-clockwise about
    its reference point ``(xc, yc)`` (its centroid). ``B^T`` maps block velocities ``(u, v, omega)`` (of
    the reference points) onto the velocity of ``b`` relative to ``a`` at the points, along ``vec``.
    Pure geometry in any consistent units: the LP (:func:`assemble`, scaled) and the check of a collapse
    state read from a file (:mod:`micro.state`, dimensional) build their matrices with it.

    Args:
        a, b: the two blocks of each point (``-1``: the ground).
        px, py: the points' coordinates.
        vec: ``(P, 2)`` unit directions (the normals or the tangents).
        xc, yc: the blocks' reference points.
        n_blocks: number of blocks (``3 * n_blocks`` rows).

    Returns:
        ``(3 n_blocks, P)`` CSC matrix, indices sorted, no explicit zeros.
    """
    P = px.size
    rows: list[IntArray] = []
    cols: list[IntArray] = []
    vals: list[FloatArray] = []
    pidx = np.arange(P, dtype=np.int64)
    for blk, sign in ((b, 1.0), (a, -1.0)):
        ok = blk >= 0
        k = blk[ok]
        fx = sign * vec[ok, 0]
        fy = sign * vec[ok, 1]
        mz = (px[ok] - xc[k]) * fy - (py[ok] - yc[k]) * fx
        c = pidx[ok]
        rows += [3 * k, 3 * k + 1, 3 * k + 2]
        cols += [c, c, c]
        vals += [fx, fy, mz]
    r, c, v = np.concatenate(rows), np.concatenate(cols), np.concatenate(vals)
    keep = v != 0.0
    m = sp.csc_matrix((v[keep], (r[keep], c[keep])), shape=(3 * n_blocks, P))
    m.sum_duplicates()
    m.sort_indices()
    return m


def generator_form(Bn: sp.csc_matrix, Bs: sp.csc_matrix, mu: FloatArray,
                   live: FloatArray) -> tuple[sp.csc_matrix, FloatArray, FloatArray]:
    """The LP in generator form from its equilibrium columns (module docstring).

    Returns:
        ``(A, col_lower, col_upper)``: ``A = [B_n + mu B_s, B_n - mu B_s, f_L]``,
        generators ``>= 0`` (``g-`` fixed at 0 where ``mu = 0``), ``lambda`` free.
    """
    P = Bn.shape[1]
    muBs = Bs @ sp.diags(mu)
    A = sp.hstack([Bn + muBs, Bn - muBs, sp.csc_matrix(live[:, None])], format="csc")
    A.eliminate_zeros()
    A.sort_indices()
    col_lower = np.concatenate([np.zeros(2 * P), [-np.inf]])
    col_upper = np.full(2 * P + 1, np.inf)
    # mu = 0 (frictionless head joints): g- would duplicate g+; fix it at 0
    col_upper[P : 2 * P][mu == 0.0] = 0.0
    return A, col_lower, col_upper


def assemble(wall: BlockWall) -> LimitLP:
    """Assemble the LP of ``wall`` with whole-array operations (no loop per contact).

    Args:
        wall: the block assemblage.

    Returns:
        The :class:`LimitLP`.
    """
    t0 = time.perf_counter()
    ls = wall.block_height
    fs = wall.reference_weight
    nbk = wall.n_blocks
    a, b, px, py, nrm, tan = point_geometry(wall)
    P = px.size
    px = px / ls
    py = py / ls
    xc = wall.xc / ls
    yc = wall.yc / ls
    n_eq = 3 * nbk
    Bn = point_columns(a, b, px, py, nrm, xc, yc, nbk)
    Bs = point_columns(a, b, px, py, tan, xc, yc, nbk)
    live = (wall.live / np.array([fs, fs, fs * ls])).ravel()
    dead = (wall.dead / np.array([fs, fs, fs * ls])).ravel()
    mu = np.repeat(wall.mu, 2)
    A, col_lower, col_upper = generator_form(Bn, Bs, mu, live)
    return LimitLP(
        wall=wall,
        A=A,
        Bn=Bn,
        Bs=Bs,
        rhs=-dead,
        col_lower=col_lower,
        col_upper=col_upper,
        n_eq=n_eq,
        n_points=P,
        mu=mu,
        dead=dead,
        live=live,
        length_scale=ls,
        force_scale=fs,
        build_seconds=time.perf_counter() - t0,
    )
