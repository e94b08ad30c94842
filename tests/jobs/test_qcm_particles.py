"""``qcm particles`` end to end with the particle library (issue 28): the bundled example, the
four instrument layouts, recovery and error calibration on synthetic studies, the flags where
the coupled resonance lies outside the overtone comb.

The truth is the synthetic study's (contactres.measurements.ParticleStudy), never a number
taken from the job's own output. Noise: 0.1 Hz on every Δf_n and ΔΓ_n (the study's default).
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from particle_files import F_F, LAYOUTS

from contactres.examples import example_path
from contactres.jobs import qcm_particles as job
from contactres.measurements import (
    PARTICLE_EXAMPLE_SEED,
    ParticleStudy,
    synthetic_particle_study,
)

ROOT = Path(__file__).resolve().parents[2]
VALUES = (
    ("kappa_N_per_m", "kappa_err_N_per_m"),
    ("xi_kg_per_s", "xi_err_kg_per_s"),
    ("coverage_per_m2", "coverage_err_per_m2"),
)


def run_study(tmp_path, study, seed, **settings):
    """The job on the study's tidy table (written to 17 digits); the result and the truth."""
    shifts, truth = synthetic_particle_study(study, seed)
    path = tmp_path / f"study_{seed}.csv"
    shifts.to_csv(path, index=False, float_format="%.17g")
    s = job.Settings(
        particle_radius=study.radius,
        particle_density=study.density,
        fundamental=study.fundamental,
        medium=study.medium,
        rocking=settings.pop("rocking", study.rocking),
        **settings,
    )
    return job.run(path, s), truth


@pytest.fixture(scope="module")
def example():
    settings = job.Settings(5e-7, 2200.0, fundamental=5e6, medium="water")
    return job.run(example_path("example_particles.csv"), settings)


def test_the_bundled_example_is_the_scripts_output(tmp_path):
    out = tmp_path / "example_particles.csv"
    script = ROOT / "scripts" / "make_example_particles.py"
    subprocess.run([sys.executable, str(script), "--out", str(out)], check=True, timeout=120)
    assert out.read_bytes() == example_path("example_particles.csv").read_bytes()


def test_the_example_recovers_the_truth_within_2_percent(example):
    _, truth = synthetic_particle_study(ParticleStudy(), PARTICLE_EXAMPLE_SEED)
    table = example.particles
    np.testing.assert_allclose(table["time_s"], truth["time_s"], rtol=1e-6)
    # step 0 has no particles: nothing identified, every value empty and the step flagged as
    # such (the empty model fits its noise as well)
    assert table.iloc[0, 1:8].isna().all() and "no-signal" in table["flags"].iloc[0]
    rest = table.iloc[1:]
    assert (rest["flags"] == "").all()  # the coupled resonance inside the comb: all identified
    for value, error in VALUES:
        deviation = rest[value] / truth[value].iloc[1:] - 1
        assert deviation.abs().max() < 0.02, value
        assert (rest[error] > 0).all() and ((rest[value] - truth[value].iloc[1:]).abs()
                                            < 6 * rest[error]).all(), value  # fmt: skip
    # the coupled resonance moves through the comb, 5-65 MHz, as the contacts stiffen
    f = rest["f_coupled_Hz"].to_numpy()
    assert 5e6 < f.min() < f.max() < 65e6 and (np.diff(f) > 0).all()


def test_particles_json_holds_the_products_the_fit_quality_and_kappa_r_per_step(example):
    import json

    _, truth = synthetic_particle_study(ParticleStudy(), PARTICLE_EXAMPLE_SEED)
    steps = json.loads(json.dumps(example.values(), allow_nan=False))["steps"]
    assert set(steps) <= set(example.columns)  # every name has its unit
    assert len(steps["time_s"]) == len(truth)
    # the products N·κ and N·ξ against the study's truth, within 2 % and 6 of their errors
    for name, err, field in (
        ("coverage_kappa_N_per_m3", "coverage_kappa_err_N_per_m3", "kappa_N_per_m"),
        ("coverage_xi_kg_per_s_m2", "coverage_xi_err_kg_per_s_m2", "xi_kg_per_s"),
    ):
        true = (truth["coverage_per_m2"] * truth[field]).to_numpy()[1:]
        value, error = np.array(steps[name][1:], float), np.array(steps[err][1:], float)
        assert np.max(np.abs(value / true - 1)) < 0.02, name
        assert np.all(np.abs(value - true) < 6 * error), name
    # step 0 has no particles: nothing, the products neither; no rocking stiffness is fitted
    assert steps["coverage_kappa_N_per_m3"][0] is None
    assert all(v is None for v in steps["kappa_r_N_m_per_rad"])
    # the noise is estimated: χ²/dof is its variance, (0.1 Hz)² (the study's); its mean over
    # 49 steps of 11 dof scatters by √(2/11)/7 = 6 %
    assert np.mean(steps["chi2_per_dof"][1:]) == pytest.approx(0.01, rel=0.25)


