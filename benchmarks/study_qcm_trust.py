"""How far the QCM analysis can be trusted: the validation study of issue 11, measured.

Generates :func:`contactres.measurements.validation_study` (3 configurations, air and
water, 6 loads, repeated experiments, 4 ramps, water noise, 15 % plateau blocks, Savkoor
experiments, running-in, drift) with ``--studies`` seeds, analyses each with the default
settings and prints

- the confusion matrix of the amplitude model per medium (true model of the generator vs the
  model the analysis chose), over the sweeps after ramp 1 of loads without drift;
- the per-load friction coefficient of ``loads.csv`` (``mu_fit_mean`` and the robust
  ``mu_fit_median`` over experiments) against the truth (the mean true μ of the same sweeps):
  median and largest |relative error| (the target is checked on the median);
- per study (seed), the share of plateau sweeps classified right in each medium (the spread
  over seeds beside the pooled rate), and the per-block μ of the load blocks whose truth is a
  plateau: median |relative error| and the share inside ±1.96 printed errors (issue 27);
- E and γ of every group against the generator's values, with the printed errors, and the
  calibration of those errors: the scatter of E and γ over the repeated studies divided by the
  mean printed error (1 is perfect; the target is within a factor 2), beside the scatter of
  an oracle (the same fit to the true κ of the same experiments): where the oracle scatters
  less or more than 3 %/√4, the seeds drew experiments closer or further apart than the
  population, which no analysis can know.

Targets (issue 11): >= 95 % of CM and >= 85 % of plateau sweeps in air right; μ per load within
10 % (air) and 15 % (water); E within 5 %; γ within 3σ; calibration within a factor 2.
Usage: ``python benchmarks/study_qcm_trust.py [--studies 4] [--experiments 4]``; exit code 1 if
a target is missed.
"""

from __future__ import annotations

import argparse
import sys
import time

import numpy as np
import pandas as pd
from scipy import stats

from contactres.analysis import AnalysisSettings, analyze, fit_jkr_mindlin
from contactres.measurements import synthetic_sweeps, validate_sweeps, validation_study

CONSTANTS = dict(overtone=3, area_m2=2.5e-5, n_contacts=3)
MODELS = ("elastic", "cattaneo-mindlin", "savkoor", "plateau")


def one_study(seed: int, n_experiments: int):
    study = validation_study(n_experiments)
    raw = synthetic_sweeps(study, seed, truth=True)
    truth_cols = [c for c in raw.columns if c.startswith("true_")]
    truth = raw.drop_duplicates("sweep")[["sweep", *truth_cols]]
    table = validate_sweeps(raw.drop(columns=truth_cols), constants=CONSTANTS)
    t0 = time.perf_counter()
    res = analyze(table, settings=AnalysisSettings(bootstrap=200, seed=seed))
    seconds = time.perf_counter() - t0
    sw = res.sweeps.merge(truth, on="sweep", how="left", validate="one_to_one")
    return study, sw, res, seconds


def confusion(sw: pd.DataFrame) -> dict[str, pd.DataFrame]:
    drifting = sw.groupby(["configuration", "medium", "experiment", "normal_force_N"])[
        "true_drift"
    ].transform("any")
    judged = sw[(sw["ramp"] > 1) & ~drifting]
    out = {}
    for medium, part in judged.groupby("medium"):
        out[medium] = pd.crosstab(part["true_model"], part["model"]).reindex(
            index=[m for m in MODELS if m in set(part["true_model"])], columns=MODELS, fill_value=0
        )
    return out


def plateau_rates(sw: pd.DataFrame) -> dict[str, float]:
    """Share of the judged plateau sweeps (as :func:`confusion`) classified plateau, per medium."""
    out = {}
    for medium, m in confusion(sw).items():
        if "plateau" in m.index and m.loc["plateau"].sum() > 0:
            out[medium] = m.loc["plateau", "plateau"] / m.loc["plateau"].sum()
    return out


