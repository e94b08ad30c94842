"""Start-up stays light: ``import contactres`` and the CLI's help do not import heavy libraries.

No wall-clock time is measured here (benchmarks/bench_startup.py does that). Instead every check
runs a fresh interpreter and asserts that pandas, scipy and matplotlib (0.5-2 s of the old
start-up) were never imported. A watcher on ``sys.meta_path`` records, for the first import of
each heavy package, the contactres frames that led to it, so a failure names the culprit line.

Also here: the lazy public API of ``contactres/__init__.py`` (PEP 562) still behaves like eager
imports (every name resolves, ``dir``, ``from contactres import *``, subpackages, errors).
"""

from __future__ import annotations

import ast
import importlib
import importlib.metadata
import json
import subprocess
import sys
import textwrap
from pathlib import Path

import click
import pytest

import contactres as cr

HEAVY = ("pandas", "scipy", "matplotlib")

# Module-level library imports the CLI may make (file -> imported module), with why. Each must
# stay light: the test below fails if building the help pulls in pandas, scipy or matplotlib.
ALLOWED_CLI_IMPORTS: dict[tuple[str, str], str] = {}

# Library modules any CLI module may import at top level, with why.
ALLOWED_IN_EVERY_CLI_MODULE: dict[str, str] = {
    "..errors": (
        "contactres.errors imports nothing (one exception class): the CLI raises and catches "
        "ContactresInputError"
    ),
}

CLI_DIR = Path(cr.__file__).parent / "cli"

# Runs in a fresh interpreter: argv[1] = JSON list of watched packages, argv[2] = code to run.
# Prints one JSON object: the first import route of each watched package, the exit code and
# the captured standard output of the code.
PROBE = textwrap.dedent(
    """
    import contextlib, io, json, sys, traceback

    watched = set(json.loads(sys.argv[1]))
    routes = {name: ["(imported at interpreter start)"] for name in watched & set(sys.modules)}

    class Watcher:
        def find_spec(self, fullname, path=None, target=None):
            # A watched name is a package (all its modules) or a module of one ("scipy.optimize").
            parts = fullname.split(".")
            names = (".".join(parts[:i]) for i in range(1, len(parts) + 1))
            top = next((n for n in names if n in watched), None)
            if top is not None and top not in routes:
                routes[top] = [
                    f"{f.filename.replace(chr(92), '/').split('/src/')[-1]}:{f.lineno}"
                    for f in traceback.extract_stack()[:-1]
                    if "contactres" in f.filename
                ] or ["(outside contactres)"]
            return None  # only watch: the normal finders do the import

    sys.meta_path.insert(0, Watcher())
    out = io.StringIO()
    code = 0
    with contextlib.redirect_stdout(out):
        try:
            exec(sys.argv[2], {"__name__": "__probe__"})
        except SystemExit as exc:
            code = exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 1)
    print(json.dumps({"routes": routes, "exit": code, "stdout": out.getvalue()}))
    """
)


def probe(code: str, watched: tuple[str, ...] = HEAVY) -> dict:
    """Run ``code`` in a fresh interpreter; return the import routes of ``watched`` and more."""
    p = subprocess.run(
        [sys.executable, "-c", PROBE, json.dumps(list(watched)), code],
        capture_output=True,
        text=True,
        check=False,
    )
    assert p.returncode == 0, f"probe crashed:\n{p.stderr}"
    return json.loads(p.stdout.splitlines()[-1])


def run_cli(args: list[str]) -> str:
    """Code that runs ``python -m contactres ARGS`` inside the probe."""
    return (
        "import runpy, sys\n"
        f"sys.argv = ['contactres', *{args!r}]\n"
        "runpy.run_module('contactres', run_name='__main__', alter_sys=True)\n"
    )


def check_light(result: dict) -> None:
    """Fail on a heavy import, naming the route by which it came in."""
    routes = result["routes"]
    assert not routes, "heavy imports at start-up:\n" + "\n".join(
        f"  {name}: via {' -> '.join(r)}" for name, r in routes.items()
    )


