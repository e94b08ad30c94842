"""Tests of ``contactres dcsf`` and ``contactres figures paper1``."""

import io
import json

import numpy as np
import pandas as pd
import pytest
from cli_checks import run

from contactres import Material, dcsf


def test_dcsf_csv_columns_and_values_match_the_library():
    r = run("dcsf", "--zener", "0.5", "--poisson", "0.25", "--model", "WA", "--ka", "0:2:5")
    assert r.exit_code == 0, r.output
    r = run(
        "dcsf", "--zener", "0.5", "--poisson", "0.25", "--model", "WA", "--ka", "0:2:5",
        "--format", "csv",
    )  # fmt: skip
    assert r.exit_code == 0, r.output
    t = pd.read_csv(io.StringIO(r.output))
    assert list(t.columns) == ["ka", "model", "re", "im"]
    assert len(t) == 5 and set(t.model) == {"WA"}
    ref = dcsf(Material.cubic_from_ratios(0.5, 0.25), np.linspace(0, 2, 5))
    np.testing.assert_allclose(t.re + 1j * t.im, ref, rtol=1e-12)
    assert abs(t.re[0] - 1.0) < 1e-14 and abs(t.im[0] - 0.02) < 1e-15


def test_dcsf_crystal_all_models_json_shear_and_loss():
    r = run(
        "dcsf", "--crystal", "Cu", "--surface", "001", "--model", "all", "--ka", "0.5,1.0",
        "--wavenumber", "shear", "--loss", "0", "--format", "json",
    )  # fmt: skip
    assert r.exit_code == 0, r.output
    rows = json.loads(r.output)
    assert len(rows) == 14
    assert {row["model"] for row in rows} == {"R0", "R1", "SA", "WA", "TP", "WA2D", "exact"}
    ref = dcsf(Material.crystal("Cu"), 1.0, model="TP", wavenumber="shear", loss=0.0)
    got = next(row for row in rows if row["model"] == "TP" and row["ka"] == 1.0)
    assert abs(got["re"] + 1j * got["im"] - ref) < 1e-14


def test_dcsf_bad_input_is_one_line_exit_2():
    for args in (
        ("dcsf", "--zener", "0.5"),  # missing --poisson
        ("dcsf", "--zener", "0.5", "--poisson", "0.25", "--ka", "-1:1:3"),
        ("dcsf", "--crystal", "Unobtainium"),
        ("dcsf", "--zener", "0.5", "--poisson", "0.25", "--loss", "-0.1"),
    ):
        r = run(*args)
        assert r.exit_code == 2, (args, r.output)
        assert r.output.count("\n") == 1 and "error" in r.output


RATIOS = {"--zener": "0.5", "--poisson": "0.25"}
CONSTANTS = {"--c11": "168.4e9", "--c12": "121.4e9", "--c44": "75.4e9"}

# One bad input per option: a unit slip, a NaN, a sign, a value outside the plausible range or
# (for the options that only mean something together) an impossible combination.
BAD = [
    ({}, "--crystal", "Unobtainium"),
    (CONSTANTS, "--c11", "168.4"),
    (CONSTANTS, "--c12", "inf"),
    (RATIOS, "--c44", "0"),
    (RATIOS, "--zener", "-2"),
    (RATIOS, "--poisson", "nan"),
    (RATIOS, "--surface", "0,0"),
    ({**RATIOS, "--surface": "111"}, "--inplane", "-1 -1 -1"),
    (RATIOS, "--model", "XX"),
    (RATIOS, "--ka", "0:100:3"),
    (RATIOS, "--loss", "1"),
    (RATIOS, "--wavenumber", "transverse"),
    (RATIOS, "--rtol", "0"),
    (RATIOS, "--format", "xml"),
]


def test_every_option_has_a_bad_input_case():
    from contactres.cli.dcsf import dcsf as command

    options = {p.opts[0] for p in command.params if p.opts[0] != "--help"}
    assert options == {option for _, option, _ in BAD}


@pytest.mark.parametrize("base, option, value", BAD, ids=[f"{o}={v}" for _, o, v in BAD])
def test_each_option_refuses_bad_input_in_one_line(base, option, value):
    options = {**base, option: value}
    r = run("dcsf", *[x for kv in options.items() for x in kv])
    assert r.exit_code == 2, r.output
    assert r.stdout == ""
    lines = r.stderr.splitlines()
    assert len(lines) == 1, r.stderr
    assert "error:" in lines[0] and option in lines[0]
    assert "Traceback" not in r.stderr and "np.float64" not in r.stderr


