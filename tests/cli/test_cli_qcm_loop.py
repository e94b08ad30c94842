"""Tests of ``contactres qcm loop`` and ``contactres figures paper2``."""

import io
import json
import re

import numpy as np
import pandas as pd
import pytest
from cli_checks import figures_not_drawn, invoke, one_line_error, option_names, run
from click.testing import CliRunner

from contactres.cli import main

CM_ARGS = ["qcm", "loop", "--kappa", "4e5", "--mu", "0.8", "--normal-force", "5e-3"]


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
    # κ = 1e9 N/m (plausible) gives Δf ≈ 1.7e6 Hz at 15 MHz, far beyond |Δf|/f = 1e-3
    r = CliRunner().invoke(main, [*CM_ARGS[:3], "1e9", *CM_ARGS[4:], "--u0", "0"])
    assert r.exit_code == 0
    assert "small-load" in r.output


CM = {"--kappa": "4e5", "--mu": "0.8", "--normal-force": "5e-3"}
SAVKOOR = {"--model": "savkoor", "--kappa": "4e5", "--tau": "20e6", "--contact-radius": "5e-6"}


# One bad input per option: a unit slip, a NaN, a sign or a value outside the plausible range.
BAD = [
    (CM, "--model", "elastic"),
    (CM, "--kappa", "4e15"),
    (CM, "--mu", "nan"),
    (CM, "--normal-force", "-5e-3"),
    (SAVKOOR, "--tau", "20"),
    (SAVKOOR, "--contact-radius", "5"),
    (CM, "--xi", "inf"),
    (CM, "--plateau", "2"),
    (CM, "--u0", "0:1e-5:3"),
    (CM, "--fundamental", "5"),
    (CM, "--overtone", "2"),
    (CM, "--area", "0.5"),
    (CM, "--zq", "8.8"),
    (CM, "--n-contacts", "0"),
    (CM, "--format", "xml"),
]


def test_every_option_has_a_bad_input_case():
    from contactres.cli.qcm_loop import loop_command

    assert option_names(loop_command) == {option for _, option, _ in BAD}


@pytest.mark.parametrize("base, option, value", BAD, ids=[f"{o}={v}" for _, o, v in BAD])
def test_each_option_refuses_bad_input_in_one_line(base, option, value):
    one_line_error(invoke(["qcm", "loop"], base, option, value), option)


def test_issue_11_amplitudes_in_nanometres():
    r = invoke(["qcm", "loop"], CM, "--u0", "0:20:5")
    one_line_error(r, "--u0")
    assert (
        "--u0 20 (in 0:20:5) is outside the plausible range: the oscillation amplitude lies in "
        "[0, 1e-6] m; it looks like nanometres (20 nm = 2e-8 m): check the unit of --u0"
    ) in r.stderr


@pytest.mark.parametrize("value, why", [("-1", "is negative"), ("nan", "is not a finite number")])
def test_issue_11_xi_negative_or_nan_is_refused_not_zero(value, why):
    r = invoke(["qcm", "loop"], CM, "--xi", value)
    one_line_error(r, "--xi")
    assert f"--xi {value} {why}: the dashpot drag coefficient lies in [0, 1e5] kg/s" in r.stderr


@pytest.mark.parametrize(
    "option, value, slip",
    [
        ("--fundamental", "5", "megahertz (5 MHz = 5e6 Hz)"),
        ("--area", "0.5", "square centimetres (0.5 cm^2 = 5e-5 m^2)"),
        ("--zq", "8.8", "megarayl (8.8 MRayl = 8.8e6 kg m^-2 s^-1)"),
        ("--plateau", "2", "nanometres (2 nm = 2e-9 m)"),
    ],
)
def test_unit_slips_name_the_option_to_check(option, value, slip):
    r = invoke(["qcm", "loop"], CM, option, value)
    assert f"it looks like {slip}: check the unit of {option}" in r.stderr


def test_plausible_extremes_print_finite_numbers():
    # the top of every range at once: still finite (the inf of issue 11 cannot come back)
    r = run(
        "qcm", "loop", "--model", "voigt", "--kappa", "1e12", "--xi", "1e5", "--u0", "1e-6",
        "--fundamental", "1e10", "--overtone", "999", "--area", "1e-8", "--zq", "1e5",
        "--format", "csv",
    )  # fmt: skip
    assert r.exit_code == 0, r.output
    t = pd.read_csv(io.StringIO(r.stdout))
    assert np.isfinite(t[["df_Hz", "dgamma_Hz", "K1_N_per_m", "K2_N_per_m"]].to_numpy()).all()


def test_help_states_units_and_shows_defaults_one_way():
    from contactres.cli.qcm_loop import loop_command

    unit = re.compile(r"(N/m|, N |, Pa |, m |, m,|, kg/s|, Hz|, m\^2|kg m\^-2 s\^-1|dimensionless)")
    for p in loop_command.params:
        if p.type.name in ("FLOAT", "INTEGER", "START:STOP:NUM"):
            assert unit.search(p.help), p.opts
        if isinstance(p.default, (str, int, float)) and p.opts[0] != "--help":
            assert p.show_default is True and isinstance(p.default, str), p.opts
    r = run("qcm", "loop", "--help")
    assert "[default: 5e6]" in r.output and "[default: 8.8e6]" in r.output


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


def test_figures_paper2_reruns_into_its_folder_and_keeps_a_file_of_the_users(tmp_path, monkeypatch):
    """Issue 27: a rerun replaces the files its manifest vouches for (an SVG rerun removes the
    PNGs); a file of the user's under one of the names is refused in one line before the work,
    byte for byte unchanged, with the folder's other files."""
    from contactres.jobs import paper2

    out = tmp_path / "fig"
    figures_not_drawn(monkeypatch)  # which files; test_figures_paper2 draws the PNGs
    assert run("figures", "paper2", "--out", str(out)).exit_code == 0
    assert "paper2_fig2_loops.png" in json.loads((out / "manifest.json").read_text())["files"]
    r = run("figures", "paper2", "--out", str(out), "--figure-format", "svg")
    assert r.exit_code == 0, r.output
    assert sorted(p.name for p in out.iterdir()) == [
        "manifest.json",
        "paper2_fig1d_shifts.csv",
        "paper2_fig1d_shifts.svg",
        "paper2_fig2_loops.csv",
        "paper2_fig2_loops.svg",
    ]
    mine = b"<svg>my own drawing</svg>"
    (out / "paper2_fig2_loops.svg").write_bytes(mine)
    before = {p.name: p.read_bytes() for p in out.iterdir()}

    def never(*args, **kwargs):
        raise AssertionError("the work started before the folder was checked")

    monkeypatch.setattr(paper2, "run", never)
    r = run("figures", "paper2", "--out", str(out), "--figure-format", "svg")
    one_line_error(r, "(paper2_fig2_loops.svg)", "did not write")
    assert {p.name: p.read_bytes() for p in out.iterdir()} == before
    assert (out / "paper2_fig2_loops.svg").read_bytes() == mine
