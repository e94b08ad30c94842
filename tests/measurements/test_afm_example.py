"""The synthetic CR-AFM map of polycrystalline Cu (``cr.example_afm_map``, the README example).

The truth is built here from :func:`indentation_modulus` and Hertz (a = (3PR/4E*)^(1/3),
k* = 2aE*) through :func:`contact_frequencies`; the inversion goes back through other code (the
closed form κ(β) of the lever, E* = √(k*³/6RP)), so recovering M_sample to 1e-6 checks both.
"""

import numpy as np
import pandas as pd
import pytest
from click.testing import CliRunner

import contactres as cr
from contactres.cli import main
from contactres.measurements._afm_example import NAMED_SURFACES, ExampleLever
from contactres.measurements._resonances import AFM_TABLE

SHAPE = (24, 20)  # small and not square: rows and columns cannot be swapped unnoticed


def _invert_file(table: pd.DataFrame, path) -> pd.DataFrame:
    table.to_csv(path, index=False)
    return cr.invert_afm_table(cr.read_resonance_table(path, AFM_TABLE), str(path))


@pytest.fixture(scope="module")
def example():
    return cr.example_afm_map(SHAPE, n_grains=6, seed=3, truth=True)


def test_truth_is_the_cu_faces_and_hertz(example):
    table, truth = example
    cu = cr.Material.crystal("Cu")
    by_grain = truth.groupby("grain").first()
    for g, hkl in enumerate(NAMED_SURFACES):
        assert by_grain.loc[g, "surface"] == "(" + "".join(map(str, hkl)) + ")"
        m = float(np.real(cr.indentation_modulus(cu.rotated(hkl))))
        assert by_grain.loc[g, "M_sample_Pa"] == pytest.approx(m, rel=1e-12)
    assert set(by_grain["surface"].iloc[3:]) == {"random"}
    # Cu: (001) is the softest face, (111) the stiffest; random faces lie between.
    m = by_grain["M_sample_Pa"].to_numpy()
    assert m[0] < m[1] < m[2] and np.all((m[3:] > m[0]) & (m[3:] < m[2]))
    lever = ExampleLever()
    m_tip = float(np.real(cr.indentation_modulus(cr.Material.crystal("Si").rotated((0, 0, 1)))))
    assert table["M_tip_Pa"].to_numpy() == pytest.approx(m_tip, rel=1e-12)
    e_star = 1 / (1 / m_tip + 1 / truth["M_sample_Pa"])
    # The example's tip and load give a/R = 0.16, beyond Hertz's a/R <= 0.1: its truth is made
    # with Hertz's relation all the same, and that relation is what is checked here.
    c = cr.hertz(e_star.to_numpy(), lever.tip_radius, lever.load, check_validity=False)
    k_star = 2 * c.contact_radius * e_star  # dF/dδ of Hertz (Johnson 1985, Eq. 4.22)
    assert truth["k_star_N_per_m"].to_numpy() == pytest.approx(k_star.to_numpy(), rel=1e-12)
    assert truth["kappa"].to_numpy() == pytest.approx(k_star.to_numpy() / 40.0, rel=1e-12)
    # Noise-free: the table's frequencies are the truth's.
    assert np.array_equal(table["fc1_Hz"], truth["fc1_Hz"])
    assert np.array_equal(table["fc2_Hz"], truth["fc2_Hz"])


def test_columns_pixels_and_schema(example, tmp_path):
    table, _ = example
    ny, nx = SHAPE
    assert len(table) == ny * nx
    extra = {"x_m", "y_m"}
    assert set(table.columns) - extra <= set(AFM_TABLE.names)
    assert table["x_m"].nunique() == nx and table["y_m"].nunique() == ny
    assert table["x_m"].iloc[1] == pytest.approx(100e-9)  # row-major: x varies fastest
    path = tmp_path / "resonances.csv"
    table.to_csv(path, index=False)
    checked = cr.read_resonance_table(path, AFM_TABLE)  # raises on any schema violation
    assert checked.attrs["given"] == list(table.columns)
    assert checked["f2_free_Hz"].iloc[0] / checked["f1_free_Hz"].iloc[0] == pytest.approx(
        6.2669, rel=1e-4
    )


