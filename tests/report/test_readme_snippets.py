"""The README's code runs as written, so the text cannot drift from the package.

* The CR-AFM walkthrough (between ``<!-- walkthrough:afm -->`` and ``<!-- /walkthrough -->``):
  its blocks run in order in a temporary directory, the Python ones in-process, the shell
  command through the shell with the venv's ``contactres`` first on PATH; the files it writes
  must exist and M_sample be finite on the map. The summary line the README quotes must be the
  one the command prints.
* Every other ```python block of the README, in document order in one namespace (the blocks
  build on each other: ``cr``, ``np``, ``cu``), except :data:`SKIPPED`.
* ``scripts/make_readme_figures.py`` runs (in this process, as ``python`` runs a script) into a
  temporary path and prints the recovered moduli the README quotes.
"""

import os
import re
import runpy
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

ROOT = Path(__file__).resolve().parents[2]
README = ROOT / "README.md"
WALKTHROUGH = re.compile(r"<!-- walkthrough:afm -->\n(?P<body>.*?)<!-- /walkthrough -->", re.S)
FENCE = re.compile(r"^```(?P<lang>\w*)\n(?P<code>.*?)^```", re.S | re.M)
#: Python blocks not run here, each with its reason (a substring that identifies the block).
SKIPPED = {
    "cr.read_sweeps(": (
        "the QCM analysis of a user's sweeps.csv: ~8 s on the bundled example data, and "
        "tests/analysis and tests/cli cover cr.analyze and write_report"
    ),
}


def _text() -> str:
    return README.read_text(encoding="utf-8")


def _squash(s: str) -> str:
    return " ".join(s.split())


def _walkthrough() -> list[tuple[str, str]]:
    match = WALKTHROUGH.search(_text())
    assert match, "README: the CR-AFM walkthrough markers are missing"
    return [(m["lang"], m["code"]) for m in FENCE.finditer(match["body"])]


def _exec(code: str, namespace: dict, name: str) -> None:
    exec(compile(code, name, "exec"), namespace)


def _shell(line: str, cwd: Path) -> subprocess.CompletedProcess:
    """Run a README shell line as written, with this interpreter's scripts first on PATH."""
    env = dict(os.environ, MPLBACKEND="Agg")
    env["PATH"] = f"{Path(sys.executable).parent}{os.pathsep}{env.get('PATH', '')}"
    return subprocess.run(
        line, shell=True, cwd=cwd, env=env, capture_output=True, text=True, timeout=60
    )


@pytest.fixture
def agg(monkeypatch, tmp_path):
    """A temporary working directory and a non-interactive matplotlib."""
    import matplotlib

    matplotlib.use("Agg")
    monkeypatch.setenv("MPLBACKEND", "Agg")
    monkeypatch.chdir(tmp_path)
    yield tmp_path
    import matplotlib.pyplot as plt

    plt.close("all")


def test_walkthrough_runs_verbatim(agg):
    blocks = _walkthrough()
    assert [lang for lang, _ in blocks] == ["python", "bash", "python"]
    printed = []
    for i, (lang, code) in enumerate(blocks):
        if lang == "python":
            _exec(code, {"__name__": "__readme__"}, f"README.md walkthrough block {i + 1}")
            continue
        for line in code.splitlines():
            if line.strip() and not line.lstrip().startswith("#"):
                r = _shell(line, agg)
                assert r.returncode == 0, f"{line}\n{r.stdout}\n{r.stderr}"
                printed.append(r.stdout)
    for name in ("resonances.csv", "stiffness.csv", "modulus_map.png"):
        assert (agg / name).is_file(), name
    assert (agg / "modulus_map.png").stat().st_size > 5000
    out = pd.read_csv(agg / "stiffness.csv")
    m = out["M_sample_Pa"].to_numpy(float)
    assert len(out) == 64 * 64
    assert np.isfinite(m).mean() > 0.95
    assert 120e9 < np.nanmin(m) and np.nanmax(m) < 160e9  # Cu, between (001) and (111)
    # The summary line quoted in the README is the one the command prints.
    quoted = re.search(r"The command prints `(?P<line>[^`]+)`", _text(), re.S)
    assert quoted, "README: the quoted summary line of `contactres afm invert` is missing"
    assert _squash(quoted["line"]) in _squash(printed[0])


def test_other_python_blocks_run(agg):
    text = WALKTHROUGH.sub("", _text())
    blocks = [m["code"] for m in FENCE.finditer(text) if m["lang"] == "python"]
    run = [b for b in blocks if not any(key in b for key in SKIPPED)]
    assert len(blocks) - len(run) == len(SKIPPED), "a SKIPPED key no longer names one block"
    assert len(run) >= 4
    namespace = {"__name__": "__readme__"}
    for i, code in enumerate(run):
        _exec(code, namespace, f"README.md python block {i + 1} (outside the walkthrough)")


def test_figure_script_runs_and_matches_the_readme(tmp_path, monkeypatch, capsys):
    # Run as `python scripts/make_readme_figures.py OUT` runs it (argv, __main__), in this
    # process: a second interpreter's start-up and imports cost more than the script. Its
    # rcParams (font size) are restored after it, so no later figure here inherits them.
    import matplotlib

    out = tmp_path / "fig.png"
    script = ROOT / "scripts" / "make_readme_figures.py"
    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(sys, "argv", [str(script), str(out)])
    with matplotlib.rc_context():
        runpy.run_path(str(script), run_name="__main__")
    stdout = capsys.readouterr().out
    assert out.is_file() and out.stat().st_size > 20_000
    assert "](docs/figures/afm_walkthrough.png)" in _text()
    assert (ROOT / "docs" / "figures" / "afm_walkthrough.png").is_file()
    # "(001): M_sample 134.0 GPa (truth 134.0 GPa)" -> the README says "134.0 GPa (001)".
    found = re.findall(r"^(\(\d{3}\)): M_sample ([\d.]+) GPa", stdout, re.M)
    assert len(found) == 3, stdout
    text = _squash(_text())
    for label, value in found:
        assert f"{value} GPa {label}" in text, (label, value)
