"""``contactres qcm analyze``: exit codes, the terminal table, the results folder."""

import json

import numpy as np
import pandas as pd
import pytest
from cli_checks import one_line_error, run

from contactres.measurements._synthetic import SweepGroup, SweepStudy, synthetic_sweeps
from contactres.resonators._qcm import QCM


@pytest.fixture(scope="module")
def sweeps_csv(tmp_path_factory):
    u = tuple(np.linspace(0.5e-9, 5e-9, 8))
    study = SweepStudy(
        groups=(SweepGroup("glass", "air", 1.1e-3, 70e9, 0.1, u, 2e4, 0.1),),
        normal_forces=(2e-3, 4e-3, 6e-3),
        n_experiments=3,
        alternate=False,
        qcm=QCM(5e6, 3, 2.5e-5),
    )
    # No constant columns in the file: the tests give them as options or in a TOML file.
    table = synthetic_sweeps(study, 7).drop(columns=["configuration", "medium", "sphere_radius_m"])
    path = tmp_path_factory.mktemp("data") / "sweeps.csv"
    table.to_csv(path, index=False)
    return path


OPTS = ["--area", "2.5e-5", "--overtone", "3", "--n-contacts", "3", "--sphere-radius", "1.1e-3"]


def test_analyze_writes_results_and_prints_table(sweeps_csv, tmp_path):
    out = tmp_path / "res"
    r = run("qcm", "analyze", sweeps_csv, "--out", out, *OPTS, "--no-figures", "--bootstrap", "20")
    assert r.exit_code == 0, r.output
    # Table 1 for a terminal: E and γ with their errors, then μ per load.
    assert "E (GPa)" in r.output and "γ (mJ/m²)" in r.output and " ± " in r.output
    assert "friction coefficient per load" in r.output and "nan" not in r.output.lower()
    assert "36 sweeps, 27 used" in r.output
    for name in ("sweeps.csv", "loads.csv", "summary.json"):
        assert (out / name).is_file()
    summary = json.loads((out / "summary.json").read_text())
    assert summary["groups"][0]["E_Pa"] == pytest.approx(70e9, rel=0.05)


def test_keep_first_ramp_and_json_output(sweeps_csv, tmp_path):
    r = run(
        "qcm", "analyze", sweeps_csv, "--out", tmp_path, *OPTS,
        "--no-figures", "--keep-first-ramp", "--format", "json", "--bootstrap", "0",
    )  # fmt: skip
    assert r.exit_code == 0, r.output
    start = r.output.index("[")
    rows = json.loads(r.output[start : r.output.rindex("]") + 1])
    assert rows[0]["n_sweeps"] == 36


def test_constants_from_toml_beside_the_data(sweeps_csv, tmp_path):
    data = tmp_path / "mine.csv"
    data.write_bytes(sweeps_csv.read_bytes())
    (tmp_path / "mine.toml").write_text(
        "area_m2 = 2.5e-5\novertone = 3\nn_contacts = 3\nsphere_radius_m = 1.1e-3\n"
    )
    r = run("qcm", "analyze", data, "--out", tmp_path / "o", "--no-figures", "--bootstrap", "0")
    assert r.exit_code == 0, r.output


def test_even_overtone_isone_line_error(sweeps_csv, tmp_path):
    opts = [o if o != "3" else "4" for o in OPTS[:4]] + OPTS[4:]
    r = run("qcm", "analyze", sweeps_csv, "--out", tmp_path, *opts)
    one_line_error(r, "overtone", "odd")


def test_missing_column_isone_line_error(sweeps_csv, tmp_path):
    bad = tmp_path / "bad.csv"
    pd.read_csv(sweeps_csv).drop(columns="df_Hz").to_csv(bad, index=False)
    r = run("qcm", "analyze", bad, "--out", tmp_path / "o", *OPTS)
    one_line_error(r, "bad.csv", "df_Hz")
    assert not (tmp_path / "o").exists()


def test_missing_constant_and_missing_file(sweeps_csv, tmp_path):
    r = run("qcm", "analyze", sweeps_csv, "--out", tmp_path)
    one_line_error(r, "missing", "area_m2", "overtone", "n_contacts", "sphere_radius_m")
    one_line_error(run("qcm", "analyze", tmp_path / "nope.csv", "--out", tmp_path, *OPTS))


def test_warnings_go_to_stderr_as_lines(sweeps_csv, tmp_path):
    dup = tmp_path / "dup.csv"
    t = pd.read_csv(sweeps_csv)
    pd.concat([t, t.iloc[[0]]]).to_csv(dup, index=False)
    r = run(
        "qcm", "analyze", dup, "--out", tmp_path / "o", *OPTS, "--no-figures", "--bootstrap", "0"
    )
    assert r.exit_code == 0
    assert "warning: " in r.output and "duplicated row" in r.output


def test_help_states_units():
    r = run("qcm", "analyze", "--help")
    assert r.exit_code == 0
    for unit in ("(m^2)", "(Hz)", "(m)"):
        assert unit in r.output


def test_keep_drift_and_law_per_load_reach_the_settings(sweeps_csv, tmp_path):
    out = tmp_path / "res"
    r = run(
        "qcm", "analyze", sweeps_csv, "--out", out, *OPTS, "--no-figures", "--bootstrap", "0",
        "--keep-drift", "--law-per-load", "--remove-drift", "--workers", "1",
    )  # fmt: skip
    assert r.exit_code == 0, r.output
    settings = json.loads((out / "summary.json").read_text())["settings"]
    assert settings["keep_drift"] is True and settings["pool_experiments"] is False
    assert settings["remove_drift"] is True and settings["workers"] == 1
    # No time column: the run says the drifting loads could not be corrected (if any drift).
    sweeps = pd.read_csv(out / "sweeps.csv")
    # Every used sweep says how its class was chosen, against which runner-up, with what evidence
    # (this study has no load without a rival: no sweep of one amplitude, no Δf of the wrong
    # sign).
    used = sweeps[sweeps["used"]]
    assert set(used["decided_by"]) == {"block"}
    assert used["runner_up"].notna().all() and np.isfinite(used["delta_bic"]).all()


def test_no_progress_bar_in_a_pipe(sweeps_csv, tmp_path):
    # The runner's stderr is no terminal, as in a pipe or a log: the bar and its label stay out.
    r = run("qcm", "analyze", sweeps_csv, "--out", tmp_path / "o", *OPTS, "--no-figures")
    assert r.exit_code == 0, r.output
    assert "analysing" not in r.output and "Table 1" in r.output
