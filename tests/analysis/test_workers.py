"""One pool of worker processes per analysis (issue 31, point 3): started once, lent to every
stage, shut down at the end or on an error; the results are the serial path's."""

import concurrent.futures
import multiprocessing
from concurrent.futures import ProcessPoolExecutor
from functools import partial
from typing import ClassVar

import numpy as np
import pandas as pd
import pytest

from contactres.analysis import AnalysisSettings, analyze
from contactres.analysis._workers import (
    AHEAD_PER_PROCESS,
    WorkerPool,
    lent_pool,
    run_in_workers,
)
from contactres.measurements._sweeps import validate_sweeps
from contactres.measurements._synthetic import SweepGroup, SweepStudy, synthetic_sweeps
from contactres.resonators._qcm import QCM

Q = QCM(fundamental=5e6, overtone=3, area=2.5e-5)


class CountingPool(ProcessPoolExecutor):
    """A ProcessPoolExecutor that records itself, the functions of the chunks of calls sent to
    it and its shutdowns."""

    made: ClassVar[list["CountingPool"]] = []

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self.functions: list = []
        self.shutdowns: list[bool] = []
        CountingPool.made.append(self)

    def submit(self, call, fn, *args, **kwargs):
        self.functions.append(fn)
        return super().submit(call, fn, *args, **kwargs)

    def shutdown(self, wait=True, *, cancel_futures=False):
        self.shutdowns.append(cancel_futures)
        super().shutdown(wait=wait, cancel_futures=cancel_futures)


@pytest.fixture
def counting(monkeypatch):
    CountingPool.made = []
    # The pool module imports ProcessPoolExecutor where it starts the processes (deferred: the
    # first call of the analysis does not pay for multiprocessing), so the name is patched
    # where that import reads it.
    monkeypatch.setattr(concurrent.futures, "ProcessPoolExecutor", CountingPool)
    return CountingPool.made


@pytest.fixture(scope="module")
def study():
    """Two groups (sweeps of 13 and of 9 points: two blocks of sweeps) of 3 experiments."""
    u = tuple(np.linspace(0.5e-9, 8e-9, 13))
    P = Q.sensitivity(3)
    frames = []
    for i, (name, points) in enumerate((("g", 13), ("h", 9))):
        group = SweepGroup(name, "air", 1.1e-3, 70e9, 0.1, u[:points], 5.0 / P, 0.2)
        s = SweepStudy(
            groups=(group,), normal_forces=(2e-3, 4e-3, 6e-3), n_experiments=3, qcm=Q, mu=1.5
        )
        frames.append(synthetic_sweeps(s, 7 + i, constants=True))
    return validate_sweeps(pd.concat(frames, ignore_index=True))


def test_one_pool_serves_every_stage_and_gives_the_serial_results(study, counting):
    serial = analyze(study, settings=AnalysisSettings(bootstrap=30))
    assert counting == []  # workers=1: no process at all
    two = analyze(study, settings=AnalysisSettings(bootstrap=30, workers=2))
    # One executor for the whole analysis, used by several stages (per-sweep fits, curves,
    # JKR fits, ...), shut down once at the end, normally.
    (pool,) = counting
    assert len(set(pool.functions)) >= 3 and pool.shutdowns == [False]
    pd.testing.assert_frame_equal(serial.sweeps, two.sweeps)
    pd.testing.assert_frame_equal(serial.curves, two.curves)
    pd.testing.assert_frame_equal(serial.blocks, two.blocks)
    # (the groups' JKR fits run in the pool too)
    pd.testing.assert_frame_equal(pd.DataFrame(serial.groups), pd.DataFrame(two.groups))
    assert len(serial.groups) == 2 and serial.groups[0]["error_method"].startswith("bootstrap")
    for one, other in zip(serial.groups, two.groups, strict=True):
        assert one.keys() == other.keys()
        for key, value in one.items():
            assert value == other[key] or (value != value and other[key] != other[key]), key


@pytest.mark.parametrize("error", [KeyboardInterrupt, RuntimeError])
def test_the_pool_is_shut_down_on_an_error_or_an_interrupt(study, counting, error):
    # Ctrl-C (or an error) while the JKR fits are under way in the workers: the exception goes
    # through, and the pool is shut down with the tasks not yet started cancelled.
    def say(step):
        if step.startswith("JKR fit"):
            raise error("stop")

    with pytest.raises(error):
        analyze(study, settings=AnalysisSettings(bootstrap=30, workers=2), progress=say)
    (pool,) = counting
    assert pool.functions and pool.shutdowns == [True]


