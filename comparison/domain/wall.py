"""The shared wall: one wall, described once, built into each model's input, and its checks.

A :class:`WallSpec` is a dimensional wall (lengths, unit weight, floor loads) in
the terms both models understand. It is made either from the paper's
nondimensional parameters (Table 4 of Argiento, Maione & Casapulla 2018) with
:meth:`WallSpec.from_paper`, or from a TOML scene with
:func:`comparison.domain.scene.load_scene`. :meth:`WallSpec.to_macro` and
:meth:`WallSpec.to_micro` build each model's own input, so that ``macro`` and
``micro`` never import each other.

Every wall parameter is checked with the one vocabulary of :mod:`macro.checks`
(re-exported here for the scene files and the command line), so that the
spec, the scenes, ``macro.MacroWall`` and ``macro.sweep`` word a bad value
alike, and within the physical bounds of :func:`macro.checks.wall_bounds`
(sizes where double precision is exact enough, a wall at least one block
long). The mapping of the paper's parameters onto a dimensional wall is
:func:`macro.paper.paper_walls` (block height 1, ``H = o``, ``L = o/t``,
``l = 1/m``, ``q = p H`` on every floor; see that module and ``docs/macro.md`` for the
reading of ``p``). The load factor is independent of the unit of length and of
``unit_weight``.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence, Set
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Literal

import numpy as np

from comparison.utilities.numbers import shortest
from macro.checks import NO_STOREY, WALL_FIELDS, friction, magnitude, non_negative, positive, positive_int, wall_bounds
from macro.paper import BLOCK_HEIGHT, paper_walls

if TYPE_CHECKING:  # pragma: no cover - typing only
    import macro
    import micro


#: The block wall's end treatments, the default first: :data:`micro.ENDS`, named here so that a macro-only
#: run does not import ``micro`` (a test holds the two together).
ENDS = ("closers", "cut")


def _one_number(name: str, value: object) -> None:
    """Refuse a sequence, a set, a mapping or an array where one wall takes one number (the number itself is
    checked by :func:`macro.paper.paper_walls`).

    Raises:
        ValueError: naming ``name``.
    """
    if isinstance(value, np.ndarray):
        one = value.ndim == 0
    else:
        one = isinstance(value, (str, bytes)) or not isinstance(value, (Sequence, Set, Mapping))
    if not one:
        raise ValueError(f"{name} must be one number (a WallSpec is one wall; macro.sweep takes arrays), got {value!r}")


@dataclass(frozen=True)
class StoreySpec:
    """One storey, numbered as the paper does (1 = top).

    Attributes:
        rows: courses of blocks in the storey (positive integer).
        thickness: thickness of the storey's blocks (the paper's ``b_i``).
        overload: floor load per unit length of wall on top of the storey
            (the paper's ``q_i``; force / length).
    """

    rows: int
    thickness: float
    overload: float = 0.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "rows", positive_int("rows", self.rows))
        object.__setattr__(self, "thickness", positive("thickness", self.thickness))
        object.__setattr__(self, "overload", non_negative("overload", self.overload))


@dataclass(frozen=True)
class WallSpec:
    """A dimensional dry-joint wall of one or more storeys.

    Attributes:
        length: wall length ``L``.
        block_length: unit block length ``l`` (the overlap is ``v = l/2``).
        block_height: unit block height ``b``.
        storeys: the storeys from the top (storey 1) down.
        unit_weight: specific weight ``gamma`` (force / volume).
        friction: friction coefficient ``f`` of every joint.
        ends: how the block wall's courses end where ``L`` is not a whole number of half blocks
            (:data:`micro.ENDS`): ``"closers"`` (the default: no piece narrower than a closer, every lap half
            a block) or ``"cut"`` (whatever remains, down to slivers); see ``docs/micro/walls.md``. The macro
            model has no blocks and ignores it.
        name: a label used in reports.
    """

    length: float
    block_length: float
    block_height: float
    storeys: tuple[StoreySpec, ...]
    unit_weight: float = 1.0
    friction: float = 0.6
    ends: str = "closers"
    name: str = field(default="", compare=False)

    def __post_init__(self) -> None:
        for name in ("length", "block_length", "block_height", "unit_weight"):
            object.__setattr__(self, name, magnitude(name, getattr(self, name)))
        object.__setattr__(self, "friction", friction("friction", self.friction))
        if isinstance(self.storeys, (str, bytes)) or not hasattr(self.storeys, "__iter__"):
            raise ValueError(f"storeys must be a tuple of StoreySpec, storey 1 (top) first, got {self.storeys!r}")
        if not isinstance(self.name, str):
            raise ValueError(f"name must be a string, got {self.name!r}")
        if self.ends not in ENDS:
            raise ValueError(f"ends must be one of {', '.join(ENDS)}, got {self.ends!r}")
        storeys = tuple(self.storeys)
        if not storeys:
            raise ValueError(NO_STOREY.format(name="storeys"))
        if not all(isinstance(s, StoreySpec) for s in storeys):
            raise ValueError("storeys must be StoreySpec instances")
        object.__setattr__(self, "storeys", storeys)
        dims = self.dimensions()
        wall_bounds(**{k: dims[k] for k in WALL_FIELDS})

    # ------------------------------------------------------------------ paper
    @classmethod
    def from_paper(
        cls,
        *,
        t: float,
        m: float,
        rows: int,
        f: float,
        p: float = 0.0,
        storeys: int = 1,
        p_height: Literal["wall", "storey"] = "wall",
        ends: str = "closers",
        name: str = "",
    ) -> WallSpec:
        """Build a wall from the paper's Table 4 parameters.

        Args:
            t: wall shape ratio ``H/L``.
            m: unit shape ratio ``b/l``, in (0, 1].
            rows: number of rows ``o = H/b``, split equally over the storeys.
            f: friction coefficient.
            p: overloading ratio (same on every floor).
            storeys: number of storeys ``N``.
            p_height: ``"wall"`` reads ``p = q/(gamma H b)`` with ``H`` the wall
                height; ``"storey"`` uses the storey height.
            ends: how the block wall's courses end (:attr:`ends`).
            name: label for reports.

        Raises:
            ValueError: with a message naming the offending parameter
                (see :func:`macro.paper.paper_walls`); an array or a list for a
                parameter (one wall is one number each: :func:`macro.sweep`
                takes arrays).
        """
        for key, value in (("t", t), ("m", m), ("rows", rows), ("f", f), ("p", p), ("storeys", storeys)):
            _one_number(key, value)
        w = paper_walls(t, m, rows, f, p, storeys, p_height)
        per = int(w.rows_per_storey[0])
        q = float(w.overload[0])
        return cls(
            length=float(w.length[0]),
            block_length=float(w.block_length[0]),
            block_height=BLOCK_HEIGHT,
            storeys=tuple(StoreySpec(per, BLOCK_HEIGHT, q) for _ in range(w.storeys)),
            unit_weight=1.0,
            friction=float(w.friction[0]),
            ends=ends,
            name=name,
        )

    def paper_parameters(self) -> dict[str, Any]:
        """The paper's nondimensional parameters of this wall (back-mapping), for output.

        ``p = q/(gamma H b)`` (``p_height="wall"`` reading) storey by storey in ``p_storeys`` (storey 1, the
        top, first); ``p`` is the paper's one value for every floor, ``None`` when the storeys' differ (a
        scene's floor loads: no one ``p`` describes them). Each ratio is printed as the scene wrote it
        (:func:`comparison.utilities.numbers.shortest`: ``m = 0.10/0.30`` is 1/3, not ``0.33333333333333337``).
        """
        height = self.height
        p = [shortest(s.overload / (self.unit_weight * height * s.thickness)) for s in self.storeys]
        return {
            "t": shortest(height / self.length),
            "m": shortest(self.block_height / self.block_length),
            "rows": self.rows,
            "storeys": len(self.storeys),
            "p": p[0] if len(set(p)) == 1 else None,
            "p_storeys": p,
            "f": self.friction,
        }

    # --------------------------------------------------------------- geometry
    @property
    def rows(self) -> int:
        """Total number of rows (courses)."""
        return sum(s.rows for s in self.storeys)

    @property
    def height(self) -> float:
        """Wall height ``H``."""
        return self.rows * self.block_height

    @property
    def overlap(self) -> float:
        """Staggering length ``v = l/2``."""
        return 0.5 * self.block_length

    def storey_base(self, storey: int) -> float:
        """Height above the wall's base of the base of ``storey`` (1 = top): where the macro model's hinge of
        that storey lies, and for every storey but the bottom one a floor level."""
        return sum(s.rows for s in self.storeys[storey:]) * self.block_height

    # ----------------------------------------------------------------- models
    def dimensions(self) -> dict[str, Any]:
        """The wall in the keyword arguments both models take (``macro.MacroWall``, ``micro.build_wall``)."""
        return {
            "length": self.length,
            "block_length": self.block_length,
            "block_height": self.block_height,
            "rows": tuple(s.rows for s in self.storeys),
            "thickness": tuple(s.thickness for s in self.storeys),
            "overload": tuple(s.overload for s in self.storeys),
            "unit_weight": self.unit_weight,
            "friction": self.friction,
        }

    def to_macro(self) -> macro.MacroWall:
        """The macro-block model's input for this wall."""
        import macro

        return macro.MacroWall(**self.dimensions())

    def to_micro(self, **options: Any) -> micro.BlockWall:
        """The micro model's block assemblage for this wall.

        Args:
            **options: builder options of :func:`micro.build_wall`
                (``first_course``, ``head_joints``, ...); ``ends`` is the spec's (:attr:`ends`) unless given.
        """
        import micro

        return micro.build_wall(**self.dimensions(), **{"ends": self.ends, **options})
