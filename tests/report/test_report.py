"""The results folder: schema of sweeps.csv, loads.csv and summary.json; atomic writing."""

import json

import numpy as np
import pandas as pd
import pytest

from contactres.analysis import AnalysisSettings, analyze
from contactres.measurements._sweeps import validate_sweeps
from contactres.measurements._synthetic import SweepGroup, SweepStudy, synthetic_sweeps
from contactres.measurements.schema import GROUP_RESULTS, SWEEP_RESULTS
from contactres.report import write_report
from contactres.resonators._qcm import QCM

Q = QCM(5e6, 3, 2.5e-5)
CONST = dict(overtone=3, area_m2=2.5e-5, n_contacts=3, sphere_radius_m=1e-3)

# The schema of the issue (exact names and order of the first columns).
ISSUE_SWEEP_COLUMNS = [
    "sweep",
    "experiment",
    "configuration",
    "medium",
    "normal_force_N",
    "ramp",
    "used",
    "model",
    "plateau_amplitude_m",
    "df0_Hz",
    "df0_err_Hz",
    "df_slope_Hz_per_m",
    "dgamma0_Hz",
    "dgamma_slope_Hz_per_m",
    "mu_df",
    "mu_dgamma",
    "mu_fit",
    "flags",
]
LOAD_QUANTITIES = [
    "df0_Hz",
    "dgamma0_Hz",
    "kappa_N_per_m",
    "omega_xi_N_per_m",
    "loss_tangent",
    "mu_df",
    "mu_dgamma",
    "mu_fit",
]


@pytest.fixture(scope="module")
def results():
    u = tuple(np.linspace(0.5e-9, 6e-9, 10))
    study = SweepStudy(
        groups=tuple(
            SweepGroup("glass", medium, 1e-3, E, 0.05, u, 1e4, 0.2)
            for medium, E in (("air", 70e9), ("water", 77e9))
        ),
        normal_forces=(2e-3, 4e-3, 8e-3),
        n_experiments=3,
        ramps=(1, 2, 3),
        alternate=False,
        qcm=Q,
        scatter=(("E", 0.02),),  # E x (1 + 0.02 z), drawn for every load
        scatter_law="normal",
        scatter_per="load",
    )
    table = validate_sweeps(synthetic_sweeps(study, 2), constants=CONST)
    return analyze(table, settings=AnalysisSettings(bootstrap=30))


def test_schema_of_the_three_outputs(results, tmp_path):
    written = write_report(results, tmp_path, formats=("csv", "json"))
    # The three outputs of the issue and the fitted curves (issue 30).
    assert {p.name for p in written} == {
        "sweeps.csv", "loads.csv", "summary.json", "curves.csv", "jkr_curves.csv"
    }  # fmt: skip
    sweeps = pd.read_csv(tmp_path / "sweeps.csv")
    assert list(sweeps.columns[: len(ISSUE_SWEEP_COLUMNS)]) == ISSUE_SWEEP_COLUMNS
    assert list(SWEEP_RESULTS.names[: len(ISSUE_SWEEP_COLUMNS)]) == ISSUE_SWEEP_COLUMNS
    assert list(sweeps.columns) == list(SWEEP_RESULTS.names)
    assert len(sweeps) == 54 and sweeps["sweep"].is_unique
    assert set(sweeps["model"]) <= {"cattaneo-mindlin", "savkoor", "elastic", "plateau"}
    assert sweeps["used"].dtype == bool and (sweeps["used"] == (sweeps["ramp"] != 1)).all()

    loads = pd.read_csv(tmp_path / "loads.csv")
    keys = ["configuration", "medium", "normal_force_N", "n_experiments", "n_sweeps"]
    expected = [*keys, "errors_from", "dof", "t95"]
    for q in LOAD_QUANTITIES:
        expected += [f"{q}_{stat}" for stat in ("mean", "sd", "sem", "median", "median_err")]
    # flags last (issue 30: mu-withheld where the group's E and γ were withheld for a unit slip)
    expected.append("flags")
    assert list(loads.columns) == expected
    assert loads["flags"].isna().all()  # no load of this study is flagged: empty cells
    assert (loads["errors_from"] == "experiments").all()
    assert len(loads) == 6 and (loads["n_experiments"] == 3).all()
    # 3 experiments: 2 degrees of freedom, t(0.975, 2) = 4.303 (Student's table)
    assert (loads["dof"] == 2).all() and np.allclose(loads["t95"], 4.3027, atol=1e-4)
    assert (loads["n_sweeps"] == 6).all()

    summary = json.loads((tmp_path / "summary.json").read_text())
    assert set(summary) >= {"groups", "settings", "version"}
    assert summary["settings"]["keep_first_ramp"] is False
    assert len(summary["groups"]) == 2
    for g in summary["groups"]:
        assert list(g) == [k for k in GROUP_RESULTS.names if k in g]  # the schema's order
        assert list(g)[:9] == list(GROUP_RESULTS.names[:9])
        assert set(g["models"]) == {"cattaneo-mindlin", "savkoor", "elastic", "plateau"}
        assert g["n_experiments"] == 3 and g["n_sweeps_used"] == 18
        assert 60e9 < g["E_Pa"] < 90e9 and g["E_err_Pa"] > 0


