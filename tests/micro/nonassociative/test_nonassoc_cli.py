"""xcheck micro --friction nonassociative."""

from __future__ import annotations

import json

import pytest

from comparison.cli import main

#: Table 7 of the paper, micro column (Orduna): sets 11-14, single storey,
#: 12 rows, f = 0.75: (t, m, lambda).
TABLE7 = [(0.5, 1 / 3, 0.69), (1.0, 1 / 3, 0.68), (1.0, 1 / 2, 0.49), (1.0, 1.0, 0.26)]


def test_cli_json(capsys: pytest.CaptureFixture[str]) -> None:
    code = main(["micro", "--t", "1", "--m", "1/3", "--rows", "12", "--f", "0.75",
                 "--friction", "nonassociative", "--json"])
    out = json.loads(capsys.readouterr().out)
    assert code == 0
    for key in ("iterations", "converged", "status", "history", "load_factor", "lambda_band"):
        assert key in out
    assert out["converged"] is True and out["status"] == "converged"
    assert out["history"][0]["iteration"] == 0
    assert len(out["history"]) == out["iterations"] + 1
    assert abs(out["load_factor"] / 0.68 - 1) <= 0.05


def test_cli_json_load_factor_is_the_value_to_quote(capsys: pytest.CaptureFixture[str]) -> None:
    """``load_factor`` means the value to quote in the JSON, on the Python result, in its record and in the
    plugin's references (Set 12, 54 blocks: the lowest certified state 0.6911, below the iterated LP's
    0.7086, which is ``iterated_load_factor`` beside it); each direction's entry is of the same kind."""
    import micro
    from comparison.domain.wall import WallSpec
    from comparison.pytest_plugin import References

    assert main(["micro", "--t", "1", "--m", "1/3", "--rows", "12", "--f", "0.75", "--friction",
                 "nonassociative", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    result = micro.solve_nonassociative(WallSpec.from_paper(t=1, m=1 / 3, rows=12, f=0.75).to_micro())
    rec = result.to_record()
    assert out["blocks"] == 54 and out["quoted"] == result.quoted == rec.quoted == "lowest certified"
    assert out["load_factor"] == result.load_factor == rec.load_factor == result.lowest_load_factor
    assert out["iterated_load_factor"] == result.iterated_load_factor == rec.iterated_load_factor
    assert out["load_factor"] < out["iterated_load_factor"] * (1 - 1e-3)  # two different numbers
    assert "quoted_load_factor" not in out and "quoted_load_factor" not in rec
    refs = References.load()
    for key, cell in (("load_factor", "load_factor"), ("iterated_load_factor", "iterated_load_factor")):
        assert out[key] == pytest.approx(refs.get("Set 12", "micro-nonassoc", cell).value, rel=1e-6)
    by_direction = out["directions"]["+x"]
    assert (by_direction["load_factor"], by_direction["iterated_load_factor"]) == (
        out["load_factor"], out["iterated_load_factor"])
    assert out["load_factor_plus"] == out["load_factor"] and out["load_factor_minus"] is None  # mirror-symmetric


def test_cli_plot(tmp_path, capsys: pytest.CaptureFixture[str]) -> None:  # type: ignore[no-untyped-def]
    png = tmp_path / "mech.png"
    code = main(["micro", "--t", "1", "--m", "1/3", "--rows", "12", "--f", "0.75",
                 "--friction", "nonassociative", "--plot", str(png), "--json"])
    out = json.loads(capsys.readouterr().out)
    assert code == 0 and out["plot"] == str(png)
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_cli_cycling_exit_code(capsys: pytest.CaptureFixture[str]) -> None:
    code = main(["micro", "--t", "1", "--m", "1", "--rows", "12", "--f", "0.75",
                 "--friction", "nonassociative", "--tuning", "relaxation=1", "--tuning", "certify=false",
                 "--tuning", "selection=vertex", "--json"])
    out = json.loads(capsys.readouterr().out)
    assert code == 1
    assert out["converged"] is False and out["status"] == "cycling" and out["load_factor"] is None


@pytest.mark.parametrize(("extra", "word"), [
    (["--tuning", "scheme=c"], "--tuning scheme"), (["--tuning", "relaxation=0"], "--tuning relaxation"),
    (["--tuning", "relaxation=x"], "--tuning relaxation"), (["--max-iterations", "x"], "--max-iterations"),
    (["--solver", "clarabel"], "--solver"), (["--global", "--node-limit", "0"], "--node-limit"),
    (["--tuning", "selection=closest"], "--tuning selection"),
    (["--tuning", "selection=proximal", "--tuning", "scheme=b"], "--tuning selection"),
    (["--tuning", "selection=vertex+proximal", "--tuning", "scheme=b"], "--tuning selection"),
    (["--tuning", "continuation=true", "--tuning", "scheme=b"], "--tuning continuation"),
    (["--tuning", "continuation=true", "--tuning", "selection=proximal"], "--tuning continuation"),
    (["--tuning", "certify=maybe"], "--tuning certify"), (["--tuning", "certify"], "--tuning"),
    (["--tuning", "colour=red"], "--tuning colour: unknown knob; the knobs are scheme, selection"),
])
def test_cli_bad_options(extra: list[str], word: str, capsys: pytest.CaptureFixture[str]) -> None:
    code = main(["micro", "--t", "1", "--m", "1/3", "--rows", "6", "--f", "0.75",
                 "--friction", "nonassociative", *extra])
    assert code == 2
    err = capsys.readouterr().err
    assert err.startswith(f"xcheck: error: {word}") and err.count("\n") == 1, err


def test_cli_help_shows_the_everyday_options_only(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["micro", "--help"]) == 0
    out = capsys.readouterr().out
    options = [line for line in out.splitlines() if line.lstrip().startswith("-")]
    # 24: the wall (its end treatment --ends among them), the method, its budgets and the outputs (--json,
    # --plot, --state); research knobs are behind --tuning
    assert len(options) <= 24, options
    for knob in ("--scheme", "--selection", "--relaxation", "--no-certify", "--fuse", "--continuation"):
        assert knob not in out
    assert "--tuning KEY=VALUE" in out


def test_cli_verbose_streams_one_line_per_lp(capsys: pytest.CaptureFixture[str]) -> None:
    """``-v`` writes one line per LP on stderr as it happens (here not a terminal), the iterated
    LP's and the descent's, each with the direction, the LP, lambda, the step, the algorithm, seconds."""
    code = main(["micro", "--t", "1", "--m", "1/3", "--rows", "12", "--f", "0.75", "--friction", "nonassociative",
                 "-v", "--json"])
    captured = capsys.readouterr()
    rec = json.loads(captured.out)
    lines = captured.err.splitlines()
    assert code == 0
    iterated = [line for line in lines if " vertex LP " in line]
    lowest = [line for line in lines if " lowest LP " in line]
    assert len(iterated) == len(rec["history"]) and len(lowest) == rec["lowest_lps"]
    assert iterated[0].startswith("  +x vertex LP 0: lambda 0.712047, step -, clarabel, ")
    assert iterated[1].startswith("  +x vertex LP 1: lambda ") and "e-0" in iterated[1]
    assert all(line.endswith(" s") for line in lines)


def test_cli_vertex_then_proximal(capsys: pytest.CaptureFixture[str]) -> None:
    """``--tuning selection=vertex+proximal`` says that the proximal sequence ran and how the vertex one ended;
    the JSON record carries the same."""
    args = ["micro", "--t", "1", "--m", "1/3", "--rows", "12", "--f", "0.75", "--friction", "nonassociative",
            "--tuning", "selection=vertex+proximal", "--tuning", "retry_iterations=4", "--max-iterations", "4",
            "--no-lowest"]
    assert main(args) == 0
    out = capsys.readouterr().out
    assert "(certified)" in out
    assert "proximal sequence (" in out and "after the vertex sequence ended max_iterations (4 LPs, lambda in [" in out
    assert main([*args, "--json"]) == 0
    rec = json.loads(capsys.readouterr().out)
    assert rec["selection"] == "proximal" and rec["vertex_stop_reason"] == "max_iterations"
    assert rec["options"]["selection"] == "vertex+proximal" and len(rec["vertex_lambda_band"]) == 2


def test_cli_global_node_limit(capsys: pytest.CaptureFixture[str]) -> None:
    """A node-limited search (5 blocks): the lowest state, the bound and the gap, flat JSON keys."""
    code = main(["micro", "--t", "1", "--m", "1", "--rows", "2", "--f", "0.6", "--friction", "nonassociative",
                 "--global", "--node-limit", "5", "--json"])
    out = json.loads(capsys.readouterr().out)
    assert code == 0
    assert out["lowest_load_factor"] == pytest.approx(0.5, rel=1e-9)
    assert out["lowest_load_factor"] == out["load_factor"] <= out["iterated_load_factor"]
    assert out["global_status"] in ("node_limit", "optimal") and out["global_nodes"] >= 1
    assert out["global_lower_bound"] <= out["global_load_factor"] <= out["lowest_load_factor"] * (1 + 1e-7)


def test_cli_fuse_and_continuation(capsys: pytest.CaptureFixture[str]) -> None:
    """``--tuning fuse=true --tuning continuation=true`` runs both and says how the wall was fused."""
    code = main(["micro", "--t", "1", "--m", "1/3", "--rows", "12", "--f", "0.75", "--friction", "nonassociative",
                 "--tuning", "fuse=true", "--tuning", "continuation=true", "--no-lowest", "--json"])
    out = json.loads(capsys.readouterr().out)
    assert code == 0 and out["converged"] is True
    assert out["fused_bodies"] > 0 and out["fused_points"] > 0 and len(out["history"]) > 32


def test_cli_no_fused_retry(capsys: pytest.CaptureFixture[str]) -> None:
    """``--tuning fused_retry=false`` reaches the tuning (on by default); a run that
    needs no retry has no unfused attempt to report."""
    args = ["micro", "--t", "1", "--m", "1/3", "--rows", "12", "--f", "0.75", "--friction", "nonassociative",
            "--no-lowest", "--json"]
    for extra, on in (([], True), (["--tuning", "fused_retry=false"], False)):
        assert main([*args, *extra]) == 0
        out = json.loads(capsys.readouterr().out)
        assert out["options"]["fused_retry"] is on and out["unfused_stop_reason"] == ""


@pytest.mark.parametrize("flags, runs", [([], True), (["--lowest", "off"], False), (["--no-lowest"], False),
                                         (["--lowest", "on"], True), (["--lowest", "40"], True)])
def test_cli_lowest_on_off(flags: list[str], runs: bool, capsys: pytest.CaptureFixture[str]) -> None:
    """``--lowest on`` (the default, on every wall) or ``N`` (a budget of N LPs) descends, ``off`` (or the old
    ``--no-lowest``) does not; the value to quote is the lowest state where it ran, the iterated LP's else."""
    code = main(["micro", "--t", "1", "--m", "1/3", "--rows", "12", "--f", "0.75", "--friction", "nonassociative",
                 "--json", *flags])
    out = json.loads(capsys.readouterr().out)
    assert code == 0 and (out["lowest_load_factor"] is not None) is runs
    assert (out["lowest_status"] == "found") is runs
    assert out["load_factor"] == (out["lowest_load_factor"] if runs else out["iterated_load_factor"])
    assert out["quoted"] == ("lowest certified" if runs else "iterated")
    assert list(out)[:3] == ["load_factor", "quoted", "iterated_load_factor"]  # the value to quote leads
    if flags == ["--lowest", "40"]:
        assert [d["budget"] for d in out["lowest"]] == [40]


def test_cli_leads_with_the_lowest_certified_state(capsys: pytest.CaptureFixture[str]) -> None:
    """The words' first line, ``-q`` and the plot title give the lowest certified state (Set 12: 0.691108,
    below the iterated LP's 0.708622), the iterated value beside it; a descent stopped by ``--lowest N``
    says so in the first line."""
    args = ["micro", "--t", "1", "--m", "1/3", "--rows", "12", "--f", "0.75", "--friction", "nonassociative"]
    assert main([*args, "-q"]) == 0
    assert capsys.readouterr().out.strip() == "0.691108"
    assert main(args) == 0
    out = capsys.readouterr().out
    first, second = out.splitlines()[:2]
    assert "nan" not in out  # a certified state's warm/cold difference is a number or absent, never nan
    assert first.startswith("lambda = 0.691108 (+x): the lowest certified collapse state") and "finished" in first
    assert "iterated LP" in second and "lambda = 0.708622" in second and "[0.694899, 0.710055]" in second
    assert main([*args, "--lowest", "3"]) == 0
    first = capsys.readouterr().out.splitlines()[0]
    assert "the lowest certified collapse state" in first and "spent its budget of 3 LPs" in first
    assert "not finished" in first and "--lowest N raises it" in first


def test_cli_plot_title_leads_with_the_lowest_certified_state(tmp_path, monkeypatch: pytest.MonkeyPatch,
                                                              capsys: pytest.CaptureFixture[str]) -> None:
    import micro.plot

    titles: list[str] = []
    monkeypatch.setattr(micro.plot, "plot_velocities", lambda *a, title, **k: titles.append(title))
    assert main(["micro", "--t", "1", "--m", "1/3", "--rows", "12", "--f", "0.75", "--friction", "nonassociative",
                 "--plot", str(tmp_path / "m.png")]) == 0
    capsys.readouterr()
    assert titles == ["non-associative micro λ = 0.6911 (lowest certified; iterated LP 0.7086), +x, 54 blocks"]


def test_cli_lowest_bad_choice(capsys: pytest.CaptureFixture[str]) -> None:
    code = main(["micro", "--rows", "12", "--t", "1", "--m", "1/3", "--f", "0.75", "--friction", "nonassociative",
                 "--lowest", "sometimes"])
    err = capsys.readouterr().err
    assert code == 2 and "--lowest" in err and len(err.strip().splitlines()) == 1


def test_cli_says_when_the_descent_was_not_run(capsys: pytest.CaptureFixture[str]) -> None:
    """With ``--lowest off`` the first line gives the iterated LP's state and says why it is not the lowest."""
    args = ["micro", "--t", "1", "--m", "1/3", "--rows", "12", "--f", "0.75", "--friction", "nonassociative"]
    assert main([*args, "--lowest", "off"]) == 0
    first = capsys.readouterr().out.splitlines()[0]
    assert first == ("lambda = 0.708622 (+x): the iterated LP's collapse state, non-associative friction; the "
                     "lowest certified state was not searched (--lowest off)")
