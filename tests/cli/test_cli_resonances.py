"""``contactres afm invert`` and ``rum invert``: tables of resonances -> k* (and modulus)."""

import numpy as np
import pandas as pd
import pytest
from click.testing import CliRunner

from contactres.cli import main
from contactres.normal import hertz
from contactres.resonators._cantilever import Cantilever, contact_frequencies


def _run(*args):
    return CliRunner().invoke(main, list(args))


@pytest.fixture
def afm_table(tmp_path):
    """Three pixels of a lever (k_c = 40 N/m, r = 0.95) on a sample whose contact stiffness is
    that of Hertz for M_sample = 50 GPa, a 165 GPa tip, R = 50 nm and P = 1, 2, 4 µN."""
    lever = Cantilever((160e3, 1003e3), 40.0)
    P = np.array([1e-6, 2e-6, 4e-6])
    E_star = 1 / (1 / 50e9 + 1 / 165e9)
    # a/R = 0.2-0.3, beyond Hertz's a/R <= 0.1: the table is made with Hertz's relation all the
    # same (the inversion reads k* with it; its range is not this file's matter)
    c = hertz(E_star, 50e-9, P, check_validity=False)
    k_star = 2 * c.contact_radius * E_star  # Johnson, Eq. 4.22 differentiated: dF/dδ = 2aE*
    f = contact_frequencies(lever, k_star / 40.0, 0.95, modes=(1, 2))
    frame = pd.DataFrame(
        {
            "pixel": [1, 2, 3],
            "f1_free_Hz": 160e3,
            "f2_free_Hz": 1003e3,
            "k_c_N_per_m": 40.0,
            "tip_position": 0.95,
            "fc1_Hz": f[:, 0],
            "tip_radius_m": 50e-9,
            "load_N": P,
            "M_tip_Pa": 165e9,
        }
    )
    path = tmp_path / "afm.csv"
    frame.to_csv(path, index=False)
    return path, k_star


def test_afm_invert_recovers_stiffness_and_modulus(afm_table, tmp_path):
    path, k_star = afm_table
    r = _run("afm", "invert", str(path), "--out", str(tmp_path / "out.csv"))
    assert r.exit_code == 0, r.output
    out = pd.read_csv(tmp_path / "out.csv")
    assert list(out["pixel"]) == [1, 2, 3]
    np.testing.assert_allclose(out["k_star_N_per_m"], k_star, rtol=1e-8)
    np.testing.assert_allclose(out["M_sample_Pa"], 50e9, rtol=1e-7)
    assert (out["normalisation"] == "global").all()


def test_afm_invert_counts_the_rows_without_a_modulus(afm_table, tmp_path):
    """A row with k* but a blank tip radius has no modulus: the summary says in how many rows
    the median is taken, not only the output's blank cell (issue 27's closing campaign)."""
    path, _ = afm_table
    frame = pd.read_csv(path)
    frame.loc[1, "tip_radius_m"] = np.nan
    frame.to_csv(path, index=False)
    r = _run("afm", "invert", str(path), "--out", str(tmp_path / "out.csv"))
    assert r.exit_code == 0, r.output
    assert "3 rows, 3 with k*" in r.stdout and "GPa in 2 of the 3 rows with k*" in r.stdout
    out = pd.read_csv(tmp_path / "out.csv")
    assert np.isnan(out["M_sample_Pa"][1]) and np.isfinite(out["M_sample_Pa"][[0, 2]]).all()


def test_afm_invert_refuses_bad_input_in_one_line(afm_table, tmp_path):
    path, _ = afm_table
    frame = pd.read_csv(path)
    frame.loc[1, "f1_free_Hz"] = 160.0  # kHz typed as Hz
    bad = tmp_path / "bad.csv"
    frame.to_csv(bad, index=False)
    r = _run("afm", "invert", str(bad), "--out", str(tmp_path / "o.csv"))
    assert r.exit_code != 0
    assert "line 3, column 'f1_free_Hz'" in r.output and "kilohertz" in r.output
    assert "Traceback" not in r.output and len(r.output.strip().splitlines()) == 1
    r = _run("afm", "invert", str(path), "--out", str(path))
    assert r.exit_code != 0 and "would overwrite the input" in r.output
    r = _run("afm", "invert", str(path), "--out", str(tmp_path / "o.csv"), "--normalisation", "x")
    assert r.exit_code == 2