# Every command and group of the CLI, as argument lists (``[]`` is the root group). Written out
# rather than read from the click tree so that collecting this file never imports the library;
# test_cli_command_list_is_complete keeps the list in step with the tree.
CLI_COMMANDS: list[list[str]] = [
    [],
    ["afm"],
    ["afm", "invert"],
    ["afm", "map"],
    ["contact"],
    ["crystals"],
    ["dcsf"],
    ["demo"],
    ["examples"],
    ["figures"],
    ["figures", "paper1"],
    ["figures", "paper2"],
    ["maps"],
    ["maps", "fit"],
    ["maps", "predict"],
    ["maps", "synthetic"],
    ["qcm"],
    ["qcm", "analyze"],
    ["qcm", "loop"],
    ["qcm", "particles"],
    ["qcm", "spectra"],
    ["qcm", "stiffness"],
    ["rum"],
    ["rum", "invert"],
]


# --- the probe itself -------------------------------------------------------------------------


def test_probe_sees_an_import_and_its_route():
    """The watcher is not blind: it reports a watched import and the exit code."""
    result = probe("import json\nraise SystemExit(3)", watched=("json",))
    # json may already be loaded by the probe itself; either way it must be reported.
    assert "json" in result["routes"]
    assert result["exit"] == 3
    result = probe("import contactres.validation", watched=("numpy",))
    assert any("contactres/validation.py" in r for r in result["routes"]["numpy"])


def test_probe_route_names_the_contactres_lines():
    result = probe(run_cli(["crystals", "--format", "csv"]))
    assert result["exit"] == 0 and result["stdout"].startswith("name,")
    # Running a command may import pandas; the route must point into contactres.
    assert any(r.startswith("contactres/") for r in result["routes"]["pandas"])


# --- start-up ---------------------------------------------------------------------------------


def test_cli_modules_import_no_library_module_at_top_level():
    """Building the click tree runs only click, the standard library and the CLI's own modules.

    A static guard beside the probes: while a pending route exists, a probe sees only the first
    import of each heavy package, and this check still pins every module-level import of cli/.
    """
    allowed_top = {"click", *sys.stdlib_module_names}
    offenders = []
    for path in sorted(CLI_DIR.glob("*.py")):
        tree = ast.parse(path.read_text(encoding="utf-8"))
        for node in tree.body:  # module level; `if TYPE_CHECKING:` blocks never run
            if isinstance(node, ast.Import):
                names = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom):
                names = ["." * node.level + (node.module or "")]
            else:
                continue
            for name in names:
                if name.startswith(".") and not name.startswith(".."):
                    continue  # the CLI's own modules
                if name.partition(".")[0] in allowed_top or name == "__future__":
                    continue
                if (path.name, name) in ALLOWED_CLI_IMPORTS or name in ALLOWED_IN_EVERY_CLI_MODULE:
                    continue
                offenders.append(f"cli/{path.name}:{node.lineno}: {ast.unparse(node)}")
    assert not offenders, "module-level library imports in the CLI:\n" + "\n".join(offenders)


def test_import_contactres_imports_no_heavy_library():
    check_light(probe("import contactres"))


def test_import_contactres_imports_nothing_of_the_library():
    """The root package defers everything, even numpy, until a name is used."""
    result = probe("import contactres", watched=("numpy", "click"))
    assert result["routes"] == {}


def test_touching_analyze_imports_no_heavy_library():
    """The first real use of the analysis, ``contactres.analyze`` and its settings, loads
    neither pandas nor scipy (nor numpy): the steps and their libraries come with the first call
    (issue 31). The name is still the function itself, not a stand-in."""
    code = (
        "import contactres\n"
        "f = contactres.analyze\n"
        "contactres.AnalysisSettings(bootstrap=0)\n"
        "print(f.__module__, f.__name__)\n"
    )
    result = probe(code, watched=(*HEAVY, "numpy"))
    check_light(result)
    assert result["stdout"].split() == ["contactres.analysis._pipeline", "analyze"]


# The first call of the analysis, as benchmarks/bench_startup.py times it: it imports the steps
# and their libraries, then refuses None before any work.
FIRST_CALL = (
    "import sys\n"
    "import contactres\n"
    "try:\n"
    "    contactres.analyze(None)\n"
    "except TypeError:\n"
    "    print('contactres.analysis._steps' in sys.modules)\n"
)


