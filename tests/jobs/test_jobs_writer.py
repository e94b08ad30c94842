"""The generic report writer: any job's Result as CSV tables, JSON values and its registered
figures and page, in one result set; the QCM analysis through the same registries."""

import json
from dataclasses import dataclass
from types import MappingProxyType

import numpy as np
import pandas as pd
import pytest

from contactres.errors import ContactresInputError
from contactres.jobs import qcm_stiffness, qcm_sweeps
from contactres.jobs.contract import JobResult
from contactres.report import _writer as writer_module
from contactres.report import write_report
from contactres.report._writer import FORMATS, figure_registry, html_registry, report_names

EXPORT = "src/contactres/data/example_qcmd.csv"
SWEEPS = "src/contactres/data/example_sweeps.csv"


@dataclass(frozen=True)
class Toy(JobResult):
    SCHEMAS = MappingProxyType({"points": None})
    NAME = "toy"

    points: pd.DataFrame
    slope: float
    label: str
    warnings: tuple[str, ...] = ()


def test_a_result_is_written_as_its_tables_and_values(tmp_path):
    toy = Toy(pd.DataFrame({"x_m": [0.5, 1.0]}), np.float64(2.5), "a", warnings=("w",))
    written = write_report(toy, tmp_path / "out")
    assert sorted(p.name for p in written) == ["points.csv", "toy.json"]
    assert pd.read_csv(tmp_path / "out" / "points.csv")["x_m"].tolist() == [0.5, 1.0]
    # The values as plain JSON; the warnings are for the user, not values of the result.
    assert json.loads((tmp_path / "out" / "toy.json").read_text()) == {"slope": 2.5, "label": "a"}
    assert report_names(Toy) == ("points.csv", "toy.json")
    assert report_names(Toy, "csv") == ("points.csv",)


def test_a_non_finite_value_is_written_as_null():
    toy = Toy(pd.DataFrame({"x_m": [0.5]}), float("nan"), "b")
    assert toy.values() == {"slope": None, "label": "b"}


def test_only_results_are_written(tmp_path):
    with pytest.raises(TypeError, match="write_report"):  # the caller's fault, not the input's
        write_report({"a": 1}, tmp_path / "x")
    with pytest.raises(ContactresInputError, match="format"):
        write_report(Toy(pd.DataFrame(), 1.0, "c"), tmp_path / "y", formats=("xml",))


def test_the_stiffness_job_report_has_its_figure(tmp_path):
    settings = qcm_stiffness.Settings(
        area=2e-5, n_contacts=3, conventions={"dissipation_scale": 1e-6, "fundamental": 4.95e6}
    )
    result = qcm_stiffness.run(EXPORT, settings)
    assert figure_registry()[qcm_stiffness.Result][0][0] == "stiffness.png"
    written = write_report(result, tmp_path / "s")
    assert [p.name for p in written] == ["stiffness.csv", "stiffness.json", "stiffness.png"]
    sidecar = json.loads((tmp_path / "s" / "stiffness.json").read_text(encoding="utf-8"))
    assert list(sidecar) == ["conventions", "constants", "equation", "columns"]
    table = pd.read_csv(tmp_path / "s" / "stiffness.csv")
    # κ = Δf/P, P = n_P/(2nπ² A_eff Z_q) (paper 2, Eq. 2), written out here independently.
    n = table["overtone"].to_numpy()
    P = 3 / (2 * n * np.pi**2 * 2e-5 * 8.8e6)
    assert table["kappa_N_per_m"].to_numpy() == pytest.approx(table["df_Hz"] / P, rel=1e-9)


def test_the_registries_are_immutable():
    with pytest.raises(TypeError):
        figure_registry()[Toy] = ()
    with pytest.raises(TypeError):
        html_registry()[Toy] = ("toy.html", str)


def test_a_drawing_with_nothing_to_draw_writes_no_file(tmp_path, monkeypatch):
    registry = MappingProxyType({Toy: (("empty.png", lambda result: None),)})
    monkeypatch.setattr(writer_module, "figure_registry", lambda: registry)
    toy = Toy(pd.DataFrame({"x_m": [1.0]}), 1.0, "d")
    # Every format: the figure in each figure format, the workbook and the NetCDF file.
    assert report_names(Toy, FORMATS) == (
        "points.csv",
        "toy.json",
        "empty.png",
        "empty.svg",
        "empty.pdf",
        "results.xlsx",
        "results.nc",
    )
    written = write_report(toy, tmp_path / "out", ("csv", "png", "html"))  # Toy has no page
    assert [p.name for p in written] == ["points.csv"]
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == ["manifest.json", "points.csv"]


def test_the_sweep_analysis_is_reported_through_the_registries(tmp_path, monkeypatch):
    from contactres.report import _html

    result = qcm_sweeps.run(SWEEPS, qcm_sweeps.Settings(bootstrap=0))
    # The page's own content is tests/report's (test_html_report); here the registry's route
    # to it: html_report of this analysis, for the job as for the library (a stand-in page,
    # which spares the page's figures drawn three times).
    seen = []

    def page_of(given):
        seen.append(given)
        return f"<!DOCTYPE html><p>{len(given.groups)} groups, {len(given.sweeps)} sweeps</p>\n"

    monkeypatch.setattr(_html, "html_report", page_of)
    figures = [name for name, _ in figure_registry()[qcm_sweeps.Result]]
    assert figures[-1] == "radiation_loss.png" and len(figures) == 5
    assert html_registry()[qcm_sweeps.Result][0] == "report.html"
    assert report_names(qcm_sweeps.Result, ("csv", "json", "html")) == (
        "sweeps.csv",
        "loads.csv",
        "radiation.csv",
        "curves.csv",
        "jkr_curves.csv",
        "summary.json",
        "report.html",
    )
    formats = ("csv", "json", "html")
    job = write_report(result, tmp_path / "job", formats)
    library = write_report(result.analysis, tmp_path / "library", formats)
    # No materials: no radiation table; the analysis alone is written as the job's Result.
    names = [
        "sweeps.csv",
        "loads.csv",
        "curves.csv",
        "jkr_curves.csv",
        "summary.json",
        "report.html",
    ]
    assert [p.name for p in job] == [p.name for p in library] == names
    for name in names:
        assert (tmp_path / "job" / name).read_bytes() == (tmp_path / "library" / name).read_bytes()
    page = (tmp_path / "job" / "report.html").read_text(encoding="utf-8")
    assert page == _html.html_report(result.analysis)
    assert len(seen) == 3 and all(given is result.analysis for given in seen)
    summary = json.loads((tmp_path / "job" / "summary.json").read_text(encoding="utf-8"))
    assert len(summary["groups"]) == len(result.analysis.groups) and "radiation" not in summary
    swept = pd.read_csv(tmp_path / "job" / "sweeps.csv")
    assert swept["sweep"].tolist() == result.analysis.sweeps["sweep"].tolist()
