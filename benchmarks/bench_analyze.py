"""Benchmark: ``contactres qcm analyze`` on ~1,300 sweeps (~16,000 points), without figures.

Target: under 5 s end to end on the 2-core reference machine (wall time; the CPU time of each
stage and the peak resident memory are printed beside it). The table is the
recipe of the bundled example data (:func:`contactres.measurements.example_study`)
with 14 experiments: 1,344 sweeps, 16,128 points. Timed, once, as a user's run would be:
reading + validating the CSV, the whole analysis (every sweep fitted with four amplitude models
and the exact Cattaneo-Mindlin loop, drift tests, per-load statistics, JKR fits with a
200-resample bootstrap, and the table of the exact loop that the analysis builds on every call)
and writing sweeps.csv, loads.csv, summary.json. The loop table alone is also timed, for
information. The interpreter's start and ``import contactres`` are not included (see
bench_startup.py).

Run: ``.venv/bin/python benchmarks/bench_analyze.py`` (exit status 1 if the target is missed).
"""

from __future__ import annotations

import resource
import sys
import tempfile
import time
from pathlib import Path

from _verdict import exit_code, target

from contactres.analysis import analyze
from contactres.analysis._loops import cm_loop_table
from contactres.measurements import EXAMPLE_SEED, example_study, read_sweeps, synthetic_sweeps
from contactres.report import write_report

TARGET_S = 5.0
N_EXPERIMENTS = 14


def cpu_s() -> float:
    """CPU time (user + system, s) of this process and of its finished worker processes."""
    me = resource.getrusage(resource.RUSAGE_SELF)
    kids = resource.getrusage(resource.RUSAGE_CHILDREN)
    return me.ru_utime + me.ru_stime + kids.ru_utime + kids.ru_stime


def main() -> int:
    table = synthetic_sweeps(example_study(N_EXPERIMENTS), EXAMPLE_SEED, constants=True)
    n_sweeps, n_points = table["sweep"].nunique(), len(table)
    with tempfile.TemporaryDirectory() as tmp:
        csv = Path(tmp) / "sweeps.csv"
        table.to_csv(csv, index=False, float_format="%.7g")

        t0 = time.perf_counter()
        cm_loop_table()
        t_table = time.perf_counter() - t0

        t0, c0 = time.perf_counter(), cpu_s()
        sweeps = read_sweeps(csv)
        t1, c1 = time.perf_counter(), cpu_s()
        res = analyze(sweeps)
        t2, c2 = time.perf_counter(), cpu_s()
        write_report(res, Path(tmp) / "out", formats=("csv", "json"))
        t3, c3 = time.perf_counter(), cpu_s()
    total = t3 - t0
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**10  # Linux: kB
    print(f"qcm analyze: {n_sweeps} sweeps, {n_points} points (wall, CPU)")
    print(f"  exact-loop table (part of analyze): {t_table:.3f} s")
    print(f"  read + validate:  {t1 - t0:.3f} s, {c1 - c0:.3f} s CPU")
    print(f"  analyze:          {t2 - t1:.3f} s, {c2 - c1:.3f} s CPU")
    print(f"  write (no figs):  {t3 - t2:.3f} s, {c3 - c2:.3f} s CPU")
    print(
        f"  per sweep:        {1e3 * total / n_sweeps:.2f} ms, "
        f"{1e3 * (c3 - c0) / n_sweeps:.2f} ms CPU"
    )
    print(f"  peak RSS of the process: {peak:.0f} MB")
    print(f"  models: {res.sweeps['model'].value_counts().to_dict()}")
    results = [target(f"qcm analyze, {n_sweeps} sweeps, no figures", total, TARGET_S)]
    return exit_code(results)


if __name__ == "__main__":
    sys.exit(main())
