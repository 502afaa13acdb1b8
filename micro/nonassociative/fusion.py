"""The fused wall: the blocks a mechanism moves as one rigid body joined, their LP, and its state made the wall's.

THE FUSED WALL. On a large wall most contacts of the collapse mechanism
neither open nor slip (on Set 10, most of its contacts; the count is on
the research page on the re-cut of the non-associative package (``docs/research/``)), yet
every LP carries all their forces and the warm dual simplex wanders through
their statically indeterminate fields. :func:`rigid_bodies` joins the blocks
linked by such RIGID contacts into bodies (those linked to the ground into
the ground; a block with a moving contact stays a body of its own), and
:func:`fuse` writes the LP of the bodies: a body's three equilibrium rows
are the sums of its blocks' rows, moments taken about the mean of its
blocks' centroids (a sparse AGGREGATION matrix ``R``, 3 rows per body and 3
columns per block); the rows of the blocks at rest and the points inside a
body or the ground drop out. The result is again a
:class:`~micro.lp.LimitLP`, so the iterated LP runs on it unchanged; its
duals are the bodies' velocities, and ``R^T`` spreads them to the blocks.

A state of the bodies is not yet a state of the wall: inside every body the
forces must still carry the blocks' loads with ``|s| <= mu n``. The
certificate of the whole wall decides (:func:`on_the_wall`), with the bodies'
mechanism spread to the blocks; any field it finds is an exact collapse
state of the WALL, and nothing less is accepted. The fusion restricts the
mechanisms the sequence can reach: the state is one of the wall's collapse
states, not necessarily the one the unfused sequence would reach
(``docs/micro/nonassociative.md``).
"""

from __future__ import annotations

import dataclasses
import math
import time
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray
from scipy.sparse.csgraph import connected_components

from micro.backends.base import Outcome
from micro.backends.roles import ANY_FAILURE, solve_interior
from micro.limit_result import DirectionResult
from micro.lp import LimitLP, generator_form
from micro.mechanism import mechanism_from_duals
from micro.nonassociative import final_checks
from micro.nonassociative.certificate import Certificate
from micro.nonassociative.config import EQUILIBRIUM_RESIDUAL, Resolved
from micro.nonassociative.nonassociative_result import CONVERGED, SOLVER_FAILURE, FusionDiagnostics

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]

#: A contact is rigid, and the blocks it joins are fused into one body, when
#: its opening and slip rates in the associative mechanism (Clarabel's
#: interior point) are below this fraction of the largest rate. That mechanism
#: has no clean zero, so the threshold is a choice: the largest at which the
#: fused states of the paper's walls that need fusing are still certified on
#: the whole wall (a looser one fuses blocks that move, and the state lands at
#: the end of its band where the wall's certificate misses it). The counts per
#: threshold: the research page on the re-cut of the non-associative package
#: (``docs/research/``, "Figures moved from the code").
FUSE_RIGID_TOL = 1e-5


def rigid_bodies(lp: LimitLP, velocities: FloatArray, tol: float = FUSE_RIGID_TOL, *,
                 single_band: bool = True) -> tuple[IntArray, int]:
    """The rigid bodies of a mechanism.

    Args:
        lp: the wall's LP.
        velocities: block velocities (duals of the equilibrium rows, ``3 n_blocks``).
        tol: a contact is rigid when the opening and slip rates at both its
            points are below this fraction of the largest rate.
        single_band: keep every block with a contact that is not rigid a body
            of its own (below); ``False``: join the blocks by their rigid
            contacts only (the reduced wall's coarsest model,
            :mod:`micro.nonassociative.reduced`).

    Returns:
        ``(body, n_bodies)``: the body of every block, ``-1`` for the blocks
        joined to the ground by rigid contacts (at rest). A block with a
        contact that is not rigid is a body of its own, so that the sequence
        can shift a crack of the associative mechanism by a block (fused up
        to its moving contacts, Set 9 ended at the LP cap; as here, it is
        certified: the research page on the re-cut of the non-associative package (``docs/research/``)).
    """
    wall = lp.wall
    nb = wall.n_blocks
    dn, ds = lp.Bn.T @ velocities, lp.Bs.T @ velocities
    rate = np.maximum(np.abs(dn), np.abs(ds)).reshape(-1, 2).max(axis=1)
    rigid = rate <= tol * max(float(rate.max(initial=0.0)), 1e-300)
    ground = nb  # node of the ground in the contact graph
    a = np.where(wall.contact_a < 0, ground, wall.contact_a)
    b = np.where(wall.contact_b < 0, ground, wall.contact_b)
    # a block with a moving contact stays single: the cracks may shift by a block
    single = np.zeros(nb + 1, dtype=bool)
    if single_band:
        single[a[~rigid]] = True
        single[b[~rigid]] = True
    single[ground] = False
    join = rigid & ~single[a] & ~single[b]
    graph = sp.coo_matrix((np.ones(int(join.sum())), (a[join], b[join])), shape=(nb + 1, nb + 1))
    _, label = connected_components(graph, directed=False)
    moving = label[:nb] != label[ground]
    # number the moving bodies 0, 1, ... in the order of their first block
    _, first, inverse = np.unique(label[:nb][moving], return_index=True, return_inverse=True)
    order = np.argsort(np.argsort(first))
    body = np.full(nb, -1, dtype=np.int64)
    body[moving] = order[inverse]
    return body, int(first.size)


