"""Tests of ``contactres qcm spectra`` and of ``qcm analyze`` on spectra (issue 14)."""

from importlib.resources import files

import numpy as np
import pandas as pd
import pytest
from cli_checks import invoke, one_line_error, option_names, run

SPECTRA = str(files("contactres") / "data" / "example_spectra.csv")


def test_bundled_spectra_to_sweeps_and_fits(tmp_path):
    """The bundled example: every measured spectrum gives a row with Δf, ΔΓ, their errors and
    u0; the conventions are printed; the input is not modified."""
    before = (files("contactres") / "data" / "example_spectra.csv").read_bytes()
    out, fits = tmp_path / "sweeps.csv", tmp_path / "fits.csv"
    r = run("qcm", "spectra", SPECTRA, "--out", out, "--fits", fits)
    assert r.exit_code == 0, r.output
    rows, fitted = pd.read_csv(out, comment="#"), pd.read_csv(fits)
    assert len(fitted) == 158 and len(rows) == 156
    for col in ("sweep", "amplitude_m", "df_Hz", "dgamma_Hz", "df_err_Hz", "dgamma_err_Hz"):
        assert rows[col].notna().all(), col
    assert (rows["df_err_Hz"] > 0).all() and (rows["amplitude_m"] <= 1.1e-8).all()
    assert "not divided by n" in r.stdout and "4 d26 Q U" in r.stdout
    assert (files("contactres") / "data" / "example_spectra.csv").read_bytes() == before


def test_analyze_reads_spectra_directly_and_the_docs_quote_what_it_prints(tmp_path):
    """`qcm analyze` reads the bundled spectra directly. README and the spectra guide quote E and
    γ of them: the numbers must be the ones `qcm analyze` prints (they went stale once when the
    analysis moved; a text guard, not a check of the physics — the recovery of E and γ is
    tested in tests/analysis)."""
    import re
    from pathlib import Path

    r = run("qcm", "analyze", SPECTRA, "--out", tmp_path / "o", "--no-figures")
    assert r.exit_code == 0, r.output
    loads = pd.read_csv(tmp_path / "o" / "loads.csv")
    assert len(loads) == 6 and (loads["kappa_N_per_m_mean"] > 0).all()
    row = re.search(r"SiO2_1\.2mm\s+air\s+([\d.]+) ± ([\d.]+)\s+([\d.]+) ± ([\d.]+)", r.stdout)
    assert row is not None, r.stdout
    e, e_err, g, g_err = (float(x) for x in row.groups())
    root = Path(__file__).resolve().parents[2]
    guide = (root / "docs" / "guide" / "spectra.md").read_text(encoding="utf-8")
    assert f"SiO2_1.2mm air {row[1]} ± {row[2]} {row[3]} ± {row[4]}" in guide
    readme = (root / "README.md").read_text(encoding="utf-8")
    quoted = re.search(r"gives E = ([\d.]+) ± ([\d.]+) GPa and γ = (\d+) ± (\d+) mJ/m²", readme)
    assert quoted is not None
    # The README rounds (E and its error to 0.1 GPa, γ to 1 mJ/m²): half a unit, and a hair.
    assert float(quoted[1]) == pytest.approx(e, abs=0.05 + 1e-9)
    assert float(quoted[2]) == pytest.approx(e_err, abs=0.05 + 1e-9)
    assert float(quoted[3]) == pytest.approx(g, abs=0.5 + 1e-9)
    assert float(quoted[4]) == pytest.approx(g_err, abs=0.5 + 1e-9)


def test_calibration_replaces_the_formula(tmp_path):
    out = tmp_path / "s.csv"
    r = run("qcm", "spectra", SPECTRA, "--out", out, "--calibration", 2e-9)
    assert r.exit_code == 0, r.output
    rows = pd.read_csv(out, comment="#")
    assert rows["amplitude_m"].to_numpy() == pytest.approx(
        2e-9 * rows["drive_voltage_V"].to_numpy(), rel=1e-9
    )


BASE = {"--out": "OUT"}
BAD = [
    ("--out", "/nonexistent/folder/s.csv"),
    ("--fits", SPECTRA),
    ("--reference", "nope"),
    ("--layout", "XY"),
    ("--reference-impedance", "-5"),
    ("--two-port", "S12"),
    ("--voltage", "peak"),
    ("--d26", "3.3"),
    ("--calibration", "0"),
    ("--format", "xml"),
]


