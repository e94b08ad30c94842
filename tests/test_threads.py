"""Tests of contactres._threads.one_blas_thread: one BLAS thread inside, the previous counts
after, whichever Python thread opens or closes the last context.

The thread counts are read with threadpoolctl's own fresh lookup (threadpool_info), not through
the module's code path.
"""

import threading

import numpy as np
import pytest
import scipy.linalg  # noqa: F401  (loads scipy's BLAS too, so that both libraries are checked)
from threadpoolctl import threadpool_info, threadpool_limits

from contactres._threads import one_blas_thread


def _blas_threads() -> list[int]:
    return [lib["num_threads"] for lib in threadpool_info() if lib["user_api"] == "blas"]


@pytest.fixture
def two_threads():
    """Two BLAS threads per library for the test (the package's default on a 2-core machine),
    whatever the environment set (make test runs with OPENBLAS_NUM_THREADS=1)."""
    with threadpool_limits(limits=2, user_api="blas"):
        if not _blas_threads() or max(_blas_threads()) < 2:
            pytest.skip("no BLAS library that takes two threads")
        yield _blas_threads()


def test_one_thread_inside_and_the_previous_counts_after(two_threads):
    with one_blas_thread():
        assert set(_blas_threads()) == {1}
        np.linalg.solve(np.eye(3), np.ones(3))
    assert _blas_threads() == two_threads


def test_nested_context_keeps_one_thread_until_the_outer_closes(two_threads):
    with one_blas_thread():
        with one_blas_thread():
            assert set(_blas_threads()) == {1}
        assert set(_blas_threads()) == {1}
    assert _blas_threads() == two_threads


def test_counts_restored_after_an_exception(two_threads):
    with pytest.raises(RuntimeError, match="inside"):
        with one_blas_thread():
            raise RuntimeError("inside")
    assert _blas_threads() == two_threads


def test_overlapping_contexts_of_two_threads(two_threads):
    # A opens first and closes first, while B's context is still open: B must keep one thread
    # (its results would otherwise depend on the timing), and B's close restores the counts.
    a_in, b_in, a_out = threading.Event(), threading.Event(), threading.Event()
    seen = {}

    def a():
        with one_blas_thread():
            a_in.set()
            b_in.wait(10)
        a_out.set()

    def b():
        a_in.wait(10)
        with one_blas_thread():
            b_in.set()
            a_out.wait(10)
            seen["b after a closed"] = _blas_threads()
        seen["after both"] = _blas_threads()

    threads = [threading.Thread(target=a), threading.Thread(target=b)]
    for t in threads:
        t.start()
    for t in threads:
        t.join(30)
    assert set(seen["b after a closed"]) == {1}
    assert seen["after both"] == two_threads
    assert _blas_threads() == two_threads


class _Library:
    """A stand-in for threadpoolctl's controller of one BLAS library."""

    def __init__(self, filepath: str, threads: int):
        self.filepath, self.threads = filepath, threads

    def get_num_threads(self) -> int:
        return self.threads

    def set_num_threads(self, n: int) -> None:
        self.threads = n


def test_a_library_loaded_inside_is_held_from_the_next_opening_and_restored(monkeypatch):
    # numpy's BLAS is loaded when the outer context opens; scipy's only inside it (a module
    # imported there for the first time): the nested context must hold it to one thread too,
    # and the last close give each library back its own count.
    from contactres import _threads

    numpy_blas, scipy_blas = _Library("numpy.so", 2), _Library("scipy.so", 3)
    loaded = [numpy_blas]
    monkeypatch.setattr(_threads, "_blas_libraries", lambda: list(loaded))
    with one_blas_thread():
        assert (numpy_blas.threads, scipy_blas.threads) == (1, 3)
        loaded.append(scipy_blas)
        with one_blas_thread():
            assert (numpy_blas.threads, scipy_blas.threads) == (1, 1)
        assert (numpy_blas.threads, scipy_blas.threads) == (1, 1)
    assert (numpy_blas.threads, scipy_blas.threads) == (2, 3)


def _open_a_context() -> None:
    """A forked child's first context (as an analysis's worker process opens)."""
    with one_blas_thread():
        pass


@pytest.mark.skipif(
    "fork" not in __import__("multiprocessing").get_all_start_methods(), reason="no fork"
)
def test_a_child_forked_while_another_thread_holds_the_lock_can_open_a_context():
    # An analysis forks its worker processes inside its context; another Python thread (a
    # second analysis) may be opening or closing one at that moment, holding the module's lock.
    # The child inherits the lock held, by a thread it does not have: without a lock of its
    # own its first context waits for ever.
    import multiprocessing

    from contactres import _threads

    held, release = threading.Event(), threading.Event()

    def hold_the_lock():
        with _threads._OPEN.lock:
            held.set()
            release.wait()

    holder = threading.Thread(target=hold_the_lock)
    holder.start()
    held.wait()
    try:
        child = multiprocessing.get_context("fork").Process(target=_open_a_context)
        child.start()
    finally:
        release.set()
        holder.join()
    child.join(60)
    if child.exitcode is None:
        child.kill()
        child.join()
    assert child.exitcode == 0