@dataclass(frozen=True, eq=False)
class FusedLP:
    """The LP of a wall's bodies (module docstring).

    Attributes:
        lp: the fused LP (a :class:`LimitLP`; its ``wall`` is the whole wall's).
        aggregation: ``R``, ``(3 n_bodies, 3 n_blocks)``: the bodies' rows
            from the blocks'; ``R^T`` spreads body velocities to the blocks.
        points: the wall's index of every point of the fused LP.
        body: the body of every block (``-1``: at rest).
        n_bodies: moving bodies.
    """

    lp: LimitLP
    aggregation: sp.csr_matrix
    points: IntArray
    body: IntArray
    n_bodies: int

    @property
    def blocks_at_rest(self) -> int:
        """Blocks fused into the ground."""
        return int(np.sum(self.body < 0))

    @property
    def single_bodies(self) -> int:
        """Bodies of one block."""
        return int(np.sum(np.bincount(self.body[self.body >= 0], minlength=self.n_bodies) == 1))

    def velocities(self, body_velocities: FloatArray) -> FloatArray:
        """The blocks' velocities of a mechanism of the bodies (rigid motions)."""
        return np.asarray(self.aggregation.T @ body_velocities)


def fuse(lp: LimitLP, body: IntArray, n_bodies: int) -> FusedLP:
    """The LP of the bodies ``body`` (:func:`rigid_bodies`; module docstring)."""
    wall = lp.wall
    nb = wall.n_blocks
    xc, yc = wall.xc / lp.length_scale, wall.yc / lp.length_scale
    blk = np.flatnonzero(body >= 0)
    c = body[blk]
    count = np.bincount(c, minlength=n_bodies)
    ox = np.bincount(c, xc[blk], minlength=n_bodies) / np.maximum(count, 1)
    oy = np.bincount(c, yc[blk], minlength=n_bodies) / np.maximum(count, 1)
    ones = np.ones(blk.size)
    rows = np.concatenate([3 * c, 3 * c + 1, 3 * c + 2, 3 * c + 2, 3 * c + 2])
    cols = np.concatenate([3 * blk, 3 * blk + 1, 3 * blk + 2, 3 * blk + 1, 3 * blk])
    vals = np.concatenate([ones, ones, ones, xc[blk] - ox[c], -(yc[blk] - oy[c])])
    R = sp.csr_matrix((vals, (rows, cols)), shape=(3 * n_bodies, 3 * nb))
    side_a = np.where(wall.contact_a < 0, -1, body[np.maximum(wall.contact_a, 0)])
    side_b = np.where(wall.contact_b < 0, -1, body[np.maximum(wall.contact_b, 0)])
    points = np.flatnonzero(np.repeat(side_a != side_b, 2)).astype(np.int64)
    Bn = sp.csc_matrix(R @ lp.Bn)[:, points]
    Bs = sp.csc_matrix(R @ lp.Bs)[:, points]
    Bn.sort_indices()
    Bs.sort_indices()
    mu = lp.mu[points]
    live, dead = R @ lp.live, R @ lp.dead
    A, lower, upper = generator_form(Bn, Bs, mu, live)
    fused = dataclasses.replace(
        lp, A=A, Bn=Bn, Bs=Bs, rhs=-dead, col_lower=lower, col_upper=upper, n_eq=3 * n_bodies,
        n_points=points.size, mu=mu, dead=dead, live=live, points=points,
    )
    return FusedLP(fused, R, points, body, n_bodies)


