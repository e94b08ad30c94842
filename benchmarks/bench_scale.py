"""Benchmark: the sweep analysis at scale (issues 11, 31): 10^5 sweeps, a long one, plateaus.

Three tables, each analysed in a fresh process so that the peak resident memory it reports is
its own (``/proc/self/status`` VmHWM, reset before each stage; the worker processes' peak is
``resource.getrusage(RUSAGE_CHILDREN)``, the largest of them):

* **large**: the recipe of the bundled example (:func:`contactres.measurements.example_study`,
  14 experiments, 1,344 sweeps of 11 or 13 points) repeated 75 times with
  fresh noise (0.1 Hz on top, so that no two copies are alike): 100,800 sweeps, ~1.2 million
  points; plus one sweep of 700 points (the same forward model, one load). Built by repeating
  the forward model's output, not by calling it 10^5 times.
* **plateau**: 500 sweeps (25 experiments x 5 loads x 4 ramps) whose contact sticks up to
  d_c = 0.4 u_max (:class:`contactres.PlateauLoop`, noise 0.3 Hz, 13 points up to 10 nm);
* **cattaneo-mindlin**: the same 500 sweeps with the plain Cattaneo-Mindlin loop, for the
  per-sweep cost of the others.

Timed, as wall time and as CPU time (this process and its worker processes, user + system):
:func:`contactres.analysis._classify.fit_sweeps` with its padding (every model, the exact
plateau loop included, fitted to every sweep; the loop tables built once before), in this
process and in 2 worker processes, and the whole :func:`contactres.analysis.analyze` (no
bootstrap, which is per group, not per sweep; 2 worker processes, as ``qcm analyze`` uses all
cores from 10^4 sweeps on). For the large table also **end to end**: ``contactres qcm analyze
large.csv --no-figures`` in a fresh process (reading the 148 MB CSV, the analysis with its
200-resample bootstrap, the fitted curves, writing the folder), its CPU time (user + system,
its workers included), wall time and peak RSS (the largest of the process and its workers),
and the share of its wall time during which both cores worked (CPU / wall / cores).

The stages are measured from what a user's process holds when it calls
:func:`~contactres.analysis.analyze` (``analyze(read_sweeps(path))``): the validated sweep
table. The raw table that :func:`large_table` builds (~0.44 GB by pandas' deep count: four
columns of 1.2 million distinct Python strings, where the validated table shares one string per
distinct id) is built and validated in a process of its own, which writes the validated table
alone to a file (pickle) that the measuring process reads: freed in the measuring process, the
raw strings' memory would stay resident (Python keeps the partly used arenas of its small
objects), and the stages would start from ~0.6 GB instead of ~0.3 GB; a child of the measuring
process would count in its children's peak RSS, which includes the worker processes'. For the
same reason analyze is timed in a process of its own (``measure-analyze``), which has read the
validated table and done nothing else, as a user's process calling it. Run after the two
fit_sweeps stages in their process (``measure``, until session 28), it started from the heap
those stages left, 0.43 GB instead of a user's 0.23 GB at 10^5 sweeps; its CPU time read the
same within the noise of a loaded machine (20.0, 20.1, 20.5 s there against 19.7, 20.3,
20.3 s fresh, alternated), so the figures before and after the change compare, but the RSS
it starts from is now a user's. Each stage's peak RSS is printed beside the RSS it starts
from (``start``), so that what the stage itself adds shows.

The large table's analyze is timed a second time in a process started with one BLAS thread
(``OPENBLAS_NUM_THREADS=1``): its CPU time beside the first's shows that the analysis as
shipped holds its BLAS work to one thread (issue 31, point 1: as shipped within 1.2x of one
thread). The fit_sweeps stages run inside :func:`contactres._threads.one_blas_thread`, as
analyze runs them.

Targets (issue 31; 2-core reference machine, CPU time so that the load of other work on the
machine does not count): the large table's analyze and its end-to-end run in <= 15 s CPU and
<= 1 GB peak RSS; plateau sweeps no more than 2x the per-sweep cost of the Cattaneo-Mindlin
sweeps (fit_sweeps, one process). Wall time is printed beside CPU time (on an idle 2-core
machine the aim is wall <= 0.65 x CPU).

Run: ``.venv/bin/python benchmarks/bench_scale.py`` (exit status 1 if a target is missed; its
stages run as ``bench_scale.py build NAME PATH``, ``bench_scale.py measure PATH`` (the
fit_sweeps stages) and ``bench_scale.py measure-analyze PATH``).
"""

from __future__ import annotations

import gc
import json
import os
import pickle
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import pandas as pd
from _verdict import ONE_BLAS_THREAD_ENV, exit_code, target, thread_ratio

