"""write_report writes one result set: a killed run leaves the earlier set, a second run into the
same folder is refused, no stale file survives, non-finite numbers are empty cells, and the
figures survive odd labels and data with nothing to draw."""

import dataclasses
import json
import pickle
import signal
import subprocess
import sys
import textwrap
import time

import numpy as np
import pandas as pd
import pytest

from contactres.analysis import AnalysisSettings, analyze
from contactres.fileio import MANIFEST, OutputError
from contactres.measurements._sweeps import SweepWarning, validate_sweeps
from contactres.measurements._synthetic import SweepGroup, SweepStudy, synthetic_sweeps
from contactres.report import figures, write_report
from contactres.report._tables import sweeps_table
from contactres.resonators._qcm import QCM

FORMATS = ("csv", "json", "png")
# The files of the analysis' report, written out here (not taken from the writer's registry).
FILES = {
    "csv": ("sweeps.csv", "loads.csv", "curves.csv", "jkr_curves.csv"),
    "json": ("summary.json",),
    "png": tuple(figures.FIGURE_FILES),
}


def report_files(formats=FORMATS) -> tuple[str, ...]:
    """The files a report of the example (no radiation table) holds for ``formats``."""
    return tuple(name for f in FORMATS if f in formats for name in FILES[f])


CONST = dict(overtone=3, area_m2=2.5e-5, n_contacts=3, sphere_radius_m=1e-3)
CSV_JSON = ("csv", "json")


def _results(configuration="glass", **settings):
    u = tuple(np.linspace(0.5e-9, 6e-9, 8))
    study = SweepStudy(
        groups=(SweepGroup("glass", "air", 1e-3, 70e9, 0.05, u, 1e4, 0.2),),
        normal_forces=(2e-3, 4e-3, 8e-3),
        n_experiments=3,
        ramps=(1, 2),
        alternate=False,
        qcm=QCM(5e6, 3, 2.5e-5),
    )
    raw = synthetic_sweeps(study, 3).assign(configuration=configuration)
    table = validate_sweeps(raw, constants=CONST)
    return analyze(table, settings=AnalysisSettings(bootstrap=0, **settings))


@pytest.fixture(scope="module")
def results():
    return _results()


def _names(folder):
    return sorted(p.name for p in folder.iterdir())


def _snapshot(folder):
    return {p.name: p.read_bytes() for p in folder.iterdir()}


# ---- a kill mid-write, and a second run into the same folder ------------------------------

# Runs write_report in a child process whose figure step announces itself and then hangs, so
# that the parent can kill it while the set is being written.
CHILD = textwrap.dedent(
    """
    import pickle, sys, time
    from pathlib import Path

    import contactres.report.figures as figures
    from contactres.report import write_report

    results = pickle.loads(Path(sys.argv[1]).read_bytes())

    def hang(results):
        Path(sys.argv[3]).write_text("writing")
        time.sleep(600)

    figures.figure_sweeps = hang
    write_report(results, sys.argv[2], inputs=sys.argv[4:])
    """
)


