"""Figures as PNG, SVG and PDF (``--figure-format``); the tables as one Excel workbook and one
NetCDF file (``--save-as xlsx,netcdf``), read back with pandas/openpyxl and xarray and compared
with the CSV files of the same folder."""

import importlib.util
import json
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path
from types import MappingProxyType

import numpy as np
import pandas as pd
import pytest
from click.testing import CliRunner

import contactres
from contactres.cli import main
from contactres.errors import MissingExtraError
from contactres.jobs.contract import JobResult
from contactres.report import write_report
from contactres.report._writer import report_names

DATA = Path(contactres.__file__).parent / "data"
EXAMPLE = DATA / "example_sweeps.csv"
EXPORT = str(DATA / "example_qcmd.csv")
STIFFNESS = ["--dissipation-scale", "1e-6", "--fundamental", "4.95e6", "--area", "2e-5"]

openpyxl = pytest.importorskip("openpyxl")
xr = pytest.importorskip("xarray")


@dataclass(frozen=True)
class Labels(JobResult):
    SCHEMAS = MappingProxyType({"points": None})
    NAME = "labels"

    points: pd.DataFrame
    conventions: dict


def _stiffness(tmp_path, *more):
    out = tmp_path / "s"
    args = ["qcm", "stiffness", EXPORT, *STIFFNESS, "--n-contacts", "3", "--out", str(out)]
    return out, CliRunner().invoke(main, [*args, *more])


def _same_as_csv(csv: pd.DataFrame, other: pd.DataFrame) -> None:
    """Every column of ``other`` equals the CSV's: numbers to the CSV's 10 digits, text as
    text (missing as missing)."""
    assert list(other.columns) == list(csv.columns)
    for column in csv.columns:
        a, b = csv[column], other[column]
        if a.dtype.kind in "fiu" and b.dtype.kind in "fiu":
            np.testing.assert_allclose(b.to_numpy(float), a.to_numpy(float), rtol=1e-9)
        else:  # cell by cell: pandas 4 refuses fillna("") on a float64 column (all cells missing)
            assert _text(b) == _text(a), column


def _text(column: pd.Series) -> list[str]:
    """The cells of ``column`` as text, a missing cell as an empty string."""
    return ["" if pd.isna(v) else str(v) for v in column]


