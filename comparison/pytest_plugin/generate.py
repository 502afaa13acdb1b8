"""Write the plugin's ``references.json`` from this package's results and the paper's published values.

``xcheck references`` (:mod:`comparison.cli.references`) runs :func:`generate`:
the report's methods (:func:`comparison.report.plan.build_plan`: the macro
model, the associative LP by ``normal-ipm``, the iterated LP) on every paper case the
report runs them on, through the result cache, so that after ``xcheck report``
it only reads. Published values come from :mod:`comparison.domain.cases`.

Each cell's tolerance says how precisely its value is known, by one rule per source:
"""

from __future__ import annotations

import math
import os
from collections.abc import Iterator, Sequence
from pathlib import Path

from comparison.domain.cases import CASES, MODELS, PaperCase
from comparison.pytest_plugin.references import LOAD_FACTOR, Reference, References
from comparison.report.plan import build_plan
from comparison.runner import MACRO, Method, Record, Runner, code_version, prefetch
from comparison.runner.executor import LocalExecutor
from comparison.runner.fingerprint import versions_used
from comparison.runner.macro_record import MacroRecord
from comparison.utilities.outputs import write_text
from comparison.utilities.progress import NORMAL, Progress

#: Relative tolerance of the macro model's cells: its global search is within 6e-10 of a
#: 100,001-point brute force; 1e-6 leaves room for other platforms' floating point.
MACRO_RTOL = 1e-6
#: Absolute tolerance of the macro model's crack angle α_c in degrees: λ is flat at its minimum, so two searches
#: that agree on λ to 1e-9 can differ in α_c by 1e-4° (reference wall: 40.1473° by the grid-and-golden-section
#: search, 40.1474° by the Newton search).
MACRO_ANGLE_TOL = 1e-3
#: Relative tolerance of the associative LP's λ: ten times the largest disagreement measured
#: between the back ends (HiGHS IPM, HiGHS simplex, Clarabel, cvxpy) on the paper's walls (1.3e-6).
ASSOC_RTOL = 1e-5
#: The cell of the non-associative iterated LP's own λ (``load_factor`` is the value to quote: the lowest
#: certified collapse state).
ITERATED = "iterated_load_factor"
#: Relative tolerance of the iterated LP's λ and band: it returns one point of a band of exact
#: states, and the path to it moved λ by up to 0.25 % with another HiGHS interior point (IPX
#: against HiPO, reference wall) and 0.35 % under machine load (Set 14).
NONASSOC_RTOL = 5e-3

#: The reference methods' names for the published models of :data:`comparison.domain.cases.MODELS`.
PUBLISHED = {
    "proposed": "paper",
    "orduna_micro": "orduna-micro",
    "orduna_macro": "orduna-macro",
    "debuhan_defelice": "debuhan-defelice",
    "speranza": "speranza",
}
#: Published quantities and the cell names they are stored under.
QUANTITIES = {
    "lambda": LOAD_FACTOR,
    "alpha_c_deg": "alpha_c_deg",
    "alpha_ratio": "alpha_ratio",
    "hinge_storey": "hinge_storey",
}

__doc__ = (
    (__doc__ or "")
    + f"""
* macro: ``{MACRO_RTOL:g}`` relative (:data:`MACRO_RTOL`), α_c ``{MACRO_ANGLE_TOL:g}``° (:data:`MACRO_ANGLE_TOL`),
  the hinge storey exactly;
* micro-assoc: ``{ASSOC_RTOL:g}`` relative (:data:`ASSOC_RTOL`);
* micro-nonassoc: ``{NONASSOC_RTOL:g}`` relative (:data:`NONASSOC_RTOL`);
* published values: half a unit of the last decimal printed.
"""
)


#: What the paper's own λ is, in the source of its cells: Eq. (10)'s rocking minimum, which the paper does not
#: cap by f, whereas the ``macro`` cell ``load_factor`` is capped (Set 1: 0.519 against 0.4 = f).
PAPER_LAMBDA = "Eq. (10)'s lambda_r, not capped by f (compare the macro cell rocking_load_factor)"
#: The sources of the macro model's cells: its λ is capped by f and rigid overturning, λ_r is Eq. (10) alone.
MACRO_SOURCES = {
    LOAD_FACTOR: "macro-block model (xcheck): the least of Eq. (10)'s lambda_r, f and rigid overturning",
    "rocking_load_factor": "macro-block model (xcheck): Eq. (10)'s lambda_r alone, as the paper tabulates it",
}


def published_cells(c: PaperCase) -> Iterator[Reference]:
    """The values the paper publishes for ``c``."""
    for p in c.published:
        own = p.model == "proposed"
        what = f": {PAPER_LAMBDA}" if own and p.quantity == "lambda" else "" if own else f": {MODELS[p.model]}"
        yield Reference(
            c.label, PUBLISHED[p.model], QUANTITIES[p.quantity], p.value, p.rounding,
            f"Argiento et al. (2018), Table {p.table}{what}", "published",
        )  # fmt: skip


def _rel(value: float, rtol: float) -> float:
    return rtol * math.fabs(value)


