"""Arithmetic whose result does not depend on the BLAS library, its kernel or the CPU.

numpy's ``a @ b`` of two float vectors is BLAS's ``ddot``, whose kernels sum in
different orders: the same product comes out with other last bits under
OpenBLAS's Prescott, Haswell and SkylakeX kernels, and so on another machine.
Where such a number decides the path of a computation (a mechanism normalised
to unit live-load work, then read as "this rate is zero" against a fraction of
the largest) the path must not depend on it. :func:`exact_dot` rounds the exact
sum of the (correctly rounded) products once: the same float everywhere.
Sparse products (scipy's own loops) and numpy's reductions of elementwise
products (its pairwise sum) need no such care; BLAS-backed factorisations do
(SuperLU, CHOLMOD's supernodal code): see
the research page on the BLAS-independent descent (``docs/research/``).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike


def exact_dot(a: ArrayLike, b: ArrayLike) -> float:
    """``sum_i a_i b_i``: the products rounded once each, their sum exactly
    rounded (``math.fsum``), so the result does not depend on the BLAS kernel."""
    return math.fsum(np.multiply(a, b, dtype=float).ravel().tolist())