def test_load_statistics_are_over_experiments(results):
    # Recompute one load's mean and sd by hand from sweeps: mean per experiment, then over them.
    sw = results.sweeps[results.sweeps["used"]]
    part = sw[(sw["medium"] == "air") & (sw["normal_force_N"] == 4e-3)]
    per_exp = part.groupby("experiment")["kappa_N_per_m"].mean()
    row = results.loads[
        (results.loads["medium"] == "air") & (results.loads["normal_force_N"] == 4e-3)
    ]
    assert row["kappa_N_per_m_mean"].iloc[0] == pytest.approx(per_exp.mean())
    assert row["kappa_N_per_m_sd"].iloc[0] == pytest.approx(per_exp.std(ddof=1))


def test_nan_becomes_null_and_json_is_strict(results, tmp_path):
    write_report(results, tmp_path, formats=("json",))
    text = (tmp_path / "summary.json").read_text()
    assert "NaN" not in text and "Infinity" not in text
    json.loads(text, parse_constant=lambda c: pytest.fail(f"non-standard JSON constant {c}"))


def test_write_is_atomic_and_repeatable(results, tmp_path):
    write_report(results, tmp_path, formats=("csv",))
    first = (tmp_path / "sweeps.csv").read_bytes()
    write_report(results, tmp_path, formats=("csv", "json"))  # written again: same bytes
    assert (tmp_path / "sweeps.csv").read_bytes() == first
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".")]  # no temporaries left


def test_write_onto_a_file_is_an_error(results, tmp_path):
    f = tmp_path / "file"
    f.write_text("keep")
    with pytest.raises(ValueError, match="not a directory"):
        write_report(results, f)
    with pytest.raises(ValueError, match="unknown report format"):
        write_report(results, tmp_path / "out", formats=("docx",))
    assert f.read_text() == "keep"


def test_figures_are_written(results, tmp_path):
    written = write_report(results, tmp_path)
    pngs = sorted(p.name for p in written if p.suffix == ".png")
    assert pngs == [
        "fig4_sweeps.png",
        "fig5_df0_vs_load.png",
        "fig7_dissipation_vs_load.png",
        "fig8_friction_vs_load.png",
    ]
    for name in pngs:
        assert (tmp_path / name).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_table1(results):
    t1 = results.table1()
    assert list(t1["medium"]) == ["air", "water"]
    assert np.all(t1["E_GPa"].between(60, 90))


def test_fig5_shades_the_band_the_analysis_computed(results, monkeypatch):
    """Issue 30: each JKR curve is drawn with its 95 % band from Results.jkr (the shaded
    area spans df0_model_lo_Hz to df0_model_hi_Hz, not a band of the figure's own), the key
    says "JKR fit, 95 % band"; a group whose fit has no covariance gets its curve, no band,
    and the key says so."""
    from dataclasses import replace

    from contactres.report.figures import figure_stiffness

    def bands(fig):
        found = []
        for ax in fig.axes:
            for poly in ax.collections:
                if type(poly).__name__ in ("PolyCollection", "FillBetweenPolyCollection"):
                    y = np.concatenate([p.vertices[:, 1] for p in poly.get_paths()])
                    found.append((float(np.nanmin(y)), float(np.nanmax(y))))
        return found

    def key(fig):
        return [t.get_text() for legend in fig.legends for t in legend.get_texts()]

    fig = figure_stiffness(results)
    jkr = results.jkr
    fitted = [g for g in results.groups if np.isfinite(g["E_Pa"])]
    assert len(bands(fig)) == len(fitted) > 0
    per_group = jkr.groupby(["configuration", "medium"])
    assert sorted(lo for lo, _ in bands(fig)) == pytest.approx(
        sorted(per_group["df0_model_lo_Hz"].min()), rel=1e-12
    )
    assert sorted(hi for _, hi in bands(fig)) == pytest.approx(
        sorted(per_group["df0_model_hi_Hz"].max()), rel=1e-12
    )
    assert "JKR fit, 95 % band" in key(fig)
    # Without the fit's covariance: curves, no band, and the key names the groups.
    no_band = dict.fromkeys(
        ("kappa_lo_N_per_m", "kappa_hi_N_per_m", "df0_model_lo_Hz", "df0_model_hi_Hz"), np.nan
    )
    bare = replace(results, jkr=jkr.assign(**no_band))
    fig = figure_stiffness(bare)
    assert bands(fig) == [] and "JKR fit, 95 % band" not in key(fig)
    assert sum("without a band" in text for text in key(fig)) == len(fitted)
    # A withheld fit: no curve, no band, and the key says why; the page says so in words.
    withheld = [{**g, "E_Pa": np.nan, "checks": ["fit-at-bound"]} for g in results.groups]
    fig = figure_stiffness(replace(results, groups=withheld))
    assert bands(fig) == []
    assert sum("no JKR fit (fit-at-bound)" in text for text in key(fig)) == len(withheld)
    from contactres.report import _html
    from contactres.report._html import html_report

    # The pages' figures are drawn but not encoded (80 % of a page's cost): the words counted
    # here are the page's text, not its images.
    monkeypatch.setattr(_html, "_png", lambda figure, alt: "")
    assert html_report(bare).count("no band (") == len(fitted)
    assert html_report(results).count("no band (") == 0


