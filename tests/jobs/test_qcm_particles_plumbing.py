"""The ``qcm_particles`` job's plumbing, with a stand-in of the particle library.

The stand-in (tests/jobs/particle_files.py) is a translating particle on its contact and a fit
that returns the study's truth with the steps it is told to flag: so the checks here are about
the job (readers, the (time, overtone) grid, the tables, the empty cells and flags, the
conventions, the report files, the one-line errors), not about the physics, which
tests/jobs/test_qcm_particles.py checks through the real library.
"""

from __future__ import annotations

import json

import numpy as np
import pandas as pd
import pytest
from click.testing import CliRunner
from particle_files import F_F, LAYOUTS, fake_fit, install_standin, particle_shifts

from contactres.errors import ContactresInputError
from contactres.jobs import qcm_particles as job
from contactres.measurements import ParticleStudy
from contactres.measurements.schema import PARTICLE_SHIFTS_CSV, PARTICLES_CSV

# Few steps, no medium (the stand-in has none): the plumbing, not the physics.
STUDY = ParticleStudy(medium=None, rocking="locked", n_steps=6, noise=0.0, kappa_start=40.0)


@pytest.fixture
def study(monkeypatch):
    """The stand-in installed; the study's shifts (first step exactly zero) and truth."""
    from contactres.measurements import synthetic_particle_study

    flagged = np.zeros(STUDY.n_steps, bool)
    flagged[[0, 3]] = True
    install_standin(monkeypatch, None)
    shifts, truth = synthetic_particle_study(STUDY, seed=1)
    install_standin(monkeypatch, fake_fit(truth, flagged))
    return shifts, truth, flagged


def settings(**more):
    return job.Settings(particle_radius=STUDY.radius, particle_density=STUDY.density, **more)


def test_the_study_is_the_stand_ins_forward_model(study):
    shifts, truth, _ = study
    n = np.array(STUDY.overtones, float)
    last = shifts[shifts["time_s"] == truth["time_s"].iloc[-1]]
    from particle_files import Particle

    df, dg = particle_shifts(
        F_F, n, Particle.sphere(STUDY.radius, STUDY.density), *truth.iloc[-1, 1:4]
    )
    np.testing.assert_allclose(last["df_Hz"], df, rtol=1e-12)
    np.testing.assert_allclose(last["dgamma_Hz"], dg, rtol=1e-12)
    assert (shifts.loc[shifts["time_s"] == 0, ["df_Hz", "dgamma_Hz"]] == 0).all().all()


def test_tables_have_the_contract_columns_and_empty_cells_where_flagged(study, tmp_path):
    from contactres.report import write_report

    shifts, truth, flagged = study
    path, conventions = LAYOUTS["tidy"][0](tmp_path, shifts)
    result = job.run(path, settings(fundamental=conventions["fundamental"]))
    assert list(result.particles.columns) == list(PARTICLES_CSV.names) == [
        "time_s", "kappa_N_per_m", "kappa_err_N_per_m", "xi_kg_per_s", "xi_err_kg_per_s",
        "coverage_per_m2", "coverage_err_per_m2", "f_coupled_Hz", "flags",
    ]  # fmt: skip
    assert list(result.shifts.columns) == list(PARTICLE_SHIFTS_CSV.names)
    written = write_report(result, tmp_path / "out", ("csv", "json"))
    assert sorted(p.name for p in written) == ["particles.csv", "particles.json", "shifts.csv"]
    text = (tmp_path / "out" / "particles.csv").read_text(encoding="utf-8").splitlines()
    assert text[0] == ",".join(PARTICLES_CSV.names)
    for line, flag in zip(text[1:], flagged, strict=True):
        cells = line.split(",")
        if flag:
            # κ, its error, ξ, its error and f_coupled empty; the coverage kept; named in flags
            assert [cells[i] for i in (1, 2, 3, 4, 7)] == [""] * 5, line
            assert cells[5] != "" and cells[8] == "sauerbrey-like"
        else:
            assert "" not in cells[:8] and cells[8] == "", line
    back = pd.read_csv(tmp_path / "out" / "particles.csv")
    np.testing.assert_allclose(back["coverage_per_m2"], truth["coverage_per_m2"], rtol=1e-9)
    values = json.loads((tmp_path / "out" / "particles.json").read_text(encoding="utf-8"))
    assert values["flag_counts"] == {"sauerbrey-like": 2}
    assert values["conventions"]["reader"] == "tidy"
    assert values["conventions"]["df"].startswith("Δf_n, Hz, not divided by n")
    assert "bare sensor in the same medium" in values["conventions"]["reference"]
    assert values["constants"]["fundamental_Hz"] == F_F
    assert values["constants"]["overtones"] == list(STUDY.overtones)
    assert set(values["columns"]) >= set(PARTICLES_CSV.names) | set(PARTICLE_SHIFTS_CSV.names)
    assert values["flag_meanings"]["sauerbrey-like"].startswith("a rigid contact fits as well")
    assert "flagged time steps (of 6): sauerbrey-like 2;" in result.warnings[-1]