from contactres._threads import one_blas_thread
from contactres.analysis import AnalysisSettings, analyze
from contactres.analysis._amplitude import pad_sweeps
from contactres.analysis._classify import fit_sweeps
from contactres.analysis._loops import loop_tables
from contactres.measurements import (
    EXAMPLE_SEED,
    SweepGroup,
    SweepStudy,
    example_study,
    synthetic_sweeps,
    validate_sweeps,
)
from contactres.resonators import QCM

COPIES = 75  # x 1,344 sweeps = 100,800
LONG_POINTS = 700
TARGET_LARGE_CPU_S = 15.0
TARGET_LARGE_GB = 1.0
PLATEAU_RATIO = 2.0


def large_table() -> pd.DataFrame:
    """The example recipe repeated COPIES times (fresh noise) plus one LONG_POINTS sweep."""
    base = synthetic_sweeps(example_study(14), EXAMPLE_SEED, constants=True)
    rng = np.random.default_rng(11)
    k = np.repeat(np.arange(COPIES), len(base))
    big = pd.concat([base] * COPIES, ignore_index=True)
    tag = pd.Series(k).map("/c{}".format)
    big["sweep"] = big["sweep"] + tag
    big["experiment"] = big["experiment"] + tag
    for col in ("df_Hz", "dgamma_Hz"):
        big[col] = big[col] + rng.normal(0.0, 0.1, len(big))
    q = QCM(5e6, 3, 2.5e-5)
    u = tuple(np.linspace(0.1e-9, 10e-9, LONG_POINTS))
    group = SweepGroup("long", "air", 1.1e-3, 70e9, 0.1, u, 5.0 / q.sensitivity(3), 0.3)
    long = SweepStudy(groups=(group,), normal_forces=(4e-3,), n_experiments=1, ramps=(2,), qcm=q)
    return pd.concat([big, synthetic_sweeps(long, 5, constants=True)], ignore_index=True)


def study_table(model: str) -> pd.DataFrame:
    """500 sweeps of one loop model (plateau at 0.4 u_max, or Cattaneo-Mindlin)."""
    q = QCM(5e6, 3, 2.5e-5)
    amplitudes = tuple(np.linspace(0.5e-9, 10e-9, 13))
    group = SweepGroup("g", "air", 1.1e-3, 70e9, 0.1, amplitudes, 5.0 / q.sensitivity(3), 0.3)
    study = SweepStudy(
        groups=(group,),
        normal_forces=tuple(np.linspace(2e-3, 8e-3, 5)),
        n_experiments=25,
        qcm=q,
        model=model,
        plateau_fraction=0.4,
        scatter=(("mu", 0.05),),
    )
    return synthetic_sweeps(study, 3, constants=True)


def reset_peak() -> None:
    """Restart the peak-RSS count of this process (Linux; elsewhere the peak since start)."""
    try:
        with open("/proc/self/clear_refs", "w") as f:
            f.write("5")
    except OSError:
        pass


def peak_gb() -> float:
    """Peak resident memory of this process since :func:`reset_peak`, GB."""
    try:
        with open("/proc/self/status") as f:
            kb = next(int(line.split()[1]) for line in f if line.startswith("VmHWM"))
    except (OSError, StopIteration):
        kb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    return kb / 2**20


def cpu_s() -> float:
    """CPU time (user + system, s) of this process and of its finished worker processes."""
    me, kids = (resource.getrusage(who) for who in (resource.RUSAGE_SELF, resource.RUSAGE_CHILDREN))
    return me.ru_utime + me.ru_stime + kids.ru_utime + kids.ru_stime


def fork_workers() -> None:
    """Have the analysis's worker processes forked from this process, where fork exists.

    :func:`cpu_s` and :func:`workers_gb` read ``RUSAGE_CHILDREN``, which counts the processes
    this one has waited for: a forked worker is one, but one started by ``forkserver`` (the
    default on Linux from Python 3.14) is a child of the fork server, and its CPU time and
    memory would not be counted at all."""
    import multiprocessing

    if "fork" in multiprocessing.get_all_start_methods():
        multiprocessing.set_start_method("fork", force=True)


def workers_gb() -> float:
    """Peak resident memory of the largest finished worker process so far, GB (Linux: kB)."""
    return resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 2**20


def rss_gb() -> float:
    """Resident memory of this process now, GB (Linux; elsewhere NaN)."""
    try:
        with open("/proc/self/status") as f:
            return next(int(line.split()[1]) for line in f if line.startswith("VmRSS")) / 2**20
    except (OSError, StopIteration):
        return float("nan")


