"""The worker processes of one analysis: started once, lent to every stage, shut down at the end.

:func:`contactres.analysis.analyze` with ``workers`` > 1 fits the blocks of sweeps, the load
blocks' joint fits, the plateau loops of contending ramps, the plateau's evidence, the fitted
curves and the JKR fits of the groups in worker processes (issue 31, point 3). Each stage once
opened a process pool of its own (five per analysis, each forking, then sending its
arguments); :class:`WorkerPool` is opened by the analysis and passed down explicitly, and its
processes start on the first stage that has two or more tasks for them (a study whose every
stage has a single task never starts them; once started, all ``workers`` processes run until
the analysis ends, however few tasks the later stages hold). Every task depends on its own
arguments alone, so the results are those of the serial path, bit for bit, whichever process
runs which task.

The processes start by :mod:`multiprocessing`'s default method (``fork`` on Linux up to
Python 3.13, ``forkserver`` from 3.14, ``spawn`` on macOS and Windows). Every call's
arguments are sent to its process (pickled), never read from memory inherited by a fork, so
every method gives the same results.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Callable, Iterable, Iterator
from contextlib import contextmanager
from itertools import islice
from types import TracebackType
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from concurrent.futures import Executor, Future

#: Chunks of calls (``chunksize`` calls each) sent ahead per process: each process has its chunk
#: under way and the next ones queued (no idle wait between chunks), while the arguments and
#: results in flight stay a few chunks' worth. :meth:`concurrent.futures.Executor.map` sent
#: every call at once, so the parent padded and held every block of a stage before the first
#: came back (~0.12 GB at 10^5 sweeps, issue 31, point 3; at t4's 10^4 sweeps in blocks of
#: 4,000 points, at most 7 blocks alive against 29). The price is in wall time only: results
#: are taken in order, so a slow chunk holds back the sending of new ones, and once the chunks
#: queued behind it are done the other processes wait for it.
AHEAD_PER_PROCESS = 3

__all__ = ["WorkerPool", "lent_pool", "run_in_workers"]


class WorkerPool:
    """Up to ``processes`` worker processes, started on first use, for the stages of one analysis.

    A context manager: leaving it shuts the processes down, waiting for the tasks under way; on
    an error or a KeyboardInterrupt the tasks not yet started are cancelled first, so that the
    exception is not held up by work whose result nobody reads.

    Parameters
    ----------
    processes : the most processes (1: none; every task in this process)
    """

    def __init__(self, processes: int) -> None:
        self.processes = int(processes)
        self._executor: Executor | None = None

    def parallel(self, tasks: int) -> bool:
        """Whether ``tasks`` tasks go to worker processes (two or more of them, and of these)."""
        return self.processes > 1 and tasks > 1

    def imap(self, fn: Callable, tasks: int, *iterables: Iterable, chunksize: int = 1) -> Iterator:
        """``map(fn, *iterables)``, in the worker processes where :meth:`parallel` (``tasks``:
        the length of the shortest iterable): the results in order, each as it is ready.

        In the processes, the calls go in chunks of ``chunksize``, at most
        :data:`AHEAD_PER_PROCESS` chunks per process sent ahead of the one whose results are
        being waited for: the iterables are read as the chunks are sent (the first ones now),
        so that a generator's arguments are made a few chunks ahead, not all at once."""
        if not self.parallel(tasks):
            return map(fn, *iterables)
        # Not strict: as for map, the shortest iterable ends it (others may be endless repeats).
        calls = _chunks(zip(*iterables, strict=False), chunksize)
        first = islice(calls, AHEAD_PER_PROCESS * self.processes)
        if self._executor is not None:
            sent = deque(self._executor.submit(_call_each, fn, c) for c in first)
            return _in_order(self._executor, fn, calls, sent)
        # Imported here: the process pool (multiprocessing, ~20 modules) serves only
        # workers > 1, and the first call of the analysis should not pay for it.
        from concurrent.futures import ProcessPoolExecutor

        executor = ProcessPoolExecutor(self.processes, initializer=_start_worker)
        self._executor = executor
        sent = deque(executor.submit(_call_each, fn, c) for c in first)
        return _in_order(executor, fn, calls, sent)

    def close(self, cancel: bool = False) -> None:
        """Shut the processes down (if started), waiting for the tasks under way; ``cancel``:
        drop the tasks not yet started."""
        if self._executor is not None:
            self._executor.shutdown(wait=True, cancel_futures=cancel)
            self._executor = None

    def __enter__(self) -> WorkerPool:
        return self

    def __exit__(
        self,
        kind: type[BaseException] | None,
        error: BaseException | None,
        trace: TracebackType | None,
    ) -> None:
        self.close(cancel=kind is not None)


