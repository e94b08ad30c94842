"""The radiation loss of the QCM contacts (issue 13): analysis.radiation, its CLI options, outputs.

The reference values are computed here independently: the JKR radius from the formula written
out below (Johnson's, with paper 2's γ: work of adhesion w = 2γ), the stiffness from a separate
call of the public two-body API. No number is copied from the code's own output.
"""

import json
import math
from importlib.resources import as_file, files

import numpy as np
import pandas as pd
import pytest
from click.testing import CliRunner

from contactres.analysis._pipeline import AnalysisSettings
from contactres.analysis._radiation import (
    RADIATION_RESULTS,
    material_by_name,
    radiation_loss,
    radiation_summary,
)
from contactres.cli import main
from contactres.dynamic import _tangential_stiffness as tangential_stiffness
from contactres.dynamic._tangential_stiffness import two_body_contact_stiffness
from contactres.errors import ContactresInputError
from contactres.materials import Material, at_cut_quartz

R, NU, E, GAMMA = 1.1e-3, 0.21, 70e9, 0.05  # m, -, Pa, J/m² (paper 2's γ)
FORCES = np.array([2e-3, 5e-3, 10e-3])  # N per contact
F_QCM = 15e6  # Hz: 3rd overtone of a 5 MHz crystal


def jkr_radius(F, E_modulus, gamma, radius, nu):
    """JKR contact radius of two equal bodies, written out (Johnson, Contact Mechanics, 5.4):
    a³ = (3R/4E*) [F + 3πwR + √(6πwRF + (3πwR)²)], w = 2γ, 1/E* = 2(1 - ν²)/E."""
    E_star = E_modulus / (2 * (1 - nu**2))
    w = 2 * gamma
    b = 3 * math.pi * w * radius
    return np.cbrt(
        3 * radius / (4 * E_star) * (F + b + np.sqrt(6 * math.pi * w * radius * F + b**2))
    )


def mindlin_kappa(F, E_modulus, gamma, radius, nu):
    """κ = 8 G*_J a, 1/G*_J = 2(2 - ν)/G for two equal bodies (Johnson, Eq. 7.43)."""
    G = E_modulus / (2 * (1 + nu))
    return 8 * G / (2 * (2 - nu)) * jkr_radius(F, E_modulus, gamma, radius, nu)


def study():
    """Two groups: one with a JKR fit (3 loads), one withheld (1 load)."""
    loads = pd.DataFrame(
        {
            "configuration": ["glass"] * 4,
            "medium": ["air", "air", "air", "water"],
            "normal_force_N": [*FORCES, 4e-3],
            "loss_tangent_mean": [0.08, 0.07, 0.06, 0.1],
            "loss_tangent_sem": [0.002, 0.002, 0.001, 0.003],
            "kappa_N_per_m_mean": [*mindlin_kappa(FORCES, E, GAMMA, R, NU), 4e5],
        }
    )
    common = {"sphere_radius_m": R, "poisson": NU}
    groups = [
        {"configuration": "glass", "medium": "air", "E_Pa": E, "gamma_J_m2": GAMMA, "checks": []}
        | common,
        {
            "configuration": "glass",
            "medium": "water",
            "E_Pa": np.nan,
            "gamma_J_m2": np.nan,
            "checks": ["too-few-loads"],
        }
        | common,
    ]
    return loads, groups


@pytest.fixture(scope="module")
def glass_on_quartz():
    return Material.crystal("soda-lime-glass"), at_cut_quartz()


@pytest.fixture(scope="module")
def table(glass_on_quartz):
    loads, groups = study()
    return radiation_loss(loads, groups, *glass_on_quartz, frequency_Hz=F_QCM)


def test_columns_follow_the_schema_with_units_in_the_names(table):
    assert tuple(table.columns) == RADIATION_RESULTS.names
    for col in ("contact_radius_m", "frequency_Hz", "stiffness_static_N_per_m", "E_Pa"):
        assert RADIATION_RESULTS.column(col).unit in {"m", "Hz", "N/m", "Pa"}
    assert len(table) == 4


def test_radius_and_loss_tangent_agree_with_independent_formulas(table, glass_on_quartz):
    fitted = table.iloc[:3]
    a = jkr_radius(FORCES, E, GAMMA, R, NU)
    np.testing.assert_allclose(fitted["contact_radius_m"], a, rtol=1e-12)
    np.testing.assert_allclose(fitted["frequency_Hz"], F_QCM)
    K = two_body_contact_stiffness(*glass_on_quartz, a, F_QCM)
    K0 = two_body_contact_stiffness(*glass_on_quartz, a, 0.0)
    np.testing.assert_allclose(fitted["tan_delta_rad"], K.imag / K.real, rtol=1e-9)
    np.testing.assert_allclose(fitted["stiffness_real_N_per_m"], K.real, rtol=1e-9)
    np.testing.assert_allclose(fitted["stiffness_static_N_per_m"], np.real(K0), rtol=1e-9)
    np.testing.assert_allclose(
        fitted["dynamic_softening"], K.real / np.real(K0) - 1, rtol=1e-6, atol=1e-12
    )
    assert np.all(fitted["tan_delta_rad"] > 0)  # energy leaves the contact
    # Rows whose radiation exceeds the measured loss say so; the others have no note.
    over = fitted["radiation_share"].to_numpy() > 1
    assert fitted["note"][over].str.contains("above the measured").all()
    assert (fitted["note"][~over] == "").all()