def test_probe_sees_a_module_of_a_package():
    """A watched dotted name is reported (the pins below rely on it), and only its own modules:
    numpy's import (which imports numpy.linalg) does not count as numpy.f2py's."""
    result = probe("import numpy", watched=("numpy.linalg", "numpy.f2py"))
    assert set(result["routes"]) == {"numpy.linalg"}
    result = probe("import numpy.f2py", watched=("numpy.linalg", "numpy.f2py"))
    assert set(result["routes"]) == {"numpy.linalg", "numpy.f2py"}


def test_the_first_call_of_analyze_imports_only_what_every_analysis_needs():
    """issue 31: the first call imports the steps of every analysis (numpy and pandas) and
    nothing that only some runs use: no figures (matplotlib), no scipy (the drift test's F
    distribution, the JKR fit's t quantile and the series of the tangential loops are numpy
    alone, the JKR fit uses the package's own Levenberg-Marquardt), no process pool (workers
    > 1), no HTML escaping (a notebook's view), none of the file readers (read_sweeps), the
    report, the coated plate, the radiation or the particles."""
    watched = (
        "matplotlib",
        "scipy",
        "numpy.testing",
        "concurrent.futures.process",
        "multiprocessing",
        "html",
        "contactres.measurements.readers",
        "contactres.report",
        "contactres.analysis._coating",
        "contactres.analysis._radiation",
        "contactres.analysis._particles",
    )
    result = probe(FIRST_CALL, watched=watched)
    assert result["stdout"] == "True\n"  # the steps were imported: the pin is not vacuous
    check_light(result)
    result = probe(FIRST_CALL, watched=("pandas",))
    assert set(result["routes"]) == {"pandas"}


# The README's first analysis: the bundled example read and analysed (bootstrap and all).
FIRST_ANALYSIS = (
    "from importlib.resources import files\n"
    "import contactres as cr\n"
    "table = cr.read_sweeps(str(files('contactres.data').joinpath('example_sweeps.csv')))\n"
    "res = cr.analyze(table)\n"
    "print(len(res.table1()))\n"
)


def test_a_real_first_analysis_imports_neither_scipy_special_nor_optimize():
    """issue 31, point 3: a real first analysis (the README's snippet on the bundled example:
    drift tests, JKR fits with their bootstrap, Table 1) pays neither scipy.special (0.2-0.4 s
    of CPU: its array-API layer brings numpy.testing) nor scipy.optimize (with scipy.linalg,
    sparse, spatial, fft and constants, ~0.3 s more). The distribution functions are in
    contactres.analysis._distributions and the fits use the package's Levenberg-Marquardt."""
    pulled = ("linalg", "sparse", "spatial", "fft", "constants", "stats")
    watched = ("scipy.special", "scipy.optimize", *(f"scipy.{m}" for m in pulled))
    result = probe(FIRST_ANALYSIS, watched=(*watched, "numpy.testing"))
    assert result["stdout"] == "4\n"  # Table 1 of the example's four groups: the pin has run
    check_light(result)


def test_a_static_contact_imports_no_scipy(tmp_path, monkeypatch):
    """issue 31: the Hertz contact on a bare face needs numpy and pandas only; scipy.special
    came in with the Gauss-Legendre rule of contactres.numerics and the coated solve's
    gammaln, both imported with sphere_contact (~0.2 s of CPU)."""
    monkeypatch.chdir(tmp_path)
    args = ["contact", "--crystal", "Cu", "--radius", "1e-3", "--force", "1"]
    result = probe(run_cli(args), watched=("scipy", "matplotlib"))
    assert result["exit"] == 0 and "contact_radius_m" in result["stdout"]
    check_light(result)


def test_the_readers_registry_of_the_jobs_imports_no_scipy():
    """issue 31: the registry of every reader (an AFM map job picks its file's reader from it)
    holds the EBSD readers, whose orientations need scipy's Rotation only when a map is read
    (scipy.spatial with scipy.sparse and scipy.linalg, ~0.25 s of CPU)."""
    code = (
        "from contactres.jobs.readers import ALL_READERS\nprint(len(ALL_READERS.of_kind('ebsd')))"
    )
    result = probe(code, watched=("scipy", "matplotlib"))
    assert result["stdout"] == "3\n"
    check_light(result)


