"""The paper's cases and every value it publishes for them.

Argiento, Maione & Casapulla (2018), Tables 4-9: the reference wall and
Sets 1-10 of the sensitivity analysis (Table 5: three storeys of equal height,
the same overload on every floor) and Sets 11-17 of the validation (Table 6,
``f = 0.75``). Table 5 prints the number of rows as ``theta`` and Table 6 as
``sigma``: both are ``o``.

Published values are tagged with their table and the model that produced them:

* ``proposed``: the paper's macro-block model (Tables 5, 7, 9);
* ``orduna_micro``: Orduna's rigid-block (micro) limit analysis (Table 7);
* ``orduna_macro``, ``debuhan_defelice``, ``speranza``: other macro-block
  models (Tables 8, 9).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Literal

from comparison.domain.wall import WallSpec

MODELS = {
    "proposed": "Proposed macro-block model (Argiento et al. 2018)",
    "orduna_micro": "Micro-block model, Orduña (2003)",
    "orduna_macro": "Macro-block model, Orduña (2003)",
    "debuhan_defelice": "De Buhan & de Felice (1997)",
    "speranza": "Speranza (2003)",
}


@dataclass(frozen=True)
class Published:
    """One published number: ``value`` of ``quantity`` by ``model`` in ``table``.

    ``decimals`` is how many decimals the paper prints; half a unit of the
    last one is the rounding tolerance.
    """

    table: str
    model: str
    quantity: str
    value: float
    decimals: int

    @property
    def rounding(self) -> float:
        """Half a unit in the last printed decimal."""
        return 0.5 * 10.0 ** (-self.decimals)


@dataclass(frozen=True)
class PaperCase:
    """One of the paper's walls, in the paper's parameters, with its published values."""

    case: str
    t: float
    m: float
    rows: int
    f: float
    p: float
    storeys: int
    tables: tuple[str, ...]
    published: tuple[Published, ...] = field(default=())
    m_label: str = ""

    @property
    def label(self) -> str:
        """``"Ref"`` or ``"Set 7"``."""
        return self.case if self.case == "Ref" else f"Set {self.case}"

    def spec(self, p_height: Literal["wall", "storey"] = "wall") -> WallSpec:
        """The dimensional wall (see :meth:`WallSpec.from_paper`)."""
        return WallSpec.from_paper(
            t=self.t,
            m=self.m,
            rows=self.rows,
            f=self.f,
            p=self.p,
            storeys=self.storeys,
            p_height=p_height,
            name=self.label,
        )

    def value(self, model: str, quantity: str = "lambda") -> Published | None:
        """The published value of ``quantity`` by ``model``, if any."""
        for v in self.published:
            if v.model == model and v.quantity == quantity:
                return v
        return None


def _t5(case: str, lam: float, alpha: float, ratio: float, hinge: int = 3, **kw: float) -> PaperCase:
    base = dict(t=1.0, m=1 / 3, rows=60, f=0.6, p=0.0)
    base.update(kw)
    return PaperCase(
        case=case,
        storeys=3,
        tables=("5",),
        published=(
            Published("5", "proposed", "lambda", lam, 3),
            Published("5", "proposed", "alpha_c_deg", alpha, 2),
            Published("5", "proposed", "alpha_ratio", ratio, 2),
            Published("5", "proposed", "hinge_storey", hinge, 0),
        ),
        **base,  # type: ignore[arg-type]
    )


def _t78(
    case: str, t: float, m: float, micro: float, proposed: float, orduna: float, debuhan: float, speranza: float
) -> PaperCase:
    return PaperCase(
        case=case,
        t=t,
        m=m,
        rows=12,
        f=0.75,
        p=0.0,
        storeys=1,
        tables=("6", "7", "8"),
        published=(
            Published("7", "orduna_micro", "lambda", micro, 2),
            Published("7", "proposed", "lambda", proposed, 2),
            Published("8", "orduna_macro", "lambda", orduna, 2),
            Published("8", "debuhan_defelice", "lambda", debuhan, 2),
            Published("8", "speranza", "lambda", speranza, 2),
        ),
    )


def _t9(case: str, p: float, proposed: float, speranza: float) -> PaperCase:
    return PaperCase(
        case=case,
        t=1.0,
        m=1 / 3,
        rows=150,
        f=0.75,
        p=p,
        storeys=5,
        tables=("6", "9"),
        published=(
            Published("9", "proposed", "lambda", proposed, 2),
            Published("9", "speranza", "lambda", speranza, 2),
        ),
    )


#: Table 5 (sensitivity, three storeys) and Tables 6-9 (validation).
CASES: tuple[PaperCase, ...] = (
    _t5("Ref", 0.583, 40.15, 0.71),
    _t5("1", 0.519, 35.51, 0.63, f=0.4),
    _t5("2", 0.626, 43.34, 0.77, f=0.8),
    _t5("3", 0.578, 40.11, 0.71, p=2.0),
    _t5("4", 0.576, 40.12, 0.71, hinge=1, p=8.0),
    _t5("5", 0.513, 37.42, 0.66, rows=36),
    _t5("6", 0.585, 40.16, 0.71, rows=45),
    _t5("7", 0.406, 55.64, 0.99, t=2.0),
    _t5("8", 0.290, 56.31, 1.00, t=3.0),
    _t5("9", 0.451, 35.12, 0.78, m=0.5),
    _t5("10", 0.252, 26.57, 1.00, m=1.0),
    _t78("11", 0.5, 1 / 3, 0.69, 0.65, 0.75, 0.53, 0.67),
    _t78("12", 1.0, 1 / 3, 0.68, 0.65, 0.65, 0.53, 0.67),
    _t78("13", 1.0, 0.5, 0.49, 0.49, 0.50, 0.43, 0.52),
    _t78("14", 1.0, 1.0, 0.26, 0.26, 0.25, 0.31, 0.27),
    _t9("15", 0.0, 0.47, 0.52),
    _t9("16", 1.0, 0.47, 0.48),
    _t9("17", 8.0, 0.47, 0.37),
)

#: Table 5: the load factors of Set 4 for the hinge at storeys 1, 2, 3.
SET4_HINGE_LOAD_FACTORS = (0.576, 0.578, 0.582)


def case(name: str) -> PaperCase:
    """Look a case up by name (``"Ref"``, ``"7"``, ``"Set 7"``).

    Raises:
        TypeError: ``name`` is not a string (``7``, ``None``).
        ValueError: no such case.
    """
    if not isinstance(name, str):
        raise TypeError(f"case must be a name such as 'Ref', '7' or 'Set 7', got {name!r} ({type(name).__name__})")
    key = name.removeprefix("Set ").strip()
    for c in CASES:
        if c.case.lower() == key.lower():
            return c
    raise ValueError(f"case must be Ref or 1..17, got {name!r}")


def cases_in_table(table: str) -> tuple[PaperCase, ...]:
    """The cases of one table (``"5"``, ``"7"``, ``"8"``, ``"9"``; none for another string)."""
    return tuple(c for c in CASES if table in c.tables)
