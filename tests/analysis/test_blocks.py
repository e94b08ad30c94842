"""The exact Savkoor loop, the nested-model preference and the joint choice of a load block."""

import numpy as np
import pandas as pd
import pytest

from contactres.analysis import AnalysisSettings, analyze
from contactres.analysis._amplitude import pad_sweeps
from contactres.analysis._classify import NESTED, add_plateau_fits, fit_sweeps, prefer
from contactres.analysis._loops import (
    cm_loop_shape,
    loop_tables,
    savkoor_loop_shape,
    savkoor_loop_table,
)
from contactres.measurements._sweeps import validate_sweeps
from contactres.measurements._synthetic import (
    SweepGroup,
    SweepStudy,
    contact_loop,
    sweep_shifts,
    synthetic_sweeps,
)
from contactres.normal import effective_modulus, jkr_contact_radius
from contactres.resonators._qcm import QCM
from contactres.tangential import kappa_jkr_mindlin
from contactres.units import LINEAR_ONSET_X

Q = QCM(5e6, 3, 2.5e-5)
P = Q.sensitivity(3)
CONST = dict(overtone=3, area_m2=2.5e-5, n_contacts=3)


def test_savkoor_table_has_the_small_amplitude_limit_of_paper_2_eq_15():
    # Eq. 15: K′ = κ[1 - (5/512)(κu0/(a²τ0))²], K″ - ωξ = κ³u0²/(48π a⁴τ0²); with x = u0/d_s,
    # d_s = 4a²τ0/κ: K′/κ = 1 - (5/32)x², (K″ - ωξ)/κ = x²/(3π).
    x = np.array([1e-3, 3e-3, 1e-2])
    g1, g2 = savkoor_loop_shape(x)
    assert np.allclose((1 - g1) / x**2, 5 / 32, rtol=1e-3)
    assert np.allclose(g2 / x**2, 1 / (3 * np.pi), rtol=1e-3)


def test_savkoor_table_interpolates_the_quadrature_within_1e_6():
    t = savkoor_loop_table()
    x = np.linspace(0.0, 29.99, 4001) + 1.7e-4
    g1, g2 = savkoor_loop_shape(x)
    assert np.abs(np.interp(x, t.x, t.g1) - g1).max() < 1e-6
    assert np.abs(np.interp(x, t.x, t.g2) - g2).max() < 1e-6


def test_savkoor_loop_beyond_full_sliding_is_rigid_plastic():
    # Beyond full sliding (x >> 1) the force is πa²τ0 most of the cycle: K′ -> 0 as the loop
    # becomes a rectangle whose first harmonic gives K″ -> (4/π)(πa²τ0)/(π u0) = x^-1 κ/π·...;
    # independent check: the dissipated energy per cycle 4 F_s u0 (rectangle) = π u0² K″.
    x = np.array([200.0, 400.0])
    g1, g2 = savkoor_loop_shape(x)
    # κ = 1, a = 1/2, τ0 = 1 in savkoor_loop_shape: F_s = π/4, d_s = 1, so u0 = x.
    assert np.all(np.abs(g1) < 0.01)
    assert g2 == pytest.approx(4 * (np.pi / 4) / (np.pi * x), rel=0.02)


def test_prefer_keeps_a_nested_model_within_the_margin_but_not_a_rival():
    # Columns: the lowest is plateau (3) with CM (1) 1.5 above: CM is nested in it, kept.
    # Lowest savkoor (2) with CM 1.5 above: not nested, savkoor wins.
    crit = np.array([[10.0, 10.0], [1.5, 1.5], [5.0, 0.0], [0.0, 5.0]])
    assert prefer(crit, NESTED, 2.0).tolist() == [1, 2]
    assert prefer(crit, NESTED, 1.0).tolist() == [3, 2]