@pytest.mark.parametrize("args", CLI_COMMANDS, ids=lambda a: " ".join(a) or "(root)")
def test_cli_help_imports_no_heavy_library(args):
    result = probe(run_cli([*args, "--help"]))
    assert result["exit"] == 0 and "Usage:" in result["stdout"]
    check_light(result)


def test_cli_command_list_is_complete():
    from contactres.cli import main

    found: list[list[str]] = []

    def walk(command: click.Command, path: list[str]) -> None:
        found.append(path)
        if isinstance(command, click.Group):
            for name, sub in sorted(command.commands.items()):
                walk(sub, [*path, name])

    walk(main, [])
    assert sorted(found) == sorted(CLI_COMMANDS), "update CLI_COMMANDS to the click tree"


def test_bare_cli_and_version_import_no_heavy_library():
    result = probe(run_cli([]))
    assert result["exit"] == 0 and "Usage:" in result["stdout"]
    check_light(result)
    result = probe(run_cli(["--version"]))
    assert result["exit"] == 0
    assert result["stdout"].strip() == f"contactres, version {cr.__version__}"
    check_light(result)


# --- the lazy public API ----------------------------------------------------------------------


def test_every_public_name_resolves_and_is_listed():
    missing = [name for name in cr.__all__ if not hasattr(cr, name)]
    assert not missing, f"names in contactres.__all__ that do not resolve: {missing}"
    assert set(cr.__all__) <= set(dir(cr))
    assert len(set(cr.__all__)) == len(cr.__all__)


def test_public_names_are_the_objects_of_their_modules():
    """``cr.X`` is the very object of the module the mapping names (no copies, no wrappers)."""
    for name, module in cr._EXPORTS.items():
        assert getattr(cr, name) is getattr(importlib.import_module(module, "contactres"), name)
    assert set(cr.__all__) == {*cr._EXPORTS, "__version__"}


def test_star_import_gives_every_public_name():
    namespace: dict = {}
    exec("from contactres import *", namespace)
    assert set(cr.__all__) <= set(namespace)
    assert namespace["hertz"] is cr.hertz


def test_unknown_name_raises_the_usual_errors():
    with pytest.raises(AttributeError, match=r"^module 'contactres' has no attribute 'nope'$"):
        cr.nope  # noqa: B018
    with pytest.raises(ImportError, match="cannot import name 'nope'"):
        exec("from contactres import nope", {})


def test_version_is_the_installed_one():
    assert cr.__version__ == importlib.metadata.version("contactres")


def test_subpackages_load_on_attribute_access_in_a_fresh_interpreter():
    """``cr.dynamic.dcsf`` works without importing ``contactres.dynamic`` first."""
    code = textwrap.dedent(
        """
        import sys
        import contactres as cr

        subpackages = ["resonators", "measurements", "tangential", "normal", "dynamic",
                       "analysis", "report"]
        assert not any(f"contactres.{s}" in sys.modules for s in subpackages)
        for s in subpackages:  # the first accesses go through contactres.__getattr__
            assert getattr(cr, s).__name__ == f"contactres.{s}", s
        assert cr.dynamic.dcsf is cr.dcsf
        assert cr.normal.hertz is cr.hertz
        assert cr.tangential.VoigtLoop is cr.VoigtLoop
        assert callable(cr.analysis.analyze)
        assert {"dynamic", "analysis", "report"} <= set(dir(cr))
        for name in cr.__all__:
            getattr(cr, name)
        assert "contactres.cli" not in sys.modules, "the library imported the CLI"
        print("ok")
        """
    )
    result = probe(code)
    assert result["exit"] == 0 and result["stdout"] == "ok\n"


def test_the_dcsf_choices_are_the_librarys_names():
    """``contactres dcsf`` writes its --model and --wavenumber choices out (so that building the
    command tree imports nothing of contactres.dynamic): they must be the library's names."""
    from contactres.cli import dcsf
    from contactres.dynamic import MODELS, WAVENUMBERS

    assert dcsf.MODEL_CHOICES == MODELS
    assert dcsf.WAVENUMBER_CHOICES == WAVENUMBERS


