"""Tests of ``contactres qcm loop`` and ``contactres figures paper2``."""

import io
import json

import numpy as np
import pandas as pd
import pytest
from click.testing import CliRunner

from contactres.cli import main

CM_ARGS = ["qcm", "loop", "--kappa", "4e5", "--mu", "0.8", "--normal-force", "5e-3"]


def run(*args):
    return CliRunner().invoke(main, list(args))


def test_cm_csv_matches_paper_eq_1_at_zero_amplitude_and_falls():
    r = run(*CM_ARGS, "--u0", "0:20e-9:5", "--n-contacts", "3", "--format", "csv")
    assert r.exit_code == 0, r.output
    t = pd.read_csv(io.StringIO(r.output))
    assert list(t.columns) == ["u0_m", "df_Hz", "dgamma_Hz", "K1_N_per_m", "K2_N_per_m"]
    assert len(t) == 5
    # Eq. 1 by hand at u0 = 0: Δf = 3 κ / (2·3·π²·A·Zq)
    assert t.df_Hz[0] == pytest.approx(3 * 4e5 / (6 * np.pi**2 * 1e-5 * 8.8e6), rel=1e-12)
    assert t.dgamma_Hz[0] == 0.0
    assert np.all(np.diff(t.df_Hz) < 0) and np.all(np.diff(t.dgamma_Hz) > 0)


def test_voigt_json_and_dashpot():
    r = run(
        "qcm",
        "loop",
        "--model",
        "voigt",
        "--kappa",
        "4e5",
        "--xi",
        "1e-3",
        "--u0",
        "1e-9,5e-9",
        "--format",
        "json",
    )
    assert r.exit_code == 0, r.output
    rows = json.loads(r.output)
    omega = 2 * np.pi * 15e6
    for row in rows:
        assert row["K1_N_per_m"] == pytest.approx(4e5, rel=1e-12)
        assert row["K2_N_per_m"] == pytest.approx(omega * 1e-3, rel=1e-12)


def test_savkoor_and_plateau():
    r = run(
        "qcm",
        "loop",
        "--model",
        "savkoor",
        "--kappa",
        "4e5",
        "--tau",
        "20e6",
        "--contact-radius",
        "5e-6",
        "--plateau",
        "1e-9",
        "--u0",
        "0:1e-9:3",
        "--format",
        "csv",
    )
    assert r.exit_code == 0, r.output
    t = pd.read_csv(io.StringIO(r.output))
    np.testing.assert_allclose(t.K1_N_per_m, 4e5, rtol=1e-10)


@pytest.mark.parametrize(
    "args, message",
    [
        (["qcm", "loop", "--kappa", "4e5", "--mu", "0.8"], "--normal-force"),
        (
            ["qcm", "loop", "--model", "savkoor", "--kappa", "4e5", "--tau", "1e6"],
            "--contact-radius",
        ),
        ([*CM_ARGS, "--overtone", "2"], "overtone"),
        ([*CM_ARGS, "--u0", "-1e-9,1e-9"], "u0"),
        ([*CM_ARGS, "--mu", "-1"], "mu"),
        (["qcm", "loop", "--model", "voigt", "--kappa", "1", "--plateau", "1e-9"], "plateau"),
    ],
)
def test_bad_input_one_line(args, message):
    r = run(*args)
    assert r.exit_code == 2
    lines = r.output.strip().splitlines()
    assert len(lines) == 1 and "error" in lines[0] and message in lines[0]


def test_large_shift_warns_on_stderr():
    r = CliRunner().invoke(main, [*CM_ARGS[:3], "1e13", *CM_ARGS[4:], "--u0", "0"])
    assert r.exit_code == 0
    assert "small-load" in r.output


def test_figures_paper2(tmp_path):
    out = tmp_path / "fig"
    r = run("figures", "paper2", "--out", str(out))
    assert r.exit_code == 0, r.output
    for name in (
        "paper2_fig2_loops.png",
        "paper2_fig2_loops.csv",
        "paper2_fig1d_shifts.png",
        "paper2_fig1d_shifts.csv",
    ):
        assert (out / name).stat().st_size > 0
    t = pd.read_csv(out / "paper2_fig1d_shifts.csv")
    assert {"u0_m", "df_cm_Hz", "dgamma_cm_Hz", "df_savkoor_Hz", "dgamma_savkoor_Hz"} <= set(
        t.columns
    )