@pytest.mark.parametrize("give_r", [True, False], ids=["r-given", "r-from-two-modes"])
def test_noise_free_map_is_recovered(example, tmp_path, give_r):
    table, truth = example
    if not give_r:
        table = table.drop(columns="tip_position")
    out = _invert_file(table, tmp_path / "resonances.csv")
    m = out["M_sample_Pa"].to_numpy()
    assert np.all(np.isfinite(m))
    assert np.max(np.abs(m / truth["M_sample_Pa"].to_numpy() - 1)) <= 1e-6
    assert out["tip_position_used"].to_numpy() == pytest.approx(0.95, rel=1e-6)
    if give_r:
        assert (out["flags"] == "").all()
    # The grains come back: as many distinct M as grains, on the same pixels.
    key = np.round(np.log(m), 6)  # 1e-6 relative bins: M of two grains differ by >= 1e-3
    assert len(np.unique(key)) == truth["grain"].nunique()
    pairs = pd.DataFrame({"key": key, "grain": truth["grain"]}).drop_duplicates()
    assert len(pairs) == truth["grain"].nunique()


def test_cli_inverts_the_default_map(tmp_path):
    table, truth = cr.example_afm_map(truth=True)
    table.to_csv(tmp_path / "resonances.csv", index=False)
    args = ["afm", "invert", str(tmp_path / "resonances.csv"), "--out", str(tmp_path / "s.csv")]
    r = CliRunner().invoke(main, args)
    assert r.exit_code == 0, r.output
    assert "4096 rows, 4096 with k*" in r.output and "0 flagged" in r.output
    out = pd.read_csv(tmp_path / "s.csv")
    assert np.allclose(out["x_m"], truth["x_m"], rtol=0, atol=0)  # carried through
    err = np.abs(out["M_sample_Pa"] / truth["M_sample_Pa"] - 1)
    assert err.max() <= 1e-6
    assert truth["grain"].nunique() == 8
    for hkl in ("(001)", "(011)", "(111)"):
        assert (truth["surface"] == hkl).sum() > 100  # each named grain is visible in the map


def test_seeded_and_noise_leaves_the_grains(example):
    table, truth = example
    again, truth_again = cr.example_afm_map(SHAPE, n_grains=6, seed=3, truth=True)
    pd.testing.assert_frame_equal(table, again)
    pd.testing.assert_frame_equal(truth, truth_again)
    other = cr.example_afm_map(SHAPE, n_grains=6, seed=4, truth=True)[1]
    assert not np.array_equal(other["grain"], truth["grain"])
    noisy, truth_noisy = cr.example_afm_map(SHAPE, n_grains=6, seed=3, noise=20.0, truth=True)
    pd.testing.assert_frame_equal(truth, truth_noisy)  # the noise is drawn last
    d = (noisy[["fc1_Hz", "fc2_Hz"]] - table[["fc1_Hz", "fc2_Hz"]]).to_numpy()
    assert 15 < d.std() < 25  # Hz
    assert isinstance(cr.example_afm_map(SHAPE, seed=3), pd.DataFrame)  # truth=False: the table


@pytest.mark.parametrize(
    "kwargs, word",
    [
        (dict(n_grains=2), "n_grains"),
        (dict(noise=-1.0), "noise"),
        (dict(pixel_size=0.0), "pixel_size"),
        (dict(shape=(0, 4)), "shape"),
        (dict(shape=(3,)), "shape"),
    ],
)
def test_bad_arguments_name_the_argument(kwargs, word):
    with pytest.raises(ValueError, match=word):
        cr.example_afm_map(**kwargs)
