"""Fingerprints of built walls, for the bit-identity test of the builder.

``whole_walls.json`` holds the SHA-256 (first 16 hex digits) of every array
of the walls listed by :func:`whole_wall_cases`, as built by the builder that
refused lengths that are not a whole number of half blocks (commit e49e1ae,
before cut end blocks). Regenerate it only on purpose::

    python tests/micro/wall_fingerprints.py > tests/micro/whole_walls.json
"""

from __future__ import annotations

import hashlib
import itertools
import json
from collections.abc import Iterator
from typing import Any

import numpy as np

import micro

#: The arrays of a :class:`micro.BlockWall` that a fingerprint covers.
ARRAYS = ("x0", "x1", "y0", "y1", "course", "storey", "dead", "live", "contact_a", "contact_b", "contact_kind",
          "normal", "px", "py", "mu")


def fingerprint(wall: micro.BlockWall) -> str:
    """SHA-256 (16 hex digits) of the names, dtypes, shapes and bytes of :data:`ARRAYS`."""
    h = hashlib.sha256()
    for name in ARRAYS:
        a = np.ascontiguousarray(getattr(wall, name))
        h.update(f"{name} {a.dtype} {a.shape}".encode())
        h.update(a.tobytes())
    return h.hexdigest()[:16]


def whole_wall_cases() -> Iterator[tuple[str, dict[str, Any]]]:
    """Walls whose length is a whole number of half blocks: small synthetic
    walls of 1-15 half blocks and the paper's walls (but Set 8), both bonds."""
    from comparison.domain.cases import CASES

    for n_half, rows, first, heads, bl in itertools.product(
        range(1, 16), [(1,), (3,), (2, 3), (1, 2, 2)], ["full", "half"], ["frictional", "frictionless"], [1.0, 3.0]
    ):
        ns = len(rows)
        kw = dict(length=0.5 * bl * n_half, block_length=bl, block_height=0.4, rows=rows,
                  thickness=tuple(0.2 + 0.1 * i for i in range(ns)), overload=tuple(1.5 * i for i in range(ns)),
                  unit_weight=18.0, friction=0.6, first_course=first, head_joints=heads)
        yield f"n{n_half} r{'-'.join(map(str, rows))} {first} {heads} l{bl:g}", kw
    for case in CASES:
        if case.case == "8":
            continue
        s = case.spec()
        for first in ("full", "half"):
            kw = dict(length=s.length, block_length=s.block_length, block_height=s.block_height,
                      rows=tuple(x.rows for x in s.storeys), thickness=tuple(x.thickness for x in s.storeys),
                      overload=tuple(x.overload for x in s.storeys), unit_weight=s.unit_weight,
                      friction=s.friction, first_course=first)
            yield f"{case.label} {first}", kw


if __name__ == "__main__":
    table = {key: fingerprint(micro.build_wall(**kw)) for key, kw in whole_wall_cases()}
    print(json.dumps(table, indent=0))