def _block_table(kind, n_blocks, noise, seed, **kw):
    """``n_blocks`` load blocks of ramps 2-4 of one contact each (glass on glass, air)."""
    u = tuple(np.linspace(0.5e-9, 10e-9, 13))
    study = SweepStudy(
        groups=(SweepGroup("glass", "air", 0.6e-3, 61e9, 0.03, u, 5.0 / P, noise),),
        normal_forces=(3.27e-3,),
        n_experiments=n_blocks,
        ramps=(2, 3, 4),
        qcm=Q,
        mu=1.1,
        model=kind,
        **kw,
    )
    return synthetic_sweeps(study, seed, truth=True)


def test_pure_cattaneo_mindlin_blocks_are_rarely_called_plateau():
    # The plateau loop has one parameter more (d_c) and nests the Cattaneo-Mindlin loop.
    raw = _block_table("cattaneo-mindlin", 60, 0.3, 7)
    res = analyze(
        validate_sweeps(raw.filter(regex="^(?!true_)"), constants=CONST),
        settings=AnalysisSettings(bootstrap=0),
    )
    assert (res.blocks["model"] == "cattaneo-mindlin").mean() >= 0.95
    assert (res.sweeps["decided_by"] == "block").all()
    # Every sweep of a block carries the block's class.
    per_block = res.sweeps.groupby("block")["model"].nunique()
    assert (per_block == 1).all()


def test_block_fit_recovers_mu_of_noisy_water_like_sweeps():
    # Water-like noise: the joint fit of the 3 ramps gives μ within its error on average.
    raw = _block_table("cattaneo-mindlin", 30, 0.6, 11)
    res = analyze(
        validate_sweeps(raw.filter(regex="^(?!true_)"), constants=CONST),
        settings=AnalysisSettings(bootstrap=0),
    )
    b = res.blocks[res.blocks["model"] == "cattaneo-mindlin"]
    z = (b["mu"] - 1.1) / b["mu_err"]
    assert len(b) >= 25
    assert abs(z.mean()) < 3 / np.sqrt(len(b)) + 0.3
    assert 0.5 < z.std() < 2.0


def test_savkoor_sweep_gives_its_sliding_force():
    # A clean Savkoor sweep: the exact loop wins and πa²τ0 comes back within 1 %.
    E, gamma, R, F, nu = 61e9, 0.03, 0.6e-3, 3.27e-3, 0.17
    kappa = kappa_jkr_mindlin(F, E, gamma, R, nu)
    a = jkr_contact_radius(effective_modulus(E, nu), R, F, gamma)
    u = np.linspace(0.5e-9, 10e-9, 13)
    d_s = 2 * u[-1]
    loop = contact_loop(
        "savkoor", kappa, 1.0, F, 5.0 / P, Q.omega, contact_radius=a, sliding_amplitude=d_s
    )
    df, dg = sweep_shifts(Q, loop, u, 3)
    rng = np.random.default_rng(3)
    table = pd.DataFrame(
        dict(
            sweep="s",
            ramp=2,
            normal_force_N=F,
            amplitude_m=u,
            df_Hz=df + rng.normal(0, 0.05, u.size),
            dgamma_Hz=dg + rng.normal(0, 0.05, u.size),
            sphere_radius_m=R,
        )
    )
    res = analyze(validate_sweeps(table, constants=CONST), settings=AnalysisSettings(bootstrap=0))
    row = res.sweeps.iloc[0]
    assert row["model"] == "savkoor" and row["limits_from"] == "savkoor-loop"
    truth = np.pi * kappa * d_s / 4  # πa²τ0 with d_s = 4a²τ0/κ
    assert row["sliding_force_N"] == pytest.approx(truth, rel=0.01)
    assert abs(row["sliding_force_N"] - truth) < 4 * row["sliding_force_err_N"]
    assert np.isnan(row["mu_fit"])  # Savkoor has no friction coefficient


def test_model_sweep_keeps_the_sweeps_own_choice():
    # A block decision must not overwrite what the sweep alone would get (it once did).
    raw = _block_table("cattaneo-mindlin", 4, 0.3, 5)
    sw, _ = fit_sweeps(pad_sweeps(raw), tables=loop_tables())
    res = analyze(
        validate_sweeps(raw.filter(regex="^(?!true_)"), constants=CONST),
        settings=AnalysisSettings(bootstrap=0),
    )
    own = sw.set_index("sweep")["model"]
    assert (res.sweeps.set_index("sweep")["model_sweep"] == own.reindex(res.sweeps["sweep"])).all()


