"""Which functions hold one BLAS thread (:func:`contactres._threads.one_blas_thread`), pinned.

The decorator sits on the entry of each batched small-matrix computation (issue 31, point 1).
A helper inserted between the decorator and its function once moved the decorator onto the
helper, silently: the tangential table then ran on OpenBLAS's default threads. The list below
is the intended one; the second test checks the context is open inside the table's own work.
"""

from __future__ import annotations

import re
from pathlib import Path

import threadpoolctl

import contactres
from contactres import Material, _threads
from contactres.analysis._workers import WorkerPool
from contactres.dynamic import _tangential_table, prepare_tangential

DECORATED = {
    ("analysis/_coating.py", "apply_coating"),
    ("dynamic/_normal_stiffness.py", "evaluate_models"),
    ("dynamic/_normal_stiffness.py", "contact_displacement"),
    ("dynamic/_normal_stiffness.py", "contact_pressure"),
    ("dynamic/_dcsf.py", "dcsf_models"),
    ("dynamic/_tangential_galerkin.py", "tangential_per_a"),
    ("dynamic/_table.py", "kernel_table"),
    ("dynamic/_layered_punch.py", "layered_punch_stiffness"),
    ("dynamic/_tangential_table.py", "prepare_tangential"),
    # The analyses' public entries: their fits batch small matrices too (the plateau evidence's
    # level sums, the loops' χ² products), and at 10^5 sweeps a second thread spinning between
    # them cost 40 s of CPU against 24 s on one thread (issue 31, session 27).
    ("analysis/_pipeline.py", "analyze"),
    ("analysis/_particles.py", "fit_particles"),
    ("analysis/_resonance_tables.py", "invert_afm_table"),
    ("analysis/_resonance_tables.py", "invert_rum_table"),
    ("analysis/_cr_map.py", "invert_cr_map"),
    ("measurements/_spectra.py", "fit_resonances"),
} | {
    # Every job that computes (crystals and examples list tables and compute nothing).
    (f"jobs/{job}.py", "run")
    for job in (
        "afm_invert afm_map contact dcsf demo maps_fit maps_predict maps_synthetic paper1 "
        "paper2 qcm_loop qcm_particles qcm_spectra qcm_stiffness qcm_sweeps rum_invert"
    ).split()
}
_DECORATED_DEF = re.compile(r"^@one_blas_thread\(\)[^\n]*\n(?:@[^\n]*\n)*def (\w+)", re.M)


def test_the_decorator_sits_on_the_intended_functions():
    root = Path(contactres.__file__).parent
    found = {
        (path.relative_to(root).as_posix(), name)
        for path in root.rglob("*.py")
        for name in _DECORATED_DEF.findall(path.read_text(encoding="utf-8"))
    }
    assert found == DECORATED


def test_the_tangential_table_is_prepared_inside_the_context(monkeypatch):
    depths = []
    tail = _tangential_table.kernel_tail

    def spy(m):
        depths.append(_threads._OPEN.depth)
        return tail(m)

    monkeypatch.setattr(_tangential_table, "kernel_tail", spy)
    prepare_tangential(Material.isotropic(70e9, 0.3, 2700.0), rtol=1e-3)
    assert depths and all(d >= 1 for d in depths)


def _blas_threads(_task) -> list[int]:
    """The BLAS thread counts of the process running this (a worker's task)."""
    return [
        lib["num_threads"] for lib in threadpoolctl.threadpool_info() if lib["user_api"] == "blas"
    ]


def test_the_analysis_worker_processes_run_on_one_blas_thread():
    # Two threads in the parent (make test runs with OPENBLAS_NUM_THREADS=1, which a forked
    # worker would inherit and so pass without its initializer): each worker process sets its
    # own count, whatever the start method gives it.
    with threadpoolctl.threadpool_limits(2, user_api="blas"), WorkerPool(2) as pool:
        counts = list(pool.imap(_blas_threads, 4, range(4)))
    assert counts and all(c and set(c) == {1} for c in counts)
