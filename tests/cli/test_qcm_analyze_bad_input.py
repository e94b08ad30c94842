"""``contactres qcm analyze``: the failures of issue 11, one test each.

Every bad input is answered in one line naming the file, the row, the column, the value and the
rule, with exit code 2 and no traceback; nothing an input holds is ever lost, and results of two
runs are never mixed.
"""

import hashlib
import json
import os
import socket
import subprocess
import sys
import warnings

import numpy as np
import pandas as pd
import pytest
from cli_checks import figures_not_drawn, one_line_error
from click.testing import CliRunner

from contactres.cli import main
from contactres.fileio import MANIFEST
from contactres.measurements._synthetic import SweepGroup, SweepStudy, synthetic_sweeps
from contactres.report.figures import FIGURE_FILES
from contactres.resonators._qcm import QCM

OPTS = ["--area", "2.5e-5", "--overtone", "3", "--n-contacts", "3", "--bootstrap", "0"]
# The tables (with the fitted curves, issue 30) and the summary.
CSV_JSON = ("sweeps.csv", "loads.csv", "curves.csv", "jkr_curves.csv", "summary.json")

# The files of a default report of the example (no radiation table), written out here.
REPORT = (*CSV_JSON, *FIGURE_FILES)


def run(*args):
    return CliRunner().invoke(main, ["qcm", "analyze", *map(str, args)])


@pytest.fixture(scope="module")
def base():
    u = tuple(np.linspace(0.5e-9, 5e-9, 8))
    study = SweepStudy(
        groups=(SweepGroup("glass", "air", 1.1e-3, 70e9, 0.1, u, 2e4, 0.1),),
        normal_forces=(2e-3, 4e-3, 6e-3),
        n_experiments=3,
        alternate=False,
        qcm=QCM(5e6, 3, 2.5e-5),
    )
    return synthetic_sweeps(study, 7)  # 36 sweeps, ramps 1-3, sphere_radius_m a column


def write(folder, frame, name="data.csv"):
    folder.mkdir(parents=True, exist_ok=True)
    frame.to_csv(folder / name, index=False)
    return folder / name


def warning_lines(r):
    return [ln for ln in r.output.splitlines() if ln.startswith("contactres: warning: ")]


# 1. -------------------------------------------------------------------------------------------


@pytest.mark.parametrize("name", ["sweeps.csv", "loads.csv"])
@pytest.mark.parametrize("via_link", [False, True])
def test_an_output_never_overwrites_an_input(base, tmp_path, name, via_link):
    data = write(tmp_path / "d", base, name)
    before = data.read_bytes()
    out = tmp_path / "d"
    if via_link:
        out = tmp_path / "link"
        out.symlink_to(tmp_path / "d", target_is_directory=True)
    r = run(data, "--out", out, *OPTS, "--no-figures")
    one_line_error(r, f"{out / name}' would overwrite the input '{data}'")
    assert data.read_bytes() == before
    assert sorted(p.name for p in (tmp_path / "d").iterdir()) == [name]  # nothing written
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".")]


def test_results_beside_the_input_keep_it(base, tmp_path, monkeypatch):
    data = write(tmp_path, base)
    before = data.read_bytes()
    figures_not_drawn(monkeypatch)  # which files are written and kept, not their pixels
    assert run(data, "--out", tmp_path, *OPTS).exit_code == 0
    r = run(data, "--out", tmp_path, *OPTS, "--no-figures")  # the figures of the first go
    assert r.exit_code == 0, r.output
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted([*CSV_JSON, MANIFEST, "data.csv"])
    assert data.read_bytes() == before


# 2. -------------------------------------------------------------------------------------------


