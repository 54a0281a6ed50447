"""The ``fresnel-lut`` console command.

Public objects: ``main``.

Ctrl-C at any moment ends the command with exit status 130 and one line, never a traceback. While the
modules load (0.1–0.4 s) the interrupt is held until they are loaded — an interrupt inside a C extension's
import (numpy's) would otherwise surface as a misleading ImportError — then honoured at once; a module
loaded later, on first use (scipy), is covered by recognising such an ImportError by its cause. A closed pipe
on standard output (``fresnel-lut … | head``) ends the command quietly. Before numpy loads, its and OpenBLAS'
kernels are pinned (:mod:`fresnel_lut.kernels`) so that the files the command writes are the same bytes on every
x86-64 machine. Everything else is :func:`fresnel_lut.cli.main`.
"""

from __future__ import annotations

import sys

__all__ = ["main"]

INTERRUPTED = "\nfresnel-lut: interrupted; no file was written or replaced"

try:  # Ctrl-C while this module's own imports load (the signal module itself takes ~10 ms on a busy machine)
    import os
    import signal

    from .kernels import pin_numeric_kernels
except KeyboardInterrupt:
    print(INTERRUPTED, file=sys.stderr)
    raise SystemExit(130) from None


def main() -> int:
    pin_numeric_kernels()
    held: list[int] = []
    previous = signal.getsignal(signal.SIGINT)
    if previous is signal.default_int_handler:  # not when the shell made us ignore Ctrl-C (a background job)
        signal.signal(signal.SIGINT, lambda number, frame: held.append(number))
    try:
        from .cli import main as run
    finally:
        signal.signal(signal.SIGINT, previous)
    if held:
        print(INTERRUPTED, file=sys.stderr)
        return 130
    try:
        return run()
    except KeyboardInterrupt:
        print(INTERRUPTED, file=sys.stderr)
        return 130
    except ImportError as error:  # a module loaded later (scipy, on first use): Ctrl-C inside its C extension
        if not _caused_by_interrupt(error):
            raise
        print(INTERRUPTED, file=sys.stderr)
        return 130
    except BrokenPipeError:  # the reader of standard output went away: stop without a message
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 1


def _caused_by_interrupt(error: BaseException) -> bool:
    """Whether a KeyboardInterrupt is in the chain of causes of ``error`` (pybind11 and Cython module
    initialisation turn it into ``ImportError: initialization failed``)."""
    seen = set()
    while error is not None and id(error) not in seen:
        if isinstance(error, KeyboardInterrupt):
            return True
        seen.add(id(error))
        error = error.__cause__ or error.__context__
    return False


if __name__ == "__main__":
    sys.exit(main())
