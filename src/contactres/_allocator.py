"""glibc's malloc thresholds in the processes the package owns (ground layer).

Why: glibc's ``malloc`` serves a block of at least its mmap threshold (128 KiB at a process's
start, raised by itself to the largest such block freed, up to 32 MiB) by an ``mmap`` of its
own, unmapped at ``free``; and it gives the top of its heap back to the kernel once more than
its trim threshold (128 KiB at the start too, then twice the mmap threshold once glibc has
raised that) of it is free. The analyses' numpy columns and
temporaries at 10^5 sweeps are of a few MB each (1.2 M points of 8 bytes: 9.6 MB), made and
freed thousands of times in patterns of many sizes, so that many come as new pages from the
kernel, which zeroes them and maps them in on their first touch. With transparent huge pages
(numpy asks for them for its large arrays) that is a few faults each zeroing 2 MB, so the
fault count understates the cost: the system CPU time is the measure.

What: :func:`keep_freed_memory` sets both thresholds to :data:`THRESHOLD` with ``mallopt``
(``M_MMAP_THRESHOLD`` = -3 first, then ``M_TRIM_THRESHOLD`` = -1, glibc's ``malloc.h``), as the
variables ``MALLOC_MMAP_THRESHOLD_`` and ``MALLOC_TRIM_THRESHOLD_`` would at a process's start:
blocks below it come from the heap and go back to it, and up to that much of freed heap is kept
for the next one. A threshold the user has set (by its variable, or by ``GLIBC_TUNABLES``) is
the user's and is left alone. The cost is memory: a process keeps up to :data:`THRESHOLD` of
freed heap, and a block freed inside the heap stays resident until reused.

Measured (issue 31, point 3; 2-core machine loaded by other work, settings alternated, 3 rounds;
session 29, MA29). ``contactres qcm analyze`` of the 10^5-sweep CSV, ``--no-figures``, the
whole job by ``/usr/bin/time -v`` (workers' time included; peak RSS is the largest process's):

================  ==================  ===========================  =========================
thresholds        system CPU s        minor faults (thousands)     peak RSS GB
================  ==================  ===========================  =========================
glibc's default   2.25, 2.14, 2.99    299, 294, 293                0.78, 0.76, 0.75
32 MiB            1.25, 1.59, 1.74    288, 287, 289                0.74, 0.79, 0.76
64 MiB            1.35, 1.60, 1.73    277, 280, 278                0.78, 0.79, 0.81
256 MiB           1.57, 1.57, 1.42    283, 283, 283                0.78, 0.78, 0.78
================  ==================  ===========================  =========================

(the thresholds set by the variables, in every process from its start; user CPU, 20.7-24.3 s,
varied with the load more than with the setting). The package's own setting at 32 MiB, against
the package without it, 3 more alternated pairs: system CPU 1.38, 1.40, 1.47 s against 2.52,
2.40, 2.04 s; faults 286 k, 286 k, 290 k against 304 k, 292 k, 297 k; peak RSS 0.76 GB against
0.73-0.78 GB; the output files identical byte for byte. ``analyze`` of the same table in a
Python session (the workers alone set, 2 workers, default settings), 3 pairs: the workers'
system CPU 0.25, 0.25, 0.17 s against 0.27, 0.23, 0.21 s, faults ~40 k either way, a worker's
peak RSS 0.39-0.40 GB either way: no gain while the kernel finds huge pages for fresh memory.
Once, without the setting, it did not (the variables' rounds above): the workers then took
258 k faults and 0.80 s of system CPU, against 48 k and 0.28 s at most with it, whose heap
pages are reused whatever the kernel has. Most of the job's saving is thus the main process's
(reading the CSV, formatting and writing the files).

32 MiB saves as much as the larger thresholds within the scatter, at the least memory kept, and
is the largest mmap threshold the ``mallopt(3)`` manual page allows on a 64-bit system
(``4 * 1024 * 1024 * sizeof(long)``; older glibc refuses values above half its heap size, newer
glibc, as 2.36 here, accepts any: a glibc that refuses it is left as it is,
:func:`keep_freed_memory`).

Where: in an analysis's worker processes (their initializer,
:mod:`contactres.analysis._workers`, with every start method: a forked process inherits the
parent's allocator as it is, a spawned one starts afresh), and in the command line's own process
when it runs as the program (``contactres ...`` and ``python -m contactres``:
:mod:`contactres.cli._app`). Not when a user's Python calls ``analyze`` or ``main([...])``: the
allocator of that process is the user's, and a setting made there would last for the rest of
its life. (A user's process that runs the program itself, e.g. ``%run -m contactres`` in
IPython or ``runpy``, is the program's: as for the one-thread BLAS setting.) Thresholds are read
from the environment when the call is made, not as glibc read it at the process's start: a
variable set later counts as the user's. glibc only: elsewhere (musl, macOS, Windows) nothing is
done, silently; those allocators behave differently and the measurement says nothing about
them. (The test is for the glibc C library: an allocator preloaded in its place, e.g. tcmalloc,
takes the call without effect.)
"""

