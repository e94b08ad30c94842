"""The HTML page of ``qcm analyze`` (``report.html``): self-contained, complete, escaped."""

import json
import re
import shutil
from html.parser import HTMLParser
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

import contactres
from contactres.cli import main
from contactres.fileio import MANIFEST
from contactres.report import html_report, summary, write_html
from contactres.report._console import plus_minus

EXAMPLE = Path(contactres.__file__).parent / "data" / "example_sweeps.csv"


@pytest.fixture(scope="module")
def results(example_analysis):
    return example_analysis()  # of EXAMPLE, without bootstrap


@pytest.fixture(scope="module")
def page(example_set):
    """The page of ``results``: the one ``qcm analyze --report html --bootstrap 0`` wrote for
    the example (tests/report/conftest.py), which is html_report of this same analysis, byte for
    byte; rendering it again here would cost ~2.5 s of CPU (its four PNG figures)."""
    return (example_set / "report.html").read_text(encoding="utf-8")


class _Strict(HTMLParser):
    """Parses the page; counts the sweep rows and checks that every opened element closes."""

    VOID = frozenset(
        {"meta", "br", "hr", "img", "input", "link", "circle", "path", "polyline", "rect"}
    )

    def __init__(self):
        super().__init__()
        self.stack, self.rows, self.errors, self.in_sweeps = [], 0, [], False

    def handle_starttag(self, tag, attrs):
        if tag == "table" and ("id", "sweeps") in attrs:
            self.in_sweeps = True
        if self.in_sweeps and tag == "tr" and any(k == "data-configuration" for k, _ in attrs):
            self.rows += 1
        if tag not in self.VOID:
            self.stack.append(tag)

    def handle_startendtag(self, tag, attrs):
        pass

    def handle_endtag(self, tag):
        if tag in self.VOID:
            return
        if not self.stack or self.stack[-1] != tag:
            self.errors.append(f"</{tag}> closes {self.stack[-1:]}")
            return
        self.stack.pop()
        if tag == "table":
            self.in_sweeps = False


def parse(text):
    parser = _Strict()
    parser.feed(text)
    parser.close()
    return parser


def test_the_page_parses_and_has_one_row_per_sweep(results, page):
    parser = parse(page)
    assert parser.errors == [] and parser.stack == []
    assert parser.rows == len(results.sweeps) > 0


def test_every_table1_number_of_the_summary_is_on_the_page(results, page):
    groups = summary(results)["groups"]
    assert groups
    for g in groups:
        assert plus_minus(g["E_Pa"] / 1e9, g["E_err_Pa"] / 1e9) in page
        assert plus_minus(g["gamma_J_m2"] * 1e3, g["gamma_err_J_m2"] * 1e3) in page
    assert "example_sweeps.csv" in page and contactres.__version__ in page
    import hashlib

    assert hashlib.sha256(EXAMPLE.read_bytes()).hexdigest() in page


@pytest.fixture
def no_png(monkeypatch):
    """Pages whose figures are left out of the HTML (the figures are still drawn): encoding
    them is 80 % of a page's cost and nothing the test that takes this looks at (their
    embedding is checked on the full page by test_the_page_parses_and_has_one_row_per_sweep)."""
    from contactres.report import _html

    monkeypatch.setattr(_html, "_png", lambda figure, alt: "")


def test_the_checksum_is_the_one_taken_when_the_table_was_read(results, tmp_path, no_png):
    import dataclasses
    import hashlib

    data = EXAMPLE.read_bytes()
    copy = tmp_path / "sweeps.csv"
    copy.write_bytes(data)
    table = contactres.read_sweeps(copy)
    assert table.source_sha256 == hashlib.sha256(data).hexdigest()
    assert table.with_constants(poisson=0.25).source_sha256 == table.source_sha256
    copy.write_bytes(data + b"\n")  # changed after the analysis read it: the page keeps the old
    read = dataclasses.replace(results, table=table)
    assert table.source_sha256 in html_report(read)
    memory = contactres.validate_sweeps(table.data.drop(columns="line"))
    assert memory.source_sha256 is None


