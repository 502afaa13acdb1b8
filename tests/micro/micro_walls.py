"""Walls shared by the micro-model tests and benchmarks."""

from __future__ import annotations

import micro
from comparison.domain.wall import WallSpec

#: Table 7 of the paper: single storey, 12 rows, f = 0.75; (t, m) and
#: Orduna's non-associative micro-model load factors.
TABLE7 = {
    "set11": (0.5, 1 / 3, 0.69),
    "set12": (1.0, 1 / 3, 0.68),
    "set13": (1.0, 1 / 2, 0.49),
    "set14": (1.0, 1.0, 0.26),
}


def table7_wall(name: str, **options: object) -> micro.BlockWall:
    t, m, _ = TABLE7[name]
    return WallSpec.from_paper(t=t, m=m, rows=12, f=0.75).to_micro(**options)


def three_storey_wall(**options: object) -> micro.BlockWall:
    """A small three-storey wall with floor loads and unequal storeys."""
    return micro.build_wall(
        length=6.75, block_length=1.5, block_height=0.5, rows=(3, 4, 5), thickness=(0.3, 0.4, 0.5),
        overload=(0.0, 2.0, 3.0), unit_weight=18.0, friction=0.6, **options,
    )