def _mixed_study(seed):
    """Two experiments of one contact: e1 Cattaneo-Mindlin with stick plateaus in half its
    loads, e2 Savkoor throughout (water-like noise)."""
    u = tuple(np.linspace(0.5e-9, 10e-9, 13))
    study = SweepStudy(
        groups=(SweepGroup("glass", "air", 1.1e-3, 70e9, 0.19, u, 5.0 / P, 0.5),),
        normal_forces=(1.6e-3, 3.3e-3, 4.9e-3, 6.5e-3),
        n_experiments=2,
        ramps=(2, 3, 4),
        qcm=Q,
        mu=1.1,
        random_plateau=0.5,
        random_plateau_range=(0.3, 0.4),
        savkoor_experiments=(("glass", "air", 2),),
    )
    return synthetic_sweeps(study, seed, truth=True)


def test_plateau_fits_added_later_choose_as_if_fitted_with_the_others():
    # add_plateau_fits chooses again only the sweeps it fits: the result must be that of one
    # fit_sweeps call that fitted the plateau loop to every sweep (the second path here).
    p = pad_sweeps(_mixed_study(5))
    tables = loop_tables()
    at_once, _ = fit_sweeps(p, tables=tables)
    later = np.arange(len(p.n)) % 3 != 0  # two in three sweeps without the plateau at first
    first, fields = fit_sweeps(p, tables=tables, plateau=~later)
    # The choice does change for some of them (else the test would not test the re-choice).
    assert (first["model"] != at_once["model"]).any()
    sw, _ = add_plateau_fits(p, first, fields, np.flatnonzero(later), 2.0, tables)
    assert list(sw.columns) == list(at_once.columns)
    for col in sw.columns:
        if sw[col].dtype.kind == "f":
            np.testing.assert_allclose(sw[col], at_once[col], rtol=1e-12, atol=0, err_msg=col)
        else:
            assert (sw[col].to_numpy() == at_once[col].to_numpy()).all(), col
            assert sw[col].dtype == at_once[col].dtype, col


@pytest.mark.parametrize("pool", [True, False])
def test_the_friction_law_is_decided_per_experiment(pool):
    raw = _mixed_study(21)
    res = analyze(
        validate_sweeps(raw.filter(regex="^(?!true_)"), constants=CONST),
        settings=AnalysisSettings(bootstrap=0, pool_experiments=pool),
    )
    b = res.blocks
    law = b.groupby("experiment")["friction_law"].unique()
    if pool:
        assert law["e1"].tolist() == ["coulomb"] and law["e2"].tolist() == ["savkoor"]
        assert set(b.loc[b["experiment"] == "e1", "model"]) <= {"cattaneo-mindlin", "plateau"}
        assert (b.loc[b["experiment"] == "e2", "model"] == "savkoor").all()
    else:
        assert (b["friction_law"] == "").all()
    # Classes against the truth: with pooling every block right.
    truth = raw.drop_duplicates("sweep").set_index("sweep")["true_model"]
    right = (res.sweeps.set_index("sweep")["model"] == truth.reindex(res.sweeps["sweep"])).mean()
    assert right == 1.0 if pool else right >= 0.5


def test_a_block_without_any_fit_leaves_its_experiments_friction_law_to_the_others():
    # The rule: a block counts towards its experiment's law only where both families fitted
    # (their criteria finite). Block 1 has no fit at all (every criterion inf: Δf of the wrong
    # sign); block 0 of the same experiment decides (Coulomb by 8 > 6), block 2 alone leaves
    # its experiment open. No RuntimeWarning (inf − inf; an error in the tests).
    from contactres.analysis._blocks import _friction_law
    from contactres.analysis._models import AMPLITUDE_MODELS

    classes = np.repeat(np.asarray(AMPLITUDE_MODELS), 2)
    crit = np.full((classes.size, 3), np.inf)
    crit[classes == "cattaneo-mindlin", 0] = 10.0
    crit[classes == "savkoor", 0] = 18.0
    crit[classes == "savkoor", 2] = 5.0
    blocks = pd.DataFrame({"configuration": "c", "medium": "air", "experiment": ["e1", "e1", "e2"]})
    law = _friction_law(crit, classes, blocks, 6.0)
    assert law.tolist() == ["coulomb", "coulomb", ""]


