"""``afm invert`` and ``rum invert`` with ``--coating``: k* -> the modulus of a film on a known
substrate.

The forward contacts are built here: the film a fresh ``Material.isotropic(E, ν)`` with the
Poisson's ratio of PMMA's 1 Hz storage constants (what ``--coating pmma:...`` keeps), on fused
silica, through ``sphere_contact``; the lever or the oscillator turns k* into the frequencies.
"""

import numpy as np
import pandas as pd
import pytest
from cli_checks import one_line_error, run

from contactres import LayeredMaterial, Material, pmma, sphere_contact
from contactres.resonators._cantilever import Cantilever, contact_frequencies

SILICA = Material.crystal("fused-silica")
NU = Material(C=np.real(pmma().at(1.0).C)).isotropic_constants[1]


def _k(M, h, R, P):
    """k* (N/m) of a rigid sphere R (m) at P (N) on a film of indentation modulus M (Pa) and
    thickness h (m) on fused silica."""
    film = Material.isotropic(M * (1 - NU**2), NU, name="film")
    # The forward model as the inversion evaluates it: without the API's a/R check (issue 30
    # made the API give NaN beyond a/R = 0.5, which a tip on a compliant film reaches here).
    stack = LayeredMaterial(SILICA, [(film, h)])
    return np.asarray(sphere_contact(stack, R, P, check_validity=False).stiffness)


@pytest.fixture
def coated_afm(tmp_path):
    """Three pixels of a lever (k_c = 40 N/m, r = 0.95) on 20 nm of a 5 GPa film on fused
    silica, a rigid 50 nm tip at 1, 2 and 4 µN; a fourth row without tip radius (no Hertz)."""
    lever = Cantilever((160e3, 1003e3), 40.0)
    P = np.array([1e-6, 2e-6, 4e-6, 1e-6])
    k = _k(5e9, 20e-9, 50e-9, P)
    f = contact_frequencies(lever, k / 40.0, 0.95, modes=(1,))
    frame = pd.DataFrame(
        {
            "pixel": [1, 2, 3, 4],
            "f1_free_Hz": 160e3,
            "f2_free_Hz": 1003e3,
            "k_c_N_per_m": 40.0,
            "tip_position": 0.95,
            "fc1_Hz": f[:, 0],
            "tip_radius_m": [50e-9, 50e-9, 50e-9, np.nan],
            "load_N": P,
        }
    )
    path = tmp_path / "afm.csv"
    frame.to_csv(path, index=False)
    return path


def test_afm_invert_coated_recovers_the_film_modulus(coated_afm, tmp_path):
    out = tmp_path / "out.csv"
    r = run("afm", "invert", coated_afm, "--out", out, "--coating", "pmma:20e-9",
            "--substrate", "fused-silica")  # fmt: skip
    assert r.exit_code == 0, r.output
    # At 4 µN the contact on the compliant film is wider than half the tip (a/R > 0.5): no
    # film modulus for it, one warning line (Hertz's limit, checked at the inversion's solution).
    assert "film PMMA 20 nm on fused-silica: 1 beyond-hertz, 2 film" in r.output
    assert "contactres: warning: film_modulus_from_contact_stiffness: a/R = " in r.output
    assert "(1 of 3 pixels): beyond Hertz, no film modulus" in r.output
    assert "Traceback" not in r.output and "ContactresWarning" not in r.output
    t = pd.read_csv(out, keep_default_na=False, na_values=[""])
    np.testing.assert_allclose(t["M_film_Pa"][:2], 5e9, rtol=1e-6)
    assert np.isnan(t["M_film_Pa"][2])
    assert t["film_contact_radius_m"][2] > 0.5 * 50e-9
    assert list(t["film_verdict"].fillna("")) == ["film", "film", "beyond-hertz", ""]
    assert (t["coating"] == "PMMA 20 nm").all()
    # The homogeneous Hertz inversion of the same k* is far off: the substrate shows.
    assert (t["M_sample_Pa"][:3] > 1.5 * 5e9).all()
    assert np.isnan(t["M_film_Pa"][3])