def test_the_model_is_the_forward_model_at_the_fitted_values(example):
    from contactres.resonators import WATER, Particle, particle_shifts

    particle = Particle.sphere(5e-7, 2200.0)
    table = example.particles.set_index("time_s")
    for t, part in example.shifts.groupby("time_s"):
        row = table.loc[t]
        if np.isnan(row["kappa_N_per_m"]):
            continue
        df, dg = particle_shifts(
            F_F, part["overtone"].to_numpy(), particle, row["kappa_N_per_m"],
            row["xi_kg_per_s"], row["coverage_per_m2"], rocking="free", medium=WATER,
        )  # fmt: skip
        np.testing.assert_allclose(part["df_model_Hz"], df, rtol=1e-9, atol=1e-9)
        np.testing.assert_allclose(part["dgamma_model_Hz"], dg, rtol=1e-9, atol=1e-9)
    # and the model is within a few noise widths of the data (0.1 Hz)
    identified = table.loc[example.shifts["time_s"], "kappa_N_per_m"].to_numpy()
    fitted = example.shifts[np.isfinite(identified)]
    residual = np.r_[fitted["df_Hz"] - fitted["df_model_Hz"],
                     fitted["dgamma_Hz"] - fitted["dgamma_model_Hz"]]  # fmt: skip
    assert 0.07 < residual.std() < 0.11


def test_the_errors_match_the_scatter_over_repeated_noise(tmp_path):
    """200 steps of one state (κ, ξ and the coverage constant after step 0): each step is an
    independent draw of the noise, the stated σ = 0.1 Hz is given, and the scatter of the
    fitted values over the steps matches their printed errors within a factor 1.3 (issue 28).
    """
    study = ParticleStudy(kappa_start=15.0, kappa_end=15.0, tau=1e-6, n_steps=201)
    result, truth = run_study(tmp_path, study, 11, sigma_df=0.1, sigma_dgamma=0.1)
    steps = result.particles.iloc[1:]
    assert (steps["flags"] == "").all()
    for value, error in VALUES:
        ratio = steps[value].std() / steps[error].median()
        assert 1 / 1.3 < ratio < 1.3, (value, ratio)
        assert abs(steps[value].mean() / truth[value].iloc[-1] - 1) < 0.02, value
    # the correlations in particles.json against those of the fitted values over the 200
    # draws (ln κ, ξ, ln N are the fit's parameters; at errors of ~1 % ln is linear): the
    # correlation of 200 draws scatters by (1 - ρ²)/√200 < 0.07
    per_step = result.values()["steps"]
    fitted = {
        "kappa": np.log(steps["kappa_N_per_m"]),
        "xi": steps["xi_kg_per_s"],
        "coverage": np.log(steps["coverage_per_m2"]),
    }
    for a, b in (("kappa", "xi"), ("kappa", "coverage"), ("xi", "coverage")):
        printed = np.asarray(per_step[f"corr_{a}_{b}"][1:], float)
        assert np.all(np.abs(printed) <= 1.0 + 1e-12)
        scatter = np.corrcoef(fitted[a], fitted[b])[0, 1]
        assert np.median(printed) == pytest.approx(scatter, abs=0.15), (a, b)


@pytest.mark.parametrize(
    "kappa, regime",
    [(1e6, "sauerbrey-like"), (0.05, "outside-comb")],
    ids=["stiff: far above the comb", "soft: below the comb"],
)
def test_outside_the_comb_the_steps_are_flagged(tmp_path, kappa, regime):
    study = ParticleStudy(kappa_start=kappa, kappa_end=2 * kappa, n_steps=5)
    result, _ = run_study(tmp_path, study, 7)
    steps = result.particles.iloc[1:]
    assert steps["flags"].str.contains(regime).all()
    assert steps["flags"].str.contains("outside-comb").all()
    if regime == "sauerbrey-like":  # only the mass is identified: κ and ξ left empty
        assert steps[["kappa_N_per_m", "kappa_err_N_per_m", "f_coupled_Hz"]].isna().all().all()
    assert result.flag_counts["outside-comb"] >= len(steps)
    assert set(result.flag_meanings) == set(result.flag_counts)


LAYOUT_STUDY = ParticleStudy(n_steps=4)
LAYOUT_BASE = dict(
    particle_radius=LAYOUT_STUDY.radius, particle_density=LAYOUT_STUDY.density, medium="water"
)


