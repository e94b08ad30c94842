"""The largest table of a report written by a forked process (contactres.report._forked,
issue 31 point 3): the same files, byte for byte; the forked process's exception raised by the
report's writer as its own; the forked process ended when the writer fails; no results folder
left by a failed report."""

import os
import sys

import numpy as np
import pytest

from contactres.report import _forked

pytestmark = pytest.mark.skipif(not _forked._FORKS, reason="the writer forks on Linux only")


@pytest.fixture
def forking(monkeypatch):
    """Every table written by a forked process, whatever its size and the cores."""
    monkeypatch.setattr(_forked, "FORK_CELLS", 0)
    monkeypatch.setattr(_forked, "_cores", lambda: 2)


def _no_child_left():
    try:
        return os.waitpid(-1, os.WNOHANG) is None
    except ChildProcessError:  # no child at all
        return True


def test_the_write_runs_in_another_process_and_is_waited_for(tmp_path, forking):
    target = tmp_path / "pid"
    with _forked.beside(lambda: target.write_text(str(os.getpid())), cells=10):
        pass
    assert int(target.read_text()) != os.getpid()
    assert _no_child_left()


def test_the_forked_exception_is_raised_by_the_writer_as_its_own(forking):
    def fails():
        raise ValueError("bad cell 7")

    with pytest.raises(ValueError, match=r"^bad cell 7$"):
        with _forked.beside(fails, cells=10):
            pass
    assert _no_child_left()


def test_a_failure_of_the_writer_ends_the_forked_process_first(forking):
    """The forked write waits for ever on a pipe nobody writes to: the writer's own error
    must end it (else this test would hang in the wait)."""
    r, w = os.pipe()
    try:
        with pytest.raises(KeyError):
            with _forked.beside(lambda: os.read(r, 1), cells=10):
                raise KeyError("the writer failed")
        assert _no_child_left()
    finally:
        os.close(r)
        os.close(w)


def test_small_tables_or_one_core_are_written_here(monkeypatch, tmp_path):
    monkeypatch.setattr(_forked, "_cores", lambda: 2)
    pids = []
    with _forked.beside(lambda: pids.append(os.getpid()), cells=_forked.FORK_CELLS - 1):
        assert pids == []  # (written after the block, as the last table)
    monkeypatch.setattr(_forked, "_cores", lambda: 1)
    with _forked.beside(lambda: pids.append(os.getpid()), cells=_forked.FORK_CELLS):
        pass
    assert pids == [os.getpid()] * 2


def _study_csv(tmp_path):
    from contactres.measurements._synthetic import SweepGroup, SweepStudy, synthetic_sweeps
    from contactres.resonators._qcm import QCM

    u = tuple(np.linspace(0.5e-9, 5e-9, 8))
    study = SweepStudy(
        groups=(SweepGroup("glass", "air", 1.1e-3, 70e9, 0.1, u, 2e4, 0.1),),
        normal_forces=(2e-3, 4e-3),
        n_experiments=2,
        qcm=QCM(5e6, 3, 2.5e-5),
    )
    path = tmp_path / "sweeps.csv"
    synthetic_sweeps(study, 7, constants=True).to_csv(path, index=False)
    return path


def _run(*args):
    from click.testing import CliRunner

    from contactres.cli import main

    return CliRunner().invoke(main, [str(a) for a in args])


def test_a_report_with_a_forked_table_has_the_same_bytes(tmp_path, monkeypatch):
    path = _study_csv(tmp_path)
    for name, cells in (("here", sys.maxsize), ("forked", 0)):
        monkeypatch.setattr(_forked, "FORK_CELLS", cells)
        monkeypatch.setattr(_forked, "_cores", lambda: 2)
        r = _run("qcm", "analyze", path, "--out", tmp_path / name, "--no-figures")
        assert r.exit_code == 0, r.output
    here, forked = tmp_path / "here", tmp_path / "forked"
    assert sorted(p.name for p in here.iterdir()) == sorted(p.name for p in forked.iterdir())
    for p in here.iterdir():
        assert (forked / p.name).read_bytes() == p.read_bytes(), p.name
    assert _no_child_left()


def test_a_forked_failure_is_the_command_lines_internal_error(tmp_path, monkeypatch, forking):
    """``qcm analyze``: the exception of the table written by the forked process gives the
    one line and exit code 1 of any internal error, and the results folder is not made."""
    from contactres import _csvcells

    path = _study_csv(tmp_path)
    parent = os.getpid()
    records = _csvcells._double_records

    def failing(values, *args):
        if os.getpid() != parent:  # in the forked process only
            raise RuntimeError("formatting failed")
        return records(values, *args)

    monkeypatch.setattr(_csvcells, "_double_records", failing)
    r = _run("qcm", "analyze", path, "--out", tmp_path / "out", "--no-figures")
    assert r.exit_code == 1, r.output
    assert "internal error: RuntimeError: formatting failed" in r.output
    assert not (tmp_path / "out").exists()
    assert _no_child_left()