def test_each_figure_format_is_written_decodes_and_is_in_the_manifest(tmp_path):
    out, run = _stiffness(tmp_path, "--figure-format", "png,svg", "--figure-format", "pdf")
    assert run.exit_code == 0, run.output
    assert (out / "stiffness.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    root = ET.parse(out / "stiffness.svg").getroot()  # XML whose root element is <svg>
    assert root.tag.endswith("svg")
    assert (out / "stiffness.pdf").read_bytes()[:5] == b"%PDF-"
    listed = json.loads((out / "manifest.json").read_text(encoding="utf-8"))["files"]
    assert {"stiffness.png", "stiffness.svg", "stiffness.pdf"} <= set(listed)
    # A later run with PNG alone removes the SVG and PDF the earlier set wrote.
    out, run = _stiffness(tmp_path)
    assert run.exit_code == 0, run.output
    assert not (out / "stiffness.svg").exists() and (out / "stiffness.png").exists()


def test_a_bad_figure_format_is_one_line_before_any_work(tmp_path):
    out, run = _stiffness(tmp_path, "--figure-format", "png,jpg")
    assert run.exit_code == 2
    lines = run.output.strip().splitlines()
    assert len(lines) == 1 and "'jpg' is not a figure format" in lines[0], run.output
    assert "png, svg, pdf" in lines[0]
    assert not out.exists()


def test_the_report_names_follow_the_figure_formats():
    from contactres.jobs import qcm_stiffness

    names = report_names(qcm_stiffness.Result, ("csv", "svg", "pdf", "xlsx", "netcdf"))
    assert names == (
        "stiffness.csv",
        "stiffness.svg",
        "stiffness.pdf",
        "results.xlsx",
        "results.nc",
    )


def test_the_workbook_and_netcdf_hold_the_csv_tables(tmp_path):
    out, run = _stiffness(tmp_path, "--save-as", "xlsx", "--save-as", "netcdf")
    assert run.exit_code == 0, run.output
    csv = pd.read_csv(out / "stiffness.csv")
    sheets = pd.read_excel(out / "results.xlsx", sheet_name=None)
    assert list(sheets) == ["stiffness", "conventions"]
    _same_as_csv(csv, sheets["stiffness"])
    rows = sheets["conventions"]
    conventions = dict(zip(rows["name"], rows["value"], strict=True))
    sidecar = json.loads((out / "stiffness.json").read_text(encoding="utf-8"))
    assert conventions["conventions.reader"] == sidecar["conventions"]["reader"]
    with xr.open_dataset(out / "results.nc", engine="scipy") as ds:
        nc = pd.DataFrame({c: ds[f"stiffness.{c}"].values for c in csv.columns})
        assert ds["stiffness.kappa_N_per_m"].attrs["units"] == "N/m"
        assert json.loads(ds.attrs["conventions_json"]) == sidecar["conventions"]
    _same_as_csv(csv, nc)
    listed = json.loads((out / "manifest.json").read_text(encoding="utf-8"))["files"]
    assert {"results.xlsx", "results.nc"} <= set(listed)


def test_the_qcm_analysis_workbook_and_netcdf_hold_every_table(example_set):
    # example_set: `qcm analyze EXAMPLE --bootstrap 0 --no-figures --save-as xlsx,netcdf` (and
    # --report html), written once for the report tests (tests/report/conftest.py)
    out = example_set
    listed = json.loads((out / "manifest.json").read_text(encoding="utf-8"))["files"]
    assert {"results.xlsx", "results.nc"} <= set(listed)
    sheets = pd.read_excel(out / "results.xlsx", sheet_name=None)
    tables = ["sweeps", "loads", "curves", "jkr_curves"]
    # Table 1 too (issue 30, second review M2): the numbers a reader opens the file for.
    assert list(sheets) == [*tables, "table1", "conventions"]
    groups = json.loads((out / "summary.json").read_text(encoding="utf-8"))["groups"]
    with xr.open_dataset(out / "results.nc", engine="scipy") as ds:
        for name in tables:
            csv = pd.read_csv(out / f"{name}.csv")
            _same_as_csv(csv, sheets[name])
            _same_as_csv(csv, pd.DataFrame({c: ds[f"{name}.{c}"].values for c in csv.columns}))
        table1 = sheets["table1"]
        assert list(table1.columns[:6]) == [
            "configuration", "medium", "E_Pa", "E_err_Pa", "gamma_J_m2", "gamma_err_J_m2"
        ]  # fmt: skip
        assert {"checks", "note", "t95"} <= set(table1.columns)
        assert ds["table1.E_Pa"].dims == ("group",) and ds.sizes["group"] == len(groups)
        assert ds["table1.E_Pa"].attrs["units"] == "Pa"
        assert ds["table1.gamma_err_J_m2"].attrs["units"] == "J/m^2"
        for key in ("E_Pa", "E_err_Pa", "gamma_J_m2", "gamma_err_J_m2"):
            expected = [g[key] for g in groups]
            np.testing.assert_allclose(table1[key], expected, rtol=1e-12)
            np.testing.assert_allclose(ds[f"table1.{key}"].values, expected, rtol=1e-12)
        assert list(ds["table1.configuration"].values) == [g["configuration"] for g in groups]


def test_formulas_stay_text_in_the_workbook(tmp_path):
    labels = ['=HYPERLINK("x")', "+1", "-cmd", "@SUM(A1)", "plain", "-2.5"]
    result = Labels(pd.DataFrame({"label": labels, "x_m": np.arange(6.0)}), {"note": "=1+1"})
    write_report(result, tmp_path / "w", ("csv", "xlsx"))
    csv = pd.read_csv(tmp_path / "w" / "points.csv", dtype={"label": str})
    book = openpyxl.load_workbook(tmp_path / "w" / "results.xlsx")
    cells = [row[0] for row in book["points"].iter_rows(min_row=2)]
    # No cell is a formula; each is the text the CSV holds (the apostrophe that keeps it text).
    assert [c.data_type for c in cells] == ["s"] * 6
    assert [c.value for c in cells] == csv["label"].tolist()
    assert cells[0].value == '\'=HYPERLINK("x")' and cells[4].value == "plain"
    notes = [row[1].value for row in book["conventions"].iter_rows(min_row=2)]
    assert "'=1+1" in notes


def test_a_control_character_an_xlsx_cannot_hold_is_replaced_not_fatal(tmp_path):
    frame = pd.DataFrame({"label": ["bell\x07ring", "tab\tok"], "x_m": [1.0, 2.0]})
    write_report(Labels(frame, {}), tmp_path / "c", ("csv", "xlsx"))
    book = openpyxl.load_workbook(tmp_path / "c" / "results.xlsx")
    cells = [row[0].value for row in book["points"].iter_rows(min_row=2)]
    assert cells == ["bell\ufffdring", "tab\tok"]
    assert frame["label"].tolist() == ["bell\x07ring", "tab\tok"]  # the Result is unchanged


def test_without_openpyxl_the_workbook_is_one_line_naming_the_extra(tmp_path, monkeypatch):
    found = importlib.util.find_spec
    monkeypatch.setattr(
        importlib.util, "find_spec", lambda name, *a: None if name == "openpyxl" else found(name)
    )
    with pytest.raises(MissingExtraError, match=r"contactres\[excel\]"):
        write_report(Labels(pd.DataFrame({"a": [1]}), {}), tmp_path / "n", ("xlsx",))
    out, run = _stiffness(tmp_path, "--save-as", "xlsx")
    assert run.exit_code == 2
    assert len(run.output.strip().splitlines()) == 1 and "contactres[excel]" in run.output
    assert not out.exists()  # refused before the export was read


def test_the_paper_figures_take_the_figure_formats(tmp_path):
    out = tmp_path / "p2"
    run = CliRunner().invoke(
        main, ["figures", "paper2", "--out", str(out), "--figure-format", "svg,pdf"]
    )
    assert run.exit_code == 0, run.output
    names = sorted(p.name for p in out.iterdir())
    # Beside the figures and their CSVs, the result set's manifest (issue 27: a rerun replaces
    # only what it lists).
    assert "manifest.json" in names
    assert [n for n in names if not n.endswith(".csv") and n != "manifest.json"] == [
        "paper2_fig1d_shifts.pdf",
        "paper2_fig1d_shifts.svg",
        "paper2_fig2_loops.pdf",
        "paper2_fig2_loops.svg",
    ]
    for name in names:
        if name.endswith(".pdf"):
            assert (out / name).read_bytes()[:5] == b"%PDF-"
        elif name.endswith(".svg"):
            assert ET.parse(out / name).getroot().tag.endswith("svg")


@pytest.mark.parametrize(
    ("word", "option"), [("xlsx", "--save-as xlsx"), ("nc", "--save-as netcdf")]
)
def test_format_xlsx_points_to_save_as_before_any_work(tmp_path, word, option):
    # The issue spelled the workbook `--format xlsx`; --format chooses what is printed, so the
    # word is answered with the option that writes the file, and nothing is written.
    out = tmp_path / "q"
    run = CliRunner().invoke(
        main, ["qcm", "analyze", str(EXAMPLE), "--out", str(out), "--format", word]
    )
    assert run.exit_code == 2
    lines = run.output.strip().splitlines()
    assert len(lines) == 1 and option in lines[0] and "plain, csv, json" in lines[0]
    assert not out.exists()
