"""Run the models on walls, with results cached on disk.

* :mod:`~comparison.runner.methods`: :class:`Method` (macro, associative and
  non-associative micro LPs, with their options);
* :mod:`~comparison.runner.records`: :class:`Record`, one method's typed result
  on one wall;
* :mod:`~comparison.runner.cache`: :class:`ResultCache`, the on-disk cache, and
  where it lives by default (:func:`default_cache_dir`);
* :mod:`~comparison.runner.fingerprint`: :func:`code_version`, what a
  computation runs (the modules it imports, the packages' versions), the code
  part of the cache key;
* :mod:`~comparison.runner.executor`: local processes or a Dask cluster behind
  one interface (largest first, memory-bounded, interrupt-safe);
* :mod:`~comparison.runner.pool`: :func:`prefetch`, missing entries computed on
  an executor and stored as they arrive;
* :mod:`~comparison.runner.runner`: :func:`compute` and the caching :class:`Runner`.
"""

from comparison.runner.cache import ResultCache, default_cache_dir
from comparison.runner.fingerprint import code_version
from comparison.runner.methods import (
    MACRO,
    MICRO_ASSOC,
    MICRO_NONASSOC,
    NONASSOC_MAX_LPS,
    NONASSOC_RETRY_LPS,
    Method,
)
from comparison.runner.pool import Prefetched, approximate_blocks, prefetch
from comparison.runner.records import MechanismRecord, Record
from comparison.runner.runner import Runner, compute

__all__ = [
    "MACRO",
    "MICRO_ASSOC",
    "MICRO_NONASSOC",
    "NONASSOC_MAX_LPS",
    "NONASSOC_RETRY_LPS",
    "MechanismRecord",
    "Method",
    "Prefetched",
    "Record",
    "ResultCache",
    "Runner",
    "approximate_blocks",
    "code_version",
    "compute",
    "default_cache_dir",
    "prefetch",
]