def _start_hanging_run(tmp_path, results, out, inputs=()):
    blob = tmp_path / "results.pickle"
    blob.write_bytes(pickle.dumps(results))
    started = tmp_path / "started"
    args = [sys.executable, "-c", CHILD, str(blob), str(out), str(started), *map(str, inputs)]
    child = subprocess.Popen(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    for _ in range(1200):  # until the child is inside the figure step (at most ~2 min)
        if started.exists() or child.poll() is not None:
            break
        time.sleep(0.1)
    assert started.exists(), child.communicate()[1].decode()
    return child


@pytest.mark.skipif(not hasattr(signal, "SIGKILL"), reason="needs SIGKILL")
@pytest.mark.parametrize("beside_input", [False, True])
def test_a_kill_mid_write_leaves_the_earlier_set_and_a_lock_refuses_a_second_run(
    results, tmp_path, beside_input
):
    out = tmp_path / "out"
    out.mkdir()
    inputs = []
    if beside_input:  # a folder that also holds the data: files are moved in one by one
        (out / "data.csv").write_text("the input")
        inputs = [out / "data.csv"]
    write_report(results, out, CSV_JSON, inputs=inputs)
    before = _snapshot(out)
    child = _start_hanging_run(tmp_path, results, out, inputs)
    try:
        with pytest.raises(OutputError, match=rf"another contactres run \(process {child.pid} "):
            write_report(results, out, CSV_JSON, inputs=inputs)
    finally:
        child.send_signal(signal.SIGKILL)
        child.communicate()
    assert _snapshot(out) == before  # the earlier set, untouched: nothing new, nothing mixed
    # The next run takes over the dead run's lock, clears its leftovers and writes a whole set.
    written = write_report(results, out, inputs=inputs)
    assert sorted(p.name for p in written) == sorted(report_files(FORMATS))
    extra = ["data.csv"] if beside_input else []
    assert _names(out) == sorted([*report_files(FORMATS), MANIFEST, *extra])
    assert json.loads((out / MANIFEST).read_text())["files"].keys() == set(report_files())
    assert [p.name for p in tmp_path.iterdir() if p.name.startswith(".")] == []


def test_no_file_of_an_earlier_run_survives(results, tmp_path):
    write_report(results, tmp_path / "out")
    assert len([p for p in (tmp_path / "out").iterdir() if p.suffix == ".png"]) == 4
    write_report(results, tmp_path / "out", CSV_JSON)  # e.g. --no-figures
    assert _names(tmp_path / "out") == sorted([*report_files(CSV_JSON), MANIFEST])


def test_the_sweep_table_is_an_input_by_default(results, tmp_path):
    folder = tmp_path / "data"
    folder.mkdir()
    source = folder / "sweeps.csv"
    source.write_text("the measured points")
    mine = dataclasses.replace(
        results, table=dataclasses.replace(results.table, source=str(source))
    )
    with pytest.raises(OutputError, match=r"sweeps\.csv' would overwrite the input"):
        write_report(mine, folder)
    assert _names(folder) == ["sweeps.csv"] and source.read_text() == "the measured points"


# ---- the numbers written -------------------------------------------------------------------


def test_non_finite_numbers_are_empty_cells_and_null(results, tmp_path):
    sw = results.sweeps.copy()
    sw.loc[0, "loss_tangent"] = np.inf  # Δf0 = 0
    sw.loc[1, "df_slope_err_Hz_per_m"] = -np.inf
    loads = results.loads.copy()
    loads.loc[0, "loss_tangent_mean"] = np.inf
    groups = [dict(results.groups[0], E_err_Pa=np.inf)]
    bad = dataclasses.replace(results, sweeps=sw, loads=loads, groups=groups)
    write_report(bad, tmp_path, CSV_JSON)
    for name in ("sweeps.csv", "loads.csv"):
        assert "inf" not in (tmp_path / name).read_text().lower()
    table = pd.read_csv(tmp_path / "sweeps.csv")
    assert np.isnan(table.loc[0, "loss_tangent"])
    assert np.isnan(table.loc[1, "df_slope_err_Hz_per_m"])
    assert np.isnan(pd.read_csv(tmp_path / "loads.csv").loc[0, "loss_tangent_mean"])
    text = (tmp_path / "summary.json").read_text()
    assert json.loads(text)["groups"][0]["E_err_Pa"] is None and "Infinity" not in text
    # the finite numbers are written as before, bit for bit
    pd.testing.assert_frame_equal(
        sweeps_table(bad).drop(columns=["loss_tangent", "df_slope_err_Hz_per_m"]),
        sweeps_table(results).drop(columns=["loss_tangent", "df_slope_err_Hz_per_m"]),
    )


# ---- the figures ---------------------------------------------------------------------------


def test_labels_with_dollars_and_huge_labels_are_drawn_as_short_plain_text(tmp_path):
    odd = _results(configuration="SiO2 $x^2_$ " + "L" * 100_000)
    written = write_report(odd, tmp_path)
    assert sum(p.suffix == ".png" for p in written) == 4
    fig = figures.figure_stiffness(odd)
    title = fig.axes[0].get_title()
    # the label shortened to LABEL_CHARS characters, its dollars escaped (one backslash each)
    assert title.startswith(r"SiO2 \$x^2_\$ L") and len(title) == figures.LABEL_CHARS + 2
    fig.canvas.draw()
    # the control: the same label unescaped is mathtext, and matplotlib cannot parse it
    fig.axes[0].set_title("SiO2 $x^2_$")
    with pytest.raises(ValueError):
        fig.canvas.draw()


def test_with_no_used_sweep_no_figure_is_drawn_and_a_warning_says_so(results, tmp_path):
    only_first = dataclasses.replace(results, sweeps=results.sweeps.assign(used=False))
    with pytest.warns(SweepWarning, match="no sweep is used.*no figure is drawn"):
        written = write_report(only_first, tmp_path)
    assert sorted(p.name for p in written) == sorted(report_files(CSV_JSON))
    assert not [p for p in tmp_path.iterdir() if p.suffix == ".png"]


def test_the_file_names_are_declared_in_one_place():
    """The writer's declaration (report_names) lists the files a report holds, and those of
    the radiation table that a run with a sphere material adds."""
    from contactres.jobs import qcm_sweeps
    from contactres.report import report_names

    radiation = {"csv": ("radiation.csv",), "json": (), "png": (figures.RADIATION_FIGURE,)}
    for formats in (("png",), ("csv", "json"), FORMATS):
        expected = {*report_files(formats), *(n for f in formats for n in radiation[f])}
        assert set(report_names(qcm_sweeps.Result, formats)) == expected
    assert report_names(qcm_sweeps.Result, ("html",)) == ("report.html",)
    assert MANIFEST not in report_names(qcm_sweeps.Result, FORMATS)
