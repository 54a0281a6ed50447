"""The ``fresnel-lut`` console command.

Ctrl-C at any moment, even while the modules load (0.1–0.4 s of imports), ends the command with exit
status 130 and one line, never a traceback; a closed pipe on standard output (``fresnel-lut … | head``)
ends it quietly. Everything else is :func:`preintegrate.cli.main`.
"""

from __future__ import annotations

import os
import sys

__all__ = ["main"]


def main() -> int:
    try:
        from .cli import main as run  # the imports themselves may be interrupted

        return run()
    except KeyboardInterrupt:
        print("\nfresnel-lut: interrupted; no file was written or replaced", file=sys.stderr)
        return 130
    except BrokenPipeError:  # the reader of standard output went away: stop without a message
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 1


if __name__ == "__main__":
    sys.exit(main())
