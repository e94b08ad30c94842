"""The radiation loss on a coated plate (issue 26, point 4): analysis.radiation with a coating.

References are independent of the coated path: the bare plate's numbers from the public
two-body API (a film of the plate's own material must reproduce them), and for a soft, thin,
lossless film the quasi-static estimate "film = a massless spring in series", its stiffness from
the static punch solver (flat_punch_stiffness at f = 0, a different solver from the dynamic
layered Galerkin the coated radiation uses).
"""

import json
from importlib.resources import as_file, files

import numpy as np
import pandas as pd
import pytest
from click.testing import CliRunner

from contactres import LayeredMaterial, flat_punch_stiffness
from contactres.analysis._coating import Coating
from contactres.analysis._radiation import RADIATION_RESULTS, material_by_name, radiation_loss
from contactres.cli import main
from contactres.dynamic import tangential_contact_stiffness, two_body_contact_stiffness
from contactres.materials import Material

F_QCM = 15e6  # Hz: 3rd overtone of a 5 MHz crystal
RADII = np.array([3e-6, 6e-6])  # m: the coated fit's contact radii of the two loads
FORCES = np.array([2e-3, 5e-3])  # N


@pytest.fixture(scope="module")
def bodies():
    return material_by_name("glass"), material_by_name("quartz-AT", "plate")


def study():
    """One coated group whose record gives the contact radius of each load (as
    analysis._coating.apply_coating writes it)."""
    loads = pd.DataFrame(
        {
            "configuration": ["glass"] * 2,
            "medium": ["air"] * 2,
            "normal_force_N": FORCES,
            "loss_tangent_mean": [0.2, 0.2],
            "loss_tangent_sem": [0.01, 0.01],
            "kappa_N_per_m_mean": [1e6, 2e6],
        }
    )
    record = [
        {"normal_force_N": float(f), "contact_radius_m": float(a)}
        for f, a in zip(FORCES, RADII, strict=True)
    ]
    group = {
        "configuration": "glass",
        "medium": "air",
        "E_Pa": 70e9,
        "gamma_J_m2": 0.05,
        "sphere_radius_m": 1.1e-3,
        "poisson": 0.21,
        "checks": [],
        "coating": {"label": "film", "loads": record},
    }
    return loads, [group]


def quasi_static_tan(sphere, plate, film, h, radii):
    """The quasi-static estimate of tan δ_rad on the coated plate: the film as a massless
    spring (K_f from the static solver: 1/K_f = 1/K_coated − 1/K_bare) in series with the bare
    plate's and the sphere's dynamic tangential stiffness at F_QCM."""
    coated = flat_punch_stiffness(LayeredMaterial(plate, [(film, h)]), radii, 0.0, "tangential")
    naked = flat_punch_stiffness(plate, radii, 0.0, "tangential")
    spring = 1 / (1 / coated.real - 1 / naked.real)
    k_plate = tangential_contact_stiffness(plate, radii, F_QCM)
    k_sphere = tangential_contact_stiffness(sphere, radii, F_QCM)
    estimate = 1 / (1 / k_plate + 1 / k_sphere + 1 / spring)
    return estimate.imag / estimate.real


def test_a_film_of_the_plates_own_material_gives_the_bare_plate(bodies):
    """Issue 26, point 5 asks 1e-10; asserted 1e-9 of each column's largest |value|, against
    the bare two-body stiffness at rtol 1e-9. The coated route runs at its own fixed rtol of
    1e-4 (a share needs no more; radiation_loss takes no rtol), so its residual error, not the
    film, sets the bound: measured 3.6e-10 (imaginary part), 2.2e-10 (tan δ_rad and share),
    1.4e-10 (real part), 8.5e-11 (static). The softening K'/K₀ − 1 is a difference of nearly
    equal numbers; it is checked as K'/K₀ (measured 5.4e-11)."""
    sphere, plate = bodies
    loads, groups = study()
    out = radiation_loss(
        loads, groups, sphere, plate, frequency_Hz=F_QCM, coating=Coating(((plate, 250e-9),))
    )
    assert tuple(out.columns) == RADIATION_RESULTS.names
    np.testing.assert_allclose(out["contact_radius_m"], RADII, rtol=0)
    K = two_body_contact_stiffness(sphere, plate, RADII, F_QCM, rtol=1e-9)
    K0 = two_body_contact_stiffness(sphere, plate, RADII, 0.0, rtol=1e-9).real
    expected = {
        "stiffness_real_N_per_m": K.real,
        "stiffness_imag_N_per_m": K.imag,
        "stiffness_static_N_per_m": K0,
        "tan_delta_rad": K.imag / K.real,
        "radiation_share": K.imag / K.real / 0.2,
    }
    for column, ref in expected.items():
        err = np.max(np.abs(out[column].to_numpy(float) - ref))
        assert err < 1e-9 * np.max(np.abs(ref)), column
    softening = out["dynamic_softening"].to_numpy(float) + 1
    assert np.max(np.abs(softening - K.real / K0)) < 1e-9 * np.max(K.real / K0)
    assert set(out["plate_material"]) == {"quartz-AT coated with quartz-AT 250 nm"}
    # No refit of E on a coated plate: said, not guessed.
    assert out["E_static_corrected_Pa"].isna().all()
    assert out["note"].str.contains("E not refitted on a coated plate").all()


