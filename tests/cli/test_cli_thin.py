"""The command line is thin (issue 25): every command runs a job and does no physics itself.

Each command of the click tree of :data:`contactres.cli.main` is checked by reading its module
with :mod:`ast` (nothing runs):

(a) its callback imports a job (``from ..jobs import x``) and calls that job's ``run``;
(b) every module of the command line imports, of the library, only the jobs, the report and
    the drawing of the papers' figures (``apps``), units, file output and errors: the options
    become a job's Settings, the job computes, the report writes and the command prints. The
    few other imports are option parsing (a name checked against the library's list of names,
    the options that make the crystal of a face), each listed in :data:`OPTION_PARSING` with
    its reason.

A control: a made-up command that computes a DCSF itself is caught by both checks.
"""

from __future__ import annotations

import ast
import textwrap
from pathlib import Path

import click

import contactres.cli as cli_package
from contactres.cli import main

CLI_DIR = Path(cli_package.__file__).parent
#: The library packages a command-line module may import.
ALLOWED = frozenset({"cli", "jobs", "report", "apps", "units", "typed_units", "fileio", "errors"})
#: (CLI module, library package) -> why: option parsing or the process's set-up, not physics.
OPTION_PARSING: dict[tuple[str, str], str] = {
    ("dcsf.py", "dynamic"): "the --model and --wavenumber choices are the library's names",
    ("_common.py", "analysis"): (
        "MaterialType checks a body's name against the names the radiation loss knows"
    ),
    ("_crystal_face.py", "materials"): (
        "--crystal, --c11/--c12/--c44, --zener/--poisson, --surface, --inplane make the "
        "Material of the face (the job's input)"
    ),
    ("_map_options.py", "materials"): "the material options make the Material of the map",
    ("_map_options.py", "crystals"): "the material options look up a built-in crystal",
    ("_export_options.py", "measurements"): (
        "--reader and --baseline are checked against the export readers' names and syntax"
    ),
    ("qcm_particles.py", "resonators"): "--medium is checked against the media the model knows",
    ("afm_map.py", "analysis"): (
        "--tip-radius/--force, --punch-radius or --reference make the job's ModulusModel"
    ),
    ("qcm_analyze.py", "analysis"): "the printed summary counts the sweeps flagged for drift",
    ("_app.py", "_allocator"): (
        "the program's own process keeps freed memory (glibc's thresholds), as the analysis's "
        "worker processes do: the process's set-up, not physics"
    ),
    ("maps.py", "polycrystal"): (
        "check_map_output and write_map: the Zarr map store's output check and atomic writer"
    ),
}


def _package(node: ast.ImportFrom | ast.Import, names: list[str]) -> list[str]:
    """The library packages (first name below ``contactres``) an import statement of a module
    of ``contactres.cli`` reaches."""
    if isinstance(node, ast.Import):
        return [a.name.split(".")[1] for a in node.names if a.name.startswith("contactres.")]
    if node.level == 0:
        parts = (node.module or "").split(".")
        return [parts[1]] if parts[0] == "contactres" and len(parts) > 1 else []
    if node.level == 1:
        return ["cli"]
    if node.module:  # from ..x.y import z
        return [node.module.split(".")[0]]
    return names  # from .. import x, y


def import_problems(tree: ast.Module, filename: str) -> list[str]:
    """The imports of a CLI module outside :data:`ALLOWED` and :data:`OPTION_PARSING`."""
    bad = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import | ast.ImportFrom):
            names = [a.name for a in node.names]
            for package in _package(node, names):
                if package not in ALLOWED and (filename, package) not in OPTION_PARSING:
                    bad.append(f"{filename}:{node.lineno} imports contactres.{package}")
    return bad


def runs_a_job(function: ast.FunctionDef) -> bool:
    """True when ``function`` imports a job module and calls its ``run`` (or ``series``: a job
    over several files, which runs ``run`` on each)."""
    jobs = set()
    for node in ast.walk(function):
        if isinstance(node, ast.ImportFrom) and node.level >= 1:
            if node.module == "jobs":  # from ..jobs import x as job
                jobs |= {a.asname or a.name for a in node.names}
    return any(
        isinstance(node, ast.Call)
        and isinstance(node.func, ast.Attribute)
        and node.func.attr in ("run", "series")
        and isinstance(node.func.value, ast.Name)
        and node.func.value.id in jobs
        for node in ast.walk(function)
    )


def _commands(group: click.Group, path=()):
    for name, command in group.commands.items():
        if isinstance(command, click.Group):
            yield from _commands(command, (*path, name))
        else:
            yield " ".join((*path, name)), command


def _function(tree: ast.Module, name: str) -> ast.FunctionDef:
    return next(
        node for node in ast.walk(tree) if isinstance(node, ast.FunctionDef) and node.name == name
    )


def test_every_command_runs_a_job():
    commands = dict(_commands(main))
    assert len(commands) >= 15  # the tree was walked (qcm analyze ... figures paper2)
    thin = []
    for name, command in commands.items():
        callback = command.callback
        module = callback.__module__.rsplit(".", 1)[-1]
        tree = ast.parse((CLI_DIR / f"{module}.py").read_text(encoding="utf-8"))
        if not runs_a_job(_function(tree, callback.__name__)):
            thin.append(name)
    assert thin == [], f"commands that run no job: {thin}"


def test_the_command_line_imports_no_physics():
    bad = []
    for path in sorted(CLI_DIR.glob("*.py")):
        bad += import_problems(ast.parse(path.read_text(encoding="utf-8")), path.name)
    assert bad == []


def test_every_option_parsing_exception_is_used():
    used = set()
    for path in sorted(CLI_DIR.glob("*.py")):
        tree = ast.parse(path.read_text(encoding="utf-8"))
        for node in ast.walk(tree):
            if isinstance(node, ast.Import | ast.ImportFrom):
                for package in _package(node, [a.name for a in node.names]):
                    used.add((path.name, package))
    assert set(OPTION_PARSING) <= used, set(OPTION_PARSING) - used


FAKE = textwrap.dedent(
    """
    import click

    from ._app import main


    @main.command()
    def fake():
        from ..dynamic import dcsf
        from ..materials import Material

        click.echo(dcsf(Material.crystal("Cu"), 0.5))
    """
)


def test_control_a_command_that_does_physics_is_caught():
    tree = ast.parse(FAKE)
    assert not runs_a_job(_function(tree, "fake"))
    assert import_problems(tree, "fake.py") == [
        "fake.py:9 imports contactres.dynamic",
        "fake.py:10 imports contactres.materials",
    ]
    # and the same command made thin passes both checks
    thin = FAKE.replace("from ..dynamic import dcsf\n", "from ..jobs import dcsf as job\n")
    thin = thin.replace("    from ..materials import Material\n", "")
    thin = thin.replace('click.echo(dcsf(Material.crystal("Cu"), 0.5))', "job.run(None, None)")
    tree = ast.parse(thin)
    assert runs_a_job(_function(tree, "fake")) and import_problems(tree, "fake.py") == []