def test_a_hash_in_a_label_is_part_of_it(base, tmp_path):
    f = base.assign(configuration=np.where(base["experiment"] == "e3", "SiO2 #B", "SiO2 #A"))
    data = write(tmp_path, f)
    data.write_text("# exported by the instrument\n" + data.read_text())
    r = run(data, "--out", tmp_path / "o", *OPTS, "--no-figures")
    assert r.exit_code == 0, r.output
    groups = json.loads((tmp_path / "o" / "summary.json").read_text())["groups"]
    assert sorted(g["configuration"] for g in groups) == ["SiO2 #A", "SiO2 #B"]


# 3. -------------------------------------------------------------------------------------------


def test_a_run_into_a_folder_another_run_writes_is_refused_before_any_work(base, tmp_path):
    data = write(tmp_path, base)
    lock = tmp_path / ".o.contactres.lock"
    lock.write_text(f"{os.getpid()}\n{socket.gethostname()}\n")  # a live run: this process
    r = run(data, "--out", tmp_path / "o", *OPTS)
    one_line_error(r, "being written by another contactres run", f"process {os.getpid()}")
    assert "analysing" not in r.output and not (tmp_path / "o").exists()
    dead = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"], check=True,
                          capture_output=True, text=True).stdout.strip()  # fmt: skip
    lock.write_text(f"{dead}\n{socket.gethostname()}\n")  # what a killed run leaves
    r = run(data, "--out", tmp_path / "o", *OPTS, "--no-figures")
    assert r.exit_code == 0, r.output
    assert not lock.exists()
    manifest = json.loads((tmp_path / "o" / MANIFEST).read_text())
    assert sorted(manifest["files"]) == sorted(CSV_JSON)


def test_files_it_did_not_write_are_never_removed(base, tmp_path):
    """Issue 27 (1): a manifest.json listing a user's file made the run delete it (exit 0), and
    a folder of qcm stiffness results lost them. Now both are refused before any work."""
    data = write(tmp_path, base)
    out = tmp_path / "F"
    out.mkdir()
    (out / "raw.dat").write_text("x")
    (out / MANIFEST).write_text('{"files":{"raw.dat":{}}}')
    r = run(data, "--out", out, *OPTS, "--no-figures")
    one_line_error(r, "manifest.json that contactres did not write", "choose another folder")
    assert "analysing" not in r.output
    assert sorted(p.name for p in out.iterdir()) == [MANIFEST, "raw.dat"]
    # A folder of another command's results (as qcm stiffness writes them).
    (out / MANIFEST).unlink()
    (out / "raw.dat").unlink()
    stiffness = {"generator": "contactres", "kind": "qcm_stiffness", "files": {}}
    (out / "stiffness.csv").write_text("time_s\n")
    digest = hashlib.sha256(b"time_s\n").hexdigest()
    stiffness["files"]["stiffness.csv"] = {"bytes": 7, "sha256": digest}
    (out / MANIFEST).write_text(json.dumps(stiffness))
    r = run(data, "--out", out, *OPTS, "--no-figures")
    one_line_error(r, "another command", "qcm_stiffness")
    assert (out / "stiffness.csv").read_text() == "time_s\n"


# 4. -------------------------------------------------------------------------------------------


def test_two_sphere_radii_in_one_configuration_are_an_error(base, tmp_path):
    f = base.copy()
    f.loc[f["sweep"] == f["sweep"].iloc[-1], "sphere_radius_m"] = 6e-4
    r = run(write(tmp_path, f), "--out", tmp_path / "o", *OPTS)
    first_line = len(f) - (f["sweep"] == f["sweep"].iloc[-1]).sum() + 2
    one_line_error(
        r,
        "data.csv, configuration 'glass': conflicting values in column 'sphere_radius_m': "
        f"0.0011 (line 2) and 0.0006 (line {first_line}); one configuration has one sphere",
    )


# 5. and 6. ------------------------------------------------------------------------------------