def block_mu(sw: pd.DataFrame, blocks: pd.DataFrame) -> pd.DataFrame:
    """μ of every load block with a μ against the mean true μ of its sweeps, with the true model
    (the last ramp's: ramps 2-4 of a plateau load all have it) and the pull (μ - truth)/error."""
    member = sw[sw["block"] >= 0]
    truth = member.groupby("block").agg(
        true_model=("true_model", "last"),
        true_mu_block=("true_mu", "mean"),
        drift=("true_drift", "any"),
    )
    b = blocks.join(truth, on="block")
    b = b[b["mu"].notna() & ~b["drift"].astype(bool)].copy()
    b["rel_err"] = b["mu"] / b["true_mu_block"] - 1
    b["pull"] = (b["mu"] - b["true_mu_block"]) / b["mu_err"]
    return b


def mu_errors(sw: pd.DataFrame, loads: pd.DataFrame) -> pd.DataFrame:
    """loads.csv's μ (mean and median over experiments) against the mean true μ of the same
    used sweeps."""
    keys = ["configuration", "medium", "normal_force_N"]
    used = sw[sw["used"] & sw["true_mu"].notna()]
    truth = used.groupby([*keys, "experiment"])["true_mu"].mean().groupby(keys).mean()
    cols = ["mu_fit_mean", "mu_fit_median", "mu_fit_median_err", "t95"]
    out = loads.set_index(keys)[cols].join(truth, how="inner")
    out["rel_err"] = out["mu_fit_mean"] / out["true_mu"] - 1
    out["rel_err_median"] = out["mu_fit_median"] / out["true_mu"] - 1
    return out.reset_index()


