"""Benchmark: ``contactres qcm analyze`` on ~1,300 sweeps (~16,000 points), without figures.

Target (design.md §6): under 5 s end to end on the 2-core reference machine. The table is the
recipe of scripts/make_example_data.py with 14 experiments (1,344 sweeps, 16,128 points). Timed:
reading + validating the CSV, the whole analysis (every sweep fitted with four amplitude models
and the exact Cattaneo-Mindlin loop, drift tests, per-load statistics, JKR fits with a
200-resample bootstrap) and writing sweeps.csv, loads.csv, summary.json. The one-off table of the
exact loop (made from the forward model on first use in a process) is timed on its own and is
included in the end-to-end figure.
"""

from __future__ import annotations

import importlib.util
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
TARGET_S = 5.0


def _load_generator():
    path = HERE.parent / "scripts" / "make_example_data.py"
    spec = importlib.util.spec_from_file_location("make_example_data", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def main() -> int:
    gen = _load_generator()
    table = gen.make_sweeps(n_experiments=14)
    n_sweeps, n_points = table["sweep"].nunique(), len(table)
    with tempfile.TemporaryDirectory() as tmp:
        csv = Path(tmp) / "sweeps.csv"
        table.to_csv(csv, index=False, float_format="%.7g")

        from contactres.analysis import analyze
        from contactres.analysis.classify import cm_loop_table
        from contactres.measurements.sweeps import read_sweeps

        cm_loop_table.cache_clear()
        t0 = time.perf_counter()
        cm_loop_table()
        t_table = time.perf_counter() - t0

        cm_loop_table.cache_clear()
        t0 = time.perf_counter()
        t = read_sweeps(csv)
        t1 = time.perf_counter()
        res = analyze(t)
        t2 = time.perf_counter()
        res.write(Path(tmp) / "out", figures=False)
        t3 = time.perf_counter()
    total = t3 - t0
    print(f"sweeps: {n_sweeps}, points: {n_points}")
    print(f"  exact-loop table (once per process): {t_table:.3f} s")
    print(f"  read + validate:  {t1 - t0:.3f} s")
    print(f"  analyze:          {t2 - t1:.3f} s")
    print(f"  write (no figs):  {t3 - t2:.3f} s")
    print(f"  end to end:       {total:.3f} s  ({1e3 * total / n_sweeps:.2f} ms per sweep)")
    verdict = "OK" if total < TARGET_S else "SLOW"
    print(f"  target {TARGET_S:.1f} s: ratio {total / TARGET_S:.2f} -> {verdict}")
    models = res.sweeps["model"].value_counts().to_dict()
    print(f"  models: {models}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
