"""The ceiling of the plateau/Cattaneo-Mindlin choice on the validation study (issue 27, point 11).

A Bayes oracle classifies every load block of :func:`contactres.measurements.validation_study`
whose truth is a Cattaneo-Mindlin or a plateau loop (ramps 2-4, loads without drift), knowing the
noise σ of its medium and the generator's own prior on the plateau (probability
``random_plateau`` per load, d_c uniform in ``random_plateau_range`` times the largest
amplitude). Its posterior odds of a plateau are

    π/(1 - π) · ∫ L(d_c, ...) p(d_c) p(...) / ∫ L_CM(...) p(...),

with L the Gaussian likelihood of Δf and ΔΓ of all the block's ramps 2-4 at once (the ramps
repeat one contact: one set of parameters), or of one sweep alone (per sweep). It chooses the
class of the larger posterior (the Bayes rule: no classifier with less knowledge is right more
often on average); a second rule with equal priors (odds without π) shows each class's ceiling
when neither is favoured. Two oracles:

``--mu-sd``             κ, ωξ known (the truth); ln μ the truth (0) or with a Gaussian prior of
                        that standard deviation about it (Gauss-Hermite, :data:`N_MU` nodes: the
                        middle node is the truth, so this is an optimistic ceiling); the curves
                        are the generator's own (:func:`contact_loop`, :func:`sweep_shifts`);
``--unknown-stiffness`` Pκ and Pωξ unknown, integrated out exactly (the loop is linear in both;
                        flat priors, whose constants cancel between the classes); ln θ =
                        ln κ/(μF_N) on a fine grid (:data:`N_THETA` nodes, ±1.5 about the truth)
                        with a Gaussian prior of the given standard deviation, or flat (inf):
                        what the block's own points tell about the class. The loop shapes are the
                        analysis's vectorised ones, checked against the generator in every block.

Counts are sweeps as in ``study_qcm_trust.py``, pooled over the seeds and per seed. Usage:
``python benchmarks/study_plateau_oracle.py [--studies 10] [--media water] [--mu-sd 0,0.1]
[--unknown-stiffness inf,0.2,0.1]``.
"""

from __future__ import annotations

import argparse
import sys

import numpy as np
import pandas as pd
from scipy.special import logsumexp

from contactres.analysis._models.plateau_loop import plateau_loop
from contactres.measurements import synthetic_sweeps, validation_study
from contactres.measurements._synthetic import contact_loop, sweep_shifts

N_DC = 31  # nodes of d_c over its prior range (uniform prior: the mean over the nodes)
N_MU = 9  # Gauss-Hermite nodes of ln μ where μ is known only to a relative error


def _judged_blocks(raw: pd.DataFrame, media):
    """(configuration, medium, experiment, F_N) and the points of every load block of ``media``
    without drift whose ramps 2-4 are Cattaneo-Mindlin or plateau loops (those ramps only)."""
    judged = raw[(raw["ramp"] > 1) & raw["true_model"].isin(["cattaneo-mindlin", "plateau"])]
    judged = judged[judged["medium"].isin(media)]
    keys = ["configuration", "medium", "experiment", "normal_force_N"]
    for key, block in judged.groupby(keys, sort=False):
        if not block["true_drift"].any():
            yield key, block