def _start_worker() -> None:
    """The first thing each worker process does (the pool's initializer), whatever its start
    method: one BLAS thread (:func:`contactres._threads.one_blas_thread_for_process`; a process
    inherits the analysis's one thread only when forked inside its context), and glibc's
    allocator keeping freed memory for the next array
    (:func:`contactres._allocator.keep_freed_memory`: the processes are the package's own and
    run nothing but the analysis's fits, whose arrays of a few MB may otherwise come anew from
    the kernel each time: once, at 10^5 sweeps, 258 k page faults against 48 k, when the kernel
    found no huge pages for them)."""
    # Imported here: the workers' set-up serves only workers > 1 (module docstring of imap).
    from .._allocator import keep_freed_memory
    from .._threads import one_blas_thread_for_process

    keep_freed_memory()
    one_blas_thread_for_process()


def _chunks(calls: Iterator[tuple], size: int) -> Iterator[list[tuple]]:
    """The argument tuples of ``calls``, ``size`` to a list (the last one shorter)."""
    while chunk := list(islice(calls, size)):
        yield chunk


def _call_each(fn: Callable, chunk: list[tuple]) -> list:
    """``[fn(*args) for args in chunk]``: one chunk of calls, run in a worker process."""
    return [fn(*args) for args in chunk]


def _in_order(
    executor: Executor, fn: Callable, calls: Iterator[list[tuple]], sent: deque[Future]
) -> Iterator:
    """The results of the chunks ``sent`` and then of ``calls``, in order: for each chunk
    taken from ``sent``, one more of ``calls`` is sent before its result is waited for, so
    that as many stay ahead. On an error, or when a caller that has started reading closes
    the iterator, the chunks sent and not yet started are cancelled; chunks sent for an
    iterator that is never read are cancelled by the pool's owner when it leaves the pool on
    an error (:meth:`WorkerPool.close`), or else run and their results are dropped."""
    try:
        while sent:
            head = sent.popleft()
            more = next(calls, None)
            if more is not None:
                sent.append(executor.submit(_call_each, fn, more))
            yield from head.result()
    finally:
        for future in sent:
            future.cancel()


@contextmanager
def lent_pool(workers: int | WorkerPool) -> Iterator[WorkerPool]:
    """``workers`` if it is a :class:`WorkerPool` (left open: its owner closes it), else a pool
    of that many processes for the ``with`` block alone (a stage called by itself)."""
    if isinstance(workers, WorkerPool):
        yield workers
        return
    with WorkerPool(workers) as pool:
        yield pool


def run_in_workers(fn: Callable, workers: int | WorkerPool, first: list, *rest) -> list:
    """``[fn(a, *r) for a, *r in zip(first, *rest)]``, in the processes of ``workers`` (a
    :class:`WorkerPool`, or a number of processes for this call alone) where there are two or
    more tasks: the results in the order of ``first``, whichever process finishes first.

    ``rest`` may hold endless ``itertools.repeat()``; ``first`` sets the length.
    """
    with lent_pool(workers) as pool:
        return list(pool.imap(fn, len(first), first, *rest))