def macro_cells(c: PaperCase, rec: Record) -> Iterator[Reference]:
    """The macro model's λ, λ_r, α_c and hinge on ``c``."""
    r = rec.result
    assert isinstance(r, MacroRecord)
    source = "macro-block model (xcheck), Eqs. (1)-(12)"
    for cell, said in MACRO_SOURCES.items():
        value = float(getattr(r, cell))
        yield Reference(c.label, "macro", cell, value, _rel(value, MACRO_RTOL), said, r.status)
    yield Reference(c.label, "macro", "alpha_c_deg", r.alpha_c_deg, MACRO_ANGLE_TOL, source, r.status)
    yield Reference(c.label, "macro", "hinge_storey", float(r.hinge_storey), 0.0, source, r.status)


def micro_cells(c: PaperCase, rec: Record) -> Iterator[Reference]:
    """A micro method's λ on ``c`` (with the mechanism band for the iterated LP), or why it has none."""
    method = rec.method
    nonassoc = rec.nonassoc
    rtol = NONASSOC_RTOL if method.kind == "micro-nonassoc" else ASSOC_RTOL
    if method.kind == "micro-assoc":
        source = f"associative LP ({method.solver}), bottom course {method.first_course}, {method.head_joints} heads"
    else:
        bond = f"scheme {method.scheme}, bottom course {method.first_course}, {method.head_joints} heads"
        quoted = "lowest certified collapse state" if nonassoc is not None and nonassoc.quoted == "lowest certified" \
            else "iterated LP"
        source = f"{quoted} (the value to quote), {bond}"
    status = rec.status if not rec.message or rec.result is not None else f"{rec.status}: {rec.message}"
    cells = {LOAD_FACTOR: (rec.load_factor, source)}
    if nonassoc is not None:  # the iterated LP's own fixed point and its mechanism's band beside it
        iterated = f"iterated LP's own fixed point, {bond}"
        cells[ITERATED] = (nonassoc.iterated_load_factor, iterated)
        if nonassoc.mechanism_band is not None:
            lo, hi = nonassoc.mechanism_band
            cells |= {"band_min": (lo, iterated), "band_max": (hi, iterated)}
    for cell, (value, said) in cells.items():
        ok = math.isfinite(value)
        yield Reference(
            c.label, method.kind, cell, value if ok else None, _rel(value, rtol) if ok else None, said, status
        )


def wall_cells(walls: Sequence[PaperCase], kinds: Sequence[str], cache_dir: Path | None) -> list[Reference]:
    """Reference cells computed now for walls that have no shipped ones (a user's walls).

    Args:
        walls: the walls.
        kinds: the methods, among :data:`~comparison.pytest_plugin.references.COMPUTABLE` (the micro
            ones with the shipped cells' settings).
        cache_dir: the result cache (``None``: none).
    """
    methods: dict[str, Method] = {m.kind: m for m in (MACRO, *build_plan().methods)}
    runner = Runner(cache_dir)
    cells: list[Reference] = []
    for w in walls:
        for kind in kinds:
            rec = runner.run(w.spec(), methods[kind])
            cells += macro_cells(w, rec) if kind == "macro" else micro_cells(w, rec)
    return cells


def generate(
    out: Path,
    *,
    cache_dir: Path | None,
    quick: bool = False,
    verbosity: int = NORMAL,
) -> References:
    """Compute (or read from the cache) every reference and write ``out``.

    Args:
        out: the JSON file to write.
        cache_dir: the result cache (``None``: compute in this process, keep nothing).
        quick: the micro model on the report's quick walls only (Table 7).
        verbosity: what the progress display shows (see :mod:`comparison.utilities.progress`).

    Returns:
        The references written.
    """
    plan = build_plan(quick)
    skips = {(it.spec, it.method): it.skip for it in plan.items()}
    pairs = [(c, m) for c in plan.cases for m in plan.methods]
    with Progress(verbosity) as progress:
        runner = Runner(cache_dir, progress.advance)
        if runner.cache is not None:
            runs = [(c.spec(), m) for c, m in pairs if not skips[(c.spec(), m)]]
            todo = [item for item in runs if item not in runner.cache]
            cached = len(runs) - len(todo)
            progress.say(f"plan: {len(runs)} micro computations: {cached} cached, {len(todo)} to compute")
            with LocalExecutor(os.cpu_count() or 1) as executor:
                runner.keep(prefetch(runner.cache, todo, executor, progress, cached=cached).unstored)
    cells: list[Reference] = []
    for c in CASES:
        cells += published_cells(c)
        cells += macro_cells(c, runner.run(c.spec(), MACRO))
    for c, m in pairs:
        skip = skips[(c.spec(), m)]
        rec = Record(c.label, m, 0.0, skipped="not_run", message=skip) if skip else runner.run(c.spec(), m)
        cells += micro_cells(c, rec)
    meta = {
        "generated_by": "xcheck references" + (" --quick" if quick else ""),
        "versions": versions_used(),
        "code_version": code_version(),
        "tolerances": {"macro": MACRO_RTOL, "micro-assoc": ASSOC_RTOL, "micro-nonassoc": NONASSOC_RTOL},
        "tolerance_rule": "tolerance = rtol * |value| (rtol by method, above); macro alpha_c_deg: "
        f"{MACRO_ANGLE_TOL:g} degrees; macro hinge storey: exact; published values: half a unit of the last "
        "printed decimal",
    }
    refs = References(cells, meta)
    write_text(out, refs.to_json())
    return refs