def _likelihoods(study, block, g, mu_nodes):
    """ln L of every sweep of ``block`` (rows: sweeps) under CM at each μ node (S, M) and
    under the plateau at each μ node and d_c node (S, M, D): Gaussian, σ of the group."""
    u_up = np.asarray(g.amplitudes, float)
    first = block.iloc[0]
    kappa, F, omega_xi = (
        first["true_kappa_N_per_m"],
        first["normal_force_N"],
        first["true_omega_xi_N_per_m"],
    )
    lo, hi = study.random_plateau_range
    dcs = np.linspace(lo, hi, N_DC) * u_up[-1]

    def curve(model, mu, dc=0.0):
        loop = contact_loop(
            model, kappa, mu, F, omega_xi, study.qcm.omega, critical_displacement=dc
        )
        return sweep_shifts(study.qcm, loop, u_up, study.n_contacts)

    sweeps = list(block.groupby("sweep", sort=False))
    data = []
    for _, pts in sweeps:
        # Each sweep's points in the order of the upward amplitudes (ramps 2 and 4 run down).
        order = np.searchsorted(u_up, pts["amplitude_m"].to_numpy())
        df = np.empty(u_up.size)
        dg = np.empty(u_up.size)
        df[order], dg[order] = pts["df_Hz"].to_numpy(), pts["dgamma_Hz"].to_numpy()
        data.append((df, dg))
    s2 = g.noise**2

    def ll(c):
        return np.array(
            [-0.5 * (np.sum((df - c[0]) ** 2) + np.sum((dg - c[1]) ** 2)) / s2 for df, dg in data]
        )

    l_cm = np.stack([ll(curve("cattaneo-mindlin", mu)) for mu in mu_nodes], axis=1)
    l_pl = np.stack(
        [np.stack([ll(curve("plateau", mu, dc)) for dc in dcs], axis=1) for mu in mu_nodes],
        axis=1,
    )
    return [name for name, _ in sweeps], l_cm, l_pl


def block_log_odds(study, raw: pd.DataFrame, mu_sd: float, media=("air", "water")):
    """Per sweep (ramps 2-4, true CM or plateau, no drift, of ``media``): the log Bayes factor
    plateau : CM of the sweep alone and of its whole block. κ and ωξ are the truth; ln μ is the
    truth (``mu_sd`` = 0) or has a Gaussian prior of standard deviation ``mu_sd`` about it."""
    groups = {(g.configuration, g.medium): g for g in study.groups}
    if mu_sd > 0:
        x, w = np.polynomial.hermite_e.hermegauss(N_MU)
        lnw = np.log(w / w.sum())
    else:
        x, lnw = np.zeros(1), np.zeros(1)
    rows = []
    for key, block in _judged_blocks(raw, media):
        mu_nodes = block["true_mu"].iloc[0] * np.exp(mu_sd * x)
        names, l_cm, l_pl = _likelihoods(study, block, groups[(key[0], key[1])], mu_nodes)
        # A sweep alone: marginal over μ (and d_c) of its own likelihood.
        ev_cm = logsumexp(l_cm + lnw, axis=1)
        ev_pl = logsumexp(l_pl + lnw[:, None], axis=(1, 2)) - np.log(N_DC)
        # The block: one contact, so one μ and one d_c for all its ramps.
        blk_cm = logsumexp(l_cm.sum(axis=0) + lnw)
        blk_pl = logsumexp(l_pl.sum(axis=0) + lnw[:, None]) - np.log(N_DC)
        for i, name in enumerate(names):
            rows.append(
                dict(
                    sweep=name,
                    medium=key[1],
                    true_model=block["true_model"].iloc[0],
                    lbf_sweep=ev_pl[i] - ev_cm[i],
                    lbf_block=blk_pl - blk_cm,
                )
            )
    return pd.DataFrame(rows)


N_THETA = 121  # nodes of ln θ = ln κ/(μF_N), ±1.5 about the truth (spacing 0.025)


