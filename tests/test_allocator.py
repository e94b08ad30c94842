"""glibc's malloc thresholds where the package owns the process (:mod:`contactres._allocator`):
the analysis's worker processes, with every start method, and the command line run as the
program; never a caller's own process; a threshold the user set wins; nothing outside glibc.

glibc has no getter for its thresholds, so the setting is observed by its effect: the minor page
faults of a process over rounds of making, touching and freeing a few arrays of 8 MB (as an
analysis's fits do with their columns at 10^5 sweeps). With glibc's defaults the freed arrays go
back to the kernel (the top of the heap is trimmed once more than twice the largest freed block
is free), and every round faults their pages in anew; with the thresholds raised, the heap
keeps them and the rounds after the first fault (almost) never.
"""

from __future__ import annotations

import multiprocessing
import os
import subprocess
import sys

import numpy as np
import pytest

from contactres import _allocator
from contactres._allocator import THRESHOLD, keep_freed_memory

needs_glibc = pytest.mark.skipif(_allocator._glibc() is None, reason="glibc's allocator only")

#: The environment variables by which a user sets glibc's thresholds.
USER_VARIABLES = ("MALLOC_MMAP_THRESHOLD_", "MALLOC_TRIM_THRESHOLD_", "GLIBC_TUNABLES")
#: Rounds counted, arrays per round, doubles per array (8 MB: 24 MB a round, below THRESHOLD;
#: above the trim threshold glibc sets itself, twice the largest block freed: 16 MB).
ROUNDS, ARRAYS, SIZE = 10, 3, 1 << 20
#: At most this many faults over the rounds with the setting (a forked worker's copy on write
#: of its parent's pages: 1-5 seen); at least this many without (the 24 MB of a round are at
#: least 12 pages of 2 MB even where the kernel maps huge pages).
KEPT, RETURNED = 2 * ROUNDS, 5 * ROUNDS


def faults_of_reuse(_task: object = None) -> int:
    """The minor page faults of this process over :data:`ROUNDS` rounds of allocating,
    touching and freeing :data:`ARRAYS` arrays of :data:`SIZE` doubles (after one round
    uncounted, which finds the heap as the process left it)."""

    import resource  # (not at the top: no such module on Windows, where the rest still runs)

    def one_round() -> None:
        arrays = [np.ones(SIZE) for _ in range(ARRAYS)]
        del arrays

    one_round()
    before = resource.getrusage(resource.RUSAGE_SELF).ru_minflt
    for _ in range(ROUNDS):
        one_round()
    return resource.getrusage(resource.RUSAGE_SELF).ru_minflt - before


def _faults_of_reuse_settled(_task: object = None) -> int:
    """:func:`faults_of_reuse` measured a second time in the process. A forked worker shares
    its parent's heap copy on write: the first rounds may write into free chunks it inherited
    and copy their pages (1,518 faults in the first measurement of each worker, none in the
    second, when the parent was a test process after many tests)."""
    faults_of_reuse()
    return faults_of_reuse()


# Runs in a fresh interpreter; argv[1]: "program" (contactres as the console script runs it),
# or the code of a caller that runs a command in-process. Prints the faults of the rounds,
# measured at the process's exit (after the command).
_PROBE = """
import atexit, runpy, sys
sys.path.insert(0, {tests!r})
from test_allocator import faults_of_reuse
atexit.register(lambda: print("faults", faults_of_reuse()))
how = sys.argv.pop(1)
sys.argv = ["contactres", *sys.argv[1:]]
if how == "program":
    runpy.run_module("contactres", run_name="__main__", alter_sys=True)
else:
    exec(how)
"""
_IN_PROCESS = {
    "main": "from contactres.cli import main\nmain(sys.argv[1:])",
    "CliRunner": (
        "from click.testing import CliRunner\nfrom contactres.cli import main\n"
        "assert CliRunner().invoke(main, sys.argv[1:]).exit_code == 0"
    ),
}