def test_linear_onset_limit_is_where_the_slope_mu_reads_10_percent_low():
    # Paper 2, Eq. 11: dK′/du0 = -κ²/(6μF_N) and dK″/du0 = 2κ²/(9πμF_N) at u0 -> 0; a straight
    # line fitted to the exact loop on 13 amplitudes up to x = LINEAR_ONSET_X (κ = μF_N = 1).
    x = np.linspace(0.05, 1.0, 13) * LINEAR_ONSET_X
    g1, g2 = cm_loop_shape(x)
    ratio_df = (-1 / 6) / np.polyfit(x, g1, 1)[0]  # μ from the slope / true μ
    ratio_dg = (2 / (9 * np.pi)) / np.polyfit(x, g2, 1)[0]
    assert 0.9 < ratio_dg < 0.92 and 0.93 < ratio_df < 0.95


def test_savkoor_traction_from_the_group_modulus():
    # Whole experiments following Savkoor: τ0 = F_s/(πa²) with a = κ/(2G*) and the fitted E
    # against the generator's τ0 = κ d_s/(4a²) (d_s: full sliding at twice the largest u0).
    u = tuple(np.linspace(0.5e-9, 10e-9, 13))
    E, gamma, R, nu = 70e9, 0.1, 1.1e-3, 0.17
    loads = (1.6e-3, 3.3e-3, 4.9e-3, 6.5e-3, 8.2e-3)
    study = SweepStudy(
        groups=(SweepGroup("glass", "air", R, E, gamma, u, 5.0 / P, 0.1),),
        normal_forces=loads,
        n_experiments=3,
        ramps=(2, 3, 4),
        qcm=Q,
        savkoor_experiments=tuple(("glass", "air", e) for e in (1, 2, 3)),
    )
    raw = synthetic_sweeps(study, 4, truth=True)
    res = analyze(
        validate_sweeps(raw.filter(regex="^(?!true_)"), constants=CONST),
        settings=AnalysisSettings(bootstrap=0),
    )
    sw = res.sweeps
    assert (sw["model"] == "savkoor").all()
    F = sw["normal_force_N"].to_numpy()
    a = jkr_contact_radius(effective_modulus(E, nu), R, F, gamma)
    kappa = kappa_jkr_mindlin(F, E, gamma, R, nu)
    truth = kappa * 2 * u[-1] / (4 * a**2)
    np.testing.assert_allclose(sw["tau0_Pa"], truth, rtol=0.05)
    z = (sw["tau0_Pa"] - truth) / sw["tau0_err_Pa"]
    assert np.abs(z).max() < 4


@pytest.mark.parametrize("seed", [1, 4])
def test_every_used_sweep_has_its_limits(seed):
    # A block whose friction law (Savkoor ruled out) leaves the plateau winning must have the
    # plateau loop fitted to its ramps (it once had not: Δf0 NaN for used sweeps).
    from contactres.measurements._studies import validation_study

    raw = synthetic_sweeps(validation_study(4), seed)
    res = analyze(validate_sweeps(raw, constants=CONST), settings=AnalysisSettings(bootstrap=0))
    used = res.sweeps[res.sweeps["used"]]
    assert np.isfinite(used[["df0_Hz", "dgamma0_Hz", "kappa_N_per_m"]].to_numpy()).all()


def test_loads_of_one_experiment_take_the_block_mu_in_every_statistic():
    raw = _block_table("cattaneo-mindlin", 1, 0.3, 9)
    res = analyze(
        validate_sweeps(raw.filter(regex="^(?!true_)"), constants=CONST),
        settings=AnalysisSettings(bootstrap=0),
    )
    (load,) = res.loads.itertuples()
    mu_block = res.sweeps["mu_block"].iloc[0]
    assert np.isfinite(mu_block)
    assert load.mu_fit_mean == pytest.approx(mu_block) and load.mu_fit_median == pytest.approx(
        mu_block
    )


