"""Shared by the benchmarks: every target is printed with its ratio and a verdict.

A benchmark calls :func:`target` once per measured quantity and ends with
``sys.exit(exit_code(results))``, so that ``make bench`` can fail when a target is missed;
``benchmarks/run_all.py`` reads the printed lines back with :func:`parse_target` for its
verdict, and reports a ``TARGET`` line it cannot read.

Targets in seconds are judged on CPU time (issue 31): on a machine shared with other jobs the
wall time measures the load as much as the code. :func:`cpu_seconds` counts the process and
the child processes it has waited for (a benchmark that spawns workers pays for them);
:func:`best_time` and :func:`timed` use it. A target on parallel speed-up is a ratio of two
figures measured in the same run (printed with unit ``x``), never a wall time against a fixed
number.

Issue 31, point 1: a BLAS-bound workload prints its CPU time as shipped beside its CPU time with
one BLAS thread, and is judged on their ratio (at most :data:`THREAD_RATIO`): in process with
:func:`one_thread` (threadpoolctl's limit), or in a child process started with
:data:`ONE_BLAS_THREAD_ENV`.
"""

from __future__ import annotations

import re
import resource
import time
from typing import NamedTuple

#: As shipped / one BLAS thread, CPU time: the most a workload may pay for BLAS threads.
THREAD_RATIO = 1.2
#: The environment of a child process that runs on one BLAS thread from its start.
ONE_BLAS_THREAD_ENV = {"OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}


def one_thread(fn):
    """``fn`` made to run with one BLAS thread (threadpoolctl's limit, as under
    ``OPENBLAS_NUM_THREADS=1``)."""

    def call():
        from threadpoolctl import threadpool_limits

        with threadpool_limits(limits=1, user_api="blas"):
            return fn()

    return call


def thread_ratio(name: str, shipped: float, single: float) -> bool:
    """The target line of ``name``'s CPU time as shipped over its time with one BLAS thread
    (at most :data:`THREAD_RATIO`); True if met."""
    return target(f"{name}: as shipped / one BLAS thread", shipped / single, THREAD_RATIO, "x")


def shipped_and_one_thread(fn, repeat: int = 3) -> tuple[float, float]:
    """Best CPU time (s) of ``fn()`` as shipped and with one BLAS thread (:func:`one_thread`),
    ``repeat`` runs of each after one untimed call, in the order ABBA ABBA ... so that both
    see the same load (:func:`shipped_and_one_thread_of` with the same call every time).

    The untimed call takes the first call's costs off the shipped side: the lazy imports (the
    first ``fit_particles`` imports scipy.stats, ~650 modules, 0.7 s of CPU), the first page
    faults of its arrays, and the start of the threads of a BLAS library an import loads, which
    spin before they sleep (contactres._threads); the first fit of the 10⁴-step benchmark cost
    1.0-1.5 s more CPU than the next. Timed first, they left the shipped side one warm run
    against two of the other. The order
    ABBA puts neither side always after the other: the CPU time of a call drifts down over
    the first few calls of a process (allocator, page cache), which favoured the side timed
    second. With both sides running the same call, the plain alternation (A first, cold)
    gave "ratios" of 1.22, 1.29 and 1.22 on the shared 2-core machine (session 28).
    """
    return shipped_and_one_thread_of(lambda i: fn, repeat)


def shipped_and_one_thread_of(make, repeat: int = 3) -> tuple[float, float]:
    """:func:`shipped_and_one_thread` of a call built anew for each run: ``make(i)`` returns
    the call of run i (0 the untimed first one; 1, 2, ... the timed ones, in the order ABBA
    ABBA ...). For a workload whose cost the first run would change for the next, e.g. a
    curve of a material never seen before (``bench_dcsf``: its kernel table is built for each
    new material, and a repeated material would time the table's reuse instead)."""
    make(0)()
    shipped, single = [], []
    for i in range(repeat):
        runs = [(shipped, make(2 * i + 1)), (single, one_thread(make(2 * i + 2)))]
        for times, call in runs if i % 2 == 0 else runs[::-1]:
            times.append(timed(call)[1])
    return min(shipped), min(single)


def target(name: str, seconds: float, target_s: float, unit: str = "s") -> bool:
    """Print ``name``: measured value, target, ratio and MET/MISSED; return True if met.

    ``unit``: of the value and the target (default "s", seconds of CPU time; "MB" for memory,
    "x" for a ratio measured in the same run). The line is read back by :func:`parse_target`.
    """
    ratio = seconds / target_s
    met = seconds <= target_s
    print(
        f"  TARGET {name}: {seconds:.4g} {unit}, target {target_s:.4g} {unit}, ratio {ratio:.2f} "
        f"-> {'met' if met else 'MISSED'}"
    )
    return met


def cpu_seconds() -> float:
    """CPU time (s, user + system) of this process and of its children it has waited for.

    time.process_time (ns resolution) plus getrusage of the children (µs); os.times ticks in
    10 ms steps, too coarse for a 6 ms target."""
    children = resource.getrusage(resource.RUSAGE_CHILDREN)
    return time.process_time() + children.ru_utime + children.ru_stime


def timed(fn):
    """``(fn(), CPU seconds, wall seconds)`` of one call (CPU time as :func:`cpu_seconds`)."""
    c0, w0 = cpu_seconds(), time.perf_counter()
    out = fn()
    return out, cpu_seconds() - c0, time.perf_counter() - w0


def best_time(fn, repeat: int = 3, clock: str = "cpu") -> float:
    """Best time (s) of ``repeat`` runs of ``fn()``: CPU time (:func:`cpu_seconds`, the
    default, what targets are judged on) or, with ``clock="wall"``, wall-clock time."""
    if clock not in ("cpu", "wall"):
        raise ValueError(f"clock must be 'cpu' or 'wall', got {clock!r}")
    times = []
    for _ in range(repeat):
        _, cpu, wall = timed(fn)
        times.append(cpu if clock == "cpu" else wall)
    return min(times)


def exit_code(results: list[bool]) -> int:
    """0 when every target was met, 1 otherwise."""
    return 0 if all(results) else 1


# The line printed by :func:`target`, read back by run_all.py (keep the two in step).
TARGET_LINE = re.compile(
    r"^\s*TARGET (?P<name>.+): (?P<value>\S+) (?P<unit>\S+), target (?P<target>\S+) (?P=unit), "
    r"ratio \S+ -> (?P<verdict>met|MISSED)\s*$"
)


class Target(NamedTuple):
    """One target read back from a benchmark's output."""

    name: str
    value: float
    target: float
    met: bool
    unit: str


def parse_target(line: str) -> Target | None:
    """The :class:`Target` of a line printed by :func:`target`, else None."""
    m = TARGET_LINE.match(line)
    if m is None:
        return None
    return Target(
        m["name"], float(m["value"]), float(m["target"]), m["verdict"] == "met", m["unit"]
    )


def parse(line: str) -> tuple[str, float, float, bool] | None:
    """``(name, value, target, met)`` from a line printed by :func:`target`, else None."""
    t = parse_target(line)
    return None if t is None else (t.name, t.value, t.target, t.met)