def test_every_option_has_a_bad_input_case():
    from contactres.cli.qcm_spectra import spectra_command

    assert option_names(spectra_command) - {"spectra"} == {o for o, _ in BAD}


@pytest.mark.parametrize("option, value", BAD, ids=[o for o, _ in BAD])
def test_each_option_refuses_bad_input_in_one_line(tmp_path, option, value):
    base = {"--out": str(tmp_path / "s.csv")}
    r = invoke(["qcm", "spectra", SPECTRA], base, option, value)
    one_line_error(r)


def test_bad_spectra_files_in_one_line(tmp_path):
    bad = tmp_path / "bad.csv"
    bad.write_text("spectrum,frequency_Hz,G_S\ns,1e6,abc\n")
    one_line_error(run("qcm", "spectra", bad, "--out", tmp_path / "s.csv"), "G_S", "'abc'")
    one_line_error(run("qcm", "spectra", tmp_path / "missing.csv", "--out", tmp_path / "s.csv"))


def test_each_bad_spectrum_gets_one_line_and_the_others_are_kept(tmp_path):
    """A NaN point, a peak outside the span, one point only, no peak (noise): each of these
    spectra is left out with one warning line naming it and its flag; the run goes on."""
    frame = pd.read_csv(SPECTRA, keep_default_na=False, dtype=str)
    ids = [s for s in frame["spectrum"].unique() if s not in ("s000", "s001")][:4]
    g = frame["G_S"].astype(float)
    nan_id, edge_id, one_id, noise_id = ids
    frame.loc[(frame["spectrum"] == nan_id).to_numpy().nonzero()[0][5], "G_S"] = "nan"
    edge = (frame["spectrum"] == edge_id).to_numpy().nonzero()[0]
    one = (frame["spectrum"] == one_id).to_numpy().nonzero()[0]
    frame = frame.drop(index=[*edge[:24], *one[1:]])  # the edge spectrum starts past its peak
    noise = frame["spectrum"] == noise_id
    rng = np.random.default_rng(0)
    frame.loc[noise, "G_S"] = [f"{v:.7g}" for v in rng.normal(0, 1e-6, noise.sum())]
    frame.loc[noise, "B_S"] = [f"{v:.7g}" for v in rng.normal(0, 1e-6, noise.sum())]
    path = tmp_path / "four_bad.csv"
    frame.to_csv(path, index=False)
    r = run("qcm", "spectra", path, "--out", tmp_path / "s.csv")
    assert r.exit_code == 0, r.output
    warnings = [ln for ln in r.stderr.splitlines() if ln.startswith("contactres: warning:")]
    assert len(warnings) == 4, r.stderr
    for sid, flag in zip(
        ids, ("bad-values", "peak-not-covered", "too-few-points", "no-peak"), strict=True
    ):
        assert any(sid in w and flag in w for w in warnings), (sid, flag, warnings)
    assert len(pd.read_csv(tmp_path / "s.csv", comment="#")) == 156 - 4
    assert g.notna().all()


def test_fits_and_out_must_differ(tmp_path):
    out = tmp_path / "o.csv"
    one_line_error(run("qcm", "spectra", SPECTRA, "--out", out, "--fits", out))


def test_no_usable_spectrum_is_one_line(tmp_path):
    frame = pd.read_csv(SPECTRA, keep_default_na=False, dtype=str)
    frame.loc[frame["reference"] == "False", "G_S"] = "nan"
    path = tmp_path / "all_bad.csv"
    frame.to_csv(path, index=False)
    one_line_error(run("qcm", "spectra", path, "--out", tmp_path / "s.csv"), "no measured")


def test_references_serve_only_their_own_experiment(tmp_path):
    """Experiment "2" is experiment "1" measured 100 Hz higher, with its own references: the
    shifts of both are the same (a reference labelled "1" must not serve experiment "2")."""
    one = pd.read_csv(SPECTRA, keep_default_na=False, dtype=str)
    one["experiment"] = "1"
    two = one.copy()
    two["experiment"] = "2"
    two["spectrum"] = "b" + two["spectrum"]
    two["sweep"] = [s + "-2" if s else s for s in two["sweep"]]
    two["frequency_Hz"] = (two["frequency_Hz"].astype(float) + 100).map("{:.2f}".format)
    path = tmp_path / "two.csv"
    pd.concat([one, two]).to_csv(path, index=False)
    r = run("qcm", "spectra", path, "--out", tmp_path / "s.csv")
    assert r.exit_code == 0, r.output
    rows = pd.read_csv(tmp_path / "s.csv", comment="#")
    df = rows.groupby("experiment")["df_Hz"].mean()
    assert abs(df[1] - df[2]) < 1.0  # the fit noise of two copies; 100 Hz if mixed


