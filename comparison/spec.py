"""The shared vocabulary: one wall, described once, built into each model's input.

A :class:`WallSpec` is a dimensional wall (lengths, unit weight, floor loads) in
the terms both models understand. It is made either from the paper's
nondimensional parameters (Table 4 of Argiento, Maione & Casapulla 2018) with
:meth:`WallSpec.from_paper`, or from a TOML scene with
:func:`comparison.scene.load_scene`. :meth:`WallSpec.to_macro` and
:meth:`WallSpec.to_micro` build each model's own input, so that ``macro`` and
``micro`` never import each other.

Mapping of the paper's parameters (Table 4) onto a dimensional wall
--------------------------------------------------------------------
Lengths are measured in block heights and forces in ``unit_weight`` units:

* block height ``b = 1``, wall thickness ``= b`` (the paper's unit block is
  ``l x b x b``);
* ``o = H/b`` rows in all, split equally over the storeys: ``H = o``;
* ``t = H/L``: wall length ``L = o / t``;
* ``m = b/l``: block length ``l = 1/m``, overlap ``v = l/2``;
* ``p``: the floor load per unit length of wall, on every floor, over the
  wall's self-weight per unit length, ``q = p * unit_weight * H * thickness``
  (``p_height="wall"``, the default). The OCR prints ``q/(Hb nu)``; reading
  ``H`` as the storey height instead (``p_height="storey"``) changes the
  Table 5 load factors by less than 0.2 % (see the README).

The load factor is independent of the unit of length and of ``unit_weight``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from fractions import Fraction
from typing import TYPE_CHECKING, Literal

if TYPE_CHECKING:  # pragma: no cover - typing only
    import macro
    import micro


def _positive(name: str, value: float) -> float:
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a number, got {value!r}") from None
    if not math.isfinite(x) or x <= 0.0:
        raise ValueError(f"{name} must be a positive number, got {value!r}")
    return x


def _non_negative(name: str, value: float) -> float:
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a number, got {value!r}") from None
    if not math.isfinite(x) or x < 0.0:
        raise ValueError(f"{name} must be zero or positive, got {value!r}")
    return x


def _positive_int(name: str, value: object) -> int:
    if isinstance(value, bool):
        raise ValueError(f"{name} must be a positive integer, got {value!r}")
    if isinstance(value, float) and value.is_integer():
        value = int(value)
    if not isinstance(value, int) or value <= 0:
        raise ValueError(f"{name} must be a positive integer, got {value!r}")
    return value


def parse_fraction(name: str, text: str | float) -> float:
    """Parse a number that may be written as a fraction (``"1/3"``).

    Raises:
        ValueError: naming ``name`` when ``text`` is not a number.
    """
    if isinstance(text, (int, float)) and not isinstance(text, bool):
        return float(text)
    try:
        return float(Fraction(str(text).strip()))
    except (ValueError, ZeroDivisionError):
        raise ValueError(f"{name} must be a number or a fraction such as 1/3, got {text!r}") from None


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
        object.__setattr__(self, "rows", _positive_int("rows", self.rows))
        object.__setattr__(self, "thickness", _positive("thickness", self.thickness))
        object.__setattr__(self, "overload", _non_negative("overload", self.overload))


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
        name: a label used in reports.
    """

    length: float
    block_length: float
    block_height: float
    storeys: tuple[StoreySpec, ...]
    unit_weight: float = 1.0
    friction: float = 0.6
    name: str = field(default="", compare=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "length", _positive("length", self.length))
        object.__setattr__(self, "block_length", _positive("block length", self.block_length))
        object.__setattr__(self, "block_height", _positive("block height", self.block_height))
        object.__setattr__(self, "unit_weight", _positive("unit weight", self.unit_weight))
        object.__setattr__(self, "friction", _positive("friction f", self.friction))
        storeys = tuple(self.storeys)
        if not storeys:
            raise ValueError("storeys: a wall needs at least one storey")
        if not all(isinstance(s, StoreySpec) for s in storeys):
            raise ValueError("storeys must be StoreySpec instances")
        object.__setattr__(self, "storeys", storeys)

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
            name: label for reports.

        Raises:
            ValueError: with a message naming the offending parameter.
        """
        t = _positive("t", t)
        m = _positive("m", m)
        if m > 1.0:
            raise ValueError(f"m must be in (0, 1], got {m!r}")
        f = _positive("f", f)
        p = _non_negative("p", p)
        n_storeys = _positive_int("storeys", storeys)
        o = _positive_int("rows", rows)
        if o % n_storeys:
            raise ValueError(
                f"rows: {o} rows cannot be split equally over {n_storeys} storeys; "
                "use a scene file for unequal storeys"
            )
        if p_height not in ("wall", "storey"):
            raise ValueError(f"p_height must be 'wall' or 'storey', got {p_height!r}")
        b = 1.0
        per = o // n_storeys
        height = o * b
        ref = height if p_height == "wall" else per * b
        q = p * 1.0 * ref * b
        return cls(
            length=height / t,
            block_length=b / m,
            block_height=b,
            storeys=tuple(StoreySpec(per, b, q) for _ in range(n_storeys)),
            unit_weight=1.0,
            friction=f,
            name=name,
        )

    def paper_parameters(self) -> dict[str, float]:
        """The paper's nondimensional parameters of this wall (back-mapping).

        ``p`` is taken from the top storey's load and thickness
        (``p_height="wall"`` reading); walls whose storeys differ have no
        single paper ``p`` or ``m`` and are returned with the values of storey 1.
        """
        height = self.height
        top = self.storeys[0]
        return {
            "t": height / self.length,
            "m": self.block_height / self.block_length,
            "rows": self.rows,
            "storeys": len(self.storeys),
            "p": top.overload / (self.unit_weight * height * top.thickness),
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

    # ----------------------------------------------------------------- models
    def to_macro(self) -> macro.MacroWall:
        """The macro-block model's input for this wall."""
        import macro

        return macro.MacroWall(
            length=self.length,
            block_length=self.block_length,
            block_height=self.block_height,
            rows=tuple(s.rows for s in self.storeys),
            thickness=tuple(s.thickness for s in self.storeys),
            overload=tuple(s.overload for s in self.storeys),
            unit_weight=self.unit_weight,
            friction=self.friction,
        )

    def to_micro(self, **options: object) -> micro.BlockWall:
        """The micro model's block assemblage for this wall.

        Args:
            **options: builder options of :func:`micro.build_wall`
                (``first_course``, ``head_joints``, ...).
        """
        import micro

        return micro.build_wall(
            length=self.length,
            block_length=self.block_length,
            block_height=self.block_height,
            rows=tuple(s.rows for s in self.storeys),
            thickness=tuple(s.thickness for s in self.storeys),
            overload=tuple(s.overload for s in self.storeys),
            unit_weight=self.unit_weight,
            friction=self.friction,
            **options,
        )