def _faults_in_a_fresh_process(how: str, environ: dict[str, str] | None = None) -> int:
    env = {k: v for k, v in os.environ.items() if k not in USER_VARIABLES} | (environ or {})
    probe = _PROBE.format(tests=os.path.dirname(__file__))
    p = subprocess.run(
        [sys.executable, "-c", probe, how, "crystals"],
        env=env,
        capture_output=True,
        text=True,
        check=False,
        timeout=300,  # (a pool that hangs fails the test, not the suite)
    )
    assert p.returncode == 0, p.stderr
    return int(p.stdout.split("faults")[-1])


# Runs in a fresh interpreter; argv[1]: the start method. Prints the faults of each worker's
# rounds. A fresh parent, not this test process: a forked worker inherits its parent's
# allocator, and a test process that freed a large mmapped block earlier (another test) has
# raised glibc's own thresholds, so that its forked workers would keep freed memory without
# their initializer, and the test could not fail (review R29e).
_POOL_PROBE = """
import concurrent.futures, multiprocessing, sys
from functools import partial
sys.path.insert(0, {tests!r})
from test_allocator import _faults_of_reuse_settled
from contactres.analysis._workers import WorkerPool
method = sys.argv[1]
concurrent.futures.ProcessPoolExecutor = partial(
    concurrent.futures.ProcessPoolExecutor, mp_context=multiprocessing.get_context(method)
)
if __name__ == "__main__":
    with WorkerPool(2) as pool:
        print("faults", *pool.imap(_faults_of_reuse_settled, 4, range(4)))
"""


@needs_glibc
@pytest.mark.parametrize("method", ["fork", "spawn", "forkserver"])
def test_the_analysis_worker_processes_keep_freed_memory(method, tmp_path):
    if method not in multiprocessing.get_all_start_methods():
        pytest.skip(f"no {method}")
    # Thresholds the user set (which the workers inherit, and keep) are not the package's.
    env = {k: v for k, v in os.environ.items() if k not in USER_VARIABLES}
    # A file, not -c: spawn and forkserver re-import the parent's main module in each worker.
    probe = tmp_path / "pool_probe.py"
    probe.write_text(_POOL_PROBE.format(tests=os.path.dirname(__file__)), encoding="utf-8")
    p = subprocess.run(
        [sys.executable, str(probe), method],
        env=env,
        capture_output=True,
        text=True,
        check=False,
        timeout=300,
    )
    assert p.returncode == 0, p.stderr
    faults = [int(f) for f in p.stdout.split("faults")[-1].split()]
    assert len(faults) == 4 and max(faults) <= KEPT, faults


@needs_glibc
def test_the_command_line_run_as_the_program_keeps_freed_memory():
    assert _faults_in_a_fresh_process("program") <= KEPT


@needs_glibc
@pytest.mark.parametrize("program", list(_IN_PROCESS))
def test_a_program_calling_the_command_line_keeps_its_allocator(program):
    # The setting would last for the rest of the caller's process.
    assert _faults_in_a_fresh_process(_IN_PROCESS[program]) >= RETURNED


@needs_glibc
@pytest.mark.parametrize(
    "environ",
    [
        {"MALLOC_MMAP_THRESHOLD_": "131072", "MALLOC_TRIM_THRESHOLD_": "131072"},
        {"GLIBC_TUNABLES": "glibc.malloc.mmap_threshold=131072:glibc.malloc.trim_threshold=131072"},
    ],
    ids=["variables", "tunables"],
)
def test_thresholds_the_user_set_win_in_the_command_line(environ):
    # 128 KiB, glibc's own start, but fixed: every 8 MB array is mapped and unmapped anew.
    assert _faults_in_a_fresh_process("program", environ) >= RETURNED


class _Mallopt:
    """A stand-in for glibc's mallopt: records its calls, succeeds."""

    def __init__(self) -> None:
        self.calls: list[tuple[int, int]] = []

    def __call__(self, parameter: int, value: int) -> int:
        self.calls.append((parameter, value))
        return 1


class _Refusing(_Mallopt):
    """A glibc whose mallopt refuses an mmap threshold this high."""

    def __call__(self, parameter: int, value: int) -> int:
        super().__call__(parameter, value)
        return int(parameter != -3)


