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
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Iterator
from contextlib import contextmanager
from types import TracebackType
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from concurrent.futures import Executor

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
        the length of the shortest iterable): the results in order, each as it is ready."""
        if not self.parallel(tasks):
            return map(fn, *iterables)
        if self._executor is None:
            # Imported here: the process pool (multiprocessing, ~20 modules) serves only
            # workers > 1, and the first call of the analysis should not pay for it.
            from concurrent.futures import ProcessPoolExecutor

            from .._threads import one_blas_thread_for_process

            # Each process sets its one BLAS thread (its initializer): it inherits the
            # analysis's one thread only when forked inside its context.
            self._executor = ProcessPoolExecutor(
                self.processes, initializer=one_blas_thread_for_process
            )
        return self._executor.map(fn, *iterables, chunksize=chunksize)

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