def test_a_file_that_changes_while_it_is_read_is_refused(tmp_path):
    """The hash is of the bytes parsed: a reader that sees other bytes than were hashed (here it
    appends to the file as it reads, as a writer still at work would) is refused."""
    import dataclasses

    from contactres.measurements.readers import BUILT_IN

    copy = tmp_path / "sweeps.csv"
    copy.write_bytes(EXAMPLE.read_bytes())
    csv = next(r for r in BUILT_IN.readers if r.kind == "sweeps" and ".csv" in r.suffixes)

    def load_while_written(path):
        frame = csv.load(path)
        with open(path, "ab") as f:
            f.write(b"\n")
        return frame

    growing = dataclasses.replace(csv, name="growing", load=load_while_written)
    with pytest.raises(ValueError, match="changed while it was read"):
        contactres.read_sweeps(copy, readers=BUILT_IN.with_reader(growing))


def test_the_csv_reader_hashes_the_bytes_it_parses_and_the_file_is_read_once(tmp_path, monkeypatch):
    """The delimited-text reader's checksum (attrs["sha256"]) is that of the file's bytes, its
    byte order mark included; read_sweeps takes it without reading the file again (issue 31:
    the 148 MB table of 10^5 sweeps was read three times)."""
    import hashlib

    from contactres.measurements import _checksum
    from contactres.measurements.readers import BUILT_IN

    data = b"\xef\xbb\xbf" + EXAMPLE.read_bytes()
    copy = tmp_path / "bom.csv"
    copy.write_bytes(data)
    csv = next(r for r in BUILT_IN.readers if r.kind == "sweeps" and ".csv" in r.suffixes)
    assert csv.load(copy).attrs["sha256"] == hashlib.sha256(data).hexdigest()

    def no_second_pass(path):
        raise AssertionError(f"{path} hashed again")

    # The only file_sha256 (read_sweeps no longer imports it; it holds the old second hash).
    monkeypatch.setattr(_checksum, "file_sha256", no_second_pass)
    from contactres.measurements import _sweeps

    assert not hasattr(_sweeps, "file_sha256")
    table = contactres.read_sweeps(copy)
    assert table.source_sha256 == hashlib.sha256(data).hexdigest()


def test_the_report_draws_the_curves_of_the_analysis_without_a_model(results, monkeypatch, no_png):
    # Every loop shape refuses to be evaluated: the page and Fig. 4 draw from Results.curves.
    # (no_png: the page's figures are still drawn, only their encoding is left out.)
    from contactres.analysis._models import cm_loop, plateau_loop, savkoor_loop
    from contactres.report.figures import figure_sweeps

    def refuse(*args, **kwargs):
        raise AssertionError("the report evaluated a loop model")

    for module, name in (
        (cm_loop, "cm_shape"),
        (cm_loop, "loop_shape"),
        (savkoor_loop, "savkoor_shape"),
        (plateau_loop, "loop_shape"),
    ):
        monkeypatch.setattr(module, name, refuse)
    page = html_report(results)
    assert page.count("<polyline") == 2 * len(results.sweeps)  # Δf and ΔΓ of every sweep
    assert figure_sweeps(results).axes


def test_the_page_is_self_contained_and_small(page):
    for link in ('src="http', "src='http", 'href="http', "href='http", "@import", "url("):
        assert link not in page
    assert len(page.encode()) < 2_000_000


def test_labels_are_escaped(results, no_png):
    sweeps = results.sweeps.assign(configuration="<script>alert(1)</script>")
    odd = type(results)(**{**results.__dict__, "sweeps": sweeps})
    text = html_report(odd)
    assert "<script>alert" not in text
    assert "&lt;script&gt;alert(1)&lt;/script&gt;" in text
    assert parse(text).errors == []


