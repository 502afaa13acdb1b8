"""The macro-block model for one dimensional wall: input, solve, result."""

from __future__ import annotations

import math
import time
from dataclasses import asdict, dataclass, field
from typing import Any

import numpy as np

from macro import checks
from macro.bounds import MECHANISMS, governing, overturning_load_factor
from macro.equations import TERM_NAMES, evaluate, hinge_problems
from macro.search import DEFAULT_SEARCH, SearchSettings, minimise_walls

#: Peak memory of the search per square of the number of storeys, for one wall with the
#: minimum of every hinge (:func:`solve`), and per wall and storey for a batch that keeps
#: only each wall's minimum (:func:`macro.sweep`). Measured (resident set above the
#: imports): one wall of 1,000 / 2,000 / 4,000 one-row storeys 173 MB / 723 MB / 2.8 GB
#: (173-181 bytes N^2; their seconds: docs/speed.md); sweeps of 4,096 walls of 10 and 50 storeys and
#: 300 walls of 200 storeys 123-146 bytes per wall and storey.
SEARCH_BYTES_PER_STOREY_SQUARED = 200
SWEEP_BYTES_PER_WALL_STOREY = 200


def search_bytes(storeys: int, walls: int = 0) -> int:
    """Estimated peak memory of the search: one wall with every hinge (``walls=0``), or a sweep batch."""
    return SWEEP_BYTES_PER_WALL_STOREY * walls * storeys if walls else SEARCH_BYTES_PER_STOREY_SQUARED * storeys**2


#: The statuses of a macro result: ``"optimal"`` (a finite positive load factor) or ``"numerical_error"``.
STATUSES = ("optimal", "numerical_error")

@dataclass(frozen=True)
class MacroWall:
    """A dimensional wall for the macro-block model.

    Storey tuples are ordered as in the paper, storey 1 at the top.

    Attributes:
        length: wall length ``L``.
        block_length: unit block length ``l``; the overlap is ``v = l/2``.
        block_height: unit block height ``b``.
        rows: rows ``n_i`` of each storey (positive integers).
        thickness: block thickness ``b_i`` of each storey.
        overload: floor load ``q_i`` per unit length on top of each storey.
        unit_weight: specific weight ``gamma``.
        friction: friction coefficient ``f``.
    """

    length: float
    block_length: float
    block_height: float
    rows: tuple[int, ...]
    thickness: tuple[float, ...]
    overload: tuple[float, ...]
    unit_weight: float = 1.0
    friction: float = 0.6

    def __post_init__(self) -> None:
        for name in ("length", "block_length", "block_height", "unit_weight"):
            object.__setattr__(self, name, checks.magnitude(name, getattr(self, name)))
        object.__setattr__(self, "friction", checks.friction("friction", self.friction))
        rows = checks.per_storey("rows", self.rows, None, checks.positive_int)
        thickness = checks.per_storey("thickness", self.thickness, len(rows), checks.positive)
        overload = checks.per_storey("overload", self.overload, len(rows), checks.non_negative)
        object.__setattr__(self, "rows", rows)
        object.__setattr__(self, "thickness", thickness)
        object.__setattr__(self, "overload", overload)
        checks.wall_bounds(**{k: getattr(self, k) for k in checks.WALL_FIELDS})

    @property
    def storeys(self) -> int:
        """Number of storeys ``N``."""
        return len(self.rows)

    @property
    def overlap(self) -> float:
        """Staggering length ``v = l/2``."""
        return 0.5 * self.block_length

    @property
    def alpha_b(self) -> float:
        """``atan(v/b)`` in radians: the crack angle of pure rocking."""
        return math.atan(self.overlap / self.block_height)


@dataclass(frozen=True)
class StoreyTerms:
    """Every term of Eq. (10) for one storey of the mechanism (Table 2).

    ``x_*`` are horizontal and ``y_*`` vertical lever arms about the hinge O.
    ``F_g`` and ``F_q`` are the unreduced resultants of Eqs. (5)-(6); Eq. (10)
    multiplies their moments by ``MacroResult.friction_reduction``.
    """

    storey: int
    H_c: float
    n_c: float
    W_A: float
    x_WA: float
    y_WA: float
    W_B: float
    x_WB: float
    y_WB: float
    W_C: float
    x_WC: float
    y_WC: float
    W_D: float
    x_WD: float
    y_WD: float
    Q: float
    x_Q: float
    y_Q: float
    F_g: float
    y_Fg: float
    F_q: float
    y_Fq: float