def test_afm_and_rum_name_the_stiffness_a_column_holds(afm_table, tmp_path):
    # The lever's spring constant and the oscillator's stiffness are checked with the contact
    # stiffness's range; the message names what the column holds, not "the contact stiffness".
    path, _ = afm_table
    frame = pd.read_csv(path)
    frame.loc[0, "k_c_N_per_m"] = -40.0
    bad = tmp_path / "bad.csv"
    frame.to_csv(bad, index=False)
    r = _run("afm", "invert", str(bad), "--out", str(tmp_path / "o.csv"))
    assert r.exit_code != 0 and "column 'k_c_N_per_m'" in r.output
    assert "the spring constant of the lever lies in" in r.output
    assert "contact stiffness" not in r.output
    rum = tmp_path / "rum.csv"
    rum.write_text("pixel,f0_Hz,fc_Hz,K_eff_N_per_m\n1,1e6,1.01e6,-1e5\n")
    r = _run("rum", "invert", str(rum), "--out", str(tmp_path / "r.csv"))
    assert r.exit_code != 0 and "the effective stiffness of the oscillator lies in" in r.output


def test_afm_modulus_beyond_diamond_is_withheld(afm_table, tmp_path):
    path, _ = afm_table
    frame = pd.read_csv(path)
    frame["load_N"] = 1e-12  # a plausible force, but E* = √(k*³/6RP) comes out ~1e3 too large
    frame["M_tip_Pa"] = np.nan
    bad = tmp_path / "r.csv"
    frame.to_csv(bad, index=False)
    r = _run("afm", "invert", str(bad), "--out", str(tmp_path / "o.csv"))
    assert r.exit_code == 0, r.output
    out = pd.read_csv(tmp_path / "o.csv")
    assert (out["flags"] == "modulus-out-of-range").all() and out["M_sample_Pa"].isna().all()
    assert out["E_star_Pa"].isna().all()


def test_rum_invert_lumped_closed_form(tmp_path):
    path = tmp_path / "rum.csv"
    path.write_text("pixel,f0_Hz,fc_Hz,K_eff_N_per_m\n1,1e6,1.01e6,1e5\n2,1e6,1.02e6,1e5\n")
    r = _run("rum", "invert", str(path), "--out", str(tmp_path / "o.csv"))
    assert r.exit_code == 0, r.output
    out = pd.read_csv(tmp_path / "o.csv")
    # (f/f0)² = 1 + k*/K_eff: k* = 1e5 (1.01² - 1) = 2010 N/m, 1e5 (1.02² - 1) = 4040 N/m
    np.testing.assert_allclose(out["k_star_N_per_m"], [2010.0, 4040.0], rtol=1e-12)
    path.write_text("pixel,f0_Hz,fc_Hz,K_eff_N_per_m\n1,1e6,0.99e6,1e5\n")
    r = _run("rum", "invert", str(path), "--out", str(tmp_path / "o.csv"))
    assert r.exit_code != 0 and "line 2, column 'fc_Hz'" in r.output
    path.write_text("pixel,f0_Hz,fc_Hz\n1,1e6,1.01e6\n")
    r = _run("rum", "invert", str(path), "--out", str(tmp_path / "o.csv"))
    assert r.exit_code != 0 and "K_eff_N_per_m" in r.output