def _linear_evidence(yf, yg, g1, g2, s2):
    """ln of the likelihood of the ramps' points (``yf``, ``yg``: (R, n)) integrated over Pκ
    and Pωξ (flat priors, whose constant cancels between the classes) for the loop shapes
    ``g1``, ``g2`` (..., n): Δf = Pκ g1, ΔΓ = Pωξ + Pκ g2 is linear in both, so the integral
    is Gaussian: -χ²_min/(2σ²) - ln det(A/σ²)/2 (A the normal matrix)."""
    R = yf.shape[0]
    sf, sg = yf.sum(axis=0), yg.sum(axis=0)
    a11 = R * (np.sum(g1**2, axis=-1) + np.sum(g2**2, axis=-1))
    a12 = R * np.sum(g2, axis=-1)
    a22 = R * g1.shape[-1] * np.ones_like(a11)
    b1 = np.sum(sf * g1, axis=-1) + np.sum(sg * g2, axis=-1)
    b2 = np.full_like(a11, sg.sum())
    det = a11 * a22 - a12**2
    quad = (a22 * b1**2 - 2 * a12 * b1 * b2 + a11 * b2**2) / det
    chi2 = np.sum(yf**2) + np.sum(yg**2) - quad
    return -0.5 * chi2 / s2 - 0.5 * np.log(det / s2**2)


def _odds(yf, yg, shapes, s2, lnw):
    """ln Bayes factor plateau : CM of the ramps ``yf``, ``yg`` (R, n) for the loop shapes
    ``shapes`` (CM: (T, n); plateau: (T, D, n)) and the prior weights ``lnw`` of the T nodes of
    ln θ (d_c uniform over its D nodes)."""
    g1_cm, g2_cm, g1_pl, g2_pl = shapes
    ev_cm = logsumexp(_linear_evidence(yf, yg, g1_cm, g2_cm, s2) + lnw)
    l_pl = _linear_evidence(yf, yg, g1_pl, g2_pl, s2)
    return logsumexp(l_pl + lnw[:, None]) - np.log(N_DC) - ev_cm


