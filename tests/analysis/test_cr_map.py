"""Maps of k*, σ, tan δ, E* and M from (f, Q) maps (contactres.invert_cr_map).

The maps are made with the forward model of the lever (contactres.contact_frequencies, tested
against an independent beam elsewhere) on a Kelvin-Voigt contact of chosen k* and tan δ per pixel
(tests/conftest.py); the moduli are checked against Hertz, the flat punch and the series law
written out here.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

import contactres as cr
from contactres.analysis import CR_MAP_FLAGS, ModulusModel
from contactres.analysis._cr_map import FLAG_NEGATIVE_DAMPING
from contactres.errors import ContactresInputError

LEVER = cr.Cantilever((300e3,), 40.0, free_q_factors=(400.0,))  # Hz, N/m
R_TIP = 0.95


def lever_map(kelvin_voigt, k_star, tan_delta=0.0):
    """(f, Q) maps of mode 1 on a Kelvin-Voigt contact k*, tan δ (tests/conftest.py)."""
    return kelvin_voigt(LEVER, k_star, tan_delta, R_TIP)


def hertz_k(e_star, radius, load):
    """Hertz contact stiffness k* = 2aE*, a³ = 3PR/(4E*) (Johnson Eqs. 4.22-4.23)."""
    a = (3.0 * load * radius / (4.0 * e_star)) ** (1.0 / 3.0)
    return 2.0 * a * e_star


def test_kstar_sigma_and_loss_tangent_of_a_damped_contact(kelvin_voigt):
    k_true = np.linspace(800.0, 6000.0, 12).reshape(3, 4)  # N/m
    tan_true = np.linspace(0.01, 0.2, 4)
    f, q = lever_map(kelvin_voigt, k_true, tan_true)
    ds = cr.invert_cr_map(f, q, LEVER, tip_position=R_TIP, pixel_size=20e-9)
    np.testing.assert_allclose(ds["k_star_N_per_m"], k_true, rtol=1e-9)
    omega = 2 * np.pi * f
    np.testing.assert_allclose(ds["sigma_N_s_per_m"], tan_true * k_true / omega, rtol=1e-8)
    np.testing.assert_allclose(ds["tan_delta"], np.broadcast_to(tan_true, f.shape), rtol=1e-8)
    # A rigid tip: the sample's loss tangent is the contact's.
    np.testing.assert_allclose(ds["tan_delta_sample"], ds["tan_delta"], rtol=0)
    assert ds["x"].attrs["units"] == "m"
    np.testing.assert_allclose(ds["x"].values, np.arange(4) * 20e-9)
    assert ds["k_star_N_per_m"].attrs["units"] == "N/m"
    conv = json.loads(ds.attrs["conventions"])
    assert conv["modulus"]["method"] == "none" and conv["units"]["tan_delta"] == "1"


def test_negative_contact_damping_is_flagged_and_gives_no_loss_tangent(kelvin_voigt):
    # A contact made with tan δ < 0 (σ < 0: the measured Q above what the lever's free Q
    # allows) keeps its k*, but σ and tan δ are NaN there and the pixel is flagged.
    k_true = np.full((2, 2), 2000.0)
    tan_true = np.array([-0.001, 0.03])  # the lever alone: loss 1/400 = 0.0025, Q stays > 0
    f, q = lever_map(kelvin_voigt, k_true, tan_true)
    ds = cr.invert_cr_map(f, q, LEVER, tip_position=R_TIP)
    np.testing.assert_allclose(ds["k_star_N_per_m"], k_true, rtol=1e-8)
    negative = FLAG_NEGATIVE_DAMPING
    assert np.all(ds["flags"].values[:, 0] == negative) and np.all(ds["flags"].values[:, 1] == 0)
    for name in ("sigma_N_s_per_m", "tan_delta", "tan_delta_sample"):
        assert np.all(np.isnan(ds[name].values[:, 0])), name
    np.testing.assert_allclose(ds["tan_delta"].values[:, 1], 0.03, rtol=1e-8)
    conv = json.loads(ds.attrs["conventions"])
    assert conv["flags_present"] == ["negative_damping"]
    assert conv["flag_bits"]["flags"][str(negative)] == "negative_damping"
    assert CR_MAP_FLAGS[negative][0] == "negative_damping"
    # The bit is the map's own: none of the inversion's.
    assert cr.resonators.flag_names(negative) == []


def test_hertz_and_flat_punch_moduli_with_a_compliant_tip(kelvin_voigt):
    e_true = np.array([[2e9, 5e9], [40e9, 120e9]])  # reduced moduli, Pa
    radius, load, m_tip = 30e-9, 200e-9, 160e9
    k = hertz_k(e_true, radius, load)
    f, q = lever_map(kelvin_voigt, k, 0.03)
    hertz = ModulusModel(tip_radius=radius, load=load, tip_modulus=m_tip)
    ds = cr.invert_cr_map(f, q, LEVER, tip_position=R_TIP, modulus=hertz)
    np.testing.assert_allclose(ds["E_star_Pa"], e_true, rtol=1e-8)
    np.testing.assert_allclose(ds["M_Pa"], 1 / (1 / e_true - 1 / m_tip), rtol=1e-8)
    # The sample's loss: E* = E*′(1 + 0.03 i) in series with the real tip modulus.
    e_c = e_true * (1 + 0.03j)
    m_c = e_c * m_tip / (m_tip - e_c)
    np.testing.assert_allclose(ds["tan_delta_sample"], m_c.imag / m_c.real, rtol=1e-6)
    punch = ModulusModel(punch_radius=5e-9)
    ds = cr.invert_cr_map(f, q, LEVER, tip_position=R_TIP, modulus=punch)
    np.testing.assert_allclose(ds["E_star_Pa"], k / (2 * 5e-9), rtol=1e-8)
    np.testing.assert_allclose(ds["M_Pa"], ds["E_star_Pa"], rtol=0)


def test_reference_region_calibrates_each_map_of_a_worn_tip(kelvin_voigt):
    """Two regions (a reference of 3 GPa, a sample of 9 GPa) imaged with a sharp tip and again
    after wear (a blunter tip): each map, calibrated against its own reference region, gives
    the sample's modulus without the tip radius (Killgore et al. 2011)."""
    m_ref, m_sample, load = 3e9, 9e9, 100e-9
    e = np.full((4, 6), m_sample)
    e[:, :2] = m_ref  # the reference: columns 0-1
    model = ModulusModel(reference=(0, 4, 0, 2), reference_modulus=m_ref)
    for radius in (10e-9, 35e-9):
        f, q = lever_map(kelvin_voigt, hertz_k(e, radius, load), 0.02)
        ds = cr.invert_cr_map(f, q, LEVER, tip_position=R_TIP, modulus=model)
        np.testing.assert_allclose(ds["M_Pa"], e, rtol=1e-8)
        rec = json.loads(ds.attrs["conventions"])["modulus"]
        np.testing.assert_allclose(rec["reference_k_star_N_per_m"], hertz_k(m_ref, radius, load))