@dataclass(frozen=True)
class HingeResult:
    """The minimum of Eq. (10) with the hinge at the base of one storey."""

    hinge_storey: int
    rocking_load_factor: float
    tan_alpha_c: float
    alpha_c_deg: float


@dataclass(frozen=True)
class MacroResult:
    """Collapse load factor of the macro-block model and how it was reached.

    Attributes:
        load_factor: governing load factor, the least of
            ``rocking_load_factor``, ``f`` (the wall above a bed joint sliding
            on it) and ``overturning_load_factor`` (see :mod:`macro.bounds`).
        rocking_load_factor: minimum of Eq. (10) over ``tan(alpha_c)`` and the
            hinge storey.
        sliding_load_factor: ``lambda_s`` of Eq. (12) at the optimum crack.
        overturning_load_factor: the storeys above a storey's base turning as
            one rigid body about its far corner, least over the storeys
            (``L/H`` without floor loads).
        tan_alpha_c: crack slope at the optimum; ``alpha_c_deg`` the angle.
        tan_alpha_c_star: slope of the stepped crack of Eq. (9),
            ``tan(alpha_c) - v/(n b)`` with ``n`` the rows of the mechanism;
            ``alpha_c_star_deg`` the angle.
        alpha_b_deg: ``atan(v/b)``; ``alpha_ratio = alpha_c/alpha_b``.
        hinge_storey: storey whose base holds the hinge (1 = top).
        mechanism: ``"rocking-sliding"``, ``"rocking"`` (``alpha_c = alpha_b``,
            no friction), ``"sliding"`` (``f`` below Eq. 10's minimum) or
            ``"overturning"`` (a slender wall: the rigid overturning bound
            below both).
        status: ``"optimal"``: the search covered every smooth piece and the
            load factor is a finite positive number; ``"numerical_error"``
            otherwise, with ``load_factor`` NaN.
        friction_reduction: ``1 - alpha_c/alpha_b`` of Eq. (8).
        stabilising_moment, overturning_moment, friction_moment: the sums of
            Eq. (10)'s numerator (weights and loads), denominator, and the
            unreduced friction moment, so that
            ``rocking_load_factor = (stabilising + reduction * friction) / overturning``.
        storeys: the terms of each storey of the mechanism (1..hinge_storey).
        hinges: the minimum for every hinge storey.
        solve_seconds: wall-clock time of the solve.
    """

    load_factor: float
    rocking_load_factor: float
    sliding_load_factor: float
    overturning_load_factor: float
    tan_alpha_c: float
    alpha_c_deg: float
    tan_alpha_c_star: float
    alpha_c_star_deg: float
    alpha_b_deg: float
    alpha_ratio: float
    hinge_storey: int
    mechanism: str
    status: str
    friction_reduction: float
    stabilising_moment: float
    overturning_moment: float
    friction_moment: float
    storeys: tuple[StoreyTerms, ...]
    hinges: tuple[HingeResult, ...]
    wall: MacroWall = field(repr=False)
    solve_seconds: float = 0.0

    def __post_init__(self) -> None:
        if self.status == "optimal" and not (math.isfinite(self.load_factor) and self.load_factor > 0.0):
            raise ValueError(f"an optimal macro result needs a finite positive load factor, got {self.load_factor!r}")

    def to_dict(self) -> dict[str, Any]:
        """A JSON-ready dictionary of the result."""
        d = asdict(self)
        d["wall"] = asdict(self.wall)
        return d

    @property
    def hinge_load_factors(self) -> tuple[float, ...]:
        """The minimum of Eq. (10) for the hinge at storeys 1, 2, ..."""
        return tuple(h.rocking_load_factor for h in self.hinges)


def _problems(wall: MacroWall) -> Any:
    N = wall.storeys
    rep = lambda x: np.full(N, float(x))  # noqa: E731
    tile = lambda xs: np.tile(np.asarray(xs, dtype=float), (N, 1))  # noqa: E731
    return hinge_problems(
        length=rep(wall.length),
        overlap=rep(wall.overlap),
        block_height=rep(wall.block_height),
        unit_weight=rep(wall.unit_weight),
        friction=rep(wall.friction),
        rows=tile(wall.rows),
        thickness=tile(wall.thickness),
        overload=tile(wall.overload),
        hinge=np.arange(1, N + 1),
    )


