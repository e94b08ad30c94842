"""The generic HTML page of a job's Result (contactres.report._job_page): any JobResult, every
text escaped, nothing fetched from elsewhere."""

from __future__ import annotations

import re
from dataclasses import dataclass
from types import MappingProxyType

import pandas as pd

from contactres.jobs.contract import JobResult
from contactres.measurements.schema import STIFFNESS_CSV
from contactres.report._job_page import FIRST_ROWS, job_page

EVIL = '<script>alert("x")</script>'


@dataclass(frozen=True)
class Toy(JobResult):
    """A Result of no job: one table with flags, values nested and plain."""

    SCHEMAS = MappingProxyType({"stiffness": STIFFNESS_CSV})
    NOT_VALUES = ("source", "warnings")

    stiffness: pd.DataFrame
    constants: dict
    equation: str
    source: str = ""
    warnings: tuple[str, ...] = ()


def toy(rows=3) -> Toy:
    table = pd.DataFrame(
        {
            "time_s": [float(i) for i in range(rows)],
            "overtone": [3] * rows,
            "df_Hz": [1.5] * rows,
            "dgamma_Hz": [float("nan")] * rows,
            "kappa_N_per_m": [2.0] * rows,
            "omega_xi_N_per_m": [3.0] * rows,
        }
    )
    table["flags"] = ["a;b", "", EVIL] + [""] * (rows - 3)
    return Toy(
        stiffness=table,
        constants={"area_m2": 2e-5, "label": EVIL, "nested": {"inner": 1.0}},
        equation="κ = Δf/P",
        source=f"run {EVIL}.txt",
        warnings=(f"watch {EVIL}",),
    )


def test_every_text_of_the_data_is_escaped_and_nothing_is_fetched():
    page = job_page(toy())
    assert EVIL not in page and "<script" not in page
    assert page.count("&lt;script&gt;") >= 4  # title, heading, warning, value, flag, cell
    assert not re.search(r"(src|href)=\"(?!data:)", page)
    assert "http://" not in page and "https://" not in page


def test_the_page_holds_the_values_flags_and_the_tables_first_rows():
    page = job_page(toy(rows=FIRST_ROWS + 5))
    assert "<h1>contactres test job page: run" in page
    assert "<code>nested.inner</code>" in page and "<code>area_m2</code>" in page
    assert "κ = Δf/P" in page
    # flags counted per table: a and b once, the escaped one once
    assert re.search(r"<td>a</td><td class=\"n\">1 of 15</td>", page)
    assert f"15 rows (the first {FIRST_ROWS} shown" in page
    assert page.count('<tr><td class="n">') == FIRST_ROWS  # rows start with time_s
    assert "<th>kappa_N_per_m (N/m)</th>" in page  # units from the schema
    assert page.count('<td class="n"></td>') == FIRST_ROWS  # NaN as an empty cell


def test_figures_are_embedded_and_none_is_skipped():
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    def draw(result):
        fig = Figure(figsize=(2, 2))
        FigureCanvasAgg(fig)
        fig.subplots().plot([0, 1], [0, 1])
        return fig

    page = job_page(toy(), (("a.png", draw), ("b.png", lambda r: None)))
    assert page.count("data:image/png;base64,") == 1
    assert "<code>a.png</code>" in page and "b.png" not in page
    assert "<h2>Figures</h2>" not in job_page(toy())


def test_a_long_list_value_shows_its_head_and_its_length():
    """A per-step series (issue 28's `steps`, 10^4 time steps) is not written whole into the
    page: its first LIST_ITEMS values and the count, the rest left to the JSON."""
    from contactres.report._job_page import LIST_ITEMS

    result = toy()
    long = Toy(**{**result.__dict__, "constants": {"series": [float(i) for i in range(10_000)]}})
    page = job_page(long, ())
    assert "(10000 values; all in the JSON)" in page
    assert f"{LIST_ITEMS - 1}, " in page and f", {LIST_ITEMS + 1}," not in page
    assert len(page) < len(job_page(result, ())) + 2_000