def test_the_shifts_table_holds_the_data_and_the_fits_model(study, tmp_path):
    shifts, _, _ = study
    path, _ = LAYOUTS["tidy"][0](tmp_path, shifts)
    result = job.run(path, settings(fundamental=F_F, rocking="locked"))
    table = result.shifts
    np.testing.assert_array_equal(table["time_s"], shifts["time_s"])
    np.testing.assert_array_equal(table["overtone"], shifts["overtone"])
    np.testing.assert_allclose(table["df_Hz"], shifts["df_Hz"], rtol=0, atol=0)
    # the stand-in's model is its forward model at the truth, which made the (noiseless) data
    np.testing.assert_allclose(table["df_model_Hz"], shifts["df_Hz"], rtol=1e-12)
    np.testing.assert_allclose(table["dgamma_model_Hz"], shifts["dgamma_Hz"], rtol=1e-12)


@pytest.mark.parametrize("layout", [k for k in LAYOUTS if k != "tidy"])
def test_each_export_layout_gives_the_tidy_tables_shifts(study, tmp_path, layout):
    shifts, _, _ = study
    writer, overtones = LAYOUTS[layout]
    if overtones is not None:
        shifts = shifts[shifts["overtone"].isin(overtones)].reset_index(drop=True)
    path, conventions = writer(tmp_path, shifts)
    fundamental = conventions.pop("fundamental", None)
    result = job.run(path, settings(fundamental=fundamental, conventions=conventions))
    assert result.conventions["reader"] == layout
    np.testing.assert_allclose(result.shifts["df_Hz"], shifts["df_Hz"], rtol=1e-9, atol=1e-6)
    np.testing.assert_allclose(
        result.shifts["dgamma_Hz"], shifts["dgamma_Hz"], rtol=1e-9, atol=1e-6
    )


def test_missing_points_are_nan_in_the_grid(study, tmp_path):
    shifts, _, _ = study
    shifts = shifts.copy()
    shifts.loc[5, "dgamma_Hz"] = np.nan  # a bandwidth not measured
    shifts = shifts.drop(index=8)  # a point not measured at all
    path, _ = LAYOUTS["tidy"][0](tmp_path, shifts)
    result = job.run(path, settings(fundamental=F_F))
    grid = result.shifts
    assert len(grid) == STUDY.n_steps * len(STUDY.overtones)
    assert np.isnan(grid["dgamma_Hz"].iloc[5]) and np.isfinite(grid["df_Hz"].iloc[5])
    assert grid.iloc[8][["df_Hz", "dgamma_Hz"]].isna().all()


def _tidy_file(tmp_path, rows, header="time_s,overtone,df_Hz,dgamma_Hz"):
    path = tmp_path / "bad.csv"
    path.write_text(header + "\n" + "\n".join(rows) + "\n", encoding="utf-8")
    return path