@pytest.mark.parametrize("option", ["--out", "--fits"])
def test_an_empty_output_name_is_refused(tmp_path, monkeypatch, option):
    """Issue 27, point 15: --out '' wrote into the current folder, --fits '' was ignored."""
    monkeypatch.chdir(tmp_path)
    names = {"--out": "sweeps.csv", "--fits": "fits.csv", option: ""}
    r = run("qcm", "spectra", SPECTRA, "--out", names["--out"], "--fits", names["--fits"])
    one_line_error(r, "output file ''", "is empty")
    assert list(tmp_path.iterdir()) == []


def _two_port_folder(tmp_path, shift_Hz):
    """A reference and a measured two-port .s2p (the crystal on port 2, a resonance
    ``shift_Hz`` higher when measured), each a series R-L-C ∥ C0 written by scikit-rf."""
    skrf = pytest.importorskip("skrf", reason="scikit-rf (the peers extra) is not installed")
    folder = tmp_path / "run"
    folder.mkdir()
    f = np.linspace(14.995e6, 15.005e6, 301)
    rows = []
    for name, fr in (("ref", 15e6), ("meas", 15e6 + shift_Hz)):
        w, r, q = 2 * np.pi * f, 200.0, 2e4
        L = q * r / (2 * np.pi * 15e6)
        C = 1 / ((2 * np.pi * fr) ** 2 * L)
        y = 1 / (r + 1j * w * L + 1 / (1j * w * C)) + 1j * w * 5e-12
        params = np.zeros((f.size, 2, 2), dtype=complex)
        params[:, 1, 1] = y
        s = skrf.network.y2s(params, z0=50.0)
        skrf.Network(frequency=skrf.Frequency.from_f(f, unit="Hz"), s=s).write_touchstone(
            str(folder / name), form="ma"
        )
        rows.append({"file": f"{name}.s2p", "overtone": 3, "drive_voltage_V": 0.5,
                     "reference": name == "ref", "sweep": "" if name == "ref" else "A",
                     "normal_force_N": "" if name == "ref" else 1e-3})  # fmt: skip
    pd.DataFrame(rows).to_csv(folder / "index.csv", index=False)
    return folder


def test_a_two_port_folder_needs_the_port_and_then_gives_the_shift(tmp_path):
    """issue 30: a folder with .s2p files was misdiagnosed as a CSV without frequency_Hz. It
    now asks for --two-port in one line, and with it gives the circuit's resonance shift."""
    folder = _two_port_folder(tmp_path, 40.0)
    r = run("qcm", "spectra", folder, "--out", tmp_path / "s.csv")
    line = one_line_error(r, "--two-port", "S11, S22, S21")
    assert len(line.replace(str(folder), "")) < 140  # the meanings are in --help (was 318)
    out = tmp_path / "s.csv"
    r = run("qcm", "spectra", folder, "--out", out, "--two-port", "S22")
    assert r.exit_code == 0, r.output
    rows = pd.read_csv(out, comment="#")
    # The series resonance moves by 40 Hz; C0 pulls the conductance peak by far less than the
    # fit's error at Q = 2e4 (the resonance fit's own tests bound that pull).
    assert rows["df_Hz"].to_numpy() == pytest.approx([40.0], abs=0.05)
    assert "two_port: S22 (reflection at port 2" in r.stdout


def test_only_reference_spectra_is_one_line(tmp_path):
    folder = _two_port_folder(tmp_path, 0.0)
    index = pd.read_csv(folder / "index.csv")
    index["reference"] = True
    index.to_csv(folder / "index.csv", index=False)
    r = run("qcm", "spectra", folder, "--out", tmp_path / "s.csv", "--two-port", "S22")
    one_line_error(r, "every spectrum is a reference")
