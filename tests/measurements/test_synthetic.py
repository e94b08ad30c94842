"""The synthetic sweep generator against closed forms of paper 2 and against its own contract."""

from dataclasses import replace
from importlib.resources import files

import numpy as np
import pandas as pd
import pytest

from contactres.measurements._studies import EXAMPLE_SEED, example_study
from contactres.measurements._sweeps import validate_sweeps
from contactres.measurements._synthetic import (
    Drift,
    SweepGroup,
    SweepStudy,
    synthetic_sweeps,
)
from contactres.resonators._qcm import QCM

Q = QCM(5e6, 3, 2.5e-5)
ZQ, NP, NU = 8.8e6, 3, 0.17
# P = n_P / (2 n π² A_eff Z_q), paper 2, Eq. 1, written out.
P = NP / (2 * 3 * np.pi**2 * 2.5e-5 * ZQ)
R, E, GAMMA = 1.1e-3, 70e9, 0.1
FORCES = (2e-3, 4e-3, 8e-3)


def kappa_by_hand(F, E=E, gamma=GAMMA, R=R, nu=NU):
    """κ = 2G*a with the JKR radius, E1 = E2 = E, ν1 = ν2 = ν (paper 2, Eqs. 7-10)."""
    E_star = E / (2 * (1 - nu**2))
    s = 6 * np.pi * gamma * R
    a = (3 * R / (4 * E_star) * (F + s + np.sqrt(2 * s * F + s**2))) ** (1 / 3)
    G = E / (2 * (1 + nu))
    G_star = 1 / (2 * (2 - nu) / (4 * G))
    return 2 * G_star * a


def group(amplitudes, noise=0.0, omega_xi=2e4, medium="air", E=E, gamma=GAMMA):
    return SweepGroup("glass", medium, R, E, gamma, tuple(amplitudes), omega_xi, noise)


def study(groups, **kw):
    kw = dict(normal_forces=FORCES, n_experiments=2, qcm=Q, n_contacts=NP, poisson=NU) | kw
    return SweepStudy(groups=tuple(groups), **kw)


def by_sweep(table, column="df_Hz"):
    return {s: g[column].to_numpy() for s, g in table.groupby("sweep", sort=False)}


# ---- the forward model against closed forms ------------------------------------------------


def test_low_amplitude_shifts_are_P_kappa_and_P_omega_xi():
    # At u0 -> 0 a Cattaneo-Mindlin contact sticks: Δf -> Pκ, ΔΓ -> Pωξ (paper 2, Eqs. 1, 12).
    # The slip terms, of order κu0/(μF_N) relative (Eqs. 11-12), are below 1e-5 here.
    u = (1e-16, 2e-16, 5e-16)
    t = synthetic_sweeps(study([group(u)], ramps=(1,), n_experiments=1), 0)
    for F, part in t.groupby("normal_force_N"):
        assert np.allclose(part["df_Hz"], P * kappa_by_hand(F), rtol=1e-6, atol=0)
        assert np.allclose(part["dgamma_Hz"], P * 2e4, rtol=1e-5, atol=0)
    assert t["normal_force_N"].nunique() == len(FORCES)


def test_elastic_contact_follows_eq1_at_every_amplitude():
    u = np.linspace(1e-9, 20e-9, 7)
    t = synthetic_sweeps(study([group(u)], model="elastic", n_experiments=1), 0)
    for F, part in t.groupby("normal_force_N"):
        assert np.allclose(part["df_Hz"], P * kappa_by_hand(F), rtol=1e-12, atol=0)
        assert np.allclose(part["dgamma_Hz"], P * 2e4, rtol=1e-12, atol=0)


def test_plateau_sticks_below_the_critical_amplitude():
    # For u0 <= d_c the plateau loop is the straight line F = κu: Δf = Pκ exactly; above, slip
    # lowers Δf.
    u = np.linspace(0.5e-9, 10e-9, 20)
    t = synthetic_sweeps(study([group(u)], model="plateau", plateau_fraction=0.4, ramps=(1,)), 0)
    d_c = 0.4 * u[-1]
    for F, part in t.groupby("normal_force_N"):
        stuck = part["amplitude_m"] <= d_c
        assert np.allclose(part.loc[stuck, "df_Hz"], P * kappa_by_hand(F), rtol=1e-9, atol=0)
        assert (part.loc[~stuck, "df_Hz"] < P * kappa_by_hand(F) * (1 - 1e-6)).all()