def layout_shifts(overtones):
    """The shifts every layout writes (those of ``overtones`` only, if given)."""
    shifts, _ = synthetic_particle_study(LAYOUT_STUDY, 5)
    # absolute frequencies are read against the first point: the first step is the bare
    # sensor (no particles yet), written without noise
    shifts.loc[shifts["time_s"] == 0, ["df_Hz", "dgamma_Hz"]] = 0.0
    if overtones is not None:
        shifts = shifts[shifts["overtone"].isin(overtones)].reset_index(drop=True)
    return shifts


@pytest.fixture(scope="module")
def tidy_reference(tmp_path_factory):
    """The job's particles from the tidy table of the same shifts, one run per overtone set
    (four layouts share all overtones: the run is the same for each, so it is made once)."""
    done = {}

    def reference(overtones):
        if overtones not in done:
            path = tmp_path_factory.mktemp("reference") / "reference.csv"
            layout_shifts(overtones).to_csv(path, index=False, float_format="%.17g")
            done[overtones] = job.run(path, job.Settings(**LAYOUT_BASE, fundamental=F_F))
        return done[overtones]

    return reference


@pytest.mark.parametrize("layout", list(LAYOUTS))
def test_each_instrument_layout_runs_through_the_job(tmp_path, layout, tidy_reference):
    """The same shifts written in each layout give the tidy table's particles."""
    writer, overtones = LAYOUTS[layout]
    path, conventions = writer(tmp_path, layout_shifts(overtones))
    fundamental = conventions.pop("fundamental", None)
    settings = job.Settings(**LAYOUT_BASE, fundamental=fundamental, conventions=conventions)
    result = job.run(path, settings)
    reference = tidy_reference(overtones)
    assert result.conventions["reader"] == layout
    pd.testing.assert_frame_equal(
        result.particles.drop(columns="flags"),
        reference.particles.drop(columns="flags"),
        rtol=1e-5,
    )
    assert list(result.particles["flags"]) == list(reference.particles["flags"])


def test_a_fitted_rocking_stiffness_runs_through_the_job(tmp_path):
    result, truth = run_study(tmp_path, ParticleStudy(n_steps=4), 3, rocking="fit")
    assert result.constants["rocking"] == "fit"
    assert "rocking stiffness" in result.conventions["rocking"]
    assert np.isfinite(result.shifts["df_model_Hz"]).all()
    steps = result.particles.iloc[1:]
    deviation = steps["coverage_per_m2"] / truth["coverage_per_m2"].iloc[1:] - 1
    assert deviation.abs().max() < 0.02


# --- the command line ------------------------------------------------------------------------


def _cli(*args):
    from click.testing import CliRunner

    from contactres.cli import main

    return CliRunner().invoke(main, [str(a) for a in args])


def test_particles_inside_the_penetration_depth_are_one_line_on_the_command_line(tmp_path):
    r = _cli("qcm", "particles", example_path("example_particles.csv"), "--particle-radius",
             "5e-8", "--particle-density", "2200", "--fundamental", "5e6", "--medium", "water",
             "--out", tmp_path / "out")  # fmt: skip
    assert r.exit_code == 2, r.output
    lines = r.output.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in r.output
    assert "smaller than the penetration depth of water at every overtone" in lines[0]
    assert not (tmp_path / "out" / "particles.csv").exists()


def test_an_export_with_its_options_on_the_command_line(tmp_path):
    """A QSense export (Δf/n, D in ppm, time in minutes) read with the options of qcm
    stiffness: the same particles as the tidy table of the same shifts."""
    study = ParticleStudy(n_steps=3)
    shifts, _ = synthetic_particle_study(study, 2)
    path, _ = LAYOUTS["qsense"][0](tmp_path, shifts)
    tidy, _ = LAYOUTS["tidy"][0](tmp_path, shifts)
    common = ("--particle-radius", study.radius, "--particle-density", study.density,
              "--fundamental", F_F, "--medium", "water", "--report", "none",
              "--no-figures")  # fmt: skip
    r = _cli("qcm", "particles", path, *common, "--df-divided-by-n", "--dissipation-scale",
             "ppm", "--time-unit", "min", "--channel", "1", "--out", tmp_path / "a")  # fmt: skip
    assert r.exit_code == 0, r.output
    assert "(qsense)" in r.output
    r = _cli("qcm", "particles", tidy, *common, "--out", tmp_path / "b")
    assert r.exit_code == 0, r.output
    assert sorted(p.name for p in (tmp_path / "a").iterdir()) == [
        "manifest.json", "particles.csv", "particles.json", "shifts.csv",
    ]  # fmt: skip
    a = pd.read_csv(tmp_path / "a" / "particles.csv")
    b = pd.read_csv(tmp_path / "b" / "particles.csv")
    pd.testing.assert_frame_equal(a, b, rtol=1e-5)


