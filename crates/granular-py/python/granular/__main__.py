"""``python -m granular ARGS`` runs the same commands as the ``granular`` binary (run, check, sweep,
resume, plot, compare, reproduce, bench)."""

import sys

from . import main

if __name__ == "__main__":
    sys.exit(main())