def test_write_html_is_atomic_and_leaves_no_temporary(results, page, tmp_path, monkeypatch):
    # The page of these results is the module's fixture: the renderer hands it over instead of
    # drawing its figures again (3 s), so what is tested is the writing, and that it writes
    # exactly html_report's page of the results it was given.
    from contactres.report import _html

    def rendered(given):
        assert given is results
        return page

    monkeypatch.setattr(_html, "html_report", rendered)
    path = write_html(results, tmp_path / "report.html")
    assert path.read_text(encoding="utf-8") == page and page.startswith("<!DOCTYPE html>")
    assert [p.name for p in tmp_path.iterdir()] == ["report.html"]


def run(*args):
    return CliRunner().invoke(main, ["qcm", "analyze", *map(str, args)])


def test_the_cli_writes_report_html_into_the_set(example_set, tmp_path):
    # example_set is the set `qcm analyze --report html --bootstrap 0 --no-figures` wrote
    manifest = json.loads((example_set / MANIFEST).read_text())
    assert "report.html" in manifest["files"]
    assert parse((example_set / "report.html").read_text(encoding="utf-8")).errors == []
    assert not [p for p in example_set.parent.iterdir() if p.name.startswith(".")]
    # a later run without --report drops the page of the earlier set (a copy of it: the
    # session's set is read by other tests)
    out = tmp_path / "o"
    shutil.copytree(example_set, out)
    r = run(EXAMPLE, "--out", out, "--bootstrap", "0", "--no-figures")
    assert r.exit_code == 0, r.output
    assert not (out / "report.html").exists()


def _flat(value, path=""):
    """The test's own walk of a JSON record: {dotted path: leaf}."""
    if isinstance(value, dict):
        return {
            k: v
            for key, item in value.items()
            for k, v in _flat(item, f"{path}.{key}".lstrip(".")).items()
        }
    if isinstance(value, list):
        return {
            k: v for i, item in enumerate(value) for k, v in _flat(item, f"{path}[{i}]").items()
        }
    return {path: value}


@pytest.fixture(scope="module")
def written(example_set):
    """The results set the command line writes for the example: (summary.json, report.html)."""
    out = example_set
    record = json.loads((out / "summary.json").read_text(encoding="utf-8"))
    return record, (out / "report.html").read_text(encoding="utf-8")


def test_the_page_holds_every_number_of_summary_json(written):
    record, page = written
    cells = dict(
        re.findall(r'<tr data-key="([^"]+)"><td><code>[^<]*</code></td><td>([^<]*)</td>', page)
    )
    numbers = {
        k: v
        for k, v in _flat(record).items()
        if isinstance(v, (int, float)) and not isinstance(v, bool)
    }
    assert len(numbers) > 50  # groups, settings, running-in ...
    for key, value in numbers.items():
        assert key in cells, key
        assert float(cells[key]) == pytest.approx(value, rel=1e-6, abs=1e-300), key


def test_errors_say_the_bootstrap_was_off(results):
    # The example has 4 experiments: with --bootstrap 0 the reason is the switch, not the data.
    methods = {g["error_method"] for g in summary(results)["groups"]}
    assert methods == {"fit residuals (Jacobian), bootstrap off (--bootstrap 0)"}


def test_unresolved_load_values_are_marked(example_set):
    """issue 30: μ(ΔΓ) = 2.9 ± 3.7 was shown without a mark. Every per-load mean whose standard
    deviation is at least its magnitude (counted here from loads.csv) carries the mark, and no
    other value does (the page's legend names the mark once more)."""
    import pandas as pd

    from contactres.report._html import UNRESOLVED_MARK

    loads = pd.read_csv(example_set / "loads.csv")
    expected = 0
    for q in ("kappa_N_per_m", "loss_tangent", "mu_df", "mu_dgamma", "mu_fit"):
        mean, sd = loads[f"{q}_mean"].to_numpy(float), loads[f"{q}_sd"].to_numpy(float)
        expected += int(np.sum(np.isfinite(mean) & (np.abs(mean) > 0) & (sd >= np.abs(mean))))
    page = (example_set / "report.html").read_text(encoding="utf-8")
    assert expected > 0  # the example has such values: the check bites
    assert page.count(UNRESOLVED_MARK) == expected + 1


