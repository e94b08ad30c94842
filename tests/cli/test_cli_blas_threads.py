"""The command line asks OpenBLAS for one thread before numpy loads it
(:func:`contactres.cli._app.one_blas_thread_from_start`).

The threads OpenBLAS starts when it is loaded spin for ~0.1 s of CPU each, for work the jobs run
on one thread anyway (issue 31). Observed from outside: a fresh interpreter runs a command and
reports, at its exit, the variable and OpenBLAS's own thread count (threadpoolctl's lookup).
"""

from __future__ import annotations

import json
import os
import subprocess
import sys

import pytest

from contactres.cli import _app

_PROBE = """
import atexit, json, os, runpy, sys
def report():
    from threadpoolctl import threadpool_info
    counts = [lib["num_threads"] for lib in threadpool_info() if lib["internal_api"] == "openblas"]
    variable = os.environ.get("OPENBLAS_NUM_THREADS")
    print(json.dumps({"variable": variable, "openblas": counts, "numpy": "numpy" in sys.modules}))
atexit.register(report)
sys.argv = ["contactres", *sys.argv[1:]]
runpy.run_module("contactres", run_name="__main__", alter_sys=True)
"""
#: A cheap command that imports numpy (its table of crystals; no one-thread context opened, so
#: the count at exit is the one OpenBLAS started with).
COMMAND = ["crystals"]


#: A program that runs the command in-process, passing its arguments (numpy not yet
#: loaded when it does).
_IN_PROCESS = {
    "main": "from contactres.cli import main\nmain(sys.argv[1:])",
    "CliRunner": (
        "from click.testing import CliRunner\nfrom contactres.cli import main\n"
        "assert CliRunner().invoke(main, sys.argv[1:]).exit_code == 0"
    ),
}


def _run(environ: dict[str, str], program: str | None = None) -> dict:
    env = {k: v for k, v in os.environ.items() if k not in _app.THREAD_COUNT_VARIABLES}
    probe = _PROBE if program is None else _PROBE.split("sys.argv =")[0] + program
    p = subprocess.run(
        [sys.executable, "-c", probe, *COMMAND],
        env=env | environ,
        capture_output=True,
        text=True,
        check=False,
    )
    assert p.returncode == 0, p.stderr
    return json.loads(p.stdout.splitlines()[-1])


def test_the_command_line_starts_openblas_with_one_thread():
    out = _run({})
    assert out["numpy"]  # else the variable came too early to matter: no test
    assert out["variable"] == "1"
    # OpenBLAS's own count where numpy's BLAS is OpenBLAS (the variable is OpenBLAS's alone).
    assert max(out["openblas"], default=1) == 1


def test_the_command_line_keeps_a_thread_count_the_user_set():
    for name in _app.THREAD_COUNT_VARIABLES:
        out = _run({name: "2"})
        assert out["variable"] == ("2" if name == "OPENBLAS_NUM_THREADS" else None), name


def test_nothing_is_set_once_numpy_is_loaded(monkeypatch):
    # numpy is imported in this process (as in a CliRunner test): the count is fixed, and the
    # environment, inherited by any child process started later, must stay as it was.
    for name in _app.THREAD_COUNT_VARIABLES:
        monkeypatch.delenv(name, raising=False)
    assert "numpy" in sys.modules
    assert _app.one_blas_thread_from_start() is False
    assert not any(name in os.environ for name in _app.THREAD_COUNT_VARIABLES)


@pytest.mark.parametrize("program", list(_IN_PROCESS))
def test_a_program_calling_the_command_line_keeps_its_environment(program):
    # The variable would outlive the call: the caller's later numpy work and its children
    # would run with one BLAS thread. Here numpy loads only inside the call (else nothing
    # could be set, and the test could not fail).
    out = _run({}, _IN_PROCESS[program])
    assert out["numpy"]
    assert out["variable"] is None
