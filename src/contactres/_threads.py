"""BLAS threading of the package's small-matrix work (ground layer).

The hot paths of :mod:`contactres.dynamic` call BLAS/LAPACK on many small or moderate matrices
at once: batched 3x3 solves and eigenproblems of the half-space kernels, products of a few
hundred rows with the near-field quadrature, Galerkin matrices of a few dozen unknowns. A
second OpenBLAS thread does not shorten such a call; it wakes, then spins waiting for the next
call, so that the process pays up to 2-6x the CPU time of one thread with no gain in wall time
(issue 31, measured on a 2-core machine). :func:`one_blas_thread` is the context these paths
set around their work. Parallel work across a curve, a map or a set of sweeps belongs to chunks
of that work (processes, dask), not to BLAS threads on 3x3 matrices.

The BLAS thread count is a setting of the whole process, so the contexts of all Python threads
share one count of the contexts open (:data:`_OPEN`, under its lock): the first to open sets one
thread, the last to close restores the previous counts, and a context opened inside another
changes nothing. Without that count, two threads that each set and restore the limit could
restore it under each other's running work (whose last bits then depend on the timing) or leave
the process at one thread. threadpoolctl (>= 3.8) lets only one Python thread, the first to set
an OpenBLAS limit, change it; since the last context to close may belong to another thread than
the first, each change here releases that control again. The libraries come from threadpoolctl's
own cached lookup (about 10 µs; a fresh lookup reads /proc/self/maps, about 1.3 ms). The count
holds no result: nothing computed is kept between calls.

A context cannot undo what OpenBLAS does when it is loaded: it starts its threads at once
(one per core less one, for numpy's copy and again for scipy's), and each new thread spins,
yielding, for about 2^28 processor cycles (~0.1 s at 2.6 GHz) waiting for work before it sleeps.
On an idle machine that is ~0.1 s of CPU per copy, paid by a process that then runs all its
BLAS work on one thread: ``contactres afm invert`` of a 512 x 512 map cost 0.55 s of CPU as
shipped against 0.44 s with ``OPENBLAS_NUM_THREADS=1`` (issue 31). The command line therefore
asks for one thread before numpy is first imported (``contactres.cli._app``).
"""

from __future__ import annotations

import os
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

__all__ = ["one_blas_thread", "one_blas_thread_for_process"]


class _OpenContexts:
    """How many :func:`one_blas_thread` contexts are open in the process, and the BLAS thread
    counts to restore when the last one closes."""

    def __init__(self) -> None:
        self.lock = threading.Lock()
        self.depth = 0
        self.restore: list[tuple[Any, int]] = []

    def renew_lock(self) -> None:
        """Give a forked child a lock of its own: the fork copies the lock as it was, held if
        another thread of the parent was opening or closing a context, and no thread of the
        child would ever release it (the child's first context, e.g. in an analysis's worker
        process, would wait for ever)."""
        self.lock = threading.Lock()


#: The process-wide count of open contexts (the BLAS setting it guards is process-wide too).
_OPEN = _OpenContexts()
if hasattr(os, "register_at_fork"):  # POSIX: the analyses' worker processes are forked there
    os.register_at_fork(after_in_child=_OPEN.renew_lock)


def _set_threads(lib: Any, n: int) -> None:
    """Set the thread count of one threadpoolctl library controller from any Python thread."""
    # threadpoolctl >= 3.8: only the controlling thread's calls count; take and release it.
    release = getattr(lib, "clear_controlling_thread", None)
    if release is not None:
        release(force=True)
    lib.set_num_threads(n)
    if release is not None:
        release(force=True)


def _blas_libraries() -> list[Any]:
    """threadpoolctl's controllers of the BLAS libraries loaded in the process."""
    # numpy loads its BLAS when imported: a context opened before the first numpy import (a
    # job whose module imports numpy inside its run) would otherwise find no library to limit.
    import numpy  # noqa: F401
    import threadpoolctl

    cached = getattr(threadpoolctl, "get_cached_controller", None)  # threadpoolctl >= 3.8
    controller = cached() if cached is not None else threadpoolctl.ThreadpoolController()
    return [lib for lib in controller.lib_controllers if lib.user_api == "blas"]


@contextmanager
def one_blas_thread() -> Iterator[None]:
    """Run the body with one BLAS thread; the previous thread counts are restored when the last
    context open in the process closes (module docstring).

    Results: every BLAS call inside runs on one thread, whichever Python thread makes it, so
    a result has the same bits from a thread pool as from a serial run and on any number of
    cores (with several BLAS threads, a few operations, e.g. some Galerkin solves, differ in
    the last bit with the thread count). BLAS work of other code running meanwhile in another
    Python thread runs on one thread too. A BLAS library loaded inside the context (scipy's,
    when a module that imports scipy.linalg is first imported there) is held to one thread
    from the next context opened, nested or not, until the last one closes.

    Yields
    ------
    None

    Examples
    --------
    >>> import numpy as np
    >>> from contactres._threads import one_blas_thread
    >>> with one_blas_thread():
    ...     x = np.linalg.solve(np.eye(3), np.ones(3))
    >>> x.tolist()
    [1.0, 1.0, 1.0]
    """
    with _OPEN.lock:
        # Every opening looks for libraries loaded since the outermost one (threadpoolctl's
        # cached lookup: ~10 µs unless modules were imported meanwhile).
        held = {lib.filepath for lib, _ in _OPEN.restore}
        for lib in _blas_libraries():
            if lib.filepath not in held:
                _OPEN.restore.append((lib, lib.get_num_threads()))
                _set_threads(lib, 1)
        _OPEN.depth += 1
    try:
        yield
    finally:
        with _OPEN.lock:
            _OPEN.depth -= 1
            if _OPEN.depth == 0:
                for lib, n in _OPEN.restore:
                    _set_threads(lib, n)
                _OPEN.restore = []


def one_blas_thread_for_process() -> None:
    """Set one BLAS thread for the rest of this process's life (a worker process's initializer).

    The worker processes of an analysis (:class:`contactres.analysis._workers.WorkerPool`) run
    nothing but the analysis's small-matrix work, and each one is a core's worth of parallel
    work already: a second BLAS thread in each would only spin (module docstring). A process
    started by forking inside a :func:`one_blas_thread` context inherits its one thread; one
    started afresh (the ``spawn`` and ``forkserver`` methods) would not, hence this. Nothing is
    restored: the process ends with its pool.

    Examples
    --------
    >>> from concurrent.futures import ProcessPoolExecutor
    >>> from contactres._threads import one_blas_thread_for_process
    >>> pool = ProcessPoolExecutor(2, initializer=one_blas_thread_for_process)
    >>> pool.shutdown()
    """
    for lib in _blas_libraries():
        _set_threads(lib, 1)
