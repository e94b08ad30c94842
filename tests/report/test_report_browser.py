"""The HTML report of the bundled example in a real browser (headless Chromium).

* The page loads with no console message at all (an error, a warning or a stray log line all
  fail: the report's script logs nothing) and a screenshot is saved.
* The sweep filter works in the browser: a probe script, appended to a copy of the report, picks
  a configuration in the filter and the count of rows shown must equal the number of sweeps of
  that configuration in ``sweeps.csv``, which the test reads itself.
* The figures decode and the table of contents leads to its sections: a second probe in the
  same copy (one browser run serves both probes: ~1.5 s of a browser start saved).
* A control page with a deliberate ``console.error`` must be caught, so the console check
  cannot pass by reading nothing.

Chromium is found as ``$CONTACTRES_BROWSER`` or ``chromium``, ``chromium-browser``,
``google-chrome`` on PATH; without one the tests are skipped with that reason, except under CI
(``CI=true``), where ``.ci/run`` installs Chromium and a missing browser is a failure. The
screenshot goes to ``$CONTACTRES_ARTIFACTS`` (default: the test's temporary folder) and its path is
printed.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
from html import unescape
from pathlib import Path

import pandas as pd
import pytest

BROWSERS = ("chromium", "chromium-browser", "google-chrome")
#: Chromium writes every console message of the page to stderr as ``...:CONSOLE:<line>] "<text>"``.
CONSOLE = re.compile(r":CONSOLE(?::|\()\d+\)?\] (?P<text>.*)")


def _browser() -> str | None:
    named = os.environ.get("CONTACTRES_BROWSER")
    if named:
        return shutil.which(named) or named
    return next((path for b in BROWSERS if (path := shutil.which(b))), None)


@pytest.fixture(scope="module")
def browser() -> str:
    path = _browser()
    if path is None:
        if os.environ.get("CI") == "true":
            pytest.fail("CI: no Chromium found; .ci/run must install it (apt-get install chromium)")
        pytest.skip("no headless browser: install Chromium (apt-get install chromium) to run it")
    return path


def _run(browser: str, page: Path, profile: Path, *args: str) -> subprocess.CompletedProcess:
    """Open ``page`` in headless Chromium with console logging on stderr."""
    command = [
        browser,
        "--headless",
        "--no-sandbox",  # CI runs as root, where Chromium's sandbox refuses to start
        "--disable-gpu",
        "--no-first-run",
        f"--user-data-dir={profile}",
        "--enable-logging=stderr",
        "--v=0",
        *args,
        page.as_uri(),
    ]
    return subprocess.run(command, capture_output=True, text=True, timeout=120, check=False)


def _console(stderr: str) -> list[str]:
    return [m["text"] for m in CONSOLE.finditer(stderr)]


@pytest.fixture(scope="module")
def report(example_set) -> Path:
    """The results folder of the bundled example, with report.html (tests/report/conftest.py)."""
    return example_set


def test_the_report_loads_without_console_messages_and_is_screenshot(browser, report, tmp_path):
    shots = Path(os.environ.get("CONTACTRES_ARTIFACTS", tmp_path))
    shots.mkdir(parents=True, exist_ok=True)
    shot = shots / "report.png"
    done = _run(
        browser,
        report / "report.html",
        tmp_path / "profile",
        f"--screenshot={shot}",
        "--window-size=1280,1600",
    )
    assert done.returncode == 0, done.stderr[-2000:]
    assert _console(done.stderr) == []
    assert shot.exists() and shot.stat().st_size > 10_000  # a rendered page, not a blank
    print(f"screenshot: {shot}")


def _least_configuration(report: Path) -> tuple[str, int]:
    """The configuration with the fewest sweeps in ``sweeps.csv`` and its count (the test's own
    reading of the table, not the page's)."""
    sweeps = pd.read_csv(report / "sweeps.csv")
    configuration = sweeps["configuration"].astype(str).value_counts().index[-1]
    expected = int((sweeps["configuration"].astype(str) == configuration).sum())
    assert 0 < expected < len(sweeps)  # the filter must hide something for the check to bite
    return configuration, expected


def _filter_probe(configuration: str) -> str:
    """Picks ``configuration`` in the filter; writes the rows shown and the page's count of
    them into ``data-filter-probe`` (or the error it met, caught as in :data:`PLOTS_PROBE`)."""
    return (
        "<script>window.addEventListener('load',function(){try{"
        "var s=document.querySelector('.filters select[name=configuration]');"
        f"s.value={configuration!r};s.dispatchEvent(new Event('change'));"
        "var n=0;document.querySelectorAll('#sweeps tbody tr').forEach(function(r){"
        "if(getComputedStyle(r).display!=='none')n++;});"
        "document.body.setAttribute('data-filter-probe',n+'/'+document.getElementById('shown')"
        ".textContent);}catch(e){document.body.setAttribute('data-filter-probe','error '+e);}"
        "});</script>"
    )


#: Writes into ``data-plots-probe`` the images the browser decoded (natural width > 200), the
#: images, the table of contents' links that lead to a section, and its links (or the error
#: it met: caught, so that it neither stops the other probe nor fails that one's console check).
PLOTS_PROBE = (
    "<script>window.addEventListener('load',function(){try{"
    "var im=[].slice.call(document.querySelectorAll('img.plot'));"
    "var ok=im.filter(function(i){return i.complete&&i.naturalWidth>200;}).length;"
    "var links=[].slice.call(document.querySelectorAll('nav a'));"
    "var found=links.filter(function(a){return document.getElementById("
    "a.getAttribute('href').slice(1));}).length;"
    "document.body.setAttribute('data-plots-probe',ok+'/'+im.length+'/'+found+'/'+links.length);"
    "}catch(e){document.body.setAttribute('data-plots-probe','error '+e);}});</script>"
)


@pytest.fixture(scope="module")
def probed(browser, report, tmp_path_factory) -> subprocess.CompletedProcess:
    """A copy of the report with both probes appended (the filter's and the plots'), opened
    once with ``--dump-dom``: each probe writes its own attribute, and neither reads what the
    other changes (the filter hides table rows; the plots probe counts images and links)."""
    configuration, _ = _least_configuration(report)
    folder = tmp_path_factory.mktemp("probe")
    page = folder / "probe.html"
    html = (report / "report.html").read_text(encoding="utf-8")
    probes = _filter_probe(configuration) + PLOTS_PROBE
    page.write_text(html.replace("</body>", probes + "</body>"), encoding="utf-8")
    return _run(browser, page, folder / "profile", "--dump-dom")


def _probe_text(dom: str, name: str) -> str:
    """What probe ``name`` wrote (its error), or the start of the page if it wrote nothing."""
    found = re.search(rf'{name}="([^"]*)"', dom)
    return unescape(found[1]) if found else "it did not run: " + unescape(dom[:300])


def test_the_sweep_filter_works_in_the_browser(probed, report):
    _, expected = _least_configuration(report)
    assert _console(probed.stderr) == []
    match = re.search(r'data-filter-probe="(\d+)/(\d+)"', probed.stdout)
    assert match, "the probe failed: " + _probe_text(probed.stdout, "data-filter-probe")
    assert (int(match[1]), int(match[2])) == (expected, expected)


def test_a_console_error_is_caught(browser, tmp_path):
    page = tmp_path / "control.html"
    page.write_text("<html><body><script>console.error('boom')</script></body></html>")
    done = _run(browser, page, tmp_path / "profile", "--dump-dom")
    assert any("boom" in text for text in _console(done.stderr))


def test_the_result_plots_and_the_counts_show_in_the_browser(probed, report):
    """issue 30: the page shows κ(F_N) with the JKR fits and their bands (and Figs. 7, 8, and
    the classification's figure) as images the browser decodes (natural width > 0), a table of
    contents whose links all lead to a section, and the line of sweeps used and left out, equal
    to sweeps.csv's counts."""
    sweeps = pd.read_csv(report / "sweeps.csv")
    html = (report / "report.html").read_text(encoding="utf-8")
    assert _console(probed.stderr) == []
    match = re.search(r'data-plots-probe="(\d+)/(\d+)/(\d+)/(\d+)"', probed.stdout)
    assert match, "the probe failed: " + _probe_text(probed.stdout, "data-plots-probe")
    images, shown, links, found = int(match[2]), int(match[1]), int(match[4]), int(match[3])
    # Figs. 5, 7, 8 and the classification's figure (the model classes per group and load)
    assert images == 4 and shown == 4 and links >= 9 and found == links
    assert "Δf0 (Hz, proportional to the contact stiffness κ) against the normal force" in html
    assert "with the JKR fits and their 95 % bands" in html
    assert 'alt="The model class of the used sweeps per configuration, medium and load"' in html
    used = int(sweeps["used"].sum())
    assert f"{len(sweeps)} sweeps, {used} used; the {len(sweeps) - used} left out" in html