def test_rum_invert_coated_round_trip_thick_and_out_of_range(tmp_path):
    """Lumped oscillator, (f/f0)² = 1 + k*/K_eff: a 20 nm film resolved, the same k* on a
    100 µm film is the homogeneous Hertz inversion (too-thick), and a k* beyond the range."""
    R, P, K_eff, f0 = 2e-6, 1e-3, 1e6, 1e6
    k = np.array([_k(5e9, 200e-9, R, P), _k(5e9, 200e-9, R, P) * 50])
    fc = f0 * np.sqrt(1 + k / K_eff)
    path = tmp_path / "rum.csv"
    pd.DataFrame({"f0_Hz": f0, "fc_Hz": fc, "K_eff_N_per_m": K_eff}).to_csv(path, index=False)
    out = tmp_path / "out.csv"
    base = ("rum", "invert", path, "--out", out, "--substrate", "fused-silica", "--tip-radius", R,
            "--force", P)  # fmt: skip
    r = run(*base, "--coating", "pmma:200e-9")
    assert r.exit_code == 0, r.output
    t = pd.read_csv(out)
    assert t["M_film_Pa"][0] == pytest.approx(5e9, rel=1e-6)
    assert list(t["film_verdict"]) == ["film", "above-range"]
    assert np.isnan(t["M_film_Pa"][1])
    # The same stiffness on a film 100 µm thick: the film alone, as Hertz (Johnson 4.22-4.23).
    r = run(*base, "--coating", "pmma:1e-4")
    assert r.exit_code == 0, r.output
    t = pd.read_csv(out)
    assert t["film_verdict"][0] == "too-thick"
    # Labelled as contact's coating is (nm, µm, mm or m), not "1e+05 nm".
    assert (t["coating"] == "PMMA 100 µm").all()
    assert "film PMMA 100 µm on fused-silica: " in r.output
    assert t["M_film_Pa"][0] == pytest.approx(np.sqrt(k[0] ** 3 / (6 * R * P)), rel=1e-2)


AFM_BAD = [
    (("--coating", "pmma:-2e-8", "--substrate", "fused-silica"), ["--coating", "positive"]),
    (("--coating", "unobtainium:2e-8", "--substrate", "fused-silica"), ["unknown coating"]),
    (("--coating", "pmma:2e-8"), ["--coating", "--substrate"]),
    (("--substrate", "fused-silica"), ["--substrate", "--coating"]),
    (("--coating", "pmma:2e-8", "--coating", "pmma:2e-8", "--substrate", "Si"), ["one film"]),
    (("--coating", "pmma:2e-8", "--substrate", "Si", "--crystal", "Si"), ["--crystal"]),
    (("--coating", "pmma:2e-8", "--substrate", "Si", "--film-range", "3e9"), ["--film-range"]),
    (  # GPa typed as Pa: the unit slip is named
        ("--coating", "pmma:2e-8", "--substrate", "Si", "--film-range", "1:10"),
        ["--film-range", "gigapascals"],
    ),
    (("--coating", "pmma:2e-8", "--substrate", "nope"), ["--substrate:", "nope"]),
]


@pytest.mark.parametrize("extra, words", AFM_BAD, ids=[" ".join(e) for e, _ in AFM_BAD])
def test_afm_invert_coating_bad_input_one_line(coated_afm, tmp_path, extra, words):
    r = run("afm", "invert", coated_afm, "--out", tmp_path / "o.csv", *extra)
    one_line_error(r, *words)


RUM_BAD = [
    (("--coating", "pmma:2e-8", "--substrate", "Si"), ["--tip-radius", "--force"]),
    (("--tip-radius", "1e-6", "--force", "1e-3"), ["--coating"]),
    (
        ("--coating", "pmma:0", "--substrate", "Si", "--tip-radius", "1e-6", "--force", "1e-3"),
        ["--coating", "positive"],
    ),
    (
        (
            "--coating",
            "pmma:1e-7",
            "--substrate",
            "nope",
            "--tip-radius",
            "1e-6",
            "--force",
            "1e-3",
        ),
        ["--substrate:", "nope"],
    ),
]


@pytest.mark.parametrize("extra, words", RUM_BAD, ids=[" ".join(e) for e, _ in RUM_BAD])
def test_rum_invert_coating_bad_input_one_line(tmp_path, extra, words):
    from importlib.resources import files

    data = files("contactres") / "data" / "example_rum.csv"
    one_line_error(run("rum", "invert", data, "--out", tmp_path / "o.csv", *extra), *words)
