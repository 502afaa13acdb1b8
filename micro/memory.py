"""How much memory a wall's LP takes, and whether it fits before any array is built.

A wall is refused before it is built when the estimate of building and solving its LP
(:data:`BYTES_PER_BLOCK` a block) exceeds the memory the process may still use, so a
wall too large fails at once with one line instead of being killed by the kernel.
"""

from __future__ import annotations

import os

#: Rough memory footprint per block of building and solving the LP (bytes).
#: Measured: peak resident memory ~245 MB solving the 7,575-block wall with
#: Clarabel (~32 kB per block, ~100 MB of it interpreter and libraries);
#: doubled to leave room for cvxpy's canonicalisation copies.
BYTES_PER_BLOCK = 60_000


def available_memory_bytes() -> int | None:
    """Memory the process may still use, from ``/proc/meminfo`` (Linux).

    Returns:
        ``MemAvailable`` in bytes, or ``None`` when it cannot be read.
    """
    try:
        with open("/proc/meminfo", encoding="ascii") as fh:
            for line in fh:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    try:
        return int(os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"))
    except (ValueError, OSError, AttributeError):
        return None


def estimate_bytes(n_blocks: int) -> int:
    """Estimated peak memory of building and solving a wall of ``n_blocks``."""
    return int(n_blocks) * BYTES_PER_BLOCK


def guard_memory(n_blocks: int, max_bytes: int | None) -> None:
    """Refuse a wall whose estimated memory exceeds the budget (arithmetic only)."""
    need = estimate_bytes(n_blocks)
    budget = available_memory_bytes() if max_bytes is None else int(max_bytes)
    if budget is not None and need > budget:
        raise ValueError(
            f"wall too large: {n_blocks:,} blocks need an estimated {need / 1e9:.3g} GB "
            f"({need:,} bytes) but only {budget / 1e9:.3g} GB ({budget:,} bytes) are available"
        )