def unknown_stiffness_log_odds(study, raw: pd.DataFrame, mu_sd: float, media=("water",)):
    """As :func:`block_log_odds`, but Pκ and Pωξ unknown (integrated out, flat priors) and
    ln θ = ln κ/(μF_N) either known to ``mu_sd`` (Gaussian prior about the truth) or, with
    ``mu_sd`` = inf, flat: what the block's own points tell. The loop shapes are the
    analysis's vectorised ones (:func:`contactres.analysis._models.plateau_loop.plateau_loop`),
    checked here against the generator at the true parameters of every block."""
    groups = {(g.configuration, g.medium): g for g in study.groups}
    lo, hi = study.random_plateau_range
    dln = np.linspace(-1.5, 1.5, N_THETA)
    lnw = np.zeros(N_THETA) if not np.isfinite(mu_sd) else -0.5 * (dln / mu_sd) ** 2
    lnw = lnw - logsumexp(lnw)
    rows = []
    for key, block in _judged_blocks(raw, media):
        g = groups[(key[0], key[1])]
        u = np.asarray(g.amplitudes, float)
        first = block.iloc[0]
        kappa, mu, F = first["true_kappa_N_per_m"], first["true_mu"], key[3]
        theta = kappa / (mu * F) * np.exp(dln)[:, None, None]
        dcs = (np.linspace(lo, hi, N_DC) * u[-1])[None, :, None]
        # Shapes with Pκ = 1, Pωξ = 0: Δf/Pκ = g1, (ΔΓ - Pωξ)/Pκ = g2.
        g1_pl, g2_pl = plateau_loop(u[None, None, :], 1.0, 0.0, theta, dcs)
        g1_cm, g2_cm = plateau_loop(u[None, :], 1.0, 0.0, theta[:, 0, :], 0.0)
        # The vectorised shapes are the generator's (Δf relative to its low-amplitude limit).
        omega_xi = first["true_omega_xi_N_per_m"]
        loop = contact_loop("cattaneo-mindlin", kappa, mu, F, omega_xi, study.qcm.omega)
        df, _ = sweep_shifts(study.qcm, loop, u, study.n_contacts)
        i0 = N_THETA // 2
        assert np.allclose(df / df[0], g1_cm[i0] / g1_cm[i0][0], rtol=1e-9, atol=0)
        data = []
        for _, pts in block.groupby("sweep", sort=False):
            order = np.searchsorted(u, pts["amplitude_m"].to_numpy())
            yf, yg = np.empty(u.size), np.empty(u.size)
            yf[order], yg[order] = pts["df_Hz"].to_numpy(), pts["dgamma_Hz"].to_numpy()
            data.append((yf, yg))
        s2 = g.noise**2
        yf_all = np.stack([d[0] for d in data])
        yg_all = np.stack([d[1] for d in data])

        shapes = (g1_cm, g2_cm, g1_pl, g2_pl)
        blk = _odds(yf_all, yg_all, shapes, s2, lnw)
        for i, (name, _) in enumerate(block.groupby("sweep", sort=False)):
            rows.append(
                dict(
                    sweep=name,
                    medium=key[1],
                    true_model=first["true_model"],
                    lbf_sweep=_odds(yf_all[i : i + 1], yg_all[i : i + 1], shapes, s2, lnw),
                    lbf_block=blk,
                )
            )
    return pd.DataFrame(rows)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--studies", type=int, default=10, help="repeated studies (seeds 1000 + k)")
    ap.add_argument("--experiments", type=int, default=4, help="experiments per group")
    ap.add_argument("--mu-sd", default="0,0.05,0.1", help="relative errors of the known μ")
    ap.add_argument("--media", default="air,water", help="media to judge")
    ap.add_argument(
        "--unknown-stiffness",
        default="",
        help="relative errors of μ (inf: flat) for the oracle with κ and ωξ unknown",
    )
    args = ap.parse_args(argv)
    study = validation_study(args.experiments)
    prior = np.log(study.random_plateau / (1 - study.random_plateau))
    media = tuple(args.media.split(","))
    for mu_sd in (float(v) for v in args.unknown_stiffness.split(",") if v):
        parts = []
        for k in range(args.studies):
            raw = synthetic_sweeps(study, 1000 + k, truth=True)
            one = unknown_stiffness_log_odds(study, raw, mu_sd, media)
            parts.append(one.assign(study=k))
        print(f"\nκ, ωξ unknown, μ known to {mu_sd:.0%} (flat where inf):")
        report(pd.concat(parts, ignore_index=True), prior)
    for mu_sd in (float(v) for v in args.mu_sd.split(",") if v):
        parts = []
        for k in range(args.studies):
            raw = synthetic_sweeps(study, 1000 + k, truth=True)
            one = block_log_odds(study, raw, mu_sd, tuple(args.media.split(",")))
            parts.append(one.assign(study=k))
        print(f"\nμ known to {mu_sd:.0%} (κ, ωξ, σ known):")
        report(pd.concat(parts, ignore_index=True), prior)
    return 0


def report(res: pd.DataFrame, prior: float) -> None:
    """Print the share of sweeps each rule classifies right, pooled and per seed."""
    print("Bayes oracle, share of sweeps classified right (ramps 2-4, loads without drift):")
    for medium, part in res.groupby("medium"):
        pl = part["true_model"] == "plateau"
        for level in ("sweep", "block"):
            for rule, offset in (("Bayes (prior 0.15)", prior), ("equal priors", 0.0)):
                say_pl = part[f"lbf_{level}"] + offset > 0
                right = np.where(pl, say_pl, ~say_pl)
                per = (
                    part[pl]
                    .assign(r=right[pl.to_numpy()])
                    .groupby("study")["r"]
                    .mean()
                    .map("{:.0%}".format)
                )
                print(
                    f"  {medium:5s} per {level:5s} {rule:18s}: plateau {right[pl].mean():.1%} "
                    f"({int(right[pl].sum())}/{int(pl.sum())}), CM {right[~pl].mean():.1%} "
                    f"({int(right[~pl].sum())}/{int((~pl).sum())}); plateau per seed "
                    f"{', '.join(per)}"
                )


if __name__ == "__main__":
    sys.exit(main())