def test_share_is_the_ratio_of_the_loss_tangents(table):
    fitted = table.iloc[:3]
    np.testing.assert_allclose(fitted["tan_delta_measured"], [0.08, 0.07, 0.06])
    np.testing.assert_allclose(
        fitted["radiation_share"], fitted["tan_delta_rad"] / fitted["tan_delta_measured"]
    )


def test_a_group_without_jkr_fit_gets_nan_and_the_reason(table):
    row = table.iloc[3]
    for col in ("contact_radius_m", "tan_delta_rad", "radiation_share", "E_static_corrected_Pa"):
        assert np.isnan(row[col]), col
    assert row["tan_delta_measured"] == 0.1  # the measurement is still shown
    assert "no JKR fit" in row["note"] and "too-few-loads" in row["note"]
    (water,) = [g for g in radiation_summary(table) if g["medium"] == "water"]
    assert water["n_loads"] == 0 and water["tan_delta_rad_range"] is None
    assert "too-few-loads" in water["note"]


def test_loads_without_a_frequency_or_a_group_are_flagged_not_fitted(glass_on_quartz):
    loads, groups = study()
    f = np.array([np.nan, F_QCM, F_QCM, F_QCM])  # e.g. a load measured at two overtones
    out = radiation_loss(loads.iloc[:1], groups[1:], *glass_on_quartz, frequency_Hz=f[:1])
    assert "no JKR fit" in out.loc[0, "note"]  # the air group is not among the groups given
    out = radiation_loss(loads.iloc[:1], groups, *glass_on_quartz, frequency_Hz=f[:1])
    assert "frequency" in out.loc[0, "note"] and np.isnan(out.loc[0, "tan_delta_rad"])


def test_uniform_softening_biases_E_by_its_three_halves_power(monkeypatch):
    """κ = E^(2/3) h(F, γ): κ read s times too high at every load gives E s^(3/2) too high."""
    s, c = 0.97, 3e11  # Re K/K₀ and K₀/a (Pa) of a stand-in stiffness

    def stand_in(sphere, plate, radius, frequency, direction=0.0):
        radius, frequency = np.broadcast_arrays(radius, frequency)
        return c * radius * np.where(frequency > 0, s + 0.05j, 1.0)

    monkeypatch.setattr(tangential_stiffness, "two_body_contact_stiffness", stand_in)
    loads, groups = study()
    out = radiation_loss(loads, groups, "glass", "quartz-AT", frequency_Hz=F_QCM)
    fitted = out.iloc[:3]
    np.testing.assert_allclose(fitted["dynamic_softening"], s - 1, rtol=1e-12)
    np.testing.assert_allclose(fitted["tan_delta_rad"], 0.05 / s, rtol=1e-12)
    np.testing.assert_allclose(fitted["E_static_corrected_Pa"], E * s**-1.5, rtol=1e-4)
    np.testing.assert_allclose(fitted["E_relative_change"], s**-1.5 - 1, rtol=1e-3)


def test_a_radius_the_solver_refuses_is_a_note_not_a_crash(monkeypatch):
    def refuses(sphere, plate, radius, frequency, direction=0.0):
        # The solver's range error is the typed input error (anything else is a fault).
        raise ContactresInputError("k_s a = 99 is beyond the range\nof the solver")

    monkeypatch.setattr(tangential_stiffness, "two_body_contact_stiffness", refuses)
    loads, groups = study()
    out = radiation_loss(loads, groups, "glass", "quartz-AT", frequency_Hz=F_QCM)
    assert out["tan_delta_rad"].isna().all() and out["E_static_corrected_Pa"].isna().all()
    assert (
        out["note"].iloc[:3]
        == "stiffness not computed: k_s a = 99 is beyond the range of the solver"
    ).all()
    np.testing.assert_allclose(
        out["contact_radius_m"].iloc[:3], jkr_radius(FORCES, E, GAMMA, R, NU)
    )