@pytest.mark.parametrize(
    "rows, header, words",
    [
        (["0,5,-1,0.1", "60,5,-2,0.2"], None, ["only overtone 5", "at least two"]),
        (["0,3,-1,", "0,5,-2,"], None, ["every dgamma_Hz cell is blank"]),
        (["0,3,-1", "0,5,-2"], "time_s,overtone,df_Hz", ["no column 'dgamma_Hz'"]),
        (["0,4,-1,0.1"], None, ["line 2", "'overtone'", "'4'", "odd"]),
        (["0,3,-1,0.1", "0,3,-2,0.2"], None, ["appear more than once", "lines 2–3"]),
    ],
)
def test_bad_tables_are_one_line_errors(study, tmp_path, rows, header, words):
    path = _tidy_file(tmp_path, rows, header or "time_s,overtone,df_Hz,dgamma_Hz")
    with pytest.raises(ContactresInputError) as err:
        job.run(path, settings(fundamental=F_F))
    text = str(err.value)
    assert "\n" not in text
    for w in words:
        assert w in text, text


def test_a_tidy_table_needs_the_fundamental(study, tmp_path):
    path, _ = LAYOUTS["tidy"][0](tmp_path, study[0])
    with pytest.raises(ContactresInputError, match=r"fundamental.*--fundamental"):
        job.run(path, settings())


@pytest.mark.parametrize(
    "more, words",
    [
        (dict(particle_density=-2200.0), "density"),
        (dict(particle_radius=0.0), "radius"),
        (dict(rocking="rolling"), "rocking"),
        (dict(particle_mass=1e-15), "not both"),
    ],
)
def test_bad_particles_are_one_line_errors(study, tmp_path, more, words):
    path, _ = LAYOUTS["tidy"][0](tmp_path, study[0])
    base = dict(particle_radius=STUDY.radius, particle_density=STUDY.density, fundamental=F_F)
    with pytest.raises(ContactresInputError, match=words):
        job.run(path, job.Settings(**{**base, **more}))


def test_particles_inside_the_penetration_depth_of_a_liquid(study, tmp_path):
    path, _ = LAYOUTS["tidy"][0](tmp_path, study[0])
    # δ = √(2η/(ρω)) of water: 238 nm/√n on a 5 MHz crystal, 66 nm at n = 13: a radius of
    # 50 nm is inside it at every overtone
    s = job.Settings(particle_radius=5e-8, particle_density=2200.0, fundamental=F_F)
    with pytest.raises(ContactresInputError, match="smaller than the penetration depth") as err:
        job.run(path, job.Settings(**{**vars(s), "medium": "water"}))
    # one clause (the review: the reason's own sentence repeated it), with R and δ in it
    text = str(err.value)
    assert text.count("penetration depth") == 1 and "R = 50 nm" in text and "δ = " in text
    job.run(path, job.Settings(**{**vars(s), "medium": "air"}))  # a gas: no such check
    # 120 nm: inside δ at n = 1 and 3 only (137 nm, then 106 nm at n = 5), a warning naming them
    s = job.Settings(particle_radius=1.2e-7, particle_density=2200.0, fundamental=F_F)
    result = job.run(path, job.Settings(**{**vars(s), "medium": "water"}))
    line = next(w for w in result.warnings if "penetration depth" in w)
    assert line.startswith("overtone(s) 1, 3: ")


# --- the command line ------------------------------------------------------------------------


def _cli(*args):
    from contactres.cli import main

    return CliRunner().invoke(main, [str(a) for a in args])


def _one_line_error(r, *words):
    assert r.exit_code == 2, r.output
    lines = r.output.strip().splitlines()
    assert len(lines) == 1 and ": error: " in lines[0] and "Traceback" not in r.output, r.output
    for w in words:
        assert w in lines[0], lines[0]


