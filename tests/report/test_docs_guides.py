"""The user guides' code runs as written, so the pages cannot drift from the package.

For each page (``docs/getting-started.md``, every ``docs/guide/*.md`` and the developer page
``docs/developer/adding.md``) the fenced blocks run in document order in one temporary working
directory:

* every ```python block, all blocks of a page in one namespace (they build on each other),
  except those named in :data:`SKIPPED`;
* every line of a ```console or ```bash block that starts with ``contactres ``: split like a
  shell would (``shlex``) and run through ``contactres.cli:main``, the entry point the venv's
  ``contactres`` script calls, in this process; it must exit with status 0. In-process, because
  ~25 command lines each paying the interpreter's and the libraries' start-up (~1 s of CPU)
  would not fit this file's time budget; :func:`test_the_script_on_path_runs` checks once that
  the installed script itself runs.

The pages use the example files as an installed user has them: a page's first command that reads
one is preceded by ``contactres examples --copy .``, which copies them into the (empty) temporary
directory; no repository path is reachable from there, so a page that names one fails. Every
file a page writes lands in the temporary directory. Python blocks and
commands share that directory, so a command may read a file an earlier block wrote.
"""

import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
DOCS = ROOT / "docs"
PAGES = [
    DOCS / "getting-started.md",
    *sorted((DOCS / "guide").glob("*.md")),
    DOCS / "developer" / "adding.md",
]
EXPECTED = ["getting-started.md", "developer/adding.md"] + [
    f"guide/{name}.md"
    for name in (
        "qcm-sweeps",
        "spectra",
        "particles",
        "anisotropic-contact",
        "dynamic-stiffness",
        "cr-afm-rum",
        "cr-afm-maps",
    )
]
FENCE = re.compile(r"^```(?P<lang>\w*)\n(?P<code>.*?)^```", re.S | re.M)
SHELL_LANGS = {"console", "bash"}
#: Python blocks or command lines not run here, each with its reason (a substring that
#: identifies it).
SKIPPED = {
    "example_sweeps.csv --out qcm-results --report html": (
        "the full example analysis with figures and report (~13 s); tests/cli/test_cli_help.py "
        "and tests/report/test_html_report.py run it"
    ),
    "contactres figures paper1": "~20 s; tests/cli/test_cli_dcsf.py runs the command",
    "--values example_cu_kstar.csv --out example_fit.json": (
        "the fit of the bundled map (~2.5 s); tests/cli/test_cli_examples.py runs this command "
        "line (the listed command of example_cu_kstar.csv, another --out) from a folder of the "
        "copies"
    ),
}


def _blocks(page: Path) -> list[tuple[str, str]]:
    return [(m["lang"], m["code"]) for m in FENCE.finditer(page.read_text(encoding="utf-8"))]


def _commands(code: str) -> list[str]:
    return [line.strip() for line in code.splitlines() if line.strip().startswith("contactres ")]


def _skipped(code: str) -> bool:
    return any(key in code for key in SKIPPED)


def _env() -> dict:
    env = dict(os.environ, MPLBACKEND="Agg")
    env["PATH"] = f"{Path(sys.executable).parent}{os.pathsep}{env.get('PATH', '')}"
    return env


def _cli(line: str) -> int:
    """Run one command line through the ``contactres`` entry point; its exit status."""
    from contactres.cli import main

    args = shlex.split(line, comments=True)  # a shell ignores a trailing "# ..."
    assert args[0] == "contactres", line
    try:
        main(args[1:], prog_name="contactres")
    except SystemExit as exc:
        code = exc.code
        return code if isinstance(code, int) else (0 if code is None else 1)
    return 0


def run_page(page: Path) -> int:
    """Run the code of ``page`` in the current directory; the number of blocks and lines run.

    Raises on the first block that raises, AssertionError on a command exiting non-zero.
    """
    namespace = {"__name__": "__docs__"}
    ran = 0
    for i, (lang, code) in enumerate(_blocks(page)):
        if lang == "python" and not _skipped(code):
            exec(compile(code, f"{page.name}, block {i + 1}", "exec"), namespace)
            ran += 1
        elif lang in SHELL_LANGS:
            for line in _commands(code):
                if not _skipped(line):
                    status = _cli(line)
                    assert status == 0, f"{page.name}: exit status {status}: {line}"
                    ran += 1
    return ran


@pytest.fixture
def workdir(monkeypatch, tmp_path):
    """An empty temporary working directory and a non-interactive matplotlib."""
    import matplotlib

    matplotlib.use("Agg")
    monkeypatch.setenv("MPLBACKEND", "Agg")
    monkeypatch.delenv("CONTACTRES_DEBUG", raising=False)
    monkeypatch.chdir(tmp_path)
    yield tmp_path
    import matplotlib.pyplot as plt

    plt.close("all")


def test_every_page_exists_and_has_code():
    names = [p.relative_to(DOCS).as_posix() for p in PAGES]
    assert set(EXPECTED) <= set(names), set(EXPECTED) - set(names)
    for page in PAGES:
        langs = {lang for lang, _ in _blocks(page)}
        assert "python" in langs and SHELL_LANGS & langs, page


def test_skipped_keys_name_something():
    texts = [code for page in PAGES for _, code in _blocks(page)]
    for key in SKIPPED:
        assert sum(key in code for code in texts) == 1, f"SKIPPED key {key!r}: not one block"


def test_the_skipped_map_fit_is_the_listed_command_tested_elsewhere():
    """The guide's ``maps fit`` line is skipped because tests/cli/test_cli_examples.py runs the
    listed command of example_cu_kstar.csv: it must stay that command but for its --out."""
    import shlex

    from contactres.examples import EXAMPLES

    def without_out(words):
        i = words.index("--out")
        return words[:i] + words[i + 2 :]

    key = "--values example_cu_kstar.csv --out example_fit.json"
    lines = [
        line
        for page in PAGES
        for _, code in _blocks(page)
        for line in code.splitlines()
        if key in line
    ]
    assert len(lines) == 1, lines
    listed = shlex.split(EXAMPLES["example_cu_kstar.csv"].command)
    assert without_out(shlex.split(lines[0])) == without_out(listed)


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.relative_to(DOCS).as_posix())
def test_page_code_runs(page, workdir):
    assert run_page(page) > 0, f"{page.name}: nothing ran"


def test_a_failing_block_fails(workdir):
    """The runner can fail: a raising block raises, a failing command is an assertion."""
    bad = workdir / "bad.md"
    bad.write_text("```python\nraise RuntimeError('boom')\n```\n", encoding="utf-8")
    with pytest.raises(RuntimeError, match="boom"):
        run_page(bad)
    bad.write_text("```console\ncontactres contact --radius 1e-3\n```\n", encoding="utf-8")
    with pytest.raises(AssertionError, match="exit status 2"):
        run_page(bad)


def test_the_script_on_path_runs(tmp_path):
    """The ``contactres`` the pages' readers type: the venv's script, first on PATH."""
    r = subprocess.run(
        "contactres --help", shell=True, cwd=tmp_path, env=_env(), capture_output=True, text=True,
        timeout=60,
    )  # fmt: skip
    assert r.returncode == 0, r.stderr
    assert "qcm" in r.stdout and "afm" in r.stdout