def test_material_names_aliases_and_errors():
    glass = material_by_name("Glass")
    np.testing.assert_array_equal(glass.C, Material.crystal("soda-lime-glass").C)
    plate = material_by_name("quartz-at", "plate")
    np.testing.assert_array_equal(plate.C, at_cut_quartz().C)
    assert plate.name == "quartz-AT" and glass.name == "soda-lime-glass"
    with pytest.raises(ValueError, match=r"unknown sphere material 'quartz-AT'.*fused-silica"):
        material_by_name("quartz-AT", "sphere")  # the cut names a plate, not a sphere
    with pytest.raises(ValueError, match=r"go together"):
        AnalysisSettings(sphere_material="glass")
    with pytest.raises(ValueError, match="known: quartz-AT, glass"):
        AnalysisSettings(sphere_material="glass", plate_material="unobtainium")


# ---- the command line -----------------------------------------------------------------------


def run(*args):
    return CliRunner().invoke(main, [str(a) for a in args])


def one_line_error(r, *words):
    assert r.exit_code == 2, r.output
    lines = r.output.strip().splitlines()
    assert len(lines) == 1, r.output
    assert ": error: " in lines[0] and "Traceback" not in r.output
    for w in words:
        assert w in lines[0], lines[0]


@pytest.fixture(scope="module")
def example():
    with as_file(files("contactres") / "data" / "example_sweeps.csv") as path:
        yield path


def test_cli_writes_the_radiation_table_summary_figure_and_lines(example, tmp_path):
    out = tmp_path / "res"
    r = run(
        "qcm", "analyze", example, "--out", out, "--bootstrap", "0",
        "--sphere-material", "glass", "--plate-material", "quartz-AT",
    )  # fmt: skip
    assert r.exit_code == 0, r.output
    table = pd.read_csv(out / "radiation.csv")
    loads = pd.read_csv(out / "loads.csv")
    assert tuple(table.columns) == RADIATION_RESULTS.names and len(table) == len(loads)
    # the example's constants: fundamental 5 MHz, overtone 3
    np.testing.assert_allclose(table["frequency_Hz"], 15e6)
    merged = table.merge(loads, on=["configuration", "medium", "normal_force_N"])
    np.testing.assert_allclose(merged["tan_delta_measured"], merged["loss_tangent_mean"])
    assert set(table["sphere_material"]) == {"soda-lime-glass"}
    assert set(table["plate_material"]) == {"quartz-AT"}
    assert (out / "radiation_loss.png").stat().st_size > 10_000
    summary = json.loads((out / "summary.json").read_text())
    assert summary["settings"]["sphere_material"] == "glass"
    section = summary["radiation"]
    assert (section["sphere_material"], section["plate_material"]) == (
        "soda-lime-glass",
        "quartz-AT",
    )
    assert len(section["groups"]) == len(summary["groups"])
    for g in section["groups"]:
        part = table[
            (table["configuration"] == g["configuration"]) & (table["medium"] == g["medium"])
        ]
        assert g["tan_delta_rad_median"] == pytest.approx(part["tan_delta_rad"].median())
    lines = [ln for ln in r.output.splitlines() if "radiation loss tangent" in ln]
    assert len(lines) == len(summary["groups"])
    assert all(" µm, " in ln and "% of the measured" in ln for ln in lines)


@pytest.mark.parametrize(
    "options, words",
    [
        (["--sphere-material", "glass"], ["--plate-material", "together"]),
        (["--plate-material", "quartz-AT"], ["--sphere-material", "together"]),
        (
            ["--sphere-material", "unobtainium", "--plate-material", "quartz-AT"],
            ["--sphere-material", "unobtainium", "soda-lime-glass"],
        ),
        (
            ["--sphere-material", "glass", "--plate-material", "quartz-XY"],
            ["--plate-material", "quartz-XY", "quartz-AT"],
        ),
    ],
)
def test_cli_bad_material_options_are_one_line_errors(example, tmp_path, options, words):
    r = run("qcm", "analyze", example, "--out", tmp_path / "o", *options)
    one_line_error(r, *words)
    assert not (tmp_path / "o").exists()


def test_rows_without_an_honest_share_say_why(glass_on_quartz):
    """A measured loss tangent <= 0 gives no share; a load below the JKR pull-off force and
    one at zero contact radius give no radiation; each row says why, the others are computed,
    and the analysis is not aborted."""
    loads, groups = study()
    loads.loc[0, "loss_tangent_mean"] = -0.01
    pull_off = -3 * math.pi * GAMMA * R  # paper 2's γ: F_c = -(3/2)π w R, w = 2γ
    loads.loc[1, "normal_force_N"] = 1.5 * pull_off
    out = radiation_loss(loads, groups, *glass_on_quartz, frequency_Hz=F_QCM)
    assert np.isnan(out["radiation_share"][0]) and "<= 0" in out["note"][0]
    assert np.isfinite(out["tan_delta_rad"][0])
    assert np.isnan(out["tan_delta_rad"][1]) and "pull-off" in out["note"][1]
    assert np.isfinite(out["tan_delta_rad"][2])
