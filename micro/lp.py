"""Assembly of the static (lower-bound) limit-analysis LP of a block wall.

Formulation (Livesley 1978; Gilbert, Casapulla & Ahmed 2006), in scaled units
(lengths in block heights, forces in full-block weights of the thickest
storey, see :attr:`micro.BlockWall.reference_weight`):

* variables, in this order: the normal force ``n_p >= 0`` at every contact
  point ``p`` (compression positive), the shear ``s_p`` (free, along the
  contact tangent) and the load factor ``lambda`` (free);
* equilibrium rows, three per block (``F_x``, ``F_y``, ``M`` about the block
  centroid)::

      B [n; s] + lambda * f_L = -f_D

  where ``B [n; s]`` is the resultant of the contact forces on each block,
  ``f_D`` the dead load and ``f_L`` the live load (``+x``) per unit load
  factor — i.e. ``B x = -(f_D + lambda f_L)``;
* friction rows, two per point (associative Coulomb ``|s| <= mu n``)::

      s_p - mu_p n_p <= 0,     -s_p - mu_p n_p <= 0.

The objective is ``min -d * lambda`` with ``d = +1`` for the live load in
``+x`` and ``d = -1`` for ``-x``: the feasible load factors form an interval
``[-lambda_minus, lambda_plus]``, so one model serves both directions by a
change of one cost coefficient.

Keeping ``n`` and ``s`` as separate columns with explicit friction rows is a
deliberate choice for the next step (non-associative friction by iterated
LPs): the variant ``|s_p| <= mu_p * nbar_p`` is the friction rows switched off
(row bounds to infinity) and bounds ``[-mu nbar, mu nbar]`` on ``s_p`` — bound
changes only, so a simplex basis can be kept between solves.
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
        A: ``(n_rows, n_cols)`` CSC matrix: equilibrium rows, then friction rows.
        row_lower, row_upper: row bounds (``-inf`` / ``+inf`` where open).
        col_lower, col_upper: column bounds.
        n_eq: number of equilibrium rows (``3 * n_blocks``).
        n_points: number of contact points (``P``); columns ``0..P-1`` are
            ``n``, ``P..2P-1`` are ``s``, ``2P`` is ``lambda``.
        mu: friction coefficient per point.
        dead, live: scaled load vectors ``f_D``, ``f_L`` (length ``n_eq``).
        length_scale, force_scale: units of the scaled problem (block height,
            reference block weight).
        build_seconds: wall time of the assembly.
    """

    wall: BlockWall = field(repr=False)
    A: sp.csc_matrix = field(repr=False)
    row_lower: FloatArray = field(repr=False)
    row_upper: FloatArray = field(repr=False)
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

    @property
    def n_cols(self) -> int:
        """Number of variables."""
        return int(self.A.shape[1])

    @property
    def n_rows(self) -> int:
        """Number of rows (equilibrium + friction)."""
        return int(self.A.shape[0])

    @property
    def nnz(self) -> int:
        """Non-zeros of the constraint matrix."""
        return int(self.A.nnz)

    @property
    def lam_col(self) -> int:
        """Index of the load-factor column."""
        return 2 * self.n_points

    def cost(self, direction: int) -> FloatArray:
        """Objective of the minimisation for live load direction ``+1``/``-1``."""
        c = np.zeros(self.n_cols)
        c[self.lam_col] = -float(direction)
        return c

    def equilibrium_matrix(self) -> sp.csc_matrix:
        """``B``: the equilibrium rows restricted to the ``n``, ``s`` columns."""
        return self.A[: self.n_eq, : 2 * self.n_points].tocsc()


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

    rows: list[IntArray] = []
    cols: list[IntArray] = []
    vals: list[FloatArray] = []
    pidx = np.arange(P, dtype=np.int64)
    for col0, vec in ((0, nrm), (P, tan)):
        col = col0 + pidx
        for blk, sign in ((b, 1.0), (a, -1.0)):
            ok = blk >= 0
            k = blk[ok]
            fx = sign * vec[ok, 0]
            fy = sign * vec[ok, 1]
            mz = (px[ok] - xc[k]) * fy - (py[ok] - yc[k]) * fx
            c = col[ok]
            rows += [3 * k, 3 * k + 1, 3 * k + 2]
            cols += [c, c, c]
            vals += [fx, fy, mz]
    live = (wall.live / np.array([fs, fs, fs * ls])).ravel()
    dead = (wall.dead / np.array([fs, fs, fs * ls])).ravel()
    nz = live != 0.0
    rows.append(np.flatnonzero(nz))
    cols.append(np.full(int(nz.sum()), 2 * P, dtype=np.int64))
    vals.append(live[nz])
    # friction rows: 2p: s - mu n <= 0 ; 2p+1: -s - mu n <= 0
    mu = np.repeat(wall.mu, 2)
    n_eq = 3 * nbk
    r_plus = n_eq + 2 * pidx
    r_minus = r_plus + 1
    rows += [r_plus, r_plus, r_minus, r_minus]
    cols += [pidx, P + pidx, pidx, P + pidx]
    vals += [-mu, np.ones(P), -mu, -np.ones(P)]

    r = np.concatenate(rows)
    c = np.concatenate(cols)
    v = np.concatenate(vals)
    keep = v != 0.0
    n_rows = n_eq + 2 * P
    n_cols = 2 * P + 1
    A = sp.csc_matrix((v[keep], (r[keep], c[keep])), shape=(n_rows, n_cols))
    A.sum_duplicates()
    A.sort_indices()

    inf = np.inf
    row_lower = np.concatenate([-dead, np.full(2 * P, -inf)])
    row_upper = np.concatenate([-dead, np.zeros(2 * P)])
    col_lower = np.concatenate([np.zeros(P), np.full(P, -inf), [-inf]])
    col_upper = np.full(n_cols, inf)
    return LimitLP(
        wall=wall,
        A=A,
        row_lower=row_lower,
        row_upper=row_upper,
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