def test_unmeasured_pixels_stay_empty_and_bad_maps_are_refused(kelvin_voigt):
    f, q = lever_map(kelvin_voigt, np.full((2, 3), 2000.0), 0.02)
    f[0, 0], q[1, 2] = 0.0, np.nan
    ds = cr.invert_cr_map(f, q, LEVER, tip_position=R_TIP)
    assert np.isnan(ds["k_star_N_per_m"][0, 0]) and ds["flags"][0, 0] != 0
    assert np.isfinite(ds["k_star_N_per_m"][1, 2]) and np.isnan(ds["tan_delta"][1, 2])
    with pytest.raises(ContactresInputError, match="no positive frequency"):
        cr.invert_cr_map(np.zeros((3, 3)), None, LEVER)
    with pytest.raises(ContactresInputError, match="not inside"):
        bad = ModulusModel(reference=(0, 5, 0, 2), reference_modulus=1e9)
        cr.invert_cr_map(f, q, LEVER, tip_position=R_TIP, modulus=bad)
    with pytest.raises(ContactresInputError, match="shape"):
        cr.invert_cr_map(f, q[:, :2], LEVER)
    with pytest.raises(ContactresInputError, match="one way to the modulus"):
        ModulusModel(tip_radius=1e-8, load=1e-7, punch_radius=1e-8)


def test_a_pixel_at_the_free_resonance_has_no_contact_and_no_loss_tangent():
    lever = cr.Cantilever((88e3,), 3.0, free_q_factors=(150.0,))  # Hz, N/m
    # Just below the free resonance (a contact that does not shift it): κ = 0, no contact.
    f = np.array([[88e3 * (1 - 1e-7)]])
    ds = cr.invert_cr_map(f, np.array([[150.0]]), lever, tip_position=0.95)
    assert float(ds["k_star_N_per_m"][0, 0]) == 0.0
    assert np.isnan(ds["tan_delta"][0, 0]) and np.isnan(ds["M_Pa"][0, 0])
    bits = json.loads(ds.attrs["conventions"])["flag_bits"]["flags"]
    flags = int(ds["flags"][0, 0])
    assert [name for bit, name in bits.items() if flags & int(bit)] == ["no_contact"]


def test_a_tilted_lever_with_a_lateral_spring_is_inverted_as_it_was_made():
    lever = cr.Cantilever((88e3,), 3.0)  # Hz, N/m
    k_true = np.array([[20.0, 60.0], [150.0, 400.0]])  # N/m
    tip = {"lateral_ratio": 0.8, "tip_height": 0.03, "tilt": 11.0}
    f = cr.contact_frequencies(lever, k_true / 3.0, R_TIP, modes=(1,), **tip)[..., 0]
    ds = cr.invert_cr_map(f, None, lever, tip_position=R_TIP, **tip)
    np.testing.assert_allclose(ds["k_star_N_per_m"], k_true, rtol=1e-8)
    assert np.isnan(ds["tan_delta"]).all()  # no Q: no damping, no loss tangent
    conv = json.loads(ds.attrs["conventions"])
    assert (conv["lateral_ratio"], conv["tip_height"], conv["tilt_deg"]) == (0.8, 0.03, 11.0)
