"""``python -m comparison.cli``: the ``xcheck`` command without its console script."""

import sys

from comparison.cli import main

if __name__ == "__main__":
    sys.exit(main())