def test_the_left_out_reasons_add_up_and_flags_of_used_sweeps_are_apart(results, page):
    """Each sweep left out is counted under one reason (its flags, read from sweeps, not from
    the page's code): the reasons add up to the sweeps left out; flags of used sweeps follow."""
    sw = results.sweeps
    used = sw["used"].to_numpy(bool)
    flags = contactres.analysis.render(sw["flags"].to_numpy())
    line = re.search(r"<p><b>(\d+) sweeps, (\d+) used; the (\d+) left out for: ([^;.]*)", page)
    assert line, page[:2000]
    total, n_used, left = (int(line[i]) for i in (1, 2, 3))
    assert (total, n_used, left) == (len(sw), int(used.sum()), int((~used).sum()))
    counts = {m[0].strip(): int(m[1]) for m in re.findall(r"([a-z ]+) (\d+)", line[4])}
    assert sum(counts.values()) == left
    first = sum("first-ramp" in f for f in flags[~used])
    assert counts.get("first ramp") == first > 0
    on_used = sorted({t for f in flags[used] for t in f.split(";") if t})
    if on_used:
        tail = page[line.end() :].split("</b>")[0]
        assert tail.startswith("; flags on used sweeps: ")
        assert all(
            f"{flag} {sum(flag in f.split(';') for f in flags[used])}" in tail for flag in on_used
        )


def test_the_classification_counts_the_models_of_the_used_sweeps_per_medium(results, page):
    used = results.sweeps[results.sweeps["used"]]
    section = page.split('id="classification"')[1].split("<h2")[0]
    rows = re.findall(r"<tr>(.*?)</tr>", section.split("<tbody>")[1])
    head = re.findall(r"<th>(.*?)</th>", section)
    assert head[0] == "medium" and head[-1] == "all models"
    for row in rows:
        cells = re.findall(r"<td[^>]*>(.*?)</td>", row)
        part = used[used["medium"] == cells[0]]
        for model, n in zip(head[1:-1], cells[1:-1], strict=True):
            assert int(n) == int((part["model"] == model).sum())
        assert int(cells[-1]) == len(part)
    assert len(rows) == used["medium"].nunique()


def test_the_stiffness_plot_says_it_draws_df0_in_hz(page):
    assert "<h3>Δf0 (Hz, proportional to the contact stiffness κ) against the normal" in page


def test_the_summary_record_shows_the_groups_in_readers_units(results, page):
    section = page.split('id="summary"')[1].split("<details>")[0]
    head = re.findall(r"<th>(.*?)</th>", section)
    assert head[:4] == ["configuration", "medium", "E (GPa)", "γ (mJ/m²)"]
    rows = re.findall(r"<tr>(.*?)</tr>", section.split("<tbody>")[1])
    assert len(rows) == len(results.groups)
    for row, g in zip(rows, results.groups, strict=True):
        cells = re.findall(r"<td[^>]*>(.*?)</td>", row)
        assert cells[:2] == [g["configuration"], g["medium"]]
        E, dE = (float(x) for x in cells[2].split(" ± "))
        gamma = float(cells[3].split(" ± ")[0])
        assert E == pytest.approx(g["E_Pa"] / 1e9, abs=dE / 10)
        assert gamma == pytest.approx(g["gamma_J_m2"] * 1e3, rel=0.05)
        assert float(cells[6]) == pytest.approx(g["sphere_radius_m"] * 1e3, rel=1e-3)
