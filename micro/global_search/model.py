"""The mixed-integer model of the non-associative collapse conditions.

Columns (scaled units; ``P`` points, ``C = P/2`` interfaces, ``B`` blocks)::

    g+ (P), g- (P)   Coulomb-cone generators: n = g+ + g-, s = mu (g+ - g-)
    lambda (1)       the load factor (minimised)
    v (3B)           block velocities (u, v, omega)
    q+ (C), q- (C)   positive and negative parts of each interface's slip rate
    z (P)            binary: the point may open (then n = 0)
    a+ (C), a- (C)   binary: the interface may slip in the + (-) sense

Rows::

    B_n n + B_s s + d lambda f_L = -f_D           equilibrium          (3B)
    0 <= B_n^T v <= z                             opening rates        (2P)
    (B_s^T v)_c = q+_c - q-_c                     slip rate            (C)
    q+ <= a+,  q- <= a-,  a+ + a- <= 1            slip sense           (3C)
    g+_p + g-_p <= N_p (1 - z_p)                  open => n = 0        (P)
    g+_p <= N_p (1 - a+_c),  g-_p <= N_p (1 - a-_c)   slip => yield    (2P, mu > 0)
    sum_p (B_n^T v)_p + sum_c (q+_c + q-_c) = 1   normalised rates     (1)
    d f_L . v >= 0                                live load works      (1)
    -f_D . v <= lambda_up (d f_L . v)             energy cut           (1, optional)

The derivation, and why no bound cuts a collapse state off, is in
``docs/micro/global-search.md``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from micro.global_search import highs as gh
from micro.global_search.global_types import BigM, Pattern
from micro.lp import LimitLP

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]


@dataclass(frozen=True)
class Layout:
    """Column offsets of the model (see the module docstring).

    Attributes:
        P, C, B3: points, interfaces, velocity components (``3 * blocks``).
    """

    P: int
    C: int
    B3: int

    @property
    def lam(self) -> int:
        """Column of ``lambda``."""
        return 2 * self.P

    @property
    def v(self) -> int:
        """First velocity column."""
        return self.lam + 1

    @property
    def q(self) -> int:
        """First column of ``q+`` (``q-`` follows, ``C`` later)."""
        return self.v + self.B3

    @property
    def z(self) -> int:
        """First opening binary."""
        return self.q + 2 * self.C

    @property
    def a(self) -> int:
        """First slip binary ``a+`` (``a-`` follows, ``C`` later)."""
        return self.z + self.P

    @property
    def n_cols(self) -> int:
        """Number of columns."""
        return self.a + 2 * self.C

    @property
    def binaries(self) -> int:
        """Number of binary columns."""
        return self.P + 2 * self.C


def _slip_rows(lp: LimitLP) -> sp.csr_matrix:
    """``(C, 3B)``: the slip rate of each interface (its first point's row of
    ``B_s^T``; both points of a straight interface have the same one)."""
    BsT = lp.Bs.T.tocsr()
    first, second = BsT[0::2], BsT[1::2]
    diff = abs(first - second)
    if diff.nnz and diff.max() > 1e-9 * max(abs(first).max(), 1.0):
        raise ValueError("the two points of an interface have different slip rates (interface not straight)")
    return first


def build_mip(lp: LimitLP, direction: int, bounds: BigM, *, energy_cut: bool = True) -> tuple[gh.Model, Layout]:
    """Assemble the model of one load direction.

    Args:
        lp: the LP of the wall.
        direction: ``+1`` or ``-1``.
        bounds: the big-M bounds (:func:`micro.global_search.big_m.big_m`).
        energy_cut: add ``lift <= lambda_up * live work`` (valid when the
            mechanisms cannot lower the dead load, see :class:`BigM`).

    Returns:
        ``(HiGHS model, layout)``.
    """
    P, C, B3 = lp.n_points, lp.n_points // 2, lp.n_eq
    L = Layout(P, C, B3)
    N = bounds.normal
    I_P, I_C = sp.identity(P, format="csr"), sp.identity(C, format="csr")
    iface = sp.csr_matrix((np.ones(P), (np.arange(P), np.repeat(np.arange(C), 2))), shape=(P, C))
    fric = sp.identity(P, format="csr")[np.flatnonzero(lp.mu > 0.0)]  # selects the points with mu > 0
    nf = fric.shape[0]
    BnT, S = lp.Bn.T.tocsr(), _slip_rows(lp)
    live = float(direction) * lp.live
    eq = sp.hstack([lp.A[:, : 2 * P], sp.csc_matrix(live[:, None]), sp.csr_matrix((B3, L.n_cols - L.v))])

    def row(**blocks: sp.spmatrix) -> sp.csr_matrix:
        """One block row of the matrix: ``gp, gm, lam, v, qp, qm, z, ap, am`` pieces."""
        widths = {"gp": P, "gm": P, "lam": 1, "v": B3, "qp": C, "qm": C, "z": P, "ap": C, "am": C}
        n = next(iter(blocks.values())).shape[0]
        return sp.hstack([blocks.get(k, sp.csr_matrix((n, w))) for k, w in widths.items()]).tocsr()

    ones_P = sp.csr_matrix(np.ones((1, P)))
    parts = [
        (eq, lp.rhs, lp.rhs),
        (row(v=BnT, z=-I_P), np.full(P, -np.inf), np.zeros(P)),
        (row(v=BnT), np.zeros(P), np.full(P, np.inf)),
        (row(v=S, qp=-I_C, qm=I_C), np.zeros(C), np.zeros(C)),
        (row(qp=I_C, ap=-I_C), np.full(C, -np.inf), np.zeros(C)),
        (row(qm=I_C, am=-I_C), np.full(C, -np.inf), np.zeros(C)),
        (row(ap=I_C, am=I_C), np.full(C, -np.inf), np.ones(C)),
        (row(gp=I_P, gm=I_P, z=sp.diags(N)), np.full(P, -np.inf), N),
        (row(gp=fric, ap=fric @ sp.diags(N) @ iface), np.full(nf, -np.inf), fric @ N),
        (row(gm=fric, am=fric @ sp.diags(N) @ iface), np.full(nf, -np.inf), fric @ N),
        (row(v=ones_P @ BnT, qp=sp.csr_matrix(np.ones((1, C))), qm=sp.csr_matrix(np.ones((1, C)))), [1.0], [1.0]),
        (row(v=sp.csr_matrix(live[None, :])), [0.0], [np.inf]),
    ]
    if energy_cut and bounds.lift_nonnegative:
        lift_cut = -lp.dead - bounds.lambda_upper * live
        parts.append((row(v=sp.csr_matrix(lift_cut[None, :])), [-np.inf], [0.0]))
    A = sp.vstack([p[0] for p in parts]).tocsc()
    row_lo = np.concatenate([np.asarray(p[1], dtype=float) for p in parts])
    row_up = np.concatenate([np.asarray(p[2], dtype=float) for p in parts])
    col_lo = np.zeros(L.n_cols)
    col_up = np.ones(L.n_cols)
    col_up[: 2 * P] = np.concatenate([N, np.where(lp.mu > 0.0, N, 0.0)])
    col_lo[L.lam], col_up[L.lam] = bounds.lambda_lower, bounds.lambda_upper
    col_lo[L.v : L.q], col_up[L.v : L.q] = -np.inf, np.inf
    cost = np.zeros(L.n_cols)
    cost[L.lam] = 1.0
    h = gh.build(cost, A, (row_lo, row_up), (col_lo, col_up), integer=np.arange(L.z, L.n_cols, dtype=np.int64))
    return h, L


def solution_vector(lp: LimitLP, layout: Layout, pattern: Pattern, n: FloatArray, s: FloatArray, lam: float,
                    v: FloatArray) -> FloatArray:
    """A full column vector of the model from a collapse state (for ``setSolution``).

    The velocities are rescaled so that the rates sum to 1; the binaries are
    the pattern's.
    """
    P, C = layout.P, layout.C
    fric = lp.mu > 0.0
    ratio = s / np.where(fric, lp.mu, 1.0)
    gp = np.where(fric, np.maximum(0.5 * (n + ratio), 0.0), np.maximum(n, 0.0))
    gm = np.where(fric, np.maximum(0.5 * (n - ratio), 0.0), 0.0)
    dn = np.maximum(lp.Bn.T @ v, 0.0)
    ds = _slip_rows(lp) @ v
    total = float(dn.sum() + np.abs(ds).sum())
    x = np.zeros(layout.n_cols)
    x[:P], x[P : 2 * P], x[layout.lam] = gp, gm, lam
    x[layout.v : layout.q] = v / total
    x[layout.q : layout.q + C] = np.maximum(ds, 0.0) / total
    x[layout.q + C : layout.z] = np.maximum(-ds, 0.0) / total
    x[layout.z : layout.a] = pattern.opening
    x[layout.a : layout.a + C] = pattern.slip > 0
    x[layout.a + C :] = pattern.slip < 0
    return x


def pattern_of(layout: Layout, x: FloatArray) -> Pattern:
    """The pattern of the binaries of a model solution (rounded)."""
    b = np.rint(x[layout.z :]).astype(np.int64)
    P, C = layout.P, layout.C
    return Pattern(b[:P] == 1, (b[P : P + C] - b[P + C : P + 2 * C]).astype(np.int64))