def test_savkoor_is_parabolic_as_eq15():
    # K′ = κ[1 - (5/512)(κu0/(a²τ0))²] (paper 2, Eq. 15); with full sliding at
    # u_s = 4a²τ0/κ = 50 max(u0), κ/(a²τ0) = 4/u_s and Δf/(Pκ) - 1 = -(5/32)(u0/u_s)²; the next
    # term is (u0/u_s)² smaller.
    u = np.linspace(0.2e-9, 1e-9, 5)
    u_s = 50.0 * u[-1]
    s = study([group(u)], model="savkoor", savkoor_sliding=50.0, ramps=(1,), n_experiments=1)
    t = synthetic_sweeps(s, 0)
    for F, part in t.groupby("normal_force_N"):
        correction = part["df_Hz"].to_numpy() / (P * kappa_by_hand(F)) - 1
        assert np.allclose(correction, -(5 / 32) * (u / u_s) ** 2, rtol=2e-3, atol=0)


def test_running_in_scales_the_first_ramp():
    u = (1e-14, 2e-14)
    s = study([group(u)], running_in_kappa=0.94, running_in_mu=0.7, n_experiments=1)
    df = by_sweep(synthetic_sweeps(s, 0))
    for j in range(len(FORCES)):
        first, later = df[f"glass/air/e1/F{j}/r1"], df[f"glass/air/e1/F{j}/r3"]
        assert np.allclose(first / later, 0.94, rtol=1e-5, atol=0)


@pytest.mark.parametrize("law", ["lognormal", "normal"])
def test_scatter_of_E_follows_its_law(law):
    # Hertz (γ = 0), elastic: κ ∝ E*^(-1/3) G* ∝ E^(2/3), so (Δf/Δf_nominal)^(3/2) is the
    # factor on E; its spread must be that of the law (sd of log for lognormal, sd for normal).
    sd, n = 0.1, 1000
    s = study(
        [group((1e-9,), gamma=0.0)],
        normal_forces=(3e-3,),
        n_experiments=n,
        ramps=(2,),
        model="elastic",
        scatter=(("E", sd),),
        scatter_law=law,
    )
    factor = (
        synthetic_sweeps(s, 11)["df_Hz"].to_numpy() / (P * kappa_by_hand(3e-3, gamma=0))
    ) ** 1.5
    x = np.log(factor) if law == "lognormal" else factor - 1
    assert abs(np.mean(x)) < 4 * sd / np.sqrt(n)
    assert abs(np.std(x, ddof=1) / sd - 1) < 4 / np.sqrt(2 * n)


def test_scatter_per_experiment_is_shared_by_its_loads():
    # Hertz, elastic: κ ∝ F^(1/3) within one experiment (one E); per load the ratio scatters.
    base = dict(n_experiments=5, ramps=(2,), model="elastic", scatter=(("E", 0.05),))
    g = [group((1e-9,), gamma=0.0)]
    for per, shared in (("experiment", True), ("load", False)):
        t = synthetic_sweeps(study(g, scatter_per=per, **base), 3)
        df = t.pivot(index="experiment", columns="normal_force_N", values="df_Hz").to_numpy()
        ratio = df[:, 1:] / df[:, :1]
        hertz = (np.array(FORCES[1:]) / FORCES[0]) ** (1 / 3)
        assert np.allclose(ratio, hertz, rtol=1e-12, atol=0) == shared


def test_drift_moves_only_its_load():
    u = np.linspace(1e-9, 5e-9, 5)
    s = study([group(u, noise=0.3)], n_experiments=3)
    drift = Drift("glass", "air", experiment=2, load=1, rate=1.5)
    plain = synthetic_sweeps(s, 4)
    drifted = synthetic_sweeps(replace(s, drifts=(drift,)), 4)
    shift = (drifted["df_Hz"] - plain["df_Hz"]).to_numpy()
    hit = (drifted["experiment"] == "e2") & (drifted["normal_force_N"] == FORCES[1])
    expected = np.where(hit, 1.5 * (drifted["ramp"] - 1), 0.0)
    assert np.allclose(shift, expected, rtol=0, atol=1e-9)
    assert (drifted["dgamma_Hz"] == plain["dgamma_Hz"]).all()


# ---- noise and reproducibility ---------------------------------------------------------------