def test_flat_sweeps_are_named_and_give_empty_cells_not_inf(base, tmp_path):
    f = base.copy()
    flat = f["sweep"].unique()[4]
    f.loc[f["sweep"] == flat, "amplitude_m"] = 0.0
    r = run(write(tmp_path, f), "--out", tmp_path / "o", *OPTS, "--no-figures")
    assert r.exit_code == 0, r.output
    assert any(f"'{flat}' have all amplitudes equal" in ln for ln in warning_lines(r))
    for name in ("sweeps.csv", "loads.csv"):
        assert "inf" not in (tmp_path / "o" / name).read_text().lower()
    row = pd.read_csv(tmp_path / "o" / "sweeps.csv").set_index("sweep").loc[flat]
    assert np.isnan(row["df_slope_err_Hz_per_m"])


# 7. -------------------------------------------------------------------------------------------


def test_a_duplicated_column_is_an_error_naming_it(base, tmp_path):
    data = write(tmp_path, base)
    text = data.read_text()
    data.write_text(text.replace("\n", ",amplitude_m\n", 1).replace("\n", ",1e-9\n"))
    one_line_error(run(data, "--out", tmp_path / "o", *OPTS), "duplicate column", "amplitude_m")


@pytest.mark.parametrize(
    "toml, words",
    [
        ("overtone = true", ["data.toml, key 'overtone'", "overtone = true is a boolean"]),
        ("n_contacts = 1e300", ["data.toml, key 'n_contacts'", "1e+300 is too large"]),
    ],
)
def test_booleans_and_huge_counts_are_refused(base, tmp_path, toml, words):
    data = write(tmp_path, base)
    (tmp_path / "data.toml").write_text(toml + "\narea_m2 = 2.5e-5\n")
    rest = "overtone = 3\n" if "overtone" not in toml else "n_contacts = 3\n"
    (tmp_path / "data.toml").write_text(toml + "\narea_m2 = 2.5e-5\n" + rest)
    one_line_error(run(data, "--out", tmp_path / "o", "--bootstrap", "0"), *words)


def test_a_huge_label_is_shown_by_its_start(base, tmp_path):
    f = base.copy()
    f.loc[3, "configuration"] = "L" * 2_000_000
    line = one_line_error(run(write(tmp_path, f), "--out", tmp_path / "o", *OPTS), "line 5")
    assert len(line) < 400 and "L" * 59 + "'…" in line


# 8. -------------------------------------------------------------------------------------------


def test_odd_labels_do_not_break_the_figures(base, tmp_path):
    label = "SiO2 $x^2_$ " + "L" * 100_000
    r = run(write(tmp_path, base.assign(configuration=label)), "--out", tmp_path / "o", *OPTS)
    assert r.exit_code == 0, r.output
    assert sorted(p.name for p in (tmp_path / "o").iterdir()) == sorted([*REPORT, MANIFEST])
    assert max(len(ln) for ln in r.output.splitlines()) < 400  # the table on the terminal too


def test_ramp_one_only_writes_the_tables_and_says_why_there_are_no_figures(base, tmp_path):
    data = write(tmp_path, base[base["ramp"] == 1])
    r = run(data, "--out", tmp_path / "o", *OPTS)
    assert r.exit_code == 0, r.output
    assert any("no figure is drawn" in ln for ln in warning_lines(r))
    assert sorted(p.name for p in (tmp_path / "o").iterdir()) == sorted([*CSV_JSON, MANIFEST])


# 9. -------------------------------------------------------------------------------------------


def test_a_file_that_is_not_utf8(base, tmp_path):
    data = write(tmp_path, base)
    raw = data.read_bytes()
    data.write_bytes(raw[:300] + b"\xe9" + raw[300:])
    line = raw[:300].count(b"\n") + 1
    one_line_error(
        run(data, "--out", tmp_path / "o", *OPTS),
        f"data.csv: not UTF-8 text (byte 0xe9 at offset 300, line {line})",
    )


