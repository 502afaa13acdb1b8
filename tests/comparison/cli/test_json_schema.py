"""``--json`` output against its documented schema (``docs/schemas/*.schema.json``).

Every key the commands print must be in the schema (``additionalProperties`` /
``unevaluatedProperties`` are false), so a new or renamed key fails here until
the schema documents it; a failed analysis must carry ``load_factor: null``.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest

jsonschema = pytest.importorskip("jsonschema")

from comparison.cli import main  # noqa: E402

SCHEMAS = Path(__file__).parents[3] / "docs" / "schemas"
WALL = ["--t", "1", "--m", "1/3", "--rows", "12", "--f", "0.75"]  # Table 7, Set 12


def _validator(name: str) -> Any:
    schema = json.loads((SCHEMAS / f"{name}.schema.json").read_text())
    jsonschema.Draft202012Validator.check_schema(schema)
    return jsonschema.Draft202012Validator(schema)


def _run(argv: list[str], capsys: pytest.CaptureFixture[str]) -> tuple[int, dict[str, Any]]:
    rc = main(argv)
    return rc, json.loads(capsys.readouterr().out)


def _errors(validator: Any, doc: dict[str, Any]) -> list[str]:
    return [f"{'/'.join(map(str, e.absolute_path))}: {e.message}" for e in validator.iter_errors(doc)]


@pytest.mark.parametrize(
    "argv",
    [
        WALL,
        ["--t", "1", "--m", "1/3", "--rows", "60", "--f", "0.6", "--p", "2", "--storeys", "3"],  # Table 5, Set 3
        ["--scene", str(Path(__file__).parents[3] / "examples" / "three-storey.toml")],
    ],
    ids=["set12", "set3", "scene"],
)
def test_macro_json_matches_schema(argv: list[str], capsys: pytest.CaptureFixture[str]) -> None:
    rc, doc = _run(["macro", *argv, "--json"], capsys)
    assert rc == 0
    assert _errors(_validator("macro"), doc) == []


@pytest.mark.parametrize(
    ("argv", "rc_expected", "status"),
    [
        (["--friction", "associative", "--solver", "highs-ipm"], 0, "optimal"),
        (["--friction", "associative", "--solver", "clarabel", "--t", "0.5"], 0, "optimal"),
        (["--friction", "nonassociative"], 0, "converged"),
        (["--friction", "nonassociative", "--max-iterations", "2", "--tuning", "selection=vertex"], 1,
         "max_iterations"),
    ],
    ids=["assoc-highs", "assoc-clarabel-set11", "nonassoc", "nonassoc-failed"],
)
def test_micro_json_matches_schema(
    argv: list[str], rc_expected: int, status: str, capsys: pytest.CaptureFixture[str]
) -> None:
    rc, doc = _run(["micro", *WALL, *argv, "--json"], capsys)
    assert (rc, doc["status"]) == (rc_expected, status)
    assert _errors(_validator("micro"), doc) == []


def test_schema_refuses_undocumented_keys_and_numbers_on_failure(capsys: pytest.CaptureFixture[str]) -> None:
    """The schemas can fail: an extra key, and a number beside a failure status, are refused."""
    _, doc = _run(["micro", *WALL, "--friction", "nonassociative", "--max-iterations", "2", "--tuning",
                   "selection=vertex", "--json"], capsys)
    micro = _validator("micro")
    assert _errors(micro, {**doc, "undocumented": 1})
    assert _errors(micro, {**doc, "load_factor": 0.71})
    _, mdoc = _run(["macro", *WALL, "--json"], capsys)
    assert _errors(_validator("macro"), {**mdoc, "undocumented": 1})


CYCLING = ["--t", "0.5", "--m", "1/3", "--rows", "12", "--f", "0.4", "--tuning", "scheme=b",
           "--tuning", "certify=false", "--no-lowest"]


@pytest.mark.parametrize(
    ("argv", "status"),
    [
        ([*WALL, "--friction", "associative", "--time-limit", "1e-9"], "time_limit"),
        ([*WALL, "--friction", "associative", "--solver", "clarabel", "--time-limit", "1e-9"], "time_limit"),
        ([*WALL, "--friction", "nonassociative", "--time-limit", "1e-9"], "time_limit"),
        ([*WALL, "--friction", "nonassociative", "--max-iterations", "2", "--tuning", "selection=vertex",
          "--no-lowest"], "max_iterations"),
        ([*CYCLING, "--friction", "nonassociative"], "cycling"),
    ],
    ids=["assoc-time-limit", "assoc-clarabel-time-limit", "nonassoc-time-limit", "nonassoc-max-iterations",
         "nonassoc-cycling"],
)
def test_every_failure_status_matches_the_schema(
    argv: list[str], status: str, capsys: pytest.CaptureFixture[str]
) -> None:
    """A failed run's JSON validates against the schema: the contact states are the record's
    ``*_contacts`` keys alone (0 without a mechanism), so a pipeline validating its input does not reject
    exactly the failure records."""
    rc, doc = _run(["micro", *argv, "--json"], capsys)
    assert (rc, doc["status"], doc["load_factor"]) == (1, status, None)
    assert _errors(_validator("micro"), doc) == []
    assert "contact_states" not in doc
    assert all(isinstance(doc[f"{k}_contacts"], int) for k in ("closed", "opening", "sliding"))


def test_a_failed_nonassociative_run_carries_no_mechanism_band(capsys: pytest.CaptureFixture[str]) -> None:
    """A run whose certified state then fails the equilibrium check (``solver_failure``, exit 1) prints no
    ``mechanism_band``: the schema calls it the band of exact collapse states and refuses it beside any
    status but converged."""
    argv = ["micro", "--rows", "12", "--t", "1", "--m", "1/3", "--f", "10", "--p", "16666",
            "--friction", "nonassociative", "--json"]
    rc, doc = _run(argv, capsys)
    assert (rc, doc["status"], doc["stop_reason"]) == (1, "solver_failure", "equilibrium_residual")
    assert doc["load_factor"] is None and doc["mechanism_band"] is None
    assert _errors(_validator("micro"), doc) == []
    assert _errors(_validator("micro"), {**doc, "mechanism_band": [0.50001, 0.50002]})


def test_micro_json_names_the_wall_once(capsys: pytest.CaptureFixture[str]) -> None:
    """The wall is named once: its name or null (never ``""``), with its paper parameters as
    ``macro --json`` gives them, and the contact counts once."""
    _, doc = _run(["micro", *WALL, "--json"], capsys)
    _, mdoc = _run(["macro", *WALL, "--json"], capsys)
    assert doc["wall"] is None and doc["paper_parameters"] == mdoc["paper_parameters"]
    assert doc["paper_parameters"] == {"t": 1.0, "m": pytest.approx(1 / 3), "rows": 12, "storeys": 1, "p": 0.0,
                                       "p_storeys": [0.0], "f": 0.75}
    assert "contact_states" not in doc and doc["closed_contacts"] + doc["opening_contacts"] + doc[
        "sliding_contacts"] == doc["contacts"]
    _, sdoc = _run(["micro", "--scene", str(Path(__file__).parents[3] / "examples" / "three-storey.toml"),
                    "--json"], capsys)
    assert sdoc["wall"] == "three-storey example" and _errors(_validator("micro"), sdoc) == []


@pytest.mark.parametrize(
    ("argv", "rc_expected", "verdict"),
    [
        (["--rows", "12", "--t", "1", "--m", "1/2", "--f", "0.75"], 0, "unsafe"),  # Set 13, by a certified state
        (WALL, 0, "not refuted"),
        (["--storeys", "2", "--rows", "20", "--t", "1", "--m", "1/3", "--f", "0.75"], 0, "unsafe"),  # the bound
        ([*WALL, "--time-limit", "1e-9"], 1, None),  # every LP stopped: no verdict, no number
        (["--scene", str(Path(__file__).parents[3] / "examples" / "three-storey.toml")], 0, "unsafe"),  # by the bound
    ],
    ids=["set13", "set12", "bound", "failed", "scene"],
)
def test_compare_json_matches_schema(
    argv: list[str], rc_expected: int, verdict: str | None, capsys: pytest.CaptureFixture[str]
) -> None:
    rc, doc = _run(["compare", *argv, "--json"], capsys)
    assert (rc, doc["verdict"]) == (rc_expected, verdict)
    assert _errors(_validator("compare"), doc) == []


def test_compare_schema_refuses_a_verdict_without_its_proof(capsys: pytest.CaptureFixture[str]) -> None:
    """The schema can fail: an undocumented key, "unsafe" without a proof, a proof beside "not refuted", and a
    micro value where the non-associative solve did not run are refused."""
    _, doc = _run(["compare", *WALL, "--json"], capsys)
    v = _validator("compare")
    assert _errors(v, {**doc, "undocumented": 1})
    assert _errors(v, {**doc, "verdict": "unsafe"})
    assert _errors(v, {**doc, "proof": "certified state"})
    assert _errors(v, {**doc, "verdict": "safe", "proof": "global bound"})  # no closed global search
    assert _errors(v, {**doc, "nonassociative_status": None})


def test_the_committed_micro_schema_is_the_one_the_records_declare() -> None:
    """``docs/schemas/micro.schema.json`` is generated (``python -m comparison.cli.micro_schema``): its record
    keys from the records' field declarations, so a field added to a record fails here until the file is
    rewritten, and a hand edit of the file fails too."""
    from comparison.cli import micro_schema

    assert (SCHEMAS / "micro.schema.json").read_text(encoding="utf-8") == micro_schema.render(), (
        "docs/schemas/micro.schema.json is stale: run python -m comparison.cli.micro_schema")


def test_the_schema_writer_refuses_a_root_without_the_schemas_folder(tmp_path: Path,
                                                                     capsys: pytest.CaptureFixture[str]) -> None:
    """``python -m comparison.cli.micro_schema ROOT`` writes ``ROOT/docs/schemas/micro.schema.json``; a root
    without that folder is one line naming it and exit 2, nothing written."""
    from comparison.cli import micro_schema

    assert micro_schema.main([str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "docs/schemas is not a folder" in err and not any(tmp_path.iterdir())
    (tmp_path / "docs" / "schemas").mkdir(parents=True)
    assert micro_schema.main([str(tmp_path)]) == 0
    assert (tmp_path / micro_schema.PATH).read_text(encoding="utf-8") == micro_schema.render()
