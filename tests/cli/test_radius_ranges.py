"""A radius typed in the wrong unit is refused on every route (issue 30, second review H1).

A QCM sphere wider than a few cm cannot sit on a crystal, a QCM-D particle is nm to ~100 µm and
an AFM tip nm to tens of µm: a sphere radius of 0.6 or 1 "m" (mm meant) used to pass every route
and gave E ≈ 2 GPa for glass, and a particle radius of 0.5 "m" (µm meant) ran.
"""

from __future__ import annotations

import pandas as pd
import pytest
from cli_checks import one_line_error, run

from contactres import read_sweeps
from contactres.errors import ContactresInputError
from contactres.examples import example_path


@pytest.fixture(scope="module")
def frame():
    """Paper 2's glass sphere of the bundled example (R = 1.1 mm), one configuration."""
    f = pd.read_csv(example_path("example_sweeps.csv"), comment="#")
    return f[f["configuration"] == "SiO2_2.2mm"]


@pytest.mark.parametrize("typed", [0.6, 1.0])
def test_a_sphere_radius_in_mm_is_refused_in_a_column(tmp_path, frame, typed):
    path = tmp_path / "mm.csv"
    frame.assign(sphere_radius_m=typed).to_csv(path, index=False)
    with pytest.raises(ContactresInputError, match=r"sphere_radius_m.*millimetres"):
        read_sweeps(path)


@pytest.mark.parametrize("typed", ["0.6", "1"])
def test_a_sphere_radius_in_mm_is_refused_in_toml_and_by_the_api(tmp_path, frame, typed):
    path = tmp_path / "mm.csv"
    frame.drop(columns=["sphere_radius_m"]).to_csv(path, index=False)
    with pytest.raises(ContactresInputError, match=r"sphere_radius_m.*millimetres"):
        read_sweeps(path, sphere_radius_m=float(typed))
    (tmp_path / "mm.toml").write_text(f"sphere_radius_m = {typed}\n")
    with pytest.raises(ContactresInputError, match=r"sphere_radius_m.*millimetres"):
        read_sweeps(path)


@pytest.mark.parametrize("typed", ["0.6", "1"])
def test_a_sphere_radius_in_mm_is_refused_as_an_option(tmp_path, frame, typed):
    path = tmp_path / "mm.csv"
    frame.drop(columns=["sphere_radius_m"]).to_csv(path, index=False)
    r = run("qcm", "analyze", path, "--out", tmp_path / "out", "--sphere-radius", typed)
    one_line_error(r, f"--sphere-radius {typed}", "millimetres")
    assert not (tmp_path / "out").exists()


def test_the_bundled_radii_and_a_5_cm_sphere_pass(tmp_path, frame):
    assert set(read_sweeps(example_path("example_sweeps.csv")).data["sphere_radius_m"]) <= {
        1.1e-3,
        6e-4,
    }
    path = tmp_path / "big.csv"
    frame.drop(columns=["sphere_radius_m"]).to_csv(path, index=False)
    table = read_sweeps(path, sphere_radius_m=0.05)
    assert (table.data["sphere_radius_m"] == 0.05).all()


def test_a_particle_radius_in_um_is_refused_by_the_option_and_the_job():
    from contactres.jobs.qcm_particles import Settings, _particle

    r = run("qcm", "particles", "x.csv", "--particle-radius", "0.5", "--out", "o")
    one_line_error(r, "--particle-radius", "micrometres")
    with pytest.raises(ContactresInputError, match=r"particle radius 0\.5 .*micrometres"):
        _particle(Settings(particle_radius=0.5, particle_density=2200.0))


def test_a_tip_radius_in_nm_is_refused_in_the_afm_table(tmp_path):
    # The table's tip_radius_m keeps the sphere's range (up to 1 m): it also holds the sphere
    # of a RUM-like contact (R = 1 cm in test_cli_resonances). 50 "m" is refused all the same.
    frame = pd.read_csv(example_path("example_afm.csv"), comment="#")
    path = tmp_path / "afm.csv"
    frame.assign(tip_radius_m=50.0).to_csv(path, index=False)
    r = run("afm", "invert", path, "--out", tmp_path / "out")
    assert r.exit_code == 2 and "tip_radius_m" in r.output and "looks like" in r.output, r.output