def _two_loop_blocks(mu_cm, err_cm, mu_pl, err_pl, bic_cm, bic_pl, force=2e-3):
    """A block table and the joint CM and plateau loop fits (their fit tables) that give the μ
    and errors asked for (P = 1, Δf0 = 10 Hz without error, so the error of μ is that of ln θ
    alone)."""
    blocks = pd.DataFrame({"normal_force_N": [force]})
    joint = {}
    for key, mu, err, b in (
        ("cattaneo-mindlin-loop", mu_cm, err_cm, bic_cm),
        ("plateau-loop", mu_pl, err_pl, bic_pl),
    ):
        joint[key] = pd.DataFrame(
            {
                "df0": [10.0],
                "df0_err": [0.0],
                "inverse_slip_scale": [10.0 / (mu * force)],
                "ln_inverse_slip_scale_err": [err / mu],
                "cov_df0_ln_inverse_slip_scale": [0.0],
                "edge": [""],
                "bic_shared": [b],
            }
        )
    return blocks, joint


def test_decisive_evidence_leaves_the_winners_mu():
    from contactres.analysis._friction import model_averaged_mu

    b = _two_loop_blocks(1.0, 0.05, 0.6, 0.04, bic_cm=100.0, bic_pl=160.0)
    mu, err, w = model_averaged_mu(*b, np.ones(1))
    assert mu[0] == pytest.approx(1.0, rel=1e-12) and err[0] == pytest.approx(0.05, rel=1e-9)
    assert w[0] == pytest.approx(np.exp(-30.0), rel=1e-9)


def test_model_averaged_mu_is_the_mean_and_spread_of_the_weighted_mixture():
    """Two loops 2 units of BIC apart: weights 1 : e^-1. The averaged μ and its error are the
    mean and standard deviation of the mixture of the two normal estimates with those weights,
    checked here by drawing from that mixture (law of total variance)."""
    from contactres.analysis._friction import model_averaged_mu

    b = _two_loop_blocks(1.5, 0.10, 1.0, 0.20, bic_cm=50.0, bic_pl=52.0)
    mu, err, w = model_averaged_mu(*b, np.ones(1))
    w_pl = np.exp(-1.0) / (1 + np.exp(-1.0))
    assert w[0] == pytest.approx(w_pl, rel=1e-12)
    rng = np.random.default_rng(7)
    n = 2_000_000
    pick = rng.random(n) < w_pl
    draws = np.where(pick, rng.normal(1.0, 0.20, n), rng.normal(1.5, 0.10, n))
    assert mu[0] == pytest.approx(draws.mean(), abs=5e-4)
    assert err[0] == pytest.approx(draws.std(), rel=2e-3)


def test_the_marginal_mu_stands_for_the_plateau_fits_where_that_resolves_mu():
    # The plateau loop's μ with d_c integrated out (mu_marginal, _plateau_evidence) replaces the
    # fit's μ and error where the block has one; the fit's own verdict that μ is not resolved
    # (at the edge of the loop table, or Δf0 <= 0) still stands: no μ from the plateau then.
    from contactres.analysis._friction import model_averaged_mu

    b = _two_loop_blocks(1.2, 0.1, 0.8, 0.1, bic_cm=np.inf, bic_pl=10.0)
    b[1]["plateau-loop"]["mu_marginal"] = [0.9]
    b[1]["plateau-loop"]["mu_marginal_err"] = [0.3]
    mu, err, w = model_averaged_mu(*b, np.ones(1))
    assert (mu[0], err[0], w[0]) == pytest.approx((0.9, 0.3, 1.0))
    b[1]["plateau-loop"]["mu_marginal"] = [np.nan]  # none: the fit's own
    assert model_averaged_mu(*b, np.ones(1))[0][0] == pytest.approx(0.8)
    for col, value in (("edge", "high"), ("df0", -10.0)):
        bad = _two_loop_blocks(1.2, 0.1, 0.8, 0.1, bic_cm=np.inf, bic_pl=10.0)
        bad[1]["plateau-loop"]["mu_marginal"] = [0.9]
        bad[1]["plateau-loop"]["mu_marginal_err"] = [0.3]
        bad[1]["plateau-loop"].loc[0, col] = value
        assert np.isnan(model_averaged_mu(*bad, np.ones(1))).all()