def test_constants_in_gigapascals_and_ka_beyond_the_kernels_are_named():
    r = run("dcsf", "--c11", "168.4", "--c12", "121.4e9", "--c44", "75.4e9")
    assert "gigapascals (168.4 GPa = 1.684e11 Pa): check the unit of --c11" in r.stderr
    r = run("dcsf", "--zener", "0.5", "--poisson", "0.25", "--ka", "0,1,1e300")
    assert "--ka 1e300 (in 0,1,1e300) is outside the plausible range" in r.stderr


def test_dcsf_help_states_units_and_models():
    r = run("dcsf", "--help")
    assert r.exit_code == 0
    for word in ("WA", "TP", "k_l", "Q^-1", "Pa"):
        assert word in r.output
    from contactres.cli.dcsf import dcsf as command

    for p in command.params:
        if p.type.name in ("FLOAT", "START:STOP:NUM"):
            assert ", Pa" in p.help or "dimensionless" in p.help, p.opts
        if isinstance(p.default, (str, int, float)) and p.opts[0] != "--help":
            assert p.show_default is True and isinstance(p.default, str), p.opts
    assert "[default: 1e-6]" in r.output and "[default: 0.02]" in r.output


def test_figures_paper1_writes_png_and_csv(tmp_path, monkeypatch):
    import contactres.apps.paper1 as fp

    # a coarse grid keeps the test fast; the figure code is the same
    monkeypatch.setattr(fp, "KLA", np.linspace(0, 2, 9))
    for name in ("fig3_models", "fig4_anisotropy", "fig5_poisson"):
        f = getattr(fp, name)
        monkeypatch.setattr(fp, name, lambda f=f: f(kla=fp.KLA))
    monkeypatch.setattr(
        fp, "displacement_figure", lambda f=fp.displacement_figure: f(kla=(0.5, 1.5))
    )
    monkeypatch.setattr(
        fp, "model_ranking", lambda f=fp.model_ranking: f(kla=fp.KLA, zeners=(0.5, 2.0))
    )
    r = run("figures", "paper1", "--out", str(tmp_path))
    assert r.exit_code == 0, r.output
    stems = ("fig2_displacement", "fig3_models", "fig4_anisotropy", "fig5_poisson")
    for stem in (*stems, "model_ranking"):
        assert (tmp_path / f"paper1_{stem}.png").stat().st_size > 1000
        t = pd.read_csv(tmp_path / f"paper1_{stem}.csv")
        assert len(t) > 0 and np.all(np.isfinite(t.select_dtypes("number").to_numpy()))
    t = pd.read_csv(tmp_path / "paper1_fig2_displacement.csv")
    assert np.allclose(t.abs_ratio[t.rbar == 0], 1.0)
    rank = pd.read_csv(tmp_path / "paper1_model_ranking.csv")
    assert set(rank.model) == {"WA", "R0", "R1", "SA", "TP", "WA2D"}
    assert (rank.max_rel_error_kla_le_2 >= rank.max_rel_error_kla_le_1).all()
    assert "exact (rigid punch)" in set(pd.read_csv(tmp_path / "paper1_fig3_models.csv").curve)
    for stem, label in (("fig4_anisotropy", "A = 2 exact"), ("fig5_poisson", "ν = 0.25 exact")):
        assert label in set(pd.read_csv(tmp_path / f"paper1_{stem}.csv").curve), stem


def test_dcsf_exact_model():
    r = run("dcsf", "--zener", "2", "--poisson", "0.25", "--model", "exact", "--ka", "0,1")
    assert r.exit_code == 0, r.output
    r = run(
        "dcsf", "--zener", "2", "--poisson", "0.25", "--model", "exact", "--ka", "0,1",
        "--format", "csv",
    )  # fmt: skip
    t = pd.read_csv(io.StringIO(r.output))
    assert list(t.model) == ["exact", "exact"]
    ref = dcsf(Material.cubic_from_ratios(2, 0.25), 1.0, model="exact")
    assert abs(t.re[1] + 1j * t.im[1] - ref) < 1e-12
