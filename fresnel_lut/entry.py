"""The ``fresnel-lut`` console command.

Public objects: ``console`` (the installed command), ``main``, ``GRACE``.

Ctrl-C at any moment ends the command with exit status 130 and one line, never a traceback. While the
modules load (0.1–0.4 s) the interrupt is held until they are loaded — an interrupt inside a C extension's
import (numpy's) would otherwise surface as a misleading ImportError — then honoured at once; a module
loaded later, on first use (scipy, matplotlib), is covered by recognising any error caused by the interrupt (an
``ImportError: initialization failed``, importlib's ``RuntimeError: cannot release un-acquired lock``). Where a
library swallows the KeyboardInterrupt (a bare ``except:`` around an optional import), a watchdog started by the
first Ctrl-C ends the process after :data:`GRACE` seconds with the same line and status; what a write left
half done is what a kill leaves, which the next writer finishes (:mod:`basis.storage`). A closed pipe
on standard output (``fresnel-lut … | head``) ends the command quietly. Once the command's outcome is known, the
installed command ignores Ctrl-C to its exit (:func:`main`'s ``final``), where an interrupt could only print a
traceback after the command's last line. Before numpy loads, its and OpenBLAS'
kernels are pinned (:mod:`fresnel_lut.kernels`) so that the files the command writes are the same bytes on every
x86-64 machine. Everything else is :func:`fresnel_lut.cli.main`.
"""

from __future__ import annotations

import sys

from .interrupts import INTERRUPTED, caused_by_interrupt  # standard library only: loaded before numpy

__all__ = ["GRACE", "console", "main"]

#: Seconds between Ctrl-C and the watchdog's exit, where the interrupt did not end the command by itself.
GRACE = 1.0

try:  # Ctrl-C while this module's own imports load (the signal module itself takes ~10 ms on a busy machine)
    import os
    import signal
    import threading
    import time

    from .kernels import pin_numeric_kernels
except KeyboardInterrupt:
    print(INTERRUPTED, file=sys.stderr)
    raise SystemExit(130) from None


def main(final: bool = False) -> int:
    """The command (:func:`fresnel_lut.cli.main`) under the guard of the module docstring; its exit status. With
    ``final`` (the installed command, whose process ends when this returns: :func:`console`) Ctrl-C is ignored from
    the moment the command's outcome is known, so that nothing between it and the exit prints a traceback; for
    in-process callers (the tests) a later Ctrl-C still raises KeyboardInterrupt."""
    held: list[int] = []
    reported = threading.Event()
    try:  # one guard from the first line: a Ctrl-C between any two steps below ends with the one line, not a traceback
        previous = signal.getsignal(signal.SIGINT)
        holding = previous is signal.default_int_handler  # not when the shell made us ignore Ctrl-C (a background job)
        if holding:
            signal.signal(signal.SIGINT, lambda number, frame: held.append(number))
        try:
            pin_numeric_kernels()  # reads /proc/cpuinfo, whose codec loads on first use: held like the imports
            from .cli import main as run
        finally:  # from holding the interrupt straight to honouring it, with no moment under Python's own handler
            signal.signal(signal.SIGINT, _interrupt_handler(reported) if holding else previous)
        if held:
            raise KeyboardInterrupt
        status = run()
        _settled(final)  # a Ctrl-C before this line is still the guard's: the one line and 130
    except BrokenPipeError:  # the reader of standard output went away: stop without a message
        _settled(final)
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        status = 1
    except BaseException as error:
        _settled(final)
        if not caused_by_interrupt(error):
            raise
        print(INTERRUPTED, file=sys.stderr)
        status = 130
    reported.set()  # the command has ended and said so: the watchdog has nothing left to do
    return status


def _settled(final: bool) -> None:
    """The command's outcome is known: for the installed command (``final``), Ctrl-C is ignored from here to the
    exit, where it could only print a traceback after the command's own last line."""
    if final:
        signal.signal(signal.SIGINT, signal.SIG_IGN)


def _interrupt_handler(reported: threading.Event):
    """Ctrl-C: raise KeyboardInterrupt in the main thread, as Python's own handler does, and (the first time) start
    a watchdog that ends the process after :data:`GRACE` seconds if the command is still running then."""
    started = threading.Event()

    def watchdog() -> None:
        time.sleep(GRACE)
        if not reported.is_set():  # the interrupt was swallowed, or the command hangs in a library
            print(INTERRUPTED, file=sys.stderr, flush=True)
            os._exit(130)

    def handler(number, frame):
        if not started.is_set():
            started.set()
            threading.Thread(target=watchdog, name="fresnel-lut Ctrl-C watchdog", daemon=True).start()
        raise KeyboardInterrupt

    return handler


def console() -> int:
    """The ``fresnel-lut`` command: :func:`main`, and after an interrupt an exit without the interpreter's finalisation
    (every file is already whole or untouched; a C extension whose import Ctrl-C cut short would print its own
    reference-leak report there, after the one line)."""
    status = main(final=True)
    if status == 130:
        for stream in (sys.stdout, sys.stderr):
            try:
                stream.flush()
            except (OSError, ValueError):  # a closed pipe or stream: nothing more to say
                pass
        os._exit(130)
    return status


if __name__ == "__main__":
    sys.exit(console())