@pytest.mark.parametrize(
    "row",
    [
        "1,1000,1.01e6,1e5",  # f0 in kHz written as Hz
        "1,1e6,1.01e9,1e5",  # fc 1000 times too large (kHz figures read as MHz)
    ],
)
def test_rum_contact_resonance_far_above_the_free_one_is_a_unit_slip(tmp_path, row):
    """A contact spring raises the first mode at most to its pinned limit (1.5 f0 for a rod,
    4.39 f0 for a cantilever); fc ~ 1000 f0 is f0 and fc in different units, an error naming
    the file, line, column and value rather than k* = 1e11 N/m."""
    path = tmp_path / "rum.csv"
    path.write_text(f"pixel,f0_Hz,fc_Hz,K_eff_N_per_m\n{row}\n")
    r = _run("rum", "invert", str(path), "--out", str(tmp_path / "o.csv"))
    assert r.exit_code != 0 and not (tmp_path / "o.csv").exists()
    assert "rum.csv, line 2, column 'fc_Hz': value" in r.output and "4.39" in r.output
    # the largest raise a cantilever allows is accepted: k* = 1e5 (4.3² - 1) N/m
    path.write_text("pixel,f0_Hz,fc_Hz,K_eff_N_per_m\n1,1e6,4.3e6,1e5\n")
    r = _run("rum", "invert", str(path), "--out", str(tmp_path / "o.csv"))
    assert r.exit_code == 0, r.output
    out = pd.read_csv(tmp_path / "o.csv")
    np.testing.assert_allclose(out["k_star_N_per_m"], [1e5 * (4.3**2 - 1)], rtol=1e-9)


def test_afm_contact_below_the_free_lever_and_load_in_the_wrong_unit(afm_table, tmp_path):
    path, _ = afm_table
    frame = pd.read_csv(path)
    low = frame.assign(fc1_Hz=[150e3, *frame["fc1_Hz"][1:]])  # below f1_free: impossible
    low.to_csv(tmp_path / "low.csv", index=False)
    r = _run("afm", "invert", str(tmp_path / "low.csv"), "--out", str(tmp_path / "o.csv"))
    assert r.exit_code != 0 and "line 2, column 'fc1_Hz'" in r.output
    assert "below the free resonance" in r.output
    # µN typed as N: a = k*/(2E*) comes out ~6 µm on a 50 nm tip, no Hertz contact
    frame.assign(load_N=frame["load_N"] * 1e6).to_csv(tmp_path / "uN.csv", index=False)
    r = _run("afm", "invert", str(tmp_path / "uN.csv"), "--out", str(tmp_path / "o.csv"))
    assert r.exit_code == 0, r.output
    out = pd.read_csv(tmp_path / "o.csv")
    assert (out["flags"] == "not-hertzian").all() and out["M_sample_Pa"].isna().all()


def _invert(frame, tmp_path, *extra):
    path = tmp_path / "t.csv"
    frame.to_csv(path, index=False)
    r = _run("afm", "invert", str(path), "--out", str(tmp_path / "o.csv"), *extra)
    return r, (pd.read_csv(tmp_path / "o.csv") if r.exit_code == 0 else None)


def test_afm_reference_sample_gives_the_hertz_modulus(afm_table, tmp_path):
    """The reference method with m = 3/2 and a reference itself Hertzian (same tip, same load)
    gives the modulus Hertz gives: an independent path through the table."""
    path, _ = afm_table
    frame = pd.read_csv(path)
    lever = Cantilever((160e3, 1003e3), 40.0)
    E_ref = 1 / (1 / 100e9 + 1 / 165e9)
    P = frame["load_N"].to_numpy()
    k_ref = 2 * hertz(E_ref, 50e-9, P, check_validity=False).contact_radius * E_ref  # as above
    frame["fc1_ref_Hz"] = contact_frequencies(lever, k_ref / 40.0, 0.95, modes=(1,))[:, 0]
    frame["M_ref_Pa"] = 100e9
    frame["hardness_Pa"] = [np.nan, 1e13, np.nan]  # checked where given, with the load
    r, out = _invert(frame.drop(columns=["tip_radius_m"]), tmp_path)
    assert r.exit_code == 0, r.output
    np.testing.assert_allclose(out["M_sample_Pa"], 50e9, rtol=1e-7)
    assert out["modulus_method"].str.startswith("reference").all()
    # without k_c only ratios of k* are known: the reference method still works
    r, out = _invert(frame.drop(columns=["tip_radius_m", "k_c_N_per_m"]), tmp_path)
    assert r.exit_code == 0, r.output
    np.testing.assert_allclose(out["M_sample_Pa"], 50e9, rtol=1e-7)
    assert out["k_star_N_per_m"].isna().all()