def test_a_soft_lossless_film_lowers_the_radiation_loss_tangent(bodies):
    """A film much thinner than its shear wavelength (here 1 µm against ~1.5 mm at 15 MHz)
    stores energy and radiates almost none: a nearly lossless spring in series with the
    radiating plate. In series, the loss tangent of the pair is the plate's weighted by the
    share of the compliance that is lossy, so a soft film lowers tan δ_rad (while it stays > 0:
    the substrate still radiates)."""
    sphere, plate = bodies
    film = Material.isotropic(5e9, 0.35, density=1190.0, name="soft")
    h = 1e-6
    loads, groups = study()
    out = radiation_loss(
        loads, groups, sphere, plate, frequency_Hz=F_QCM, coating=Coating(((film, h),))
    )
    tan = out["tan_delta_rad"].to_numpy(float)
    bare = two_body_contact_stiffness(sphere, plate, RADII, F_QCM)
    assert np.all(tan > 0)
    assert np.all(tan < 0.5 * bare.imag / bare.real)
    # 2 % measured (the film's inertia and the static solver's θ average are left out).
    np.testing.assert_allclose(tan, quasi_static_tan(sphere, plate, film, h, RADII), rtol=0.05)


def test_rows_the_layered_solver_refuses_say_why(bodies):
    """An anisotropic film thin against the contact radius on the anisotropic plate is beyond
    the layered tangential punch (ContactresInputError): that row says so, the other is
    computed."""
    sphere, plate = bodies
    # A soft cubic film (A = 2), its [111] along the normal: not axisymmetric.
    film = Material.cubic(8e9, 4e9, 4e9, density=1190.0, name="soft cubic").rotated((1, 1, 1))
    loads, groups = study()
    groups[0]["coating"]["loads"][1]["contact_radius_m"] = 15e-6  # a/h = 50 (the other 10)
    out = radiation_loss(
        loads, groups, sphere, plate, frequency_Hz=F_QCM, coating=Coating(((film, 300e-9),))
    )
    assert np.isfinite(out.loc[0, "tan_delta_rad"]) and np.isnan(out.loc[1, "tan_delta_rad"])
    assert out.loc[1, "note"].startswith("stiffness not computed: ")


def test_a_thin_isotropic_film_on_the_anisotropic_plate_is_computed(bodies):
    """An isotropic film at a/h = 50 on quartz-AT (refused until the layered tangential punch
    left the edge enrichment out for a top film unchanged by rotations about the normal: 23
    of the 24 loads of the coated example had no radiation share). Against the quasi-static
    estimate (the film as a massless spring from the static solver, in series with the bare
    plate's and the sphere's dynamic stiffness), independent of the layered dynamic punch."""
    sphere, plate = bodies
    film = Material.isotropic(5e9, 0.35, density=1190.0, name="soft")
    h = 300e-9
    loads, groups = study()
    radii = np.array([3e-6, 15e-6])  # a/h = 10 and 50
    groups[0]["coating"]["loads"][1]["contact_radius_m"] = float(radii[1])
    out = radiation_loss(
        loads, groups, sphere, plate, frequency_Hz=F_QCM, coating=Coating(((film, h),))
    )
    assert not out["note"].fillna("").str.startswith("stiffness not computed").any()
    tan = out["tan_delta_rad"].to_numpy(float)
    # Measured 0.5 % and 0.4 % (the film's inertia and the static solver's θ average are left
    # out of the estimate).
    np.testing.assert_allclose(tan, quasi_static_tan(sphere, plate, film, h, radii), rtol=0.02)


def test_cli_radiation_on_the_coated_example(tmp_path):
    out = tmp_path / "res"
    # One group of the bundled example (the 2.2 mm spheres in air) at three of its six loads,
    # the lightest and the heaviest among them (a/h = 30-36 as with all six), keeps the test
    # short: each coated row is a layered tangential punch.
    with as_file(files("contactres") / "data" / "example_sweeps.csv") as example:
        rows = pd.read_csv(example)
    rows = rows[(rows["configuration"] == "SiO2_2.2mm") & (rows["medium"] == "air")]
    forces = np.unique(rows["normal_force_N"])
    assert forces.size == 6
    part = tmp_path / "sweeps.csv"
    rows[rows["normal_force_N"].isin(forces[[0, 2, 5]])].to_csv(part, index=False)
    args = ["qcm", "analyze", str(part), "--out", str(out), "--no-figures"]
    args += ["--bootstrap", "0", "--coating", "pmma:250e-9"]
    args += ["--sphere-material", "glass", "--plate-material", "quartz-AT"]
    r = CliRunner().invoke(main, args)
    assert r.exit_code == 0, r.output
    table = pd.read_csv(out / "radiation.csv", keep_default_na=False, na_values=[""])
    assert tuple(table.columns) == RADIATION_RESULTS.names
    assert set(table["plate_material"]) == {"quartz-AT coated with PMMA 250 nm"}
    summary = json.loads((out / "summary.json").read_text())
    # Each row's radius is its group's coated one, at its load (10 digits in the CSV).
    for g in summary["groups"]:
        part = table[
            (table["configuration"] == g["configuration"]) & (table["medium"] == g["medium"])
        ]
        want = {r["normal_force_N"]: r["contact_radius_m"] for r in g["coating"]["loads"]}
        np.testing.assert_allclose(
            part["contact_radius_m"], [want[f] for f in part["normal_force_N"]], rtol=1e-9
        )
    # Every row has a positive loss tangent (PMMA on quartz-AT at a/h = 30-36: the layered
    # tangential punch refused all six until the isotropic film's edge was left unenriched).
    tan = table["tan_delta_rad"].to_numpy(float)
    assert tan.size == 3
    assert np.all(np.isfinite(tan)) and np.all(tan > 0)
    assert "radiation loss of the contacts" in r.output
