"""``python -m granular ARGS`` runs the same commands as the ``granular`` binary (run, check, sweep,
resume, plot, compare, reproduce, bench)."""

import signal
import sys

from . import main


def run() -> int:
    """The ``granular`` program: Ctrl-C ends it at once, as it ends the binary (the default signal action)."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)
    return main()


if __name__ == "__main__":
    sys.exit(run())