def test_afm_hertz_needs_k_c_and_extra_columns_pass_through(afm_table, tmp_path):
    path, _ = afm_table
    frame = pd.read_csv(path).drop(columns=["k_c_N_per_m"])
    frame["x_m"] = ["", "1e-6", "note"]  # a label column whose name ends in _m
    r, out = _invert(frame, tmp_path)
    assert r.exit_code == 0, r.output
    assert out["M_sample_Pa"].isna().all() and out["kappa"].notna().all()
    assert list(out["x_m"].fillna("")) == ["", "1e-6", "note"]
    # Issue 27: the missing k* was printed as "0 flagged"; every such row now says why.
    assert (out["flags"] == "no-spring-constant").all()
    assert "3 rows, 0 with k*; 3 flagged" in r.output


def test_afm_q_given_in_some_cells_only_and_negative_tilt(afm_table, tmp_path):
    path, _ = afm_table
    frame = pd.read_csv(path)
    frame["Q1"] = [300.0, np.nan, 200.0]
    r, out = _invert(frame, tmp_path)
    assert r.exit_code == 0, r.output
    assert out["sigma_N_s_per_m"].isna().tolist() == [False, True, False]
    r, _ = _invert(frame.assign(tilt_deg=-5.0), tmp_path)
    assert r.exit_code != 0 and "column 'tilt_deg'" in r.output
    r, _ = _invert(frame.assign(Q1_free=100.0), tmp_path)  # a free Q for mode 1, not mode 2
    assert r.exit_code != 0 and "column 'Q2_free'" in r.output


def _si001():
    from contactres import Material

    return Material.crystal("Si").rotated((0, 0, 1))


def test_afm_dynamic_correction_is_negligible_for_an_afm_tip(afm_table, tmp_path):
    path, _ = afm_table
    frame = pd.read_csv(path)
    r0, plain = _invert(frame, tmp_path)
    r, out = _invert(frame, tmp_path, "--crystal", "Si", "--surface", "001")
    assert r0.exit_code == 0 and r.exit_code == 0, r.output
    assert "k_a" not in plain.columns and "dcsf_real" in out.columns
    si = _si001()
    c_l = np.sqrt(si.C[2, 2].real / si.density)  # longitudinal speed along [001]
    expected = 2 * np.pi * frame["fc1_Hz"] * out["contact_radius_m"] / c_l
    np.testing.assert_allclose(out["k_a"], expected, rtol=1e-9)
    assert out["k_a"].between(1e-7, 1e-5).all()  # the README's "k a ~ 1e-5: negligible"
    assert (np.abs(out["dcsf_real"] - 1) < 1e-9).all() and (out["dcsf_imag"] > 0).all()
    np.testing.assert_allclose(out["M_sample_Pa"], plain["M_sample_Pa"], rtol=1e-9)
    assert (out["modulus_method"] == "hertz + dynamic").all()
    assert "dynamic correction: k_l a <=" in r.output