def test_a_loop_without_a_fit_gets_no_weight():
    from contactres.analysis._friction import model_averaged_mu

    b = _two_loop_blocks(1.2, 0.1, 0.8, 0.1, bic_cm=10.0, bic_pl=np.inf)
    mu, err, w = model_averaged_mu(*b, np.ones(1))
    assert (mu[0], err[0], w[0]) == pytest.approx((1.2, 0.1, 0.0))
    b[1]["cattaneo-mindlin-loop"].loc[0, "edge"] = "high"  # beyond the table: no μ from CM
    b[1]["plateau-loop"].loc[0, "bic_shared"] = 11.0
    mu, err, w = model_averaged_mu(*b, np.ones(1))
    assert (mu[0], err[0], w[0]) == pytest.approx((0.8, 0.1, 1.0))


def test_a_loop_that_does_not_resolve_mu_leaves_the_average():
    # A plateau fit on its bound d_c = 0 gave μ = 1.05 with an error of 1100: averaged in with
    # its weight of 1.6 % (8.3 units of BIC behind CM), the block's error was 139, a hundred times
    # μ (the demo's SiO2_2.2mm/air/e2/F1 before). An error above MU_PRIOR_MAX_REL times μ is no
    # μ at all: the block keeps the loop that resolves it, and has none where neither does.
    from contactres.analysis._friction import MU_PRIOR_MAX_REL, model_averaged_mu

    b = _two_loop_blocks(1.05, 0.003, 1.05, 1100.0, bic_cm=0.0, bic_pl=8.3)
    mu, err, w = model_averaged_mu(*b, np.ones(1))
    assert (mu[0], err[0], w[0]) == pytest.approx((1.05, 0.003, 0.0))
    # Just resolved (error 0.99 μ): it stays in, with the weights of the mixture.
    b = _two_loop_blocks(1.05, 0.003, 1.0, 0.99 * MU_PRIOR_MAX_REL, bic_cm=0.0, bic_pl=8.3)
    w_pl = np.exp(-4.15) / (1 + np.exp(-4.15))
    assert model_averaged_mu(*b, np.ones(1))[2][0] == pytest.approx(w_pl, rel=1e-12)
    b = _two_loop_blocks(1.05, 2.0, 1.0, 1100.0, bic_cm=0.0, bic_pl=8.3)
    assert np.isnan(model_averaged_mu(*b, np.ones(1))).all()


def test_a_marginal_mu_beyond_max_mu_is_judged_in_ln_mu():
    # A marginal μ has a log-normal error (err = μ s, s the sd of ln μ): 30 ± 20 (s = 2/3) has
    # its 2.3 % quantile at 30 e^-4/3 = 7.9 < MAX_MU = 10 (kept), 60 ± 40 at 15.8 (beyond MAX_MU
    # by more than two errors in ln μ: withheld), though μ - 2 err < 0 for both, so the normal
    # bound (kept for a μ without the marginal) could never fire at s >= 0.5.
    from scipy.stats import lognorm

    from contactres.analysis._friction import mu_out_of_range
    from contactres.units import MAX_MU

    mu = np.array([30.0, 60.0, 60.0, 5.0, np.nan])
    err = np.array([20.0, 40.0, 40.0, 10.0, 1.0])
    lognormal = np.array([True, True, False, True, True])
    low = lognorm.ppf(0.02275, s=err / mu, scale=mu)  # exp(ln μ - 2 s)
    expect = (mu > MAX_MU) & np.where(lognormal, low > MAX_MU, mu - 2 * err > MAX_MU)
    assert expect.tolist() == [False, True, False, False, False]
    np.testing.assert_array_equal(mu_out_of_range(mu, err, lognormal), expect)
