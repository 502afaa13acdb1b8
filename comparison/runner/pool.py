"""Compute missing cache entries in parallel processes, largest walls first."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from concurrent.futures import ProcessPoolExecutor, as_completed
from pathlib import Path

from comparison.runner.methods import Method
from comparison.runner.runner import Runner
from comparison.wall import WallSpec


def _size(item: tuple[WallSpec, Method]) -> float:
    """Blocks of the wall, roughly: the order of the work."""
    spec = item[0]
    return spec.rows * spec.length / spec.block_length


def _compute_one(cache_dir: Path, spec: WallSpec, method: Method) -> str:
    lines: list[str] = []
    Runner(cache_dir, lines.append).run(spec, method)
    return lines[0] if lines else f"{spec.name}: {method.label}: cached"


def prefetch(
    cache_dir: Path,
    items: Sequence[tuple[WallSpec, Method]],
    workers: int,
    progress: Callable[[str], None] | None = None,
) -> int:
    """Compute the records of ``items`` into the cache at ``cache_dir`` in ``workers`` processes.

    The largest walls go first, so that the processes finish together.

    Returns:
        The number of computations.
    """
    if not items:
        return 0
    order = sorted(items, key=_size, reverse=True)
    with ProcessPoolExecutor(max_workers=workers) as pool:
        futures = [pool.submit(_compute_one, cache_dir, spec, method) for spec, method in order]
        for done, fut in enumerate(as_completed(futures), start=1):
            line = fut.result()
            if progress:
                progress(f"[{done}/{len(futures)}] {line}")
    return len(futures)