def test_three_nan_amplitudes_are_counted_and_located(base, tmp_path):
    f = base.astype({"amplitude_m": object})
    f.loc[[3, 9, 30], "amplitude_m"] = "nan"
    one_line_error(
        run(write(tmp_path, f), "--out", tmp_path / "o", *OPTS),
        "line 5, column 'amplitude_m' (3 such rows: lines 5, 11, 32): value 'nan' is not finite",
    )


def test_an_output_folder_that_cannot_be_written_is_found_before_reading(
    base, tmp_path, monkeypatch
):
    import contactres.measurements._sweeps as sweeps

    def never(*args, **kwargs):
        raise AssertionError("the input was read before the output folder was checked")

    monkeypatch.setattr(sweeps, "read_sweeps", never)
    data = write(tmp_path, base)
    blocked = tmp_path / "blocked"
    blocked.write_text("a file")
    one_line_error(run(data, "--out", blocked / "o", *OPTS), f"'{blocked}' is not a directory")
    one_line_error(run(data, "--out", "/dev/null/x", *OPTS), "'/dev/null' is not a directory")
    real_access = os.access
    monkeypatch.setattr(os, "access", lambda p, m: str(p) != str(tmp_path) and real_access(p, m))
    r = run(data, "--out", tmp_path / "new", *OPTS)
    one_line_error(r, f"cannot be created: '{tmp_path}' is not writable")


def test_numpy_warnings_become_one_clear_line(base, tmp_path, monkeypatch):
    # The sweeps.csv table is made by the job's Result (report.tables re-exports the function).
    import contactres.jobs.qcm_sweeps as tables

    plain = tables.sweeps_table

    def noisy(results):
        for _ in range(3):  # the same warning three times: said once
            np.sqrt(np.array([-1.0]))
        return plain(results)

    monkeypatch.setattr(tables, "sweeps_table", noisy)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # a warning that escaped the command would raise here
        r = run(write(tmp_path, base), "--out", tmp_path / "o", *OPTS, "--no-figures")
    assert r.exit_code == 0, r.output
    lines = [ln for ln in warning_lines(r) if "numerical" in ln]
    assert len(lines) == 1 and "invalid value encountered in sqrt" in lines[0]
    assert "RuntimeWarning" not in r.output and "np.sqrt" not in r.output


@pytest.mark.parametrize(
    ("option", "value", "words"),
    [
        ("--area", "25", ("--area 25", "square millimetres")),
        ("--area", "-1", ("--area -1", "negative")),
        ("--overtone", "4", ("--overtone 4", "odd")),
        ("--fundamental", "5", ("--fundamental 5", "megahertz")),
        ("--n-contacts", "0", ("--n-contacts 0",)),
        ("--poisson", "0.6", ("--poisson 0.6", "Poisson ratio")),
        ("--sphere-radius", "1.1", ("--sphere-radius 1.1", "millimetres")),
        ("--bootstrap", "-1", ("--bootstrap",)),
        ("--report", "pdf", ("--report", "'pdf' is not one of 'none', 'html'")),
    ],
)
def test_every_constant_option_is_checked_before_reading(tmp_path, base, option, value, words):
    # Refused even where the file's own column would override the option (a typo is a typo).
    data = write(tmp_path, base)
    r = run(data, "--out", tmp_path / "out", option, value)
    one_line_error(r, *words)
    assert not (tmp_path / "out").exists()


def test_a_figure_format_with_no_figures_is_refused_before_any_work(base, tmp_path):
    data, out = write(tmp_path, base), tmp_path / "out"
    r = run(data, "--out", out, *OPTS, "--figure-format", "svg", "--no-figures")
    one_line_error(r, "--figure-format", "--no-figures")
    assert not out.exists()
    r = run(data, "--out", out, *OPTS, "--no-figures")  # --no-figures alone still runs
    assert r.exit_code == 0, r.output
    assert not list(out.glob("*.png")) and not list(out.glob("*.svg"))
