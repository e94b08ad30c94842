"""The QCM sweep-analysis job through its Python API: the same analysis as the library's
``analyze``, its stages counted ahead, its tables bound to their schemas."""

import numpy as np
import pytest

from contactres import AnalysisSettings, analyze, read_sweeps
from contactres.analysis import Flag, has
from contactres.errors import ContactresInputError
from contactres.jobs import crystals, qcm_sweeps
from contactres.measurements.schema import LOAD_RESULTS, SWEEP_RESULTS

SWEEPS = "src/contactres/data/example_sweeps.csv"


@pytest.fixture(scope="module")
def job_run():
    """The job on the bundled example with the bootstrap off (figures on, as by default), its
    reading and the progress calls it made: computed once for the tests that only read it."""
    settings = qcm_sweeps.Settings(bootstrap=0)
    reading = qcm_sweeps.read(SWEEPS, settings)
    calls: list[str] = []
    return qcm_sweeps.run(reading, settings, progress=calls.append), reading, calls


@pytest.fixture(scope="module")
def job_result(job_run):
    return job_run[0]


def test_the_job_is_the_library_analysis_within_its_stages(job_run, example_analysis):
    settings = qcm_sweeps.Settings(bootstrap=0)
    result, reading, calls = job_run
    # The bar's length covers every call of the analysis, and the writing after it.
    assert len(calls) < qcm_sweeps.stages(reading, settings)
    groups = {c for c in calls if c.startswith("JKR fit")}
    assert len(groups) == reading.table.data.groupby(["configuration", "medium"]).ngroups
    direct = example_analysis()  # analyze(read_sweeps(SWEEPS), AnalysisSettings(bootstrap=0))
    assert result.analysis.table1().equals(direct.table1())
    tables = result.tables()
    assert tables["sweeps"][1] is SWEEP_RESULTS and tables["loads"][1] is LOAD_RESULTS


def test_the_radiation_loss_needs_both_bodies():
    with pytest.raises(ContactresInputError, match="both bodies"):
        qcm_sweeps.run(SWEEPS, qcm_sweeps.Settings(sphere_material="glass"))


def test_crystals_job_moduli_of_an_isotropic_solid_are_e_over_one_minus_nu2():
    table = crystals.run().table.set_index("name")
    iso = table[table["symmetry"] == "isotropic"].iloc[0]
    # A rigid sphere on an isotropic solid: M = E/(1 − ν²) on every face.
    expected = iso["E_GPa"] / (1 - iso["nu"] ** 2)
    for face in ("M001_GPa", "M011_GPa", "M111_GPa"):
        assert iso[face] == pytest.approx(expected, rel=1e-6)


def test_the_fitted_curves_are_tables_of_the_results_folder(job_result):
    """issue 30: no fitted curve was in any file. curves.csv holds the chosen model of each
    sweep on the page's grid (the curve the report draws), jkr_curves.csv the κ(F_N) of each
    group. Checked against the data, not only the code: the Δf curve at the sweep's smallest
    measured amplitude is within the largest residual of that sweep's points, and the JKR
    curve of a group passes within 3 standard deviations of its loads' mean Δf0."""
    import numpy as np

    from contactres.measurements.schema import CURVE_RESULTS, JKR_CURVE_RESULTS

    result = job_result
    tables = result.tables()
    curves, schema = tables["curves"]
    assert schema is CURVE_RESULTS and list(curves.columns) == list(CURVE_RESULTS.names)
    jkr, schema = tables["jkr_curves"]
    assert schema is JKR_CURVE_RESULTS and len(jkr) > 0
    analysis = result.analysis
    points = analysis.points
    used = analysis.sweeps[analysis.sweeps["used"]]["sweep"]
    assert set(used) <= set(curves["sweep"])
    for sweep in list(used)[:20]:
        pts = points[points["sweep"] == sweep].sort_values("amplitude_m")
        curve = curves[curves["sweep"] == sweep]
        model = np.interp(pts["amplitude_m"], curve["amplitude_m"], curve["df_model_Hz"])
        resid = np.abs(model - pts["df_Hz"].to_numpy())
        assert resid[0] <= max(resid.max(), 1e-9)  # the curve runs through the sweep
        assert resid.max() < 0.2 * np.ptp(pts["df_Hz"]) + 0.5, sweep
    loads = analysis.loads
    for (config, medium), group in jkr.groupby(["configuration", "medium"]):
        part = loads[(loads["configuration"] == config) & (loads["medium"] == medium)]
        model = np.interp(part["normal_force_N"], group["normal_force_N"], group["df0_model_Hz"])
        spread = 3 * part["df0_Hz_sd"].fillna(0).to_numpy() + 0.05 * np.abs(model)
        assert np.all(np.abs(part["df0_Hz_mean"].to_numpy() - model) <= spread), (config, medium)


def test_two_worker_processes_write_the_files_of_one_byte_for_byte(tmp_path):
    """issue 31: the per-sweep fits, the block choice and the fitted curves in 2 worker
    processes give the results folder of the serial run, byte for byte (summary.json but for
    its record of the setting ``workers``; manifest.json, which holds the time of the run and
    the checksums of the files, left out)."""
    import json

    from contactres.report import report_set, write_report

    folders = {}
    for workers in (1, 2):
        settings = qcm_sweeps.Settings(bootstrap=20, workers=workers)
        out = tmp_path / f"workers{workers}"
        with report_set(qcm_sweeps.Result, out, ("csv", "json")) as rs:
            write_report(qcm_sweeps.run(SWEEPS, settings), rs, ("csv", "json"))
        folders[workers] = out
    names = sorted(p.name for p in folders[1].iterdir())
    assert names == sorted(p.name for p in folders[2].iterdir()) and "curves.csv" in names
    for name in set(names) - {"manifest.json"}:
        one, two = ((folders[w] / name).read_bytes() for w in (1, 2))
        if name == "summary.json":
            one, two = (json.loads(b) for b in (one, two))
            assert (one["settings"].pop("workers"), two["settings"].pop("workers")) == (1, 2)
        assert one == two, name


