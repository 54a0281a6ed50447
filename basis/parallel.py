"""The project's own parallelism, and numpy's BLAS kept out of its way.

Public objects: ``worker_count``, ``one_blas_thread``, ``threaded_map``.

The integrator and the training set run their own thread pools (numpy releases the GIL). numpy's
OpenBLAS starts threads of its own: on a machine of two cores they fight the pool (a 512 × 512 ``eigh``
took 0.03 s or 3.8 s, the Gram accumulation and the render ran 2× slower), and the number of BLAS
threads changes how a product is blocked, hence the last bits of the result (the same basis build gave
three different content hashes). Every hot section therefore runs BLAS on one thread: the results are
then the same bits whatever the machine's thread settings, and the cores go to the project's workers.
"""

from __future__ import annotations

import contextlib
import os
from collections.abc import Callable, Iterable, Iterator
from concurrent.futures import ThreadPoolExecutor

from threadpoolctl import threadpool_limits

from .validation import check_positive_int

__all__ = ["one_blas_thread", "threaded_map", "worker_count"]


def worker_count(workers: int | None) -> int:
    """``workers`` validated, or the machine's cores when None."""
    return max(1, os.cpu_count() or 1) if workers is None else check_positive_int("workers", workers)


@contextlib.contextmanager
def one_blas_thread():
    """Run the enclosed code with numpy's BLAS (OpenBLAS, MKL, …) on one thread; restore it afterwards."""
    with threadpool_limits(limits=1, user_api="blas"):
        yield


def threaded_map(function: Callable, items: Iterable, workers: int | None = None) -> Iterator:
    """``function`` of each of ``items`` on ``workers`` threads (:func:`worker_count`) with BLAS on one thread, the
    results in the items' order as they are read (the pool lives while they are; a consumer that stops, Ctrl-C
    among them, leaves the items not yet started unstarted).

    >>> list(threaded_map(lambda x: x * x, range(5), workers=2))
    [0, 1, 4, 9, 16]
    """
    with one_blas_thread(), ThreadPoolExecutor(worker_count(workers)) as pool:
        yield from pool.map(function, items)
