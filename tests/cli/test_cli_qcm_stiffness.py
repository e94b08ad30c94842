"""Tests of ``contactres qcm stiffness``: κ + iωξ against time from a QCM-D export (paper 2,
Eq. 2)."""

from __future__ import annotations

import json
import warnings

import click
import numpy as np
import pandas as pd
import pytest
from cli_checks import figures_not_drawn, one_line_error, run

from contactres import QCM, shifts_from_stiffness
from contactres.cli.qcm_stiffness import READER_NAMES, stiffness_command
from contactres.measurements.readers.exports import EXPORT_READERS

F_F = 4.95e6
AREA = 2e-5
N_P = 3
ZQ = 8.8e6
T = np.arange(8) * 5.0
OVERTONES = (3, 5, 7)


def kappa_true(n):
    """A contact that stiffens in time, a little differently per overtone (N/m)."""
    return 2e5 * (1 + 0.02 * T) * (1 + 0.01 * n)


def xi_true(n):
    """Dashpot drag ξ (kg/s)."""
    return 1e-3 * (1 + 0.05 * T) / n


def awsensors_file(tmp_path, kappa=kappa_true):
    """An AWSensors export (Δf/n, ΔD in ppm) made from κ(t), ξ(t) with paper 2, Eq. 1."""
    columns = {"Time_(s)": T}
    for n in OVERTONES:
        df, dg = shifts_from_stiffness(QCM(F_F, n, AREA, ZQ), kappa(n), xi_true(n), N_P)
        columns[f"Delta_F/n_n={n}_(Hz)"] = df / n
        columns[f"Delta_D_n={n}_()"] = 2 * dg / (n * F_F) * 1e6
    path = tmp_path / "aws_run.csv"
    pd.DataFrame(columns).to_csv(path, index=False, float_format="%.17g")
    return path


def openqcm_file(tmp_path):
    """An openQCM Q-1 log of overtone 3: absolute f and D (plain), 2 Hz drop after 20 s."""
    f = 3 * F_F - np.where(T > 20, 2.0, 0.0)
    gamma = 40.0 + np.where(T > 20, 0.5, 0.0)
    table = pd.DataFrame(
        {
            "Date": "2026-04-24",
            "Time": [f"12:25:{int(t):02d}.000" for t in T],
            "Relative_time": T,
            "Temperature": 24.8,
            "Resonance_Frequency": f,
            "Dissipation": 2 * gamma / f,
        }
    )
    path = tmp_path / "q1_F0.csv"
    table.to_csv(path, index=False, float_format="%.17g")
    return path


AWS_ARGS = ["--dissipation-scale", "1e-6", "--fundamental", F_F, "--area", AREA,
            "--n-contacts", N_P]  # fmt: skip


def test_kappa_and_omega_xi_of_a_synthetic_export(tmp_path, monkeypatch):
    figures_not_drawn(monkeypatch)  # the table; test_outputs_sidecar_figure_and_summary draws
    out = tmp_path / "out"
    r = run("qcm", "stiffness", awsensors_file(tmp_path), *AWS_ARGS, "--out", out)
    assert r.exit_code == 0, r.output
    t = pd.read_csv(out / "stiffness.csv")
    assert list(t.columns) == [
        "time_s",
        "overtone",
        "df_Hz",
        "dgamma_Hz",
        "kappa_N_per_m",
        "omega_xi_N_per_m",
    ]
    for n in OVERTONES:
        part = t[t.overtone == n]
        omega = 2 * np.pi * n * F_F
        np.testing.assert_allclose(part.time_s, T)
        np.testing.assert_allclose(part.kappa_N_per_m, kappa_true(n), rtol=1e-9)
        np.testing.assert_allclose(part.omega_xi_N_per_m, omega * xi_true(n), rtol=1e-9)
    # one value by hand, paper 2, Eq. 2: κ = Δf 2nπ² A Z_q / n_P, ωξ = ΔΓ 2nπ² A Z_q / n_P,
    # with Δf = n x (Δf/n)_file and ΔΓ = ΔD n f_F / 2 from the file's own cells
    raw = pd.read_csv(tmp_path / "aws_run.csv")
    df5 = 5 * raw["Delta_F/n_n=5_(Hz)"][4]
    dg5 = raw["Delta_D_n=5_()"][4] * 1e-6 * 5 * F_F / 2
    row = t[(t.overtone == 5)].iloc[4]
    assert row.df_Hz == pytest.approx(df5, rel=1e-9)
    assert row.kappa_N_per_m == pytest.approx(df5 * 2 * 5 * np.pi**2 * AREA * ZQ / N_P, rel=1e-9)
    assert row.omega_xi_N_per_m == pytest.approx(dg5 * 2 * 5 * np.pi**2 * AREA * ZQ / N_P, rel=1e-9)
    assert row.kappa_N_per_m == pytest.approx(2e5 * 1.4 * 1.05, rel=1e-9)  # κ_true(5) at 20 s


