"""Input files are regular files, refused at once otherwise (comparison/utilities/inputs.py)."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from comparison.utilities.inputs import read_input_file


def test_a_regular_file_is_read_whole_or_up_to_one_byte_past_the_limit(tmp_path: Path) -> None:
    f = tmp_path / "scene.toml"
    f.write_bytes(b"0123456789")
    assert read_input_file(f) == b"0123456789"
    assert read_input_file(f, max_bytes=4) == b"01234"


@pytest.mark.parametrize(
    ("make", "kind"),
    [("fifo", "a named pipe"), ("dir", "a directory"), ("/dev/zero", "a character device")],
)
def test_anything_but_a_regular_file_is_refused_with_what_it_is(tmp_path: Path, make: str, kind: str) -> None:
    """A named pipe blocked ``open()`` forever (it waits for a writer); /dev/zero never ends."""
    if make == "fifo":
        path = tmp_path / "p"
        os.mkfifo(path)
    elif make == "dir":
        path = tmp_path
    else:
        path = Path(make)
        if not path.exists():  # pragma: no cover - no /dev/zero
            pytest.skip("no /dev/zero")
    with pytest.raises(OSError, match=f"not a regular file: {kind}") as info:
        read_input_file(path)
    assert info.value.filename == str(path)


def test_a_missing_file_is_the_usual_os_error(tmp_path: Path) -> None:
    with pytest.raises(FileNotFoundError):
        read_input_file(tmp_path / "missing.toml")