def test_the_command_writes_the_folder(study, tmp_path):
    path, _ = LAYOUTS["tidy"][0](tmp_path, study[0])
    out = tmp_path / "out"
    r = _cli("qcm", "particles", path, "--particle-radius", STUDY.radius, "--particle-density",
             STUDY.density, "--fundamental", F_F, "--out", out)  # fmt: skip
    assert r.exit_code == 0, r.output
    names = sorted(p.name for p in out.iterdir() if p.name != "manifest.json")
    assert names == [
        "particles.csv", "particles.json", "particles_overtones.png", "particles_plane.png",
        "particles_time.png", "report.html", "shifts.csv",
    ]  # fmt: skip
    assert "6 time steps" in r.output and "flagged time steps (of 6): sauerbrey-like 2" in r.output
    # the count is that of the files in the folder: the set's seven and its manifest
    assert "wrote 7 files and manifest.json" in r.output and len(list(out.iterdir())) == 8
    assert "noise from the residuals σ̂ = " in r.output
    page = (out / "report.html").read_text(encoding="utf-8")
    assert page.count("data:image/png;base64,") == 3 and "sauerbrey-like" in page


def test_the_help_names_paper_2s_equation_and_the_radius_unit():
    r = _cli("qcm", "particles", "--help")
    assert r.exit_code == 0, r.output
    text = " ".join(r.output.split())
    assert "paper 2's Eq. 1" in text and "Eq. 2" not in text
    assert "5e-7 m for spheres 1 µm across" in text
    assert "N particles per area A" in text and "N/A particles" not in text


@pytest.mark.parametrize(
    "option, value, words",
    [
        ("--particle-radius", "5", ["--particle-radius", "particle radius", "micrometres"]),
        ("--particle-radius", "0", ["--particle-radius"]),
        ("--particle-density", "-2200", ["--particle-density"]),
        ("--particle-density", "2.2", ["--particle-density", "g/cm^3"]),
        ("--medium", "oil", ["oil"]),
        ("--reader", "excel", ["excel", "tidy"]),
    ],
)
def test_bad_options_are_one_line_errors(study, tmp_path, option, value, words):
    path, _ = LAYOUTS["tidy"][0](tmp_path, study[0])
    base = {"--particle-radius": STUDY.radius, "--particle-density": STUDY.density,
            "--fundamental": F_F, "--out": tmp_path / "out"}  # fmt: skip
    options = {**base, option: value}
    r = _cli("qcm", "particles", path, *[x for kv in options.items() for x in kv])
    _one_line_error(r, *words)


@pytest.mark.parametrize(
    "options, option",
    [
        (["--df-divided-by-n"], "--df-divided-by-n"),
        (["--time-unit", "min"], "--time-unit"),
        (["--baseline", "first"], "--baseline"),
        (["--channel", "3"], "--channel"),
        (["--dissipation-scale", "1e-6"], "--dissipation-scale"),
    ],
)
def test_conventions_a_tidy_table_states_are_refused_naming_the_option(
    study, tmp_path, options, option
):
    # the review: the error named the API's keyword (time_unit='min') to a command-line user
    path, _ = LAYOUTS["tidy"][0](tmp_path, study[0])
    r = _cli("qcm", "particles", path, "--particle-radius", STUDY.radius, "--particle-density",
             STUDY.density, "--fundamental", F_F, "--out", tmp_path / "out", *options)  # fmt: skip
    _one_line_error(r, f"({option} on the command line)", "does not apply to a tidy shift table")


@pytest.mark.parametrize(
    "rows, header, words",
    [
        (["0,5,-1,0.1", "60,5,-2,0.2"], None, ["only overtone 5"]),
        (["0,3,-1,", "0,5,-2,"], None, ["dgamma_Hz"]),
        (["0,3,-1", "0,5,-2"], "time_s,overtone,df_Hz", ["dgamma_Hz"]),
    ],
)
def test_bad_data_on_the_command_line(study, tmp_path, rows, header, words):
    path = _tidy_file(tmp_path, rows, header or "time_s,overtone,df_Hz,dgamma_Hz")
    r = _cli("qcm", "particles", path, "--particle-radius", STUDY.radius, "--particle-density",
             STUDY.density, "--fundamental", F_F, "--out", tmp_path / "out")  # fmt: skip
    _one_line_error(r, *words)
    assert not (tmp_path / "out" / "particles.csv").exists()