def timed(out: dict, stage: str, fn) -> None:
    """Run ``fn()``; put its wall and CPU time (s), the RSS it starts from and its peak RSS
    (GB) into ``out``."""
    gc.collect()  # what is garbage before the stage is not the stage's
    out[f"{stage}_start_gb"] = rss_gb()
    reset_peak()
    t0, c0 = time.perf_counter(), cpu_s()
    fn()
    out[f"{stage}_s"] = time.perf_counter() - t0
    out[f"{stage}_cpu"] = cpu_s() - c0
    out[f"{stage}_gb"] = max(peak_gb(), workers_gb())


def build(name: str, path: Path) -> None:
    """Table ``name`` (``large`` or a :func:`study_table` model), validated, pickled to ``path``
    (run in a process of its own: module docstring)."""
    table = validate_sweeps(large_table() if name == "large" else study_table(name))
    with open(path, "wb") as f:
        pickle.dump(table, f, protocol=pickle.HIGHEST_PROTOCOL)


def measure(path: str | Path) -> dict:
    """Time fit_sweeps on the validated table pickled at ``path`` by :func:`build`, in this
    process and in 2 worker processes (run in a fresh process; analyze is timed in another,
    :func:`measure_analyze`)."""
    # A user's process holds the validated table, not the raw one it was made from.
    with open(path, "rb") as f:
        sweeps = pickle.load(f)
    out: dict = {"points": len(sweeps)}
    loop_table = loop_tables()
    for workers in (1, 2):

        def fit(workers=workers, loop_table=loop_table):
            # analyze runs its fits on one BLAS thread (its decorator): so do these stages.
            with one_blas_thread():
                out["sw"], _ = fit_sweeps(
                    pad_sweeps(sweeps.data), tables=loop_table, workers=workers
                )

        timed(out, f"fit_sweeps_{workers}", fit)
    sw = out.pop("sw")
    return out | {
        "sweeps": len(sw),
        "longest": int(sw["n_points"].max()),
        "models": sw["model"].value_counts().to_dict(),
    }


def measure_analyze(path: str | Path) -> dict:
    """Time analyze alone on the validated table pickled at ``path`` (run in a fresh process,
    as a user's process calls it; run again with one BLAS thread set in its environment, for
    the as-shipped / one-thread ratio)."""
    with open(path, "rb") as f:
        sweeps = pickle.load(f)
    out: dict = {}
    timed(
        out, "analyze", lambda: analyze(sweeps, settings=AnalysisSettings(bootstrap=0, workers=2))
    )
    return out


def end_to_end() -> dict:
    """``contactres qcm analyze`` of the large table written as CSV, in a fresh process."""
    with tempfile.TemporaryDirectory() as tmp:
        csv = Path(tmp) / "large.csv"
        large_table().to_csv(csv, index=False, float_format="%.7g")
        script = Path(sys.executable).with_name("contactres")
        cli = [str(script)] if script.exists() else [sys.executable, "-m", "contactres"]
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        t0 = time.perf_counter()
        subprocess.run(
            [*cli, "qcm", "analyze", str(csv), "--out", str(Path(tmp) / "out"), "--no-figures"],
            check=True,
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
        )
        wall = time.perf_counter() - t0
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = sum(getattr(after, k) - getattr(before, k) for k in ("ru_utime", "ru_stime"))
    return {"wall_s": wall, "cpu_s": cpu, "gb": after.ru_maxrss / 2**20}