def test_afm_dynamic_correction_recovers_the_modulus_of_a_large_fast_contact(tmp_path):
    # RUM-like contact, k_l a ~ 0.1 on Si(001): the measured stiffness of each mode is the
    # dynamic one at its own frequency, K_static Re DCSF(k_l(f_n) a) (paper 1, Eq. 29), built
    # here by its own fixed point on f_n; the static inversion is then 0.3-2 % off, the
    # corrected one exact, with one mode and with two (each corrected at its own frequency).
    from contactres import dcsf, indentation_modulus

    si = _si001()
    M = indentation_modulus(si)  # rigid tip: E* = M
    c_l = np.sqrt(si.C[2, 2].real / si.density)
    lever = Cantilever((160e3, 1003e3), 1.0e6)
    a = np.array([1.5e-4, 2.2e-4])
    R, K_s = 1e-2, 2 * a * M
    P = 4 * M * a**3 / (3 * R)  # Hertz: a³ = 3PR/(4E*)
    f = np.full((2, 2), 600e3)
    for _ in range(30):
        D = np.asarray(dcsf(si, 2 * np.pi * f * a[:, None] / c_l, model="exact")).real
        for n in (1, 2):
            kappa = K_s * D[:, n - 1] / 1.0e6
            f[:, n - 1] = contact_frequencies(lever, kappa, 0.95, modes=(n,))[:, 0]
    frame = pd.DataFrame(
        {
            "f1_free_Hz": 160e3,
            "f2_free_Hz": 1003e3,
            "k_c_N_per_m": 1.0e6,
            "tip_position": 0.95,
            "fc1_Hz": f[:, 0],
            "fc2_Hz": f[:, 1],
            "tip_radius_m": R,
            "load_N": P,
        }
    )
    for columns in (["fc2_Hz"], []):  # mode 1 alone, then modes 1 and 2
        table = frame.drop(columns=columns)
        r0, plain = _invert(table, tmp_path)
        r, out = _invert(table, tmp_path, "--crystal", "Si")
        assert r0.exit_code == 0 and r.exit_code == 0, r.output
        assert out["k_a"].between(0.05, 0.2).all()
        np.testing.assert_allclose(out["M_sample_Pa"], M, rtol=1e-8)
        np.testing.assert_allclose(out["contact_radius_m"], a, rtol=1e-8)
        np.testing.assert_allclose(out["k_static_N_per_m"], K_s, rtol=1e-8)
        assert (np.abs(plain["M_sample_Pa"] / M - 1) > 1e-3).all()  # uncorrected: visibly off


def test_afm_three_modes_choose_the_crossing_and_report_their_spread(tmp_path):
    lever = Cantilever((160e3, 1003e3, 2810e3), 40.0)
    f = contact_frequencies(lever, np.array([20.0, 50.0, 80.0]), 0.7, modes=(1, 2, 3))
    frame = pd.DataFrame(f, columns=["fc1_Hz", "fc2_Hz", "fc3_Hz"]).assign(
        f1_free_Hz=160e3, f2_free_Hz=1003e3, f3_free_Hz=2810e3, k_c_N_per_m=40.0
    )
    frame.loc[2, "fc3_Hz"] *= 1.01  # mode 3 off by 1 %: no crossing of modes 1-2 agrees with it
    r, out = _invert(frame, tmp_path)
    assert r.exit_code == 0, r.output
    np.testing.assert_allclose(out["tip_position_used"][:2], 0.7, atol=1e-9)
    assert (out["mode_spread"][:2] < 1e-9).all() and (out["flags"][:2].isna()).all()
    assert "inconsistent-modes" in out["flags"][2] and out["mode_spread"][2] > 0.05
    r, _ = _invert(frame, tmp_path, "--mode-tolerance", "7")
    assert r.exit_code != 0 and "--mode-tolerance" in r.output and "Traceback" not in r.output
    r, _ = _invert(frame, tmp_path, "--surface", "111")
    assert r.exit_code != 0 and "--crystal" in r.output
    r, _ = _invert(frame, tmp_path, "--crystal", "unobtainium")
    assert r.exit_code != 0 and "--crystal" in r.output and "Traceback" not in r.output


def test_afm_modewise_needs_the_free_frequency_of_every_mode_used(afm_table, tmp_path):
    path, _ = afm_table
    frame = pd.read_csv(path).drop(columns=["f2_free_Hz"])
    frame["fc2_Hz"] = 1.2e6
    r, _ = _invert(frame, tmp_path, "--normalisation", "modewise")
    assert r.exit_code != 0 and "f2_free_Hz" in r.output and "line 2" in r.output
    assert "Traceback" not in r.output and "[" not in r.output.split("error:")[1]