from __future__ import annotations

import ctypes
import os
from typing import Any

__all__ = ["THRESHOLD", "keep_freed_memory"]

#: The value (bytes) both thresholds are set to: 32 MiB (module docstring: measured effect, and
#: why not more).
THRESHOLD = 32 * 1024 * 1024

#: glibc's ``mallopt`` parameter numbers (``malloc.h``), each with the environment variable and
#: the ``GLIBC_TUNABLES`` name by which a user sets the same threshold.
_PARAMETERS = (
    (-3, "MALLOC_MMAP_THRESHOLD_", "glibc.malloc.mmap_threshold"),
    (-1, "MALLOC_TRIM_THRESHOLD_", "glibc.malloc.trim_threshold"),
)


def _glibc() -> Any | None:
    """The C library of this process if it is glibc, else None."""
    try:
        libc = ctypes.CDLL(None)  # the symbols already loaded in the process
    except (OSError, TypeError):  # Windows: no handle for the process itself
        return None
    # glibc alone has this function (musl has a mallopt that does nothing; macOS has none).
    if not hasattr(libc, "gnu_get_libc_version") or not hasattr(libc, "mallopt"):
        return None
    return libc


def _set_by_user(variable: str, tunable: str) -> bool:
    """Whether the user has set the threshold of ``variable`` in the environment."""
    tunables = os.environ.get("GLIBC_TUNABLES", "")
    # An item without "=" is no setting: glibc skips it (review R29e), and reading it as the
    # user's would leave the trim threshold set alone, the state keep_freed_memory avoids.
    return variable in os.environ or any(
        sep and name == tunable
        for name, sep, _ in (item.partition("=") for item in tunables.split(":"))
    )


def keep_freed_memory() -> tuple[str, ...]:
    """Raise glibc's mmap and trim thresholds to :data:`THRESHOLD` in this process, for the rest
    of its life (module docstring: why, and where the package calls it).

    A threshold the user has set (``MALLOC_MMAP_THRESHOLD_``, ``MALLOC_TRIM_THRESHOLD_``, or
    the same in ``GLIBC_TUNABLES``) is kept. Outside glibc, nothing is done. No result of a
    computation changes: the allocator decides where the bytes live, not what they hold.

    Returns
    -------
    tuple of str
        The variables' names of the thresholds set (empty if none).

    Examples
    --------
    A process the program owns calls it first thing, e.g. a pool's worker processes:

    >>> from concurrent.futures import ProcessPoolExecutor
    >>> from contactres._allocator import keep_freed_memory
    >>> pool = ProcessPoolExecutor(2, initializer=keep_freed_memory)
    >>> pool.shutdown()
    """
    libc = _glibc()
    if libc is None:
        return ()
    libc.mallopt.argtypes = [ctypes.c_int, ctypes.c_int]
    libc.mallopt.restype = ctypes.c_int
    done = []
    for parameter, variable, tunable in _PARAMETERS:
        if _set_by_user(variable, tunable):
            continue
        if libc.mallopt(parameter, THRESHOLD) != 1:
            # Refused (a glibc that caps the mmap threshold lower): setting the trim threshold
            # alone would also fix the mmap threshold where it is, at 128 KiB, where glibc's
            # default raises it with the blocks freed; better leave both as they are.
            break
        done.append(variable)
    return tuple(done)