def test_noise_level_recovered_from_residuals():
    # The same study without noise and the same seed has the same contacts (noise is drawn
    # even at σ = 0), so the residuals are the noise alone; σ differs per group.
    u = np.linspace(0.5e-9, 8e-9, 12)
    sigma = {"air": 0.3, "water": 0.6}
    noisy = study(
        [group(u, s, medium=m) for m, s in sigma.items()],
        n_experiments=6,
        scatter=(("E", 0.03), ("gamma", 0.2), ("mu", 0.05)),
        running_in_kappa=0.94,
        random_plateau=0.3,
    )
    clean = replace(noisy, groups=tuple(replace(g, noise=0.0) for g in noisy.groups))
    a, b = synthetic_sweeps(noisy, 9), synthetic_sweeps(clean, 9)
    assert (a["amplitude_m"] == b["amplitude_m"]).all()
    for medium, s in sigma.items():
        m = (a["medium"] == medium).to_numpy()
        for col in ("df_Hz", "dgamma_Hz"):
            r = a.loc[m, col].to_numpy() - b.loc[m, col].to_numpy()
            n = r.size
            assert abs(r.mean()) < 4 * s / np.sqrt(n)
            assert abs(r.std(ddof=1) / s - 1) < 4 / np.sqrt(2 * n)
        rf = a.loc[m, "df_Hz"].to_numpy() - b.loc[m, "df_Hz"].to_numpy()
        rg = a.loc[m, "dgamma_Hz"].to_numpy() - b.loc[m, "dgamma_Hz"].to_numpy()
        assert abs(np.corrcoef(rf, rg)[0, 1]) < 4 / np.sqrt(rf.size)


def test_seeded_and_reproducible():
    s = study([group(np.linspace(1e-9, 5e-9, 4), noise=0.2)], scatter=(("E", 0.05),))
    one, two = synthetic_sweeps(s, 5), synthetic_sweeps(s, 5)
    pd.testing.assert_frame_equal(one, two)
    pd.testing.assert_frame_equal(one, synthetic_sweeps(s, np.random.default_rng(5)))
    assert not np.allclose(one["df_Hz"], synthetic_sweeps(s, 6)["df_Hz"])
    rng = np.random.default_rng(5)  # a generator is used and advanced
    first, second = synthetic_sweeps(s, rng), synthetic_sweeps(s, rng)
    assert not np.allclose(first["df_Hz"], second["df_Hz"])


# ---- the table ----------------------------------------------------------------------------------


def test_shape_columns_and_ramp_directions():
    u_air, u_water = np.linspace(1e-9, 6e-9, 5), np.linspace(0.5e-9, 3e-9, 7)
    s = study([group(u_air), group(u_water, medium="water")], n_experiments=3)
    t = synthetic_sweeps(s, 1, constants=True)
    assert list(t.columns) == [
        "sweep", "experiment", "configuration", "medium", "ramp", "normal_force_N",
        "amplitude_m", "df_Hz", "dgamma_Hz", "sphere_radius_m",
        "fundamental_Hz", "overtone", "area_m2", "n_contacts", "poisson",
    ]  # fmt: skip
    n_sweeps = 2 * 3 * len(FORCES) * 4
    assert t["sweep"].nunique() == n_sweeps
    assert len(t) == 3 * len(FORCES) * 4 * (u_air.size + u_water.size)
    assert (t["overtone"] == 3).all() and (t["n_contacts"] == NP).all()
    assert (t["area_m2"] == 2.5e-5).all() and (t["poisson"] == NU).all()
    assert set(t["experiment"]) == {"e1", "e2", "e3"}
    for name, sweep in t.groupby("sweep"):
        assert sweep[["experiment", "ramp", "normal_force_N", "medium"]].nunique().max() == 1
        ramp = sweep["ramp"].iloc[0]
        u = u_air if sweep["medium"].iloc[0] == "air" else u_water
        assert np.array_equal(sweep["amplitude_m"], u if ramp % 2 else u[::-1]), name
    same_way = synthetic_sweeps(replace(s, alternate=False), 1)
    assert same_way.groupby("sweep")["amplitude_m"].apply(lambda a: a.is_monotonic_increasing).all()
    assert "fundamental_Hz" not in synthetic_sweeps(s, 1).columns
    validated = validate_sweeps(t)
    assert len(validated) == len(t)


def test_bad_study_is_refused():
    g = group((1e-9, 2e-9))
    with pytest.raises(ValueError, match="model"):
        study([g], model="coulomb")
    with pytest.raises(ValueError, match="scatter"):
        study([g], scatter=(("R", 0.1),))
    with pytest.raises(ValueError, match="increase"):
        group((2e-9, 1e-9))
    with pytest.raises(ValueError, match="normal_forces"):
        study([g], normal_forces=(1e-3, -1e-3))


def test_bundled_example_is_the_documented_recipe():
    # The packaged example_sweeps.csv must be what example_study() and EXAMPLE_SEED give
    # (scripts/make_example_data.py writes it with 7 significant digits).
    table = synthetic_sweeps(example_study(), EXAMPLE_SEED, constants=True)
    text = table.to_csv(index=False, float_format="%.7g")
    bundled = files("contactres").joinpath("data/example_sweeps.csv").read_text()
    assert text == bundled