# Every command that reads an input file, with a path that does not exist (and its required
# options): the check is click's, made while parsing, before any library import.
MISSING_INPUT: list[list[str]] = [
    ["qcm", "analyze", "nosuch.csv", "--out", "nosuch-out"],
    ["qcm", "spectra", "nosuch.csv", "--out", "nosuch.csv.out"],
    ["qcm", "particles", "nosuch.csv", "--out", "nosuch-out"],
    ["qcm", "stiffness", "nosuch.csv", "--out", "nosuch-out"],
    ["afm", "invert", "nosuch.csv", "--out", "nosuch-out.csv"],
    ["afm", "map", "nosuch.ibw", "--out", "nosuch-out"],
    ["rum", "invert", "nosuch.csv", "--out", "nosuch-out.csv"],
    ["maps", "predict", "nosuch.zarr", "--out", "nosuch-out.zarr"],
    ["maps", "fit", "nosuch.zarr", "--out", "nosuch-out.json"],
]


@pytest.mark.parametrize("args", MISSING_INPUT, ids=lambda a: " ".join(a[:2]))
def test_a_missing_input_file_is_refused_before_any_heavy_import(args, tmp_path, monkeypatch):
    """issue 30: ``qcm analyze nosuch.csv`` imported scipy (1.4 s of CPU) before saying so."""
    monkeypatch.chdir(tmp_path)
    result = probe(run_cli(args))
    assert result["exit"] == 2
    check_light(result)
    assert not any(tmp_path.iterdir())  # no output folder made either


def test_a_static_afm_invert_imports_neither_scipy_nor_matplotlib(tmp_path, monkeypatch):
    """issue 31, point 5: ``afm invert`` of a table without ``--crystal`` needs numpy and pandas
    only; scipy came in through the dynamic correction's imports (scipy.special with the kernel
    tables, scipy.interpolate and scipy.optimize with the DCSF curve: ~0.5 s of CPU)."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "t.csv").write_text(
        "f1_free_Hz,k_c_N_per_m,tip_position,fc1_Hz,tip_radius_m,load_N,M_tip_Pa\n"
        "160000,40,0.95,250000,5e-08,1e-06,1.65e11\n"
    )
    result = probe(
        run_cli(["afm", "invert", "t.csv", "--out", "o.csv"]), watched=("scipy", "matplotlib")
    )
    assert result["exit"] == 0
    check_light(result)
    assert (tmp_path / "o.csv").read_text().count("\n") == 2


def test_an_afm_invert_from_archive_to_archive_imports_no_pandas(tmp_path, monkeypatch):
    """issue 31, point 5: a map read from a numpy archive and written to one is held as numpy
    columns from file to file; pandas' import was a third of the CPU time of a 512² map. Nor
    numpy.ma (np.median's check for masked arrays, in the summary's median) nor secrets (a
    temporary file's name): ~25 ms of CPU together, of a command held to 1 s. Nor the readers
    of other inputs than resonance tables (instrument exports, AFM map files: ~2 % of it), nor
    the materials (crystals, half-space kernels: ~1 %): the moduli of the table are numbers."""
    import numpy as np

    monkeypatch.chdir(tmp_path)
    columns = {
        "f1_free_Hz": [160000.0, 160000.0],
        "k_c_N_per_m": [40.0, 40.0],
        "tip_position": [0.95, 0.95],
        "fc1_Hz": [250000.0, 260000.0],
        "tip_radius_m": [5e-08, 5e-08],
        "load_N": [1e-06, 1e-06],
        "label": ["a", "b"],
    }
    np.savez(tmp_path / "t.npz", **{k: np.array(v) for k, v in columns.items()})
    args = ["afm", "invert", "t.npz", "--out", "o.npz"]
    watched = ("pandas", "scipy", "matplotlib", "numpy.ma", "secrets")
    others = (
        "contactres.measurements.readers.exports",
        "contactres.measurements._afm_maps",
        "contactres.materials",
    )
    result = probe(run_cli(args), watched=(*watched, *others))
    assert result["exit"] == 0
    check_light(result)
    with np.load(tmp_path / "o.npz") as out:
        assert out["label"].tolist() == ["a", "b"] and np.isfinite(out["M_sample_Pa"]).all()
