"""Cycle detection on synthetic sequences."""

from __future__ import annotations

import numpy as np

from micro.nonassociative import detect_cycle

#: Table 7 of the paper, micro column (Orduna): sets 11-14, single storey,
#: 12 rows, f = 0.75: (t, m, lambda).
TABLE7 = [(0.5, 1 / 3, 0.69), (1.0, 1 / 3, 0.68), (1.0, 1 / 2, 0.49), (1.0, 1.0, 0.26)]


def test_detect_cycle_synthetic() -> None:
    tol = 1e-6
    assert detect_cycle([0.5, 0.6, 0.5, 0.6], [1.0] * 4, tol, 10) == ("repeating", (0.5, 0.6))
    assert detect_cycle([0.5, 0.6, 0.7, 0.5, 0.6, 0.7], [1.0] * 6, tol, 10)[0] == "repeating"
    conv = [0.5 + 0.1 * 0.5**k for k in range(30)]
    assert detect_cycle(conv, [0.5**k for k in range(30)], tol, 10) is None
    rng = np.random.default_rng(0)
    noisy = list(0.5 + 0.01 * rng.random(30))
    assert detect_cycle(noisy, [1.0] * 30, tol, 10)[0] == "oscillating"
    flat = [0.5] * 30
    assert detect_cycle(flat, [0.1] * 30, tol, 10)[0] == "stagnation"
    assert detect_cycle(flat, [0.5**k for k in range(30)], tol, 10) is None