def test_fig5_draws_the_jkr_curve_the_analysis_computed(results):
    """Issue 25: the report draws curves the analysis computed (Results.jkr) and evaluates no
    model; the curve itself is paper 2's Eqs. 6-10 with the fitted E and γ (kappa_jkr_mindlin,
    times P, Eq. 1)."""
    from dataclasses import replace

    from contactres.report.figures import figure_stiffness
    from contactres.tangential import kappa_jkr_mindlin

    for g in results.groups:
        if not np.isfinite(g["E_Pa"]):
            continue
        jkr = results.jkr
        c = jkr[(jkr["configuration"] == g["configuration"]) & (jkr["medium"] == g["medium"])]
        k = kappa_jkr_mindlin(
            c["normal_force_N"], g["E_Pa"], g["gamma_J_m2"], g["sphere_radius_m"], g["poisson"]
        )
        np.testing.assert_allclose(c["df0_model_Hz"], g["P_Hz_per_N_per_m"] * k, rtol=1e-12)
    # A changed curve changes the figure: the figure draws it, it does not recompute it.
    doubled = results.jkr.assign(df0_model_Hz=2 * results.jkr["df0_model_Hz"])
    lines = [
        ln.get_ydata()
        for fig in (figure_stiffness(results), figure_stiffness(replace(results, jkr=doubled)))
        for ax in fig.axes
        for ln in ax.get_lines()
        if str(ln.get_label()).startswith("JKR-Mindlin fit")
    ]
    half = len(lines) // 2
    assert half > 0
    for a, b in zip(lines[:half], lines[half:], strict=True):
        np.testing.assert_allclose(b, 2 * np.asarray(a), rtol=1e-12)


def test_the_classification_figure_stacks_the_models_of_the_used_sweeps(results):
    """Issue 30: one panel per (configuration, medium), one bar per load; the bars of a model
    sum to its count of used sweeps in that panel (counted here from Results.sweeps), every
    model in one colour in all panels, and the key names each model drawn once."""
    from contactres.report.figures import figure_classification

    fig = figure_classification(results)
    used = results.sweeps[results.sweeps["used"]]
    groups = used.groupby(["configuration", "medium"])
    panels = [ax for ax in fig.axes if ax.get_visible()]
    assert len(panels) == groups.ngroups
    colours: dict = {}
    for ax, ((config, medium), part) in zip(panels, groups, strict=True):
        assert ax.get_title() == f"{config}, {medium}"
        assert len(ax.get_xticks()) == part["normal_force_N"].nunique()
        drawn: dict = {}
        for bars in ax.containers:
            label = bars.get_label()
            drawn[label] = drawn.get(label, 0) + sum(b.get_height() for b in bars)
            colours.setdefault(label, set()).add(tuple(bars[0].get_facecolor()))
        assert drawn == part["model"].value_counts().to_dict()
    assert all(len(c) == 1 for c in colours.values())
    key = [t.get_text() for legend in fig.legends for t in legend.get_texts()]
    assert sorted(key) == sorted(used["model"].unique())


def test_no_classification_figure_without_used_sweeps(results):
    from dataclasses import replace

    from contactres.report.figures import figure_classification

    assert figure_classification(replace(results, sweeps=results.sweeps.assign(used=False))) is None