def test_without_figures_the_curves_are_those_of_the_page_grid_alone(tmp_path):
    """issue 31, point 3: a run that draws no figure computes the fitted curves on the 30-point
    grid of curves.csv and of the page only (Fig. 4's 100-point grid was 77 % of their cost
    when every sweep was on it):
    the files it writes are those of a run with figures, byte for byte; its Results hold that
    one grid; drawing Fig. 4 from them says why it cannot.

    One group of the bundled example (the 1.2 mm spheres in water: 96 sweeps, Cattaneo-Mindlin
    and plateau ones, and sweeps Fig. 4 draws) keeps the two runs and their pages short (the
    page's figures are most of the cost); a no-figure run whose curves differ from the
    figure run's (e.g. curves.csv off its grid) fails on it as on the whole example."""
    import pandas as pd

    from contactres.analysis import FIGURE_POINTS, PAGE_POINTS
    from contactres.report import report_set, write_report
    from contactres.report.figures import figure_sweeps

    rows = pd.read_csv(SWEEPS)
    rows = rows[(rows["configuration"] == "SiO2_1.2mm") & (rows["medium"] == "water")]
    part = tmp_path / "sweeps.csv"
    rows.to_csv(part, index=False)
    runs = {}
    assert qcm_sweeps.Settings(bootstrap=0).figures  # the default draws figures
    for figures in (True, False):
        settings = qcm_sweeps.Settings(bootstrap=0, figures=figures)
        result = qcm_sweeps.run(part, settings)
        out = tmp_path / f"figures{figures}"
        with report_set(qcm_sweeps.Result, out, ("csv", "json", "html")) as rs:
            write_report(result, rs, ("csv", "json", "html"))
        runs[figures] = result, out
    (full, with_figures), (page, without) = runs[True], runs[False]
    assert set(full.analysis.sweeps["model"]) >= {"cattaneo-mindlin", "plateau"}
    assert sorted(full.analysis.curves["grid_points"].unique()) == [PAGE_POINTS, FIGURE_POINTS]
    assert set(page.analysis.curves["grid_points"]) == {PAGE_POINTS}
    names = sorted(p.name for p in with_figures.iterdir())
    assert names == sorted(p.name for p in without.iterdir()) and "curves.csv" in names
    for name in set(names) - {"manifest.json"}:
        assert (with_figures / name).read_bytes() == (without / name).read_bytes(), name
    with pytest.raises(ContactresInputError, match="grid"):
        figure_sweeps(page.analysis)


@pytest.mark.parametrize("grids", [(), (30, 30), (1,), (30.5,), 30, [[30, 60]], (True, 30)])
def test_curve_grids_are_distinct_numbers_of_points(grids):
    with pytest.raises(ContactresInputError, match="curve_grids"):
        analyze(read_sweeps(SWEEPS), settings=AnalysisSettings(bootstrap=0), curve_grids=grids)


def test_a_plateau_sweep_on_its_bound_is_flagged_and_prints_no_plateau_amplitude(job_result):
    # The bundled example has plateau sweeps (by their block's evidence) whose own loop fit ends
    # on d_c = 0: a value at its bound is flagged, not printed, and so is its error; every other
    # plateau sweep prints a positive plateau amplitude with a finite error.
    sw = job_result.analysis.sweeps
    plateau = sw[sw["model"] == "plateau"]
    bound = has(plateau["flags"], Flag.PLATEAU_AT_BOUND)
    assert 0 < bound.sum() < len(plateau)
    assert plateau.loc[bound, ["plateau_amplitude_m", "plateau_amplitude_err_m"]].isna().all().all()
    rest = plateau[~bound]
    assert np.all(rest["plateau_amplitude_m"] > 0) and np.all(
        np.isfinite(rest["plateau_amplitude_err_m"])
    )
    assert not has(sw.loc[sw["model"] != "plateau", "flags"], Flag.PLATEAU_AT_BOUND).any()


def test_the_stages_count_each_group_once_whatever_the_order_of_the_rows(job_run):
    """The progress bar's length has one stage per (configuration, medium) group, counted on
    the first rows of runs of equal cells (issue 31, point 3): the same count as a set of the
    pairs of every row, for the rows as read and shuffled (runs of one row) alike."""
    import dataclasses

    _, reading, _ = job_run
    settings = qcm_sweeps.Settings(bootstrap=0)
    data = reading.table.data
    pairs = set(zip(data["configuration"], data["medium"], strict=True))
    assert len(pairs) > 1
    shuffled = data.sample(frac=1.0, random_state=3).reset_index(drop=True)
    again = qcm_sweeps.Reading(dataclasses.replace(reading.table, data=shuffled))
    assert qcm_sweeps.stages(reading, settings) == 7 + len(pairs)
    assert qcm_sweeps.stages(again, settings) == 7 + len(pairs)