def oracle_E(sw: pd.DataFrame) -> dict:
    """E of the JKR + Mindlin fit to the *true* κ of the used sweeps of every group: what a
    perfect analysis of the same experiments would give. Its scatter over the studies is the
    sampling of the experiments alone (with 4 experiments and 3 % scatter, ~1.5 %)."""
    out = {}
    used = sw[sw["used"]]
    for key, part in used.groupby(["configuration", "medium"]):
        pts = part.groupby(["experiment", "normal_force_N"])["true_kappa_N_per_m"].mean()
        F = pts.index.get_level_values("normal_force_N")
        R, nu = part["sphere_radius_m"].iloc[0], part["poisson"].iloc[0]
        out[key] = fit_jkr_mindlin(F, pts.to_numpy(), R, nu).values["E"]
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--studies", type=int, default=4, help="repeated studies (seeds)")
    ap.add_argument("--experiments", type=int, default=4, help="experiments per group")
    args = ap.parse_args(argv)
    totals: dict[str, pd.DataFrame] = {}
    mus, groups, rates, block_mus = [], [], [], []
    for k in range(args.studies):
        study, sw, res, seconds = one_study(1000 + k, args.experiments)
        print(f"study {k + 1}: {len(sw)} sweeps analysed in {seconds:.1f} s")
        for medium, m in confusion(sw).items():
            totals[medium] = m if medium not in totals else totals[medium].add(m, fill_value=0)
        mus.append(mu_errors(sw, res.loads).assign(study=k))
        rates.append(plateau_rates(sw))
        block_mus.append(block_mu(sw, res.blocks).assign(study=k))
        truth = {(g.configuration, g.medium): g for g in study.groups}
        oracle = oracle_E(sw)
        for g in res.groups:
            t = truth[(g["configuration"], g["medium"])]
            groups.append(
                dict(
                    study=k,
                    group=f"{g['configuration']}/{g['medium']}",
                    E=g["E_Pa"] / t.E - 1,
                    E_err=g["E_err_Pa"] / t.E,
                    E_oracle=oracle[(g["configuration"], g["medium"])] / t.E - 1,
                    gamma=g["gamma_J_m2"],
                    gamma_err=g["gamma_err_J_m2"],
                    gamma_true=t.gamma,
                    error_method=g.get("error_method", ""),
                    dof=g.get("err_dof", np.nan),
                )
            )
    ok = True
    print(
        "\nconfusion matrix (rows: true model, columns: chosen), ramps 2-4 of loads without drift"
    )
    for medium, m in totals.items():
        m = m.astype(int)
        print(f"\n{medium}:\n{m.to_string()}")
        for model in ("cattaneo-mindlin", "plateau", "savkoor"):
            if model in m.index:
                rate = m.loc[model, model] / m.loc[model].sum()
                target = {"cattaneo-mindlin": 0.95, "plateau": 0.85}.get(model)
                hit = (
                    ""
                    if medium != "air" or target is None
                    else ("  ok" if rate >= target else f"  MISSED (target {target:.0%})")
                )
                ok &= not hit.endswith(")")
                print(f"  {model}: {rate:.1%} right{hit}")
    print("\nplateau sweeps right per study (seed 1000 + k):")
    for medium in ("air", "water"):
        r = [f"{x[medium]:.0%}" for x in rates if medium in x]
        print(f"  {medium}: {', '.join(r)}")
    bm = pd.concat(block_mus)
    print("per-block μ (shared joint fits, model-averaged) of blocks with a μ, by true model:")
    for (medium, model), part in bm.groupby(["medium", "true_model"]):
        inside = (part["pull"].abs() <= 1.96).mean()
        print(
            f"  {medium} {model}: {len(part)} blocks, median |rel. error| "
            f"{part['rel_err'].abs().median():.1%}, inside ±1.96 errors {inside:.1%}"
        )
    mu = pd.concat(mus)
    print("\nper-load μ of loads.csv vs truth, |relative error| over the loads:")
    for medium, part in mu.groupby("medium"):
        target = 0.10 if medium == "air" else 0.15
        for col, name in (("rel_err", "mu_fit_mean"), ("rel_err_median", "mu_fit_median")):
            e = part[col].abs()
            verdict = "ok" if e.max() <= target else f"MISSED (target {target:.0%})"
            if col == "rel_err_median":  # the robust location is the one to meet the target
                ok &= e.max() <= target
            print(
                f"  {medium} {name}: median {e.median():.1%}, 90th pct {e.quantile(0.9):.1%}, "
                f"max {e.max():.1%} over {len(e)} loads  {verdict}"
            )
        # Where a load misses, does its printed error say so? (t95: Student t of its repeats)
        z = (part["mu_fit_median"] - part["true_mu"]) / part["mu_fit_median_err"]
        miss = part["rel_err_median"].abs() > target
        covered = (z.abs() <= part["t95"])[miss]
        print(
            f"    within {target:.0%}: {1 - miss.mean():.1%} of the loads; "
            f"of the {int(miss.sum())} misses {covered.mean() if miss.any() else 1:.0%} "
            "lie inside their printed 95 % "
            f"interval (± t95 x error); pulls (mu - truth)/error: sd {z.std():.2f}"
        )
    g = pd.DataFrame(groups)
    print("\nE and γ per group (relative E error; γ in J/m²):")
    rows = []
    for name, part in g.groupby("group", sort=False):
        zg = (part["gamma"] - part["gamma_true"]) / part["gamma_err"]
        rows.append(
            dict(
                group=name,
                E_err_max=part["E"].abs().max(),
                E_scatter=part["E"].std(ddof=1),
                E_printed=part["E_err"].mean(),
                E_oracle_scatter=part["E_oracle"].std(ddof=1),
                gamma_z_max=zg.abs().max(),
                gamma_scatter=part["gamma"].std(ddof=1),
                gamma_printed=part["gamma_err"].mean(),
                method=part["error_method"].iloc[0],
            )
        )
    tab = pd.DataFrame(rows)
    tab["E_ratio"] = tab["E_scatter"] / tab["E_printed"]
    tab["gamma_ratio"] = tab["gamma_scatter"] / tab["gamma_printed"]
    with pd.option_context("display.width", 160, "display.float_format", "{:.3g}".format):
        print(tab.to_string(index=False))
    ok &= bool((tab["E_err_max"] <= 0.05).all() and (tab["gamma_z_max"] <= 3).all())
    # With errors from 4 experiments (3 dof) a 3-error deviation is not rare: Student t.
    zE = g["E"] / g["E_err"]
    zg = (g["gamma"] - g["gamma_true"]) / g["gamma_err"]
    expect = float(np.mean(2 * stats.t.sf(3.0, g["dof"])))
    print(
        f"  |z| > 3 in {np.mean(zE.abs() > 3):.1%} (E) and {np.mean(zg.abs() > 3):.1%} (γ) of "
        f"{len(g)} group fits; Student t with their degrees of freedom expects {expect:.1%}"
    )
    if args.studies > 2:
        for q in ("E_ratio", "gamma_ratio"):
            r = tab[q]
            print(f"  {q} (scatter / printed error): {r.min():.2f} ... {r.max():.2f}")
            ok &= bool(((r >= 0.5) & (r <= 2)).all())
    print("\nall targets met" if ok else "\nsome targets missed")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
