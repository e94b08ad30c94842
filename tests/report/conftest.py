"""Fixtures shared by the report tests."""

import contextlib
import importlib.util
import os
import shutil
from pathlib import Path

import pytest
from click.testing import CliRunner

import contactres
from contactres.cli import main

EXAMPLE = Path(contactres.__file__).parent / "data" / "example_sweeps.csv"


def _write_example_set(out: Path) -> None:
    args = ["qcm", "analyze", str(EXAMPLE), "--out", str(out), "--report", "html"]
    if all(importlib.util.find_spec(name) for name in ("openpyxl", "xarray")):
        # the workbook and the NetCDF file too, for tests/report/test_formats.py: one analysis
        args += ["--save-as", "xlsx,netcdf"]
    result = CliRunner().invoke(main, [*args, "--bootstrap", "0", "--no-figures"])
    assert result.exit_code == 0, result.output


@contextlib.contextmanager
def _locked(path: Path):
    """An exclusive lock on ``path`` (POSIX ``flock``), held while the block runs."""
    import fcntl

    with open(path, "a") as handle:
        fcntl.flock(handle, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(handle, fcntl.LOCK_UN)


@pytest.fixture(scope="session")
def example_set(tmp_path_factory) -> Path:
    """The results folder ``qcm analyze --report html --save-as xlsx,netcdf`` writes for the
    bundled example (no bootstrap, no figures; the workbook and NetCDF file where openpyxl and
    xarray are installed): analysed once for every test that reads it. Read-only: every
    worker's tests share the one folder, so a test that writes copies it first (as
    ``test_the_cli_writes_report_html_into_the_set`` does).

    Under pytest-xdist (``make test``) the test files that read it may run on different
    workers; the first worker writes it into the run's common temporary folder and the others
    wait for it and read that one (~4 s of CPU each otherwise). The set is complete when
    ``done`` exists beside it: a worker that died while writing leaves no ``done`` and the next
    one writes the set again. A run without workers (or without ``fcntl``) writes its own."""
    worker = os.environ.get("PYTEST_XDIST_WORKER")
    try:
        import fcntl  # noqa: F401  (POSIX only)
    except ImportError:
        worker = None
    if worker is None:
        out = tmp_path_factory.mktemp("example") / "results"
        _write_example_set(out)
        return out
    common = tmp_path_factory.getbasetemp().parent  # this run's, shared by its workers
    out, done = common / "example" / "results", common / "example-set-done"
    with _locked(common / "example-set.lock"):
        if not done.exists():
            shutil.rmtree(out.parent, ignore_errors=True)  # a dead worker's partial set
            _write_example_set(out)
            done.touch()
    return out
