"""The report's "How to reproduce" section: the commands and the versions the numbers were computed under.

The machine is named in ``timings.md`` (:mod:`comparison.report.timings`), apart from the results.
"""

from __future__ import annotations

import os
import platform
from collections.abc import Mapping
from typing import Any

from comparison.runner.fingerprint import code_version, versions_used


def machine() -> str:
    """The machine in one line: OS, architecture, CPUs."""
    return f"{platform.system()} {platform.release()} on {platform.machine()}, {os.cpu_count()} CPUs"


def how_to_reproduce(meta: Mapping[str, Any]) -> str:
    """The section's markdown for a report run with ``meta`` (``quick``)."""
    quick = " --quick" if meta.get("quick") else ""
    versions = ", ".join(f"{k} {v}" for k, v in versions_used().items())
    return f"""\
From a clone of the repository:

```sh
python3 -m venv .venv && .venv/bin/pip install -e .
.venv/bin/xcheck report{quick} --out reports          # this report (cached results are reused)
.venv/bin/xcheck stability --out reports          # stability.md: the iterated LP over 120 walls
.venv/bin/xcheck stability --table7 --out reports # table7_nonassoc.md: Table 7 per bond variant
.venv/bin/xcheck references --out comparison/pytest_plugin/references.json   # the plugin's references
```

`--no-cache` recomputes everything (the cache: [docs/cli.md](../docs/cli.md#the-report-command-and-its-cache)).
Versions of this run (part of every result's cache key, so a result read from the cache was computed
under them too): {versions}; code fingerprint {code_version()}.
The machine and the run times are in [timings.md](timings.md). Every number in the tables is
independent of the machine but for the timings: the iterated LP decides on iteration and LP counts,
never on seconds.
"""