def test_outputs_sidecar_figure_and_summary(tmp_path):
    out = tmp_path / "out"
    r = run("qcm", "stiffness", awsensors_file(tmp_path), *AWS_ARGS, "--out", out)
    assert r.exit_code == 0, r.output
    assert sorted(p.name for p in out.iterdir()) == [
        "manifest.json",
        "stiffness.csv",
        "stiffness.json",
        "stiffness.png",
    ]
    assert (out / "stiffness.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    side = json.loads((out / "stiffness.json").read_text(encoding="utf-8"))
    conv = side["conventions"]
    assert conv["reader"] == "awsensors" and conv["source_file"].endswith("aws_run.csv")
    assert conv["df_as_read"] == "divided by n (Δf_n/n)"
    assert conv["dissipation_scale"] == 1e-6 and conv["fundamental_Hz"] == F_F
    assert conv["baseline"].startswith("as exported")
    assert side["constants"] == {"area_m2": AREA, "n_contacts": N_P, "zq_kg_per_m2_s": ZQ,
                                 "fundamental_Hz": F_F}  # fmt: skip
    assert side["columns"]["kappa_N_per_m"].startswith("N/m")
    assert "Eqs. 1-2" in side["equation"]
    assert "n = 3: 8 points" in r.stdout and "wrote 3 files" in r.stdout


def test_absolute_log_with_a_baseline(tmp_path, monkeypatch):
    figures_not_drawn(monkeypatch)  # the table; test_outputs_sidecar_figure_and_summary draws
    out = tmp_path / "out"
    r = run("qcm", "stiffness", openqcm_file(tmp_path), "--dissipation-scale", "1",
            "--baseline", "window:0:12", "--overtone", "3", "--area", AREA, "--n-contacts", 1,
            "--out", out)  # fmt: skip
    assert r.exit_code == 0, r.output
    t = pd.read_csv(out / "stiffness.csv")
    late = t[t.time_s > 20]
    np.testing.assert_allclose(late.df_Hz, -2.0, rtol=1e-6)
    np.testing.assert_allclose(late.dgamma_Hz, 0.5, rtol=1e-6)
    P = 1 / (2 * 3 * np.pi**2 * AREA * ZQ)  # paper 2, Eq. 1, one contact
    np.testing.assert_allclose(late.kappa_N_per_m, -2.0 / P, rtol=1e-6)
    side = json.loads((out / "stiffness.json").read_text(encoding="utf-8"))
    assert side["conventions"]["reference_frequency_Hz"]["3"] == pytest.approx(3 * F_F)
    assert side["constants"]["fundamental_Hz"] == pytest.approx(F_F)


def test_a_missing_convention_is_one_line_naming_file_and_option(tmp_path):
    path = awsensors_file(tmp_path)
    r = run("qcm", "stiffness", path, "--area", AREA, "--n-contacts", N_P, "--out", tmp_path / "o")
    one_line_error(r, "aws_run.csv", "--fundamental")
    assert not (tmp_path / "o").exists()
    # The header's D unit '()' is dimensionless, so no scale is asked for; this file's D is in
    # ppm, which a plain D shift cannot reach: one line asking for the scale (issue 27, 12).
    r = run("qcm", "stiffness", path, "--area", AREA, "--n-contacts", N_P, "--fundamental", F_F,
            "--out", tmp_path / "o")  # fmt: skip
    one_line_error(r, "aws_run.csv", "--dissipation-scale 1e-6", "'()'")
    assert not (tmp_path / "o").exists()


def test_small_load_warning_is_one_line_and_the_run_goes_on(tmp_path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # the same check, making the file
        path = awsensors_file(tmp_path, kappa=lambda n: 2e8 * np.ones_like(T))
    r = run("qcm", "stiffness", path, *AWS_ARGS, "--out", tmp_path / "o")
    assert r.exit_code == 0, r.output
    warned = [ln for ln in r.stderr.splitlines() if ln.startswith("contactres: warning:")]
    assert warned and all("small-load" in ln for ln in warned) and "Traceback" not in r.output


def test_help_names_units_readers_and_an_example():
    text = " ".join(run("qcm", "stiffness", "--help").output.split())
    for words in ("m^2", "Hz", "N/m", "kg m^-2 s^-1", "dimensionless", "Example", "--out"):
        assert words in text, words
    assert READER_NAMES == tuple(r.name for r in EXPORT_READERS)


# ------------------------------------------------------------------ bad input, every option
def files(tmp_path):
    aws = awsensors_file(tmp_path)
    qsense = tmp_path / "qsense.txt"
    qsense.write_text("Time_1;F_1:3;D_1:3;Time_2;F_2:3;D_2:3\n0;0;0;0;0;0\n1;-1,5;0,2;1;-1;0,1\n")
    a_file = tmp_path / "a_file"
    a_file.write_text("x")
    return {"aws": aws, "qsense": qsense, "a_file": a_file, "out": tmp_path / "out"}


# (option, value, file, words in the error line; default: the option itself)
BAD = [
    ("--out", "a_file", "aws", ["--out", "is a file"]),
    ("--area", "1", "aws", None),
    ("--n-contacts", "0", "aws", None),
    ("--reader", "biolin", "aws", ["known: qsense"]),
    ("--df-per-overtone", None, "aws", ["contradicts"]),
    ("--dissipation-scale", "2", "aws", ["(0, 1]"]),
    ("--baseline", "last", "aws", ["window:T0:T1"]),
    ("--time-unit", "sec", "aws", None),
    ("--channel", "Z", "qsense", ["'Z'", "1, 2"]),
    ("--overtone", "4", "aws", ["odd"]),
    ("--fundamental", "4.95", "aws", ["megahertz"]),
    ("--zq", "8.8", "aws", ["megarayl"]),
    ("--figure-format", "jpg", "aws", ["'jpg' is not a figure format", "png, svg, pdf"]),
    ("--save-as", "csv", "aws", ["'csv'", "xlsx, netcdf"]),
]


def test_every_option_has_a_bad_input_case():
    options = {p.opts[0] for p in stiffness_command.params if isinstance(p, click.Option)}
    assert options - {"--help"} == {option for option, *_ in BAD}


@pytest.mark.parametrize("option, value, which, words", BAD, ids=[b[0] for b in BAD])
def test_each_option_refuses_bad_input_in_one_line(tmp_path, option, value, which, words):
    paths = files(tmp_path)
    base = {"--area": AREA, "--n-contacts": N_P, "--out": paths["out"],
            "--dissipation-scale": "1e-6", "--fundamental": F_F}  # fmt: skip
    if which == "qsense":
        base.update({"--time-unit": "s", "--df-divided-by-n": None})
    value = str(paths["a_file"]) if value == "a_file" else value
    base[option] = value
    args = [x for k, v in base.items() for x in ((k,) if v is None else (k, v))]
    r = run("qcm", "stiffness", paths[which], *args)
    one_line_error(r, *(words or [option]))
    assert not paths["out"].exists()


def test_the_export_argument_is_checked(tmp_path):
    r = run("qcm", "stiffness", tmp_path / "missing.txt", "--area", AREA, "--n-contacts", 1,
            "--out", tmp_path / "o")  # fmt: skip
    one_line_error(r, "EXPORT", "does not exist")
    (tmp_path / "run.xlsx").write_bytes(b"PK\x03\x04")
    r = run("qcm", "stiffness", tmp_path / "run.xlsx", "--area", AREA, "--n-contacts", 1,
            "--out", tmp_path / "o")  # fmt: skip
    one_line_error(r, "run.xlsx", "export the data")


def test_a_film_export_with_negative_stiffness_is_said_not_printed_silently(tmp_path):
    """Issue 27: real film exports (Δf < 0: mass loading) printed negative κ medians without a
    word. A contact spring raises f (Eq. 1-2), so κ < 0 is named per overtone."""
    path = awsensors_file(tmp_path, kappa=lambda n: -2e5 * np.ones_like(T))
    r = run("qcm", "stiffness", path, *AWS_ARGS, "--out", tmp_path / "o")
    assert r.exit_code == 0, r.output
    warned = [ln for ln in r.stderr.splitlines() if ln.startswith("contactres: warning:")]
    assert [ln.split(":")[2].strip() for ln in warned] == [f"overtone {n}" for n in OVERTONES]
    assert all("8 of 8 points have κ < 0: a negative Δf is mass loading" in ln for ln in warned)


def test_an_overtone_left_out_is_said_on_the_console(tmp_path, monkeypatch):
    """Issue 27, point 3: an overtone without its dissipation column is named, not dropped."""
    figures_not_drawn(monkeypatch)  # the console, not the figure's pixels
    path = awsensors_file(tmp_path)
    text = path.read_text().splitlines()
    text[0] = text[0].replace("Delta_D_n=5_()", "Delta_Q_n=5")
    path.write_text("\n".join(text) + "\n")
    r = run("qcm", "stiffness", path, *AWS_ARGS, "--out", tmp_path / "o")
    assert r.exit_code == 0, r.output
    warned = [ln for ln in r.stderr.splitlines() if ln.startswith("contactres: warning:")]
    assert any("overtone 5 not read" in ln and "Delta_F/n_n=5_(Hz)" in ln for ln in warned), warned
    assert "n = 5" not in r.stdout and "n = 7" in r.stdout


def test_a_stiffness_csv_contactres_did_not_write_is_not_overwritten(tmp_path, monkeypatch):
    """Issue 27: a stiffness.csv of the user's in --out (no manifest vouches for it) was
    overwritten. Refused in one line naming it, before the export is read; nothing changes."""
    from contactres.jobs import qcm_stiffness

    export = awsensors_file(tmp_path)
    out = tmp_path / "out"
    out.mkdir()
    (out / "stiffness.csv").write_bytes(b"time,kappa\n0,1\n")
    (out / "raw.dat").write_bytes(b"x\n")

    def never(*args, **kwargs):
        raise AssertionError("the work started before the folder was checked")

    monkeypatch.setattr(qcm_stiffness, "run", never)
    r = run("qcm", "stiffness", export, *AWS_ARGS, "--out", out)
    one_line_error(r, "'" + str(out) + "'", "(stiffness.csv)", "did not write")
    assert sorted(p.name for p in out.iterdir()) == ["raw.dat", "stiffness.csv"]
    assert (out / "stiffness.csv").read_bytes() == b"time,kappa\n0,1\n"
    assert (out / "raw.dat").read_bytes() == b"x\n"