def load_factor_curve(wall: MacroWall, hinge_storey: int, tan_alpha_c: np.ndarray) -> dict[str, np.ndarray]:
    """Eq. (10) and Eq. (12) along given crack slopes, for plots and checks.

    Args:
        wall: the wall.
        hinge_storey: the hinge storey ``k`` (1 = top).
        tan_alpha_c: crack slopes, any shape after flattening.

    Returns:
        ``lambda_r`` and ``lambda_s`` with the shape of ``tan_alpha_c``.
    """
    if not 1 <= hinge_storey <= wall.storeys:
        raise ValueError(f"hinge_storey must be in 1..{wall.storeys}, got {hinge_storey!r}")
    sub = _problems(wall).select(slice(hinge_storey - 1, hinge_storey))
    tau = np.asarray(tan_alpha_c, dtype=float)
    out = evaluate(tau.reshape(1, -1), sub)
    return {key: out[key].reshape(tau.shape) for key in ("lambda_r", "lambda_s")}


def solve(wall: MacroWall, settings: SearchSettings = DEFAULT_SEARCH) -> MacroResult:
    """Minimise Eq. (10) over the crack slope and the hinge storey.

    For each hinge storey the admissible interval of Eq. (11) is split at the
    kinks ``tan(alpha_pi)`` and searched globally (see :class:`SearchSettings`).

    Args:
        wall: the wall.
        settings: the search's resolution.

    Returns:
        The governing :class:`MacroResult`.

    Raises:
        TypeError: ``wall`` is not a :class:`MacroWall` (``WallSpec.to_macro()`` gives one) or
            ``settings`` not a :class:`SearchSettings`.
        ValueError: a wall whose search would not fit in memory (:class:`macro.checks.TooLarge`).
    """
    if not isinstance(wall, MacroWall):
        hint = "; WallSpec.to_macro() gives one" if hasattr(wall, "to_macro") else ""
        raise TypeError(f"wall must be a macro.MacroWall{hint}, got {type(wall).__name__}")
    if not isinstance(settings, SearchSettings):
        raise TypeError(f"settings must be a macro.SearchSettings, got {settings!r} ({type(settings).__name__})")
    start = time.perf_counter()
    n = wall.storeys
    checks.fits_in_memory("storeys", f"the search over {n} storeys", search_bytes(n))
    found = minimise_walls(
        [wall.length], [wall.overlap], [wall.block_height], [wall.unit_weight], [wall.friction],
        [wall.rows], [wall.thickness], [wall.overload], settings,
    )  # fmt: skip
    lam, tau = found.rocking_load_factor[0], found.tan_alpha_c[0]
    pb = _problems(wall)
    k = int(np.argmin(lam))
    hinges = tuple(
        HingeResult(i + 1, float(lam[i]), float(tau[i]), math.degrees(math.atan(tau[i]))) for i in range(wall.storeys)
    )
    at = evaluate(np.array([[tau[k]]]), pb.select(slice(k, k + 1)), detail=True)
    storeys = tuple(
        StoreyTerms(storey=i + 1, **{name: float(at[name][0, 0, i]) for name in TERM_NAMES}) for i in range(k + 1)
    )
    lam_r = float(lam[k])
    ratio = math.atan(tau[k]) / wall.alpha_b
    tau_star = float(tau[k]) - wall.overlap / (sum(wall.rows[: k + 1]) * wall.block_height)
    lam_o = float(
        overturning_load_factor(
            [wall.length], [wall.block_height], [wall.unit_weight], [wall.rows], [wall.thickness], [wall.overload]
        )[0]
    )
    lam_g, mech = governing(lam_r, wall.friction, lam_o, ratio)
    ok = bool(np.isfinite(lam_g) and lam_g > 0.0)
    return MacroResult(
        load_factor=float(lam_g) if ok else math.nan,
        rocking_load_factor=lam_r,
        sliding_load_factor=float(at["lambda_s"][0, 0]),
        overturning_load_factor=lam_o,
        tan_alpha_c=float(tau[k]),
        alpha_c_deg=math.degrees(math.atan(tau[k])),
        tan_alpha_c_star=tau_star,
        alpha_c_star_deg=math.degrees(math.atan(tau_star)),
        alpha_b_deg=math.degrees(wall.alpha_b),
        alpha_ratio=ratio,
        hinge_storey=k + 1,
        mechanism=MECHANISMS[int(mech)],
        status=STATUSES[0] if ok else STATUSES[1],
        friction_reduction=float(at["reduction"][0, 0]),
        stabilising_moment=float(at["stabilising"][0, 0]),
        overturning_moment=float(at["overturning"][0, 0]),
        friction_moment=float(at["friction_moment"][0, 0]),
        storeys=storeys,
        hinges=hinges,
        wall=wall,
        solve_seconds=time.perf_counter() - start,
    )
