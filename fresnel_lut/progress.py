"""Progress on standard error for work that takes more than a second.

Public objects: ``Progress``, ``peak_rss_mib``.

On a terminal the line is redrawn in place; elsewhere (CI logs, pipes) a line is printed at most every
few seconds. Nothing is printed for work that finishes within ``delay`` seconds.
"""

from __future__ import annotations

import resource
import sys
import time
from pathlib import Path

__all__ = ["Progress", "peak_rss_mib"]


def _duration(seconds: float) -> str:
    """``42 s``, ``3.5 min``, ``2.1 h``: an estimate as a person reads it."""
    if seconds < 90:
        return f"{seconds:.0f} s"
    return f"{seconds / 60:.1f} min" if seconds < 5400 else f"{seconds / 3600:.1f} h"


class Progress:
    """Callable ``progress(done, total)`` that reports ``label: 42% (done/total unit) 12.0s, about 16 s left`` (the
    time left at the rate so far)."""

    def __init__(self, label: str, unit: str = "", delay: float = 1.0, interval: float = 5.0, stream=None):
        self.label, self.unit, self.delay, self.interval = label, unit, delay, interval
        self.stream = sys.stderr if stream is None else stream
        self.start = time.perf_counter()
        self.last = -float("inf")
        self.shown = False
        self.tty = hasattr(self.stream, "isatty") and self.stream.isatty()

    def __call__(self, done: int, total: int | None = None) -> None:
        now = time.perf_counter()
        if now - self.start < self.delay or (not self.tty and now - self.last < self.interval and done != total):
            return
        self.last = now
        elapsed = now - self.start
        share = f"{100.0 * done / total:5.1f}% " if total else ""
        counts = f"({done}/{total} {self.unit})" if total else f"({done} {self.unit})"
        left = f", about {_duration(elapsed * (total - done) / done)} left" if total and 0 < done < total else ""
        text = f"{self.label}: {share}{counts} {elapsed:.1f}s{left}"
        self.stream.write(("\r" + text) if self.tty else (text + "\n"))
        self.stream.flush()
        self.shown = True

    def close(self) -> None:
        """End the in-place line on a terminal."""
        if self.shown and self.tty:
            self.stream.write("\n")
            self.stream.flush()


def peak_rss_mib() -> float:
    """Peak resident memory of this process in MiB.

    Linux's VmHWM belongs to the current program image; ``ru_maxrss`` would also count the memory of a
    parent that forked this process (e.g. the report measuring a basis build in a child).
    """
    try:
        for line in Path("/proc/self/status").read_text().splitlines():
            if line.startswith("VmHWM:"):
                return int(line.split()[1]) / 1024
    except OSError:
        pass
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
