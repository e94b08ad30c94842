"""The documentation site's sources agree with the package (the build itself is ``make docs``).

* The API reference lists every public name of ``contactres`` at the public path it is
  exported from (``contactres.report.write_report``, not the private module that defines it),
  so a name added to ``contactres.__all__`` cannot be missing from the reference; every entry
  names a public name of a public module; and every public name of the subpackages whose
  modules are private (scipy's rule: their ``__init__`` is their public surface) is listed.
* Every name of the ``__all__`` of every public module (a package or module without a leading
  underscore in its path: the subpackages, the jobs, the top-level modules) is listed at that
  module's path: nothing public goes undocumented.
* The README links the docs' entry page, and that page exists.
"""

import importlib
import pkgutil
import re
from pathlib import Path

import contactres

DOCS = Path(__file__).resolve().parents[2] / "docs"
README = DOCS.parent / "README.md"


# Subpackages whose implementation modules are private: every name of their __all__ is listed.
PRIVATE_MODULE_PACKAGES = [
    "analysis",
    "apps",
    "dynamic",
    "measurements",
    "polycrystal",
    "report",
    "resonators",
]


def _listed() -> set[str]:
    return set(re.findall(r"^   ~([\w.]+)$", (DOCS / "api.md").read_text(encoding="utf-8"), re.M))


def test_the_api_reference_lists_every_public_name_at_its_public_path():
    listed = _listed()
    names = [n for n in contactres.__all__ if n != "__version__"]  # a string, not an object
    expected = {f"contactres{contactres._EXPORTS[n]}.{n}" for n in names}
    assert sorted(expected - listed) == []
    for package in PRIVATE_MODULE_PACKAGES:
        module = importlib.import_module(f"contactres.{package}")
        assert sorted(f"contactres.{package}.{n}" for n in module.__all__ if n[0] != "_") == sorted(
            entry for entry in listed if entry.rpartition(".")[0] == f"contactres.{package}"
        )


def test_every_entry_of_the_api_reference_is_a_public_name_of_a_public_module():
    for entry in sorted(_listed()):
        module, _, name = entry.rpartition(".")
        assert not any(part.startswith("_") for part in entry.split(".")), entry
        assert name in importlib.import_module(module).__all__, entry


def _public_modules() -> list[str]:
    found = []
    for info in pkgutil.walk_packages(contactres.__path__, "contactres."):
        if not any(part.startswith("_") for part in info.name.split(".")):
            found.append(info.name)
    return sorted(found)


def test_every_name_of_every_public_module_is_listed():
    listed = _listed()
    modules = _public_modules()
    assert "contactres.fileio" in modules and "contactres.jobs.maps" in modules  # the walk works
    missing = []
    for name in modules:
        module = importlib.import_module(name)
        missing += [
            f"{name}.{n}" for n in getattr(module, "__all__", []) if f"{name}.{n}" not in listed
        ]
    assert missing == []


def test_the_readme_links_the_docs_entry_page():
    assert "](docs/index.md)" in README.read_text(encoding="utf-8")
    assert (DOCS / "index.md").is_file()


def test_getting_started_shows_the_command_tree_and_names_every_subcommand():
    import click
    from click.testing import CliRunner

    from contactres.cli import main

    text = (DOCS / "getting-started.md").read_text(encoding="utf-8")
    tree = text[text.index("Commands:") :]
    tree = tree[: tree.index("```")]
    out = CliRunner().invoke(main, ["--help"]).output
    listed = [line.split()[0] for line in tree.splitlines()[1:] if line.strip()]
    printed = [line.split()[0] for line in out[out.index("Commands:") :].splitlines()[1:]]
    assert listed == printed == sorted(main.commands)  # the tree as the command prints it
    for name, command in main.commands.items():
        if isinstance(command, click.Group):
            for sub in command.commands:
                assert f"`{sub}`" in text, f"getting started does not name '{name} {sub}'"


def test_getting_started_names_every_extra():
    """Every optional extra of pyproject.toml is named in getting started, as `name` (issue 30,
    point 6: the page did not know the maps extra)."""
    import tomllib

    pyproject = tomllib.loads((DOCS.parent / "pyproject.toml").read_text(encoding="utf-8"))
    extras = pyproject["project"]["optional-dependencies"]
    text = (DOCS / "getting-started.md").read_text(encoding="utf-8")
    assert extras, "pyproject.toml lists no extras"
    missing = [name for name in extras if f"`{name}`" not in text]
    assert not missing, f"getting started does not name the extra(s) {missing}"


def test_getting_started_names_the_packages_of_every_users_extra():
    """Each package a user's extra installs is named where getting started describes it (issue
    30: `peers` did not name orix; `.h5oina` needs h5py, now in `maps` too)."""
    import re

    import tomllib

    pyproject = tomllib.loads((DOCS.parent / "pyproject.toml").read_text(encoding="utf-8"))
    extras = pyproject["project"]["optional-dependencies"]
    text = (DOCS / "getting-started.md").read_text(encoding="utf-8").lower()
    for extra in ("maps", "afm", "excel", "peers"):
        for requirement in extras[extra]:
            package = re.split(r"[\[<>=!~ ]", requirement, maxsplit=1)[0].lower()
            assert package in text, f"getting started does not name {package} (extra {extra})"
    assert "`.h5oina`" in text