def test_a_pool_starts_only_for_two_or_more_tasks(counting):
    with WorkerPool(2) as pool:
        assert run_in_workers(abs, pool, [-3]) == [3]  # one task: in this process
        assert counting == []
        assert run_in_workers(divmod, pool, [7, 9], [2, 4]) == [(3, 1), (2, 1)]
        with lent_pool(pool) as lent:  # a lent pool is the same, and stays open after
            assert lent is pool
        assert run_in_workers(pow, pool, [2, 3], [3, 2]) == [8, 9]
    # Both calls went to the one executor, shut down when the pool's block ended.
    (executor,) = counting
    assert executor.functions == [divmod, divmod, pow, pow] and executor.shutdowns == [False]
    assert run_in_workers(abs, 1, [-1, -2]) == [1, 2] and len(counting) == 1


def _counted(made: list[int], n: int):
    """-0, -1, ... -(n - 1), each noted in ``made`` as it is read (what the pool has sent)."""
    for k in range(n):
        made.append(k)
        yield -k


def test_the_calls_are_sent_a_few_ahead_of_the_results():
    # A stage's arguments come from a generator (each block padded when its call is sent):
    # the parent should hold a few calls' arguments at a time, not every one of the stage.
    made: list[int] = []

    ahead = AHEAD_PER_PROCESS * 2
    with WorkerPool(2) as pool:
        results = pool.imap(abs, 40, _counted(made, 40))
        assert len(made) == ahead  # the first calls are sent at once
        for k, value in enumerate(results):
            assert value == k
            # the result k taken: calls up to k + ahead sent (one more for each one taken)
            assert len(made) == min(40, k + 1 + ahead)
        assert len(made) == 40
        # chunks of calls: the same results, in order
        assert list(pool.imap(divmod, 9, range(9), [2] * 9, chunksize=4)) == [
            divmod(k, 2) for k in range(9)
        ]


def test_chunks_of_calls_are_sent_whole_and_ahead():
    # chunksize calls go together: the first AHEAD_PER_PROCESS chunks per process are sent at
    # once, so that many chunks' arguments are read, not that many calls'.
    made: list[int] = []

    with WorkerPool(2) as pool:
        results = pool.imap(abs, 40, _counted(made, 40), chunksize=4)
        assert len(made) == 4 * AHEAD_PER_PROCESS * 2
        assert list(results) == list(range(40))


class PendingPool:
    """An executor whose first chunk is done at once (in this process) and whose others stay
    pending until cancelled: what a pool's queue holds, without processes or timing."""

    def __init__(self, *args, **kwargs):
        self.futures: list[concurrent.futures.Future] = []

    def submit(self, call, *args):
        future: concurrent.futures.Future = concurrent.futures.Future()
        if not self.futures:
            future.set_result(call(*args))
        self.futures.append(future)
        return future

    def shutdown(self, wait=True, *, cancel_futures=False):
        pass


def test_the_chunks_not_started_are_cancelled_when_the_reader_closes(monkeypatch):
    # A caller that takes a result and closes the rest: what is queued is not run for nobody.
    # (A real pool's chunks may have started by then, whatever the test waits: a pending
    # executor makes it exact.)
    monkeypatch.setattr(concurrent.futures, "ProcessPoolExecutor", PendingPool)
    with WorkerPool(2) as pool:
        results = pool.imap(abs, 20, range(0, -20, -1))
        assert next(results) == 0
        results.close()
        executor = pool._executor
        assert len(executor.futures) == AHEAD_PER_PROCESS * 2 + 1
        assert all(f.cancelled() for f in executor.futures[1:])


@pytest.mark.parametrize("method", ["spawn", "forkserver"])
def test_the_pool_works_with_processes_started_afresh(study, method, monkeypatch):
    # Python 3.14 starts processes by forkserver by default on Linux (spawn on macOS and
    # Windows): the workers then import the package themselves and receive every argument.
    if method not in multiprocessing.get_all_start_methods():
        pytest.skip(f"no {method}")
    monkeypatch.setattr(
        concurrent.futures,
        "ProcessPoolExecutor",
        partial(ProcessPoolExecutor, mp_context=multiprocessing.get_context(method)),
    )
    serial = analyze(study, settings=AnalysisSettings(bootstrap=0))
    two = analyze(study, settings=AnalysisSettings(bootstrap=0, workers=2))
    pd.testing.assert_frame_equal(serial.sweeps, two.sweeps)
    pd.testing.assert_frame_equal(serial.curves, two.curves)
    pd.testing.assert_frame_equal(serial.blocks, two.blocks)
    # (the groups' JKR fits run in the pool too)
    pd.testing.assert_frame_equal(pd.DataFrame(serial.groups), pd.DataFrame(two.groups))
