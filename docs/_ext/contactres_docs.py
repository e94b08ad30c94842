"""Build-time pages of the contactres docs: the data dictionary, generated from the schema.

Each table of :func:`contactres.report.dictionary.dictionary_tables` is written to
``_generated/<name>.md`` when the build starts; ``dictionary.md`` includes them, so the page
cannot drift from the columns the package reads and writes.

Also: the description of a constant that a subpackage exports from one of its private modules
(``contactres.analysis.DESCRIPTIONS``). autodoc reads a constant's ``#:`` comment in the module
it is documented in, the subpackage, which only names it; without the comment it falls back to
the docstring of the value's type (``dict``'s, whose ``**kwargs`` breaks the markup). The
comment is taken from the module that defines the constant instead.

And which package pages list the names of the package's ``__all__``: those of a subpackage whose
modules are private (scipy's rule: ``contactres.dynamic``, whose names live in ``_exact``,
``_table``, ...), since each name is documented there only. A package that re-exports names of
its public modules lists none of them: they are documented on their modules' pages, and twice
would make every short reference to them ambiguous.
"""

from __future__ import annotations

import importlib
import importlib.util
import inspect
import pkgutil
from pathlib import Path


def _write_dictionary(app) -> None:
    from contactres.report.dictionary import dictionary_tables

    out = Path(app.srcdir) / "_generated"
    out.mkdir(exist_ok=True)
    for name, table in dictionary_tables().items():
        path = out / f"{name}.md"
        text = table + "\n"
        # Rewrite only on change, so an incremental build does not re-read every page.
        if not path.exists() or path.read_text(encoding="utf-8") != text:
            path.write_text(text, encoding="utf-8")


def _defining_modules(full_name: str) -> list[str]:
    """The private modules that may define an exported constant ``package.NAME``: its
    ``_EXPORTS`` entry (a lazy package), else every private module of the package."""
    package_name, _, name = full_name.rpartition(".")
    try:
        package = importlib.import_module(package_name)
    except ImportError:
        return []
    relative = getattr(package, "_EXPORTS", {}).get(name)
    if relative:
        return [importlib.util.resolve_name(relative, package_name)]
    if not hasattr(package, "__path__"):
        return []
    return [
        f"{package_name}.{m.name}"
        for m in pkgutil.iter_modules(package.__path__)
        if m.name.startswith("_") and not m.ispkg
    ]


def _constant_comment(app, what, name, obj, options, lines) -> None:
    """The ``#:`` comment of a constant a subpackage exports, from the module defining it."""
    if what != "data":
        return
    from sphinx.pycode import ModuleAnalyzer

    short = name.rpartition(".")[2]
    for module in _defining_modules(name):
        if getattr(importlib.import_module(module), short, None) is not obj:
            continue
        comment = ModuleAnalyzer.for_module(module).find_attr_docs().get(("", short))
        if comment:
            lines[:] = list(comment)
            return
    if type(obj).__doc__ and "\n".join(lines).strip() == inspect.cleandoc(type(obj).__doc__):
        lines[:] = []  # the docstring of the value's type says nothing of the constant


def _names_live_in_private_modules(modname: str) -> bool:
    """True for a package whose public names all come from its private modules."""
    module = importlib.import_module(modname)
    if not hasattr(module, "__path__") or not getattr(module, "__all__", None):
        return False
    exports = getattr(module, "_EXPORTS", None)
    if exports is not None:  # a lazy __init__: name -> the module behind it
        return all(source.startswith("._") for source in exports.values())
    submodules = [m.name for m in pkgutil.iter_modules(module.__path__) if not m.ispkg]
    return bool(submodules) and all(name.startswith("_") for name in submodules)


def _package_pages_list_private_names(app, docname, source) -> None:
    """Add ``:ignore-module-all:`` to a generated module page unless its names are its own.

    On the page of a subpackage whose names are its own, its constants are added one by one:
    autodoc documents a module's constant only if the module holds its ``#:`` comment, and the
    subpackage only names it (the comment is in the private module that defines it).
    """
    if not docname.startswith("generated/contactres"):
        return
    modname = docname.partition("/")[2]
    marker = f".. automodule:: {modname}\n"
    if marker not in source[0]:
        return
    if not _names_live_in_private_modules(modname):
        source[0] = source[0].replace(marker, marker + "   :ignore-module-all:\n", 1)
        return
    from sphinx.pycode import ModuleAnalyzer

    module = importlib.import_module(modname)
    own = ModuleAnalyzer.for_module(modname).find_attr_docs()  # documented by automodule
    constants = [
        name
        for name in module.__all__
        if not (inspect.isclass(getattr(module, name)) or callable(getattr(module, name)))
        and ("", name) not in own
    ]
    if constants:
        lines = [f".. autodata:: {modname}.{name}\n   :no-value:\n" for name in constants]
        source[0] += "\n.. rubric:: Constants\n\n" + "\n".join(lines)


def setup(app):
    app.connect("builder-inited", _write_dictionary)
    app.connect("autodoc-process-docstring", _constant_comment)
    app.connect("source-read", _package_pages_list_private_names)
    return {"version": "1", "parallel_read_safe": True, "parallel_write_safe": True}
