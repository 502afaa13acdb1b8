"""The shipped reference values: complete, consistent with the code and the paper, and the assertion helper."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

import macro
from comparison.cli import main
from comparison.domain.cases import CASES, case
from comparison.pytest_plugin import MissingReference, ReferenceMismatch, References
from comparison.pytest_plugin.generate import PUBLISHED, QUANTITIES


@pytest.fixture(scope="module")
def refs() -> References:
    return References.load()


def test_every_case_has_published_macro_and_micro_cells(refs: References) -> None:
    for c in CASES:
        methods = refs.methods(c)
        assert {"paper", "macro"} <= set(methods), c.label
        assert c.rows > 12 or {"micro-assoc", "micro-nonassoc"} <= set(methods), c.label
    for ref in refs:
        assert (ref.value is None) == (ref.tolerance is None), ref.name
        assert ref.value is None or (math.isfinite(ref.value) and ref.tolerance >= 0), ref.name  # type: ignore[operator]
        assert ref.source and ref.status, ref.name


def test_published_cells_are_the_papers(refs: References) -> None:
    for c in CASES:
        for p in c.published:
            ref = refs.get(c, PUBLISHED[p.model], QUANTITIES[p.quantity])
            assert (ref.value, ref.tolerance) == (p.value, p.rounding)


def test_macro_cells_are_current(refs: References) -> None:
    """The shipped macro values are what the macro model gives today (regenerate with ``xcheck references``)."""
    for c in CASES:
        r = macro.solve(c.spec().to_macro())
        refs.check(c, "macro", r.load_factor)
        refs.check(c, "macro", r.alpha_c_deg, "alpha_c_deg")
        assert refs.value(c, "macro", "hinge_storey") == r.hinge_storey


def test_regenerated_cells_match_the_shipped_ones(refs: References, tmp_path: Path) -> None:
    """``xcheck references --quick`` recomputes Table 7's micro cells and every macro and published cell: each
    lies within the shipped cell's tolerance (the shipped file is current), and the command says what it wrote."""
    out = tmp_path / "refs.json"
    assert main(["references", "--quick", "--no-cache", "--out", str(out), "-q"]) == 0
    fresh = References.load(out)
    assert len(fresh) >= 150 and fresh.meta["generated_by"] == "xcheck references --quick"
    for cell in fresh:
        shipped = refs.get(cell.case, cell.method, cell.cell)
        assert cell.value is not None and cell.tolerance is not None, cell.name
        refs.check(cell.case, cell.method, cell.value, cell.cell)
        assert (cell.source, cell.status) == (shipped.source, shipped.status)


def test_check_failure_names_case_method_and_cell(refs: References) -> None:
    ref = refs.get("12", "micro-nonassoc")
    assert ref.value is not None and ref.tolerance is not None
    refs.check(case("12"), "micro-nonassoc", ref.value + 0.99 * ref.tolerance)
    with pytest.raises(ReferenceMismatch) as err:
        refs.check("Set 12", "micro-nonassoc", 0.7021 if ref.value > 0.71 else ref.value - 2 * ref.tolerance)
    assert str(err.value).startswith("Set 12 / micro-nonassoc / load_factor: ")
    assert f"outside {ref.value:.4f} ± {ref.tolerance:.4f} (lowest certified collapse state" in str(err.value)
    with pytest.raises(ReferenceMismatch, match=r"Set 12 / paper / load_factor: 0\.7500 outside 0\.6500 ± 0\.0375"):
        refs.check("Set 12", "paper", 0.75, rel=0.05)  # 0.005 rounding + 5 % of 0.65
    with pytest.raises(ReferenceMismatch, match="nan outside"):
        refs.check("Set 12", "paper", math.nan, rel=1.0)


def test_missing_references_say_why(refs: References) -> None:
    with pytest.raises(
        MissingReference, match=r"Set 12 / speranza-micro / load_factor: no such reference \(methods: .*paper"
    ):
        refs.check("12", "speranza-micro", 0.5)
    with pytest.raises(
        MissingReference, match="my wall / macro / load_factor: no such reference .*not one of the paper"
    ):
        refs.get("my wall", "macro")
    empty = [r for r in refs if r.value is None]
    for r in empty:  # a method that gave no number keeps its cell with the status
        with pytest.raises(MissingReference, match="no reference value"):
            refs.check(r.case, r.method, 0.5, r.cell)


def test_the_failure_quoted_in_the_docstrings_is_the_references_own(refs: References) -> None:
    """The example failure in ``References.check``'s docstring and the plugin's module docstring (value 0.25,
    ``rel=0.02``) carries the reference and the interval ``references.json`` gives (they quoted the iterated
    LP's 0.2684 ± 0.0067 after the reference became the lowest certified state, 0.2658)."""
    import comparison.pytest_plugin as plugin

    with pytest.raises(ReferenceMismatch) as info:
        refs.check("Set 14", "micro-nonassoc", 0.25, rel=0.02)
    head = str(info.value).split(" (", 1)[0]  # "Set 14 / micro-nonassoc / load_factor: 0.2500 outside ..."
    source = refs.get("Set 14", "micro-nonassoc").source.split(",", 1)[0]
    for doc in (References.check.__doc__ or "", plugin.__doc__ or ""):
        text = " ".join(doc.split())
        assert head in text, (head, text)
    assert f"{head} ({source}, ...;" in " ".join((References.check.__doc__ or "").split())