def test_too_few_overtones_for_an_estimated_noise_are_one_line_asking_for_the_noise(tmp_path):
    # three overtones: 3 dof for 3 parameters, too few to estimate the noise from the residuals
    study = ParticleStudy(n_steps=3, overtones=(3, 5, 7))
    shifts, _ = synthetic_particle_study(study, 2)
    tidy, _ = LAYOUTS["tidy"][0](tmp_path, shifts)
    common = ("--particle-radius", study.radius, "--particle-density", study.density,
              "--fundamental", F_F, "--medium", "water", "--report", "none",
              "--no-figures")  # fmt: skip
    r = _cli("qcm", "particles", tidy, *common, "--out", tmp_path / "a")
    assert r.exit_code == 2, r.output
    lines = r.output.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in r.output
    assert "degrees of freedom" in lines[0] and "--noise" in lines[0]
    # with the noise stated the same file runs
    r = _cli("qcm", "particles", tidy, *common, "--noise", "0.1", "--out", tmp_path / "b")
    assert r.exit_code == 0, r.output


def test_overtones_inside_the_penetration_depth_are_dropped_and_named(tmp_path):
    """R = 120 nm in water: inside δ at n = 1 and 3 only (238 and 138 nm at 5 and 15 MHz), so
    those two are left out, named in every step's flags and in a warning line, and κ and the
    coverage are fitted from n = 5..13."""
    from contactres.resonators import WATER, Particle, particle_shifts

    n = np.arange(1, 14, 2)
    particle = Particle.sphere(0.12e-6, 1050.0)
    df, dg = particle_shifts(F_F, n, particle, 2.0, 1e-9, 5e10, medium=WATER)
    rows = [(t, k, a, b) for t in (0.0, 1.0) for k, a, b in zip(n, df, dg, strict=True)]
    table = pd.DataFrame(rows, columns=["time_s", "overtone", "df_Hz", "dgamma_Hz"])
    table.to_csv(tmp_path / "small.csv", index=False, float_format="%.17g")
    settings = job.Settings(0.12e-6, 1050.0, fundamental=F_F, medium="water", sigma_df=0.1,
                            sigma_dgamma=0.1)  # fmt: skip
    result = job.run(tmp_path / "small.csv", settings)
    flags = result.particles["flags"]
    assert flags.str.startswith("dropped-overtones-R<delta: 1,3;").all()
    assert not flags.str.contains("unresolved").any()
    np.testing.assert_allclose(result.particles["kappa_N_per_m"], 2.0, rtol=1e-6)
    np.testing.assert_allclose(result.particles["coverage_per_m2"], 5e10, rtol=1e-6)
    assert "left out of the fit" in " ".join(result.warnings)
    assert "penetration depth" in result.flag_meanings["dropped-overtones-R<delta: 1,3"]


def test_the_noise_and_f_coupleds_error_are_in_particles_json_and_on_the_page(example):
    """Issue 28's second review: σ̂ and the series' own noise are recorded; f_coupled's error
    goes with the per-step values; the page opens with the summary and the figures and leaves
    the per-step lists to the JSON."""
    from contactres.report._job_page import job_page

    constants = example.constants
    assert constants["noise_fit_Hz"] == pytest.approx(0.1, rel=0.15)  # the study's noise
    assert constants["noise_series_Hz"] >= constants["noise_fit_Hz"]  # the signal moves too
    # f_coupled's error: f ∝ √κ in vacuum, so about half κ's relative error (the medium
    # bends it a little): within a factor 1.5 of that
    f, f_err = example.particles["f_coupled_Hz"], np.asarray(example.steps["f_coupled_err_Hz"])
    ok = np.isfinite(f.to_numpy())
    rel_k = (example.particles["kappa_err_N_per_m"] / example.particles["kappa_N_per_m"])[ok]
    ratio = (f_err[ok] / f[ok]) / (0.5 * rel_k)
    assert ratio.between(1 / 1.5, 1.5).all()
    page = job_page(example)
    assert page.index("<h2>Summary</h2>") < page.index("<h2>Values</h2>")
    assert "values; all in the JSON" not in page and "model_curves</code>" in page
    assert "49 of 50" in page  # the summary's "identified" column


def test_the_wrong_rotation_is_a_misfit_with_one_warning_line(tmp_path):
    settings = job.Settings(5e-7, 2200.0, fundamental=5e6, medium="water", rocking="locked")
    result = job.run(example_path("example_particles.csv"), settings)
    assert result.particles["kappa_N_per_m"].isna().all()
    assert result.flag_counts["model-misfit"] == len(result.particles)
    lines = [w for w in result.warnings if "does not fit" in w]
    assert len(lines) == 1 and "--rocking" in lines[0] and "radius" in lines[0]
    assert result.constants["noise_fit_Hz"] > 3 * result.constants["noise_series_Hz"]