def main() -> int:
    import multiprocessing

    method = multiprocessing.get_start_method()
    if method != "fork":
        # The measuring stages fork their workers (fork_workers); the command line run end to
        # end cannot be told to, and RUSAGE_CHILDREN does not reach a fork server's children.
        print(
            f"NOTE: worker processes start by {method} here: the end-to-end CPU time and peak "
            "RSS below leave out the workers' (the other stages fork theirs)"
        )
    runs = {}
    for name in ("large", "plateau", "cattaneo-mindlin"):
        with tempfile.TemporaryDirectory() as tmp:
            path = str(Path(tmp) / f"{name}.pickle")
            subprocess.run([sys.executable, __file__, "build", name, path], check=True)
            out = subprocess.run(
                [sys.executable, __file__, "measure", path],
                capture_output=True,
                text=True,
                check=True,
            )
            alone = subprocess.run(
                [sys.executable, __file__, "measure-analyze", path],
                capture_output=True,
                text=True,
                check=True,
            )
            if name == "large":  # the same analyze with one BLAS thread set from the start
                one = subprocess.run(
                    [sys.executable, __file__, "measure-analyze", path],
                    capture_output=True,
                    text=True,
                    check=True,
                    env=os.environ | ONE_BLAS_THREAD_ENV,
                )
        runs[name] = json.loads(out.stdout.splitlines()[-1])
        runs[name] |= json.loads(alone.stdout.splitlines()[-1])
        r = runs[name]
        print(f"{name}: {r['sweeps']} sweeps, {r['points']} points (longest {r['longest']})")
        print(f"  models: {r['models']}")
        for stage in ("fit_sweeps_1", "fit_sweeps_2", "analyze"):
            per = 1e3 * r[f"{stage}_cpu"] / r["sweeps"]
            print(
                f"  {stage + ':':13s} {r[f'{stage}_cpu']:8.2f} s CPU ({per:.3f} ms per sweep), "
                f"{r[f'{stage}_s']:8.2f} s wall, peak RSS {r[f'{stage}_gb']:.2f} GB "
                f"(start {r[f'{stage}_start_gb']:.2f} GB)"
            )
    large, pl, cm = runs["large"], runs["plateau"], runs["cattaneo-mindlin"]
    n = large["sweeps"]
    # In a fresh process too: the peak RSS of finished children is the largest since start.
    out = subprocess.run(
        [sys.executable, __file__, "end-to-end"], capture_output=True, text=True, check=True
    )
    e2e = json.loads(out.stdout.splitlines()[-1])
    cores = os.cpu_count() or 1
    print(
        f"qcm analyze, {n} sweeps, end to end: {e2e['cpu_s']:.2f} s CPU, {e2e['wall_s']:.2f} s "
        f"wall ({e2e['cpu_s'] / e2e['wall_s']:.2f} cores of {cores}), peak RSS {e2e['gb']:.2f} GB"
    )
    results = [
        target(f"analyze, {n} sweeps (CPU)", large["analyze_cpu"], TARGET_LARGE_CPU_S),
        target(f"peak RSS of analyze, {n} sweeps (GB as s)", large["analyze_gb"], TARGET_LARGE_GB),
        target(f"qcm analyze end to end, {n} sweeps (CPU)", e2e["cpu_s"], TARGET_LARGE_CPU_S),
        target(f"peak RSS of qcm analyze, {n} sweeps (GB as s)", e2e["gb"], TARGET_LARGE_GB),
    ]
    one_thread = json.loads(one.stdout.splitlines()[-1])["analyze_cpu"]
    print(
        f"  analyze, {n} sweeps, CPU: as shipped {large['analyze_cpu']:.2f} s | one BLAS "
        f"thread (OPENBLAS_NUM_THREADS=1) {one_thread:.2f} s"
    )
    results.append(thread_ratio(f"analyze, {n} sweeps", large["analyze_cpu"], one_thread))
    speedup = large["fit_sweeps_1_s"] / large["fit_sweeps_2_s"]
    cost = large["fit_sweeps_2_cpu"] / large["fit_sweeps_1_cpu"]
    print(
        f"  fit_sweeps, 2 processes instead of 1: {speedup:.2f}x faster in wall time, "
        f"{cost:.2f}x the CPU time"
    )
    for stage in ("fit_sweeps_1", "analyze"):
        ratio = (pl[f"{stage}_cpu"] / pl["sweeps"]) / (cm[f"{stage}_cpu"] / cm["sweeps"])
        print(f"  plateau / cattaneo-mindlin per-sweep cost, {stage}: {ratio:.2f}")
    # At scale: the per-sweep rate of the large table plus the extra cost of a plateau refit.
    extra = (pl["fit_sweeps_1_cpu"] - cm["fit_sweeps_1_cpu"]) / pl["models"].get("plateau", 1)
    rate = large["fit_sweeps_1_cpu"] / n
    print(
        f"  a plateau sweep at the rate of the large table: {1e3 * (rate + extra):.3f} ms, "
        f"{(rate + extra) / rate:.2f}x the others ({1e3 * extra:.3f} ms for its refit)"
    )
    # The target is on the per-sweep fits of equal tables, where the plateau refit happens.
    ratio = (pl["fit_sweeps_1_cpu"] / pl["sweeps"]) / (cm["fit_sweeps_1_cpu"] / cm["sweeps"])
    results.append(target("plateau per-sweep cost (ratio as s)", ratio, PLATEAU_RATIO))
    return exit_code(results)


if __name__ == "__main__":
    if len(sys.argv) > 1:  # the stages of main(), each in a fresh process
        stage, args = sys.argv[1], sys.argv[2:]
        if stage == "build" and len(args) == 2:
            build(args[0], Path(args[1]))
        elif stage == "measure" and len(args) == 1:
            fork_workers()
            print(json.dumps(measure(args[0])))
        elif stage == "measure-analyze" and len(args) == 1:
            fork_workers()
            print(json.dumps(measure_analyze(args[0])))
        elif stage == "end-to-end" and not args:
            print(json.dumps(end_to_end()))
        else:
            sys.exit(
                "usage: bench_scale.py [build NAME PATH | measure PATH | measure-analyze PATH | "
                "end-to-end] "
                f"(got {' '.join(sys.argv[1:])!r})"
            )
        sys.exit(0)
    sys.exit(main())
