"""The iterated LP talks to HiGHS only through the persistent model of micro.backends."""

from __future__ import annotations

from pathlib import Path

import micro.nonassociative


def test_the_iterated_lp_never_touches_highspy() -> None:
    files = sorted(Path(micro.nonassociative.__file__).parent.glob("*.py"))
    assert len(files) >= 8
    for f in files:
        text = f.read_text()
        # neither the library nor the private HiGHS object of PersistentHighsModel
        assert "highspy" not in text and "_highs" not in text, f.name
