"""The largest CSV table of a report written by a forked process beside the writing of the rest:
:func:`beside`.

Why: ``qcm analyze`` of 10^5 sweeps formats ~16 million cells (~1.1 s of CPU on one core, issue
31, point 3), three quarters of them in its curve table. numpy lets go of the interpreter lock
around each of its calls, but a chunk of a table is thousands of calls, and two threads
formatting side by side handed the lock back and forth at each (~15,600 context switches a
report; +50 % CPU for no shorter wall, measured on idle cores). A forked process has a lock of
its own: the curve table written by it while this process writes the others took the writing
from ~1.2-1.5 s to ~0.68 s of wall at the same CPU (prototype, idle cores). The forked process
reads the table from the memory it shares with this one (copy on write; nothing is pickled),
writes its file into the report's staging folder (atomically, as every file) and ends.

Only on Linux, where :mod:`multiprocessing` itself forks its workers (up to Python 3.13): macOS
has ``os.fork``, but a forked child of a process that used Apple's frameworks (Accelerate, under
numpy's BLAS there) may crash in them, which is why macOS's default there is ``spawn``; Windows
has no fork. Elsewhere, or with one core, the table is written here as before. The forked
process runs the CSV writer alone (numpy's arithmetic and the file's writes: no BLAS, nothing
logged or printed) and ends by ``os._exit`` (no exit handlers of this process run twice).
An exception of the forked process is raised here, as its own type and message, when it is
waited for; if this process fails first, the forked one is ended before the error goes on, so
that nothing writes into the staging folder that the result set then removes.
"""

from __future__ import annotations

import os
import pickle
import signal
import sys
from collections.abc import Callable, Iterator
from contextlib import contextmanager

__all__ = ["FORK_CELLS", "beside"]

#: The fewest cells of a table written by a forked process: below it (~0.1 s of formatting)
#: the fork and the wait cost more than they save.
FORK_CELLS = 2**21


#: Whether this system forks the writer (Linux: see the module's docstring).
_FORKS = sys.platform.startswith("linux") and hasattr(os, "fork")


def _cores() -> int:
    try:
        return len(os.sched_getaffinity(0))
    except (AttributeError, OSError):  # (not on every system)
        return os.cpu_count() or 1


@contextmanager
def beside(write: Callable[[], object], cells: int) -> Iterator[None]:
    """Run ``write()`` in a forked process while the block runs (here, after the block, where
    forking is not worth it or not done: fewer than :data:`FORK_CELLS` cells, one core, a
    system other than Linux). Leaving the block waits for it and raises its exception, if any; an
    exception of the block ends it first."""
    if cells < FORK_CELLS or _cores() < 2 or not _FORKS:
        yield
        write()
        return
    read, sent = os.pipe()
    pid = os.fork()
    if pid == 0:  # the forked process: write, send any exception, end without cleaning up
        code = 0
        try:
            os.close(read)
            write()
        except BaseException as exc:  # (sent as it is, to be raised by the parent)
            code = 1
            _send(sent, exc)
        finally:
            os._exit(code)  # (no atexit handlers, no flush of the parent's copied buffers)
    os.close(sent)
    try:
        yield
    except BaseException:
        os.kill(pid, signal.SIGKILL)
        os.waitpid(pid, 0)
        os.close(read)
        raise
    _wait(pid, read)


def _send(fd: int, exc: BaseException) -> None:
    try:
        data = pickle.dumps(exc)
        pickle.loads(data)  # (an exception that cannot be rebuilt is sent as its text)
    except Exception:
        data = pickle.dumps(RuntimeError(f"{type(exc).__name__}: {exc}"))
    view = memoryview(data)
    while view:
        view = view[os.write(fd, view) :]


def _wait(pid: int, fd: int) -> None:
    """Wait for the forked process ``pid``; raise the exception it sent on ``fd``."""
    chunks = []
    with os.fdopen(fd, "rb") as pipe:
        while block := pipe.read(1 << 16):
            chunks.append(block)
    _, status = os.waitpid(pid, 0)
    if chunks:
        raise pickle.loads(b"".join(chunks))
    if status != 0:
        raise RuntimeError(f"the process writing a table ended with status {status}")
