"""The forged collapse state files of issue 54 through ``xcheck verify``: the exit code of each.

Run from the repository's root with the code to test first on the path::

    python docs/research/2026-11-29-state-forgeries.py            # this checkout
    PYTHONPATH=/path/to/old/checkout python docs/research/2026-11-29-state-forgeries.py

The genuine states are written by the code on the path (version 1 before issue 54, version 2 after; a
version-2 state is also tried as version 1 wrote it); the forgeries are the functions of
``tests/micro/state_forgeries.py``, the version-1 file of ``tests/micro/states/set12-v1.json`` as main
a21edb9 wrote it among them. Prints one row per forgery and file: the exit code, the version, the forgery,
and what ``verify`` said (the residuals that fail, or the malformed field).
"""

from __future__ import annotations

import dataclasses
import importlib.util
import json
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def _forgeries():  # type: ignore[no-untyped-def]
    spec = importlib.util.spec_from_file_location("state_forgeries", ROOT / "tests" / "micro" / "state_forgeries.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _state(wall, folder: Path, name: str, source: dict, solve=None) -> dict:  # type: ignore[no-untyped-def]
    import micro

    result = (solve or micro.solve_nonassociative)(wall)
    path = micro.write_state(result, folder / f"{name}.json", wall=wall, source=source)
    return json.loads(path.read_text())


def genuine(folder: Path) -> dict[str, dict]:
    """The genuine states the forgeries start from, written by the code on the path."""
    import micro
    try:
        from comparison.domain.wall import WallSpec
    except ImportError:  # main before issue 56 moved it
        from comparison.wall import WallSpec  # type: ignore[no-redef]

    def paper(t: float, m: float, f: float) -> tuple:  # type: ignore[type-arg]
        spec = WallSpec.from_paper(t=t, m=m, rows=12, f=f)
        return spec.to_micro(), {"wall": None, "paper_parameters": spec.paper_parameters(),
                                 "first_course": "full", "head_joints": "frictional"}

    set12, src12 = paper(1, 1 / 3, 0.75)
    set14, src14 = paper(1, 1, 0.75)
    soft, src_soft = paper(1, 1 / 3, 0.5)
    keep = set12.contact_kind != micro.geometry.HEAD
    columns = dataclasses.replace(set12, **{k: getattr(set12, k)[keep] for k in (
        "contact_a", "contact_b", "contact_kind", "normal", "px", "py", "mu")})
    return {
        "set12": _state(set12, folder, "set12", src12),
        "set14": _state(set14, folder, "set14", src14),
        "set12 at f 0.5": _state(soft, folder, "soft", src_soft),
        "set12 without head joints": _state(columns, folder, "columns", src12),
    }


def forged(states: dict[str, dict], fixture: dict) -> list[tuple[str, object]]:
    """``(name, document or text)`` of every forgery."""
    f = _forgeries()
    s12 = states["set12"]
    out: list[tuple[str, object]] = [
        ("live loads x 1.03, lambda / 1.03", f.live_scaled(s12)),
        ("a far block of 1e5 x 1e4, lambda 0.60", f.far_block(s12, load_factor=0.60)),
        ("a far block of dead load 1e12, every force zero, lambda 0.01",
         f.far_block(s12, load_factor=0.01, weight=1e12, zero_forces=True)),
        ("a vertex at x = 1e9 hiding a moment", f.bogus_vertex(s12)),
        ("every force x 1e-308, lambda 0.05", f.scaled_numbers(s12)),
        ("a rocking block's toe moved inward", f.toe_moved_inward(version=s12["version"])),
        ("dead loads halved, weights unchanged", f.dead_halved(s12)),
        ("Set 14's state labelled Set 12", f.relabelled(states["set14"], s12)),
        ("mu 0.5 contacts labelled f 0.75", f.friction_relabelled(states["set12 at f 0.5"], 0.75)),
        ("head-joint points deleted", f.relabelled(states["set12 without head joints"], s12)),
        ("a duplicate load_factor key", f.duplicate_key(s12)),
        ("the version-1 fixture: live loads x 1.03, lambda / 1.03", f.live_scaled(fixture)),
        ("the version-1 fixture: dead loads halved", f.dead_halved(fixture)),
        ("the version-1 fixture: a far block, lambda 0.60", f.far_block(fixture, load_factor=0.60)),
    ]
    if s12["version"] == 2:
        out += [(f"{name} (as version 1)", f.as_version_1(doc) if isinstance(doc, dict) else doc)
                for name, doc in out[:10] if isinstance(doc, dict) and doc.get("version") == 2]
    return out


def main() -> None:
    fixture = json.loads((ROOT / "tests" / "micro" / "states" / "set12-v1.json").read_text())
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        states = genuine(folder)
        for i, (name, doc) in enumerate(forged(states, fixture)):
            path = folder / f"forged-{i}.json"
            path.write_text(doc if isinstance(doc, str) else json.dumps(doc))
            run = subprocess.run([sys.executable, "-m", "comparison.cli", "verify", str(path), "--json"],
                                 capture_output=True, text=True, check=False)
            version = json.loads(path.read_text()).get("version") if not isinstance(doc, str) else "-"
            if run.returncode == 2:
                said = run.stderr.strip().replace(str(path), "FILE").split(": ", 2)[-1]
            else:
                failed = [r["name"] for r in json.loads(run.stdout)["residuals"] if not r["passed"]]
                said = ", ".join(failed) or "genuine"
            print(f"{run.returncode} | v{version} | {name} | {said[:110]}")


if __name__ == "__main__":
    main()
