"""What Ctrl-C looks like to the command: its one line, and the errors that an interrupt turns into.

Public objects: ``INTERRUPTED``, ``caused_by_interrupt``.

Standard library only: :mod:`fresnel_lut.entry` imports it before numpy loads, :mod:`fresnel_lut.cli` after.
"""

from __future__ import annotations

__all__ = ["INTERRUPTED", "caused_by_interrupt"]

#: The one line every interrupted command ends with (the blank line first ends a progress line left open).
INTERRUPTED = "\nfresnel-lut: interrupted; no file was written or replaced"


def caused_by_interrupt(error: BaseException) -> bool:
    """Whether ``error`` is a KeyboardInterrupt or one is in its chain of causes and contexts (pybind11 and Cython
    module initialisation turn it into ``ImportError: initialization failed``; an interrupt inside importlib's
    module lock leaves ``RuntimeError: cannot release un-acquired lock``).

    >>> try:
    ...     try:
    ...         raise KeyboardInterrupt
    ...     except KeyboardInterrupt:
    ...         raise RuntimeError("cannot release un-acquired lock")
    ... except RuntimeError as error:
    ...     caused_by_interrupt(error)
    True
    >>> caused_by_interrupt(ValueError("a value of its own"))
    False
    """
    seen = set()
    while error is not None and id(error) not in seen:
        if isinstance(error, KeyboardInterrupt):
            return True
        seen.add(id(error))
        error = error.__cause__ or error.__context__
    return False