class _Glibc:
    def __init__(self, mallopt: type[_Mallopt] = _Mallopt) -> None:
        self.mallopt = mallopt()

    def gnu_get_libc_version(self) -> bytes:
        return b"2.36"


class _OtherLibc:
    """A C library with a mallopt but not glibc's (musl's does nothing)."""

    def __init__(self) -> None:
        self.mallopt = _Mallopt()


@pytest.fixture
def no_user_thresholds(monkeypatch):
    for name in USER_VARIABLES:
        monkeypatch.delenv(name, raising=False)


def test_both_thresholds_are_set_with_glibc_numbers(monkeypatch, no_user_thresholds):
    libc = _Glibc()
    monkeypatch.setattr(_allocator.ctypes, "CDLL", lambda name: libc)
    assert set(keep_freed_memory()) == {"MALLOC_MMAP_THRESHOLD_", "MALLOC_TRIM_THRESHOLD_"}
    # glibc's malloc.h: M_TRIM_THRESHOLD -1, M_MMAP_THRESHOLD -3.
    assert sorted(libc.mallopt.calls) == [(-3, THRESHOLD), (-1, THRESHOLD)]


def test_a_refused_mmap_threshold_leaves_the_trim_threshold_alone(monkeypatch, no_user_thresholds):
    # The trim threshold set alone would fix the mmap threshold at 128 KiB (no more dynamic
    # threshold): every block above it would be mapped anew, the opposite of the aim.
    libc = _Glibc(_Refusing)
    monkeypatch.setattr(_allocator.ctypes, "CDLL", lambda name: libc)
    assert keep_freed_memory() == ()
    assert libc.mallopt.calls == [(-3, THRESHOLD)]


@pytest.mark.parametrize(
    ("name", "value", "kept"),
    [
        ("MALLOC_MMAP_THRESHOLD_", "65536", -3),
        ("MALLOC_TRIM_THRESHOLD_", "65536", -1),
        ("GLIBC_TUNABLES", "glibc.malloc.arena_max=2:glibc.malloc.mmap_threshold=65536", -3),
        ("GLIBC_TUNABLES", "glibc.malloc.trim_threshold=65536", -1),
    ],
)
def test_a_threshold_the_user_set_is_left_alone(monkeypatch, no_user_thresholds, name, value, kept):
    libc = _Glibc()
    monkeypatch.setattr(_allocator.ctypes, "CDLL", lambda name: libc)
    monkeypatch.setenv(name, value)
    keep_freed_memory()
    assert [parameter for parameter, _ in libc.mallopt.calls] == [p for p in (-1, -3) if p != kept]


@pytest.mark.parametrize(
    "tunables",
    [
        "glibc.malloc.arena_max=2",
        # a name without a value: glibc skips it (review R29e), so it is no user's setting
        "glibc.malloc.mmap_threshold",
        "glibc.malloc.mmap_threshold:glibc.malloc.arena_max=2",
    ],
)
def test_another_tunable_does_not_count_as_a_threshold(monkeypatch, no_user_thresholds, tunables):
    libc = _Glibc()
    monkeypatch.setattr(_allocator.ctypes, "CDLL", lambda name: libc)
    monkeypatch.setenv("GLIBC_TUNABLES", tunables)
    assert len(keep_freed_memory()) == 2


class _NoMallopt:
    """macOS's C library: no mallopt at all."""


def _no_process_handle(name):
    raise TypeError("no handle for the process itself")  # ctypes.CDLL(None) on Windows


@pytest.mark.parametrize("platform", ["musl", "macOS", "Windows"])
def test_nothing_is_done_outside_glibc(monkeypatch, no_user_thresholds, platform):
    other = _OtherLibc()
    cdll = {
        "musl": lambda name: other,
        "macOS": lambda name: _NoMallopt(),
        "Windows": _no_process_handle,
    }[platform]
    monkeypatch.setattr(_allocator.ctypes, "CDLL", cdll)
    assert keep_freed_memory() == ()
    assert other.mallopt.calls == []