def test_afm_invert_no_contact_row_and_the_crossing_not_taken(afm_table, tmp_path):
    # Row 1 at the free resonance: κ = 0 and k* = 0 flagged no-contact (was an empty row).
    # Rows 2-3 with r blank and both modes: r solved, and the other crossing of the two modes
    # (near r = 0.66 for this lever, its κ larger) in the columns beside it.
    path, k_star = afm_table
    lever = Cantilever((160e3, 1003e3), 40.0)
    f = contact_frequencies(lever, k_star / 40.0, 0.95, modes=(1, 2))
    frame = pd.read_csv(path).assign(fc2_Hz=f[:, 1], tip_position=[0.95, np.nan, np.nan])
    frame.loc[0, "fc1_Hz"] = 160e3
    frame.loc[0, "fc2_Hz"] = np.nan
    r, out = _invert(frame, tmp_path)
    assert r.exit_code == 0, r.output
    assert out.loc[0, "kappa"] == 0 and out.loc[0, "k_star_N_per_m"] == 0
    assert out.loc[0, "flags"] == "no-contact" and np.isnan(out.loc[0, "M_sample_Pa"])
    assert np.allclose(out["tip_position_used"][1:], 0.95, atol=1e-9)
    assert np.allclose(out["k_star_N_per_m"][1:], k_star[1:], rtol=1e-8)
    assert (out["flags"][1:] == "several-crossings").all()
    other = out["tip_position_other"][1:].to_numpy()
    assert np.all((other > 0.6) & (other < 0.7)) and np.isnan(out.loc[0, "tip_position_other"])
    assert np.all(out["kappa_other"][1:] > out["kappa"][1:])


def test_afm_reference_at_the_free_frequency_calibrates_nothing(afm_table, tmp_path):
    # A reference resonance equal to the free one is no contact (κ_ref = 0): no reference
    # modulus for that row (no division by k*_ref = 0, no error), the others still calibrate.
    path, _ = afm_table
    frame = pd.read_csv(path).drop(columns=["tip_radius_m"])
    lever = Cantilever((160e3, 1003e3), 40.0)
    frame["fc1_ref_Hz"] = contact_frequencies(lever, 30.0, 0.95, modes=(1,))[0]
    frame.loc[0, "fc1_ref_Hz"] = 160e3
    frame["M_ref_Pa"] = 100e9
    r, out = _invert(frame, tmp_path)
    assert r.exit_code == 0, r.output
    assert np.isnan(out.loc[0, "M_sample_Pa"]) and out.loc[0, "modulus_method"] != "reference"
    assert np.isfinite(out["M_sample_Pa"][1:]).all()


def test_afm_tip_radius_above_a_millimetre_is_flagged_and_warned(afm_table, tmp_path):
    """tip_radius_m = 5e-2 (50 nm typed as cm) is no CR-AFM tip (1 nm-1 µm): the row keeps its
    values, but its flags say large-tip and one warning line names the file, line, column and
    value; the rows with a 50 nm tip are unchanged (a mm sphere stays a valid input, see the
    dynamic-correction test above)."""
    path, _ = afm_table
    frame = pd.read_csv(path)
    _, plain = _invert(frame, tmp_path)
    slipped = frame.assign(tip_radius_m=[50e-9, 5e-2, 50e-9])
    r, out = _invert(slipped, tmp_path)
    assert r.exit_code == 0, r.output
    assert out["flags"][1] == "large-tip" and out["flags"][[0, 2]].isna().all()
    np.testing.assert_allclose(out["M_sample_Pa"][[0, 2]], plain["M_sample_Pa"][[0, 2]])
    warned = [line for line in r.output.splitlines() if line.startswith("contactres: warning:")]
    assert len(warned) == 1
    assert "t.csv, line 3, column 'tip_radius_m': value 0.05" in warned[0]
    assert "check the unit" in warned[0]
