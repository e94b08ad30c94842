"""glibc's malloc thresholds in the processes the package owns (ground layer).

Why: glibc's ``malloc`` serves every block of at least ``M_MMAP_THRESHOLD`` bytes (128 KiB to
start with) by a fresh ``mmap`` of its own, and gives it back to the kernel at ``free``; and it
gives the top of its heap back (``M_TRIM_THRESHOLD``) once more than a few hundred KiB of it are
free. numpy's arrays and temporaries of the analyses at 10^5 sweeps are of a few MB each (a
column of 1.2 M points is 9.6 MB), made and freed thousands of times: each one comes as new
pages from the kernel, which zeroes them and maps them in, page fault by page fault, on their
first touch. ``contactres qcm analyze`` of 10^5 sweeps spent ~2.5 s of its ~23 s of CPU in the
kernel that way (issue 31, point 3). With both thresholds raised to :data:`THRESHOLD`, such
blocks come from the heap and go back to it, and its freed pages are kept for the next one.

What: :func:`keep_freed_memory` sets both thresholds with ``mallopt`` (``M_TRIM_THRESHOLD`` =
-1, ``M_MMAP_THRESHOLD`` = -3 in glibc's ``malloc.h``), as the variables
``MALLOC_TRIM_THRESHOLD_`` and ``MALLOC_MMAP_THRESHOLD_`` would at a process's start. A
threshold the user has set (by its variable, or by ``GLIBC_TUNABLES``) is the user's and is left
alone. The cost is memory: the heap keeps up to :data:`THRESHOLD` bytes of freed pages, and a
block below the threshold freed inside the heap may stay resident until the blocks above it are
freed too.

Measured (``/usr/bin/time -v``, 2-core machine loaded by other work, alternated runs): see
:data:`THRESHOLD`.

Where: in an analysis's worker processes (their initializer,
:mod:`contactres.analysis._workers`, with every start method: a forked process inherits the
parent's allocator as it is, a spawned one starts afresh), and in the command line's own process
when it runs as the program (``contactres ...`` and ``python -m contactres``:
:mod:`contactres.cli._app`). Not when a user's Python calls ``analyze`` or ``main([...])``: the
allocator of that process is the user's, and a setting made there would last for the rest of
its life. glibc only: elsewhere (musl, macOS, Windows) nothing is done, silently; those
allocators behave differently and the measurement says nothing about them.
"""

from __future__ import annotations

import ctypes
import os
from typing import Any

__all__ = ["THRESHOLD", "keep_freed_memory"]

#: The value (bytes) both thresholds are set to. See the module docstring; measured effect at
#: 10^5 sweeps in the note below.
THRESHOLD = 256 * 1024 * 1024

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
    return variable in os.environ or any(
        item.split("=", 1)[0] == tunable for item in tunables.split(":")
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