def fused_wall(lp: LimitLP, direction: int, resolved: Resolved) -> tuple[FusedLP, Outcome] | None:
    """The fused wall of one direction: the associative LP of the whole wall
    (``InteriorLP``, and ``InteriorLPRetry`` where it fails, as the iterated LP's
    start: :func:`~micro.backends.roles.solve_interior`) gives the mechanism whose
    rigid bodies are fused.

    Returns:
        ``(the fused LP, the associative outcome)``, or ``None`` where the
        associative LP fails or nothing moves (the wall itself must run).
    """
    assoc, _ = solve_interior(lp, direction, retry_on=ANY_FAILURE, time_limit=resolved.options.time_limit)
    if not assoc.ok or assoc.duals is None:
        return None
    body, n_bodies = rigid_bodies(lp, np.asarray(assoc.duals[: lp.n_eq]))
    if n_bodies == 0:
        return None
    return fuse(lp, body, n_bodies), assoc


def on_the_wall(lp: LimitLP, direction: int, fused: FusedLP, assoc: Outcome, r: DirectionResult,
                resolved: Resolved, t0: float, t_fuse: float) -> DirectionResult:
    """The fused wall's result ``r`` as the wall's (module docstring): a
    converged state is accepted only when the certificate of the whole wall
    finds a field for the bodies' mechanism at its ``lambda``; the result has
    forces at all the wall's points and the mechanism of all its blocks.

    Args:
        lp: the wall's LP.
        direction: ``+1`` or ``-1``.
        fused: the fused wall (:func:`fused_wall`).
        assoc: the wall's associative outcome whose mechanism was fused.
        r: the sequences' result on ``fused.lp``.
        resolved: what the stages read (the scheme, the time limit).
        t0: when the fusing started (``time.perf_counter()``).
        t_fuse: the seconds of the associative LP and the fusion.
    """
    n_bodies = fused.n_bodies
    assert r.sequence is not None
    seq = r.sequence
    lam = seq.last_load_factor
    seq = dataclasses.replace(seq, associative_load_factor=float(assoc.load_factor))
    fusion = FusionDiagnostics(
        bodies=n_bodies, single_bodies=fused.single_bodies, blocks_at_rest=fused.blocks_at_rest,
        points=fused.lp.n_points, wall_points=lp.n_points, rigid_tol=FUSE_RIGID_TOL,
        seconds=t_fuse, wall_certificate="",
    )
    mechanism = None
    if r.mechanism is not None:
        v = fused.velocities(r.mechanism.velocities.ravel())
        mechanism = mechanism_from_duals(lp, v, direction)
    if not r.converged or mechanism is None:
        return dataclasses.replace(
            r, normal=None, shear=None, mechanism=mechanism, seconds=time.perf_counter() - t0,
            message=f"on the fused wall ({n_bodies} bodies): {r.message}",
            sequence=dataclasses.replace(seq, fusion=fusion))
    v = mechanism.velocities.ravel()
    cert = Certificate(lp, direction, resolved.tuning.scheme).certify(v, lam, time_limit=resolved.options.user_limit)
    t_cert = cert.seconds
    if cert.forces is None:
        if cert.band is None:
            band = "no state"
        elif math.isfinite(cert.band[1]):
            band = f"states only for lambda in [{cert.band[0]:.9g}, {cert.band[1]:.9g}]"
        else:
            band = f"states only from lambda = {cert.band[0]:.9g}"
        fusion = dataclasses.replace(fusion, wall_certificate="rejected", certificate_seconds=t_cert)
        return dataclasses.replace(
            r, status=SOLVER_FAILURE, load_factor=math.nan, normal=None, shear=None, mechanism=mechanism,
            seconds=time.perf_counter() - t0,
            message=(f"the fused wall's state at lambda = {lam:.9g} is not a state of the wall: the certificate "
                     f"of the whole wall finds {band} with its mechanism"),
            sequence=dataclasses.replace(seq, stop_reason="fused_state_rejected", lambda_band=None,
                                         fusion=fusion))
    n, s = cert.forces
    state = final_checks.final_state(lp, direction, v, n, s, lam)
    fusion = dataclasses.replace(fusion, wall_certificate="certified", certificate_seconds=t_cert)
    seq = dataclasses.replace(
        seq, mechanism_band=cert.band, coulomb_residual=state.coulomb, dilatancy_residual=state.dilatancy,
        equilibrium_residual=state.equilibrium, sliding_points=state.sliding_points, fusion=fusion)
    status, message = CONVERGED, ""
    if state.equilibrium > EQUILIBRIUM_RESIDUAL:
        status, message = SOLVER_FAILURE, f"equilibrium residual {state.equilibrium:.2e} block weights on the wall"
        seq = dataclasses.replace(seq, stop_reason="equilibrium_residual", mechanism_band=None)
    fs = lp.force_scale
    return dataclasses.replace(
        r, status=status, load_factor=lam if status == CONVERGED else math.nan, normal=n * fs, shear=s * fs,
        mechanism=state.mechanism, seconds=time.perf_counter() - t0, message=message, sequence=seq)
