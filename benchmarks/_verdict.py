"""Shared by the benchmarks: every timed target is printed with its ratio and a verdict.

A benchmark calls :func:`target` once per timed quantity and ends with
``sys.exit(exit_code(results))``, so that ``make bench`` can fail when a target is missed;
``benchmarks/run_all.py`` reads the printed lines back with :func:`parse` for its verdict.
"""

from __future__ import annotations

import re
import time


def target(name: str, seconds: float, target_s: float) -> bool:
    """Print ``name``: measured time, target, ratio and MET/MISSED; return True if met."""
    ratio = seconds / target_s
    met = seconds <= target_s
    print(
        f"  TARGET {name}: {seconds:.4g} s, target {target_s:.4g} s, ratio {ratio:.2f} "
        f"-> {'met' if met else 'MISSED'}"
    )
    return met


def best_time(fn, repeat: int = 3, clock=time.perf_counter) -> float:
    """Best time (s) of ``repeat`` runs of ``fn()`` on ``clock`` (default: the wall clock)."""
    times = []
    for _ in range(repeat):
        t0 = clock()
        fn()
        times.append(clock() - t0)
    return min(times)


def best_cpu_time(fn, repeat: int = 3) -> float:
    """Best CPU time (s, ``time.process_time``: every thread of this process) of ``repeat``
    runs of ``fn()``; on a shared machine the fair measure of the work done, where the wall
    time counts the other jobs too."""
    return best_time(fn, repeat, time.process_time)


def exit_code(results: list[bool]) -> int:
    """0 when every target was met, 1 otherwise."""
    return 0 if all(results) else 1


# The line printed by :func:`target`, read back by run_all.py (keep the two in step).
TARGET_LINE = re.compile(
    r"^\s*TARGET (?P<name>.+): (?P<seconds>\S+) s, target (?P<target>\S+) s, "
    r"ratio \S+ -> (?P<verdict>met|MISSED)\s*$"
)


def parse(line: str) -> tuple[str, float, float, bool] | None:
    """``(name, seconds, target_s, met)`` from a line printed by :func:`target`, else None."""
    m = TARGET_LINE.match(line)
    if m is None:
        return None
    return m["name"], float(m["seconds"]), float(m["target"]), m["verdict"] == "met"
