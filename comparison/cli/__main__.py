"""``python -m comparison.cli``: the ``xcheck`` command without its console script."""

import sys

from comparison.cli import main

if __name__ == "__main__":
    code = main()
    # CPython keeps a record of a KeyboardInterrupt raised inside exec() of a string (dataclasses and
    # namedtuple build their methods so while the suite loads) even when it was handled, and a run by
    # ``python -m`` then ends by SIGINT (exit -2) instead of main's 130 (measured: 21 of 80 Ctrl-Cs while
    # loading); a string exec'd to its end clears the record. The console script exits before it is read.
    exec("pass")
    sys.exit(code)
