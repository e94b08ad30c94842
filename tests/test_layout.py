"""The package layout: imports run one way, along the physics (issue 10).

Every module of ``src/contactres`` is parsed with :mod:`ast` (nothing is imported) and every
import statement is collected, including those inside functions (a deferred import is still a
dependency, it only runs later) and under ``if TYPE_CHECKING:`` (a type from a higher layer is
a dependency of the design even if it never runs). The tests fail on

(a) an import cycle between modules;
(b) an upward import (against :data:`LAYERS`), an import between the kept-apart units of one
    layer (:data:`KEPT_APART`), a module without a layer, or an import that resolves to no module;
(c) an import of ``contactres.cli`` from outside the CLI (``python -m contactres``, i.e.
    ``__main__``, is the one entry point that runs it);
(d) a private name (``_x``, not a dunder) taken from another module of the package: imported,
    as ``from .x import _y`` or ``from .x import _y as z``, or reached through a module, as
    ``from . import x`` then ``x._y`` (or ``import contactres.x as m`` then ``m._y``, or
    ``contactres.x._y``); or a private module (``pkg._m``) imported or reached from outside its
    package ``pkg``. Private names of other distributions are not our concern;

and, separately, on a module over :data:`MAX_LINES` lines of code (docstrings, comments and
blank lines not counted: documentation is never shortened to meet the rule), and on
module-level caches (a fit or a forward model is a pure function of its arguments):

(e) any use of ``functools.lru_cache`` / ``functools.cache``;
(f) a hand-written cache: a module-level name bound to a mutable container (a dict, list or set
    display or comprehension, or a call of ``dict``/``list``/``set`` or of
    ``collections.defaultdict``/``OrderedDict``/``deque``/``Counter``; annotated or not) that the
    module mutates (``X[k] = v``, ``X[k] += v``, ``del X[k]``, ``X.append(...)``/``update``/
    ``setdefault``/``pop``/... or ``X += ...``), and any module-level name a function rebinds
    through ``global X``. A container that is only read (a constant lookup table) is fine; a
    deliberate registry is listed, with its reason, in :data:`REGISTRIES`. Mutations are found
    in every scope of the module (functions, classes, import time); a function's own local or
    parameter of the same name shadows the module name and is not counted.

How imports resolve (the subtle part):

- ``from . import y`` / ``from .pkg import y`` name the *module* ``pkg.y`` when ``pkg/y.py`` (or
  ``pkg/y/``) exists, otherwise the attribute ``y`` of ``pkg/__init__.py``. So a child importing
  a sibling through its package depends on the sibling, not on the package; but a child that
  imports a name the package ``__init__`` re-exports depends on the ``__init__``, which depends
  on its children: that is a real cycle and is reported.
- A package ``__init__`` importing from its own children (``from .x import y``) depends on them.
  The reverse edge that Python adds implicitly (importing ``pkg.x`` first runs
  ``pkg/__init__.py``) is *not* counted for modules inside ``pkg``: the package is already being
  imported when its children run, so a re-exporting ``__init__`` is not a cycle with them.
- For a module *outside* ``pkg``, importing ``pkg.x`` does run ``pkg/__init__.py`` first, so that
  is counted as an implicit edge (labelled "via package __init__"): it can close a real cycle
  between packages. It never adds a layer violation (a package and its modules share a layer).

Not seen here: imports by string (``importlib.import_module``), which is how the root
``__init__`` loads its public names lazily; tests/test_startup.py resolves every one of them and
checks that the library never imports the CLI. Nor ``getattr(module, "_x")``, nor a container
mutated from *another* module (``from .m import X`` then ``X.append(...)``).

An import exception would live in :data:`ALLOWED`, with its reason (there is none); it is honoured
only for an import inside a function (at call time), never for one at module level. An entry of
:data:`REGISTRIES` that no longer names a mutated module-level container is reported (stale).
"""

from __future__ import annotations

import ast
import dataclasses
import io
import itertools
import tokenize
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[1] / "src"
PACKAGE = "contactres"

# Bottom to top. The key of a module is its first name below the package root
# (contactres.dynamic._exact -> "dynamic"). The root package (__init__: re-exports only) and
# __main__ sit above every layer.
LAYERS: tuple[frozenset[str], ...] = (
    frozenset(
        {
            "_lazy",
            "_threads",
            "_allocator",
            "_csvcells",
            "_column_names",
            "_decimal_text",
            "_ownership",
            "_summary",
            "_png",
            "errors",
            "validation",
            "fileio",
            "examples",
            "fitting",
            "_levenberg_marquardt",
            "crystals",
            "units",
            "typed_units",
            "numerics",
            "_version",
        }
    ),
    frozenset({"materials", "viscoelastic"}),
    frozenset({"halfspace"}),
    frozenset({"layered"}),
    frozenset({"normal"}),
    frozenset({"dynamic", "tangential"}),
    frozenset({"resonators"}),
    frozenset({"measurements"}),
    frozenset({"analysis"}),
    frozenset({"polycrystal"}),
    frozenset({"jobs"}),
    frozenset({"report"}),
    frozenset({"apps"}),
    frozenset({"cli"}),
)
LAYER_NAMES: tuple[str, ...] = (
    "ground",
    "materials",
    "halfspace",
    "layered",
    "normal",
    "dynamic/tangential",
    "resonators",
    "measurements",
    "analysis",
    "polycrystal",
    "jobs",
    "report",
    "apps",
    "cli",
)

# Units of one layer that must not import each other (they may share only lower layers).
KEPT_APART: tuple[frozenset[str], ...] = (frozenset({"dynamic", "tangential"}),)

# (importer module, imported module or package) -> why. Honoured for call-time imports only.
ALLOWED: dict[tuple[str, str], str] = {}

# (module, module-level name) -> why: containers mutated on purpose (registries, not caches).
# (The reader registry is an immutable value now: contactres.measurements.readers.Readers.)
REGISTRIES: dict[tuple[str, str], str] = {}

CLI = "cli"
ENTRY_POINTS = frozenset({"__main__"})  # may import the CLI: `python -m contactres`
# Lines of code: past ~450 a module usually holds two concepts (split it).
MAX_LINES = 450
CACHE_DECORATORS = frozenset({"functools.lru_cache", "functools.cache"})
# Calls that build a mutable container (builtins by name, the rest by dotted origin).
MUTABLE_FACTORIES = frozenset(
    {
        "dict",
        "list",
        "set",
        "collections.defaultdict",
        "collections.OrderedDict",
        "collections.deque",
        "collections.Counter",
    }
)
MUTABLE_DISPLAYS = (ast.Dict, ast.List, ast.Set, ast.DictComp, ast.ListComp, ast.SetComp)
MUTATING_METHODS = frozenset(
    {
        "append",
        "extend",
        "insert",
        "update",
        "setdefault",
        "pop",
        "popitem",
        "clear",
        "add",
        "discard",
        "remove",
        "sort",
        "reverse",
        "appendleft",
        "extendleft",
        "popleft",
        "rotate",
        "difference_update",
        "intersection_update",
        "symmetric_difference_update",
    }
)


# --- machinery -------------------------------------------------------------------------------


@dataclass(frozen=True)
class Rules:
    """What the layout of one package must obey (the real package or a synthetic one)."""

    package: str
    layers: tuple[frozenset[str], ...]
    layer_names: tuple[str, ...] | None = None
    kept_apart: tuple[frozenset[str], ...] = ()
    allowed: Mapping[tuple[str, str], str] = field(default_factory=dict)
    registries: Mapping[tuple[str, str], str] = field(default_factory=dict)
    cli: str = CLI
    entry_points: frozenset[str] = ENTRY_POINTS


@dataclass(frozen=True)
class Module:
    """One parsed source file."""

    name: str  # dotted: contactres.dynamic._exact; a package is named by its __init__
    path: Path
    is_package: bool
    tree: ast.Module
    n_lines: int


@dataclass(frozen=True)
class Edge:
    """``importer`` depends on module ``target`` through one import statement."""

    importer: str
    target: str
    line: int
    where: str  # "top level", "deferred" (inside a function) or "type-checking only"
    names: tuple[str, ...] = ()  # attributes taken from ``target`` (from-imports)
    implicit: bool = False  # ``target`` is a package whose __init__ runs first
    statement: str = ""

    def at(self, modules: Mapping[str, Module], root: Path) -> str:
        path = modules[self.importer].path
        try:
            path = path.relative_to(root)
        except ValueError:
            pass
        return f"{path}:{self.line}"


@dataclass(frozen=True)
class Unresolved:
    """An import that names a module of the package which does not exist."""

    importer: str
    line: int
    statement: str


def scan(src: Path, package: str) -> dict[str, Module]:
    """Parse every ``.py`` file of ``src/package``; keys are dotted module names."""
    modules: dict[str, Module] = {}
    for path in sorted((src / package).rglob("*.py")):
        parts = list(path.relative_to(src).with_suffix("").parts)
        is_package = parts[-1] == "__init__"
        if is_package:
            parts = parts[:-1]
        text = path.read_text(encoding="utf-8")
        tree = ast.parse(text, filename=str(path))
        modules[".".join(parts)] = Module(
            name=".".join(parts),
            path=path,
            is_package=is_package,
            tree=tree,
            n_lines=code_lines(text, tree),
        )
    return modules


def _is_type_checking(test: ast.expr) -> bool:
    return (isinstance(test, ast.Name) and test.id == "TYPE_CHECKING") or (
        isinstance(test, ast.Attribute) and test.attr == "TYPE_CHECKING"
    )


def _imports(tree: ast.Module) -> Iterable[tuple[ast.Import | ast.ImportFrom, str]]:
    """Every import statement of a module with where it runs, functions and classes included."""

    def visit(node: ast.AST, where: str) -> Iterable[tuple[ast.Import | ast.ImportFrom, str]]:
        for child in ast.iter_child_nodes(node):
            if isinstance(child, ast.Import | ast.ImportFrom):
                yield child, where
            elif isinstance(child, ast.FunctionDef | ast.AsyncFunctionDef | ast.Lambda):
                yield from visit(child, "deferred")
            elif isinstance(child, ast.If) and _is_type_checking(child.test):
                inner = where if where == "deferred" else "type-checking only"
                for stmt in child.body:
                    yield from visit(ast.Module(body=[stmt], type_ignores=[]), inner)
                for stmt in child.orelse:
                    yield from visit(ast.Module(body=[stmt], type_ignores=[]), where)
            elif isinstance(child, ast.stmt | ast.excepthandler | ast.match_case):
                # An import is a statement, and only these hold statements: expressions
                # (lambdas included), arguments and the like are not entered (most of the tree).
                yield from visit(child, where)

    yield from visit(tree, "top level")


def _contains(package: str, module: str) -> bool:
    return module == package or module.startswith(package + ".")


def _implicit(importer: str, target: str, package: str, edge: Edge) -> list[Edge]:
    """Edges to the packages whose __init__ runs before ``target`` (outside the importer's)."""
    out = []
    parts = target.split(".")
    for n in range(len(parts) - 1, 1, -1):  # enclosing packages, the root excluded
        ancestor = ".".join(parts[:n])
        if _contains(ancestor, importer) or ancestor == package:
            break
        out.append(
            Edge(importer, ancestor, edge.line, edge.where, (), True, edge.statement),
        )
    return out


def _here(module: Module) -> str:
    """The package that relative imports of ``module`` start from."""
    return module.name if module.is_package else module.name.rpartition(".")[0]


def _from_base(node: ast.ImportFrom, here: str) -> str | None:
    """The dotted module a from-import reads from (None: a relative import above the top)."""
    if not node.level:
        return node.module or ""
    parts = here.split(".")
    if node.level - 1 >= len(parts):
        return None
    base = ".".join(parts[: len(parts) - (node.level - 1)])
    return f"{base}.{node.module}" if node.module else base


def collect(modules: Mapping[str, Module], package: str) -> tuple[list[Edge], list[Unresolved]]:
    """Every dependency between modules of ``package`` (explicit and implicit edges)."""
    edges: list[Edge] = []
    unresolved: list[Unresolved] = []
    for module in modules.values():
        here = _here(module)
        for node, where in _imports(module.tree):
            statement = ast.unparse(node)
            found: dict[str, list[str]] = {}  # target module -> attribute names taken from it
            if isinstance(node, ast.Import):
                for alias in node.names:
                    if not _contains(package, alias.name):
                        continue  # another distribution
                    if alias.name not in modules:
                        unresolved.append(Unresolved(module.name, node.lineno, statement))
                        continue
                    found.setdefault(alias.name, [])
            else:
                base = _from_base(node, here)
                if base is None:
                    unresolved.append(Unresolved(module.name, node.lineno, statement))
                    continue
                if not _contains(package, base):
                    continue  # another distribution
                if base not in modules:
                    unresolved.append(Unresolved(module.name, node.lineno, statement))
                    continue
                for alias in node.names:
                    submodule = f"{base}.{alias.name}"
                    if submodule in modules:  # `from . import sibling`: the module itself
                        found.setdefault(submodule, [])
                    else:  # an attribute of `base` (for a package: of its __init__)
                        found.setdefault(base, []).append(alias.name)
            for target, names in found.items():
                if target == module.name:
                    continue  # `from . import x` in pkg/__init__, x not a module: itself
                edge = Edge(module.name, target, node.lineno, where, tuple(names), False, statement)
                edges.append(edge)
                edges.extend(_implicit(module.name, target, package, edge))
    return _unique(edges), unresolved


def _unique(edges: Iterable[Edge]) -> list[Edge]:
    seen: dict[tuple[str, str, int, bool], Edge] = {}
    for e in edges:
        seen.setdefault((e.importer, e.target, e.line, e.implicit), e)
    return list(seen.values())


def unit_of(module: str, package: str) -> str:
    """``contactres.dynamic._exact`` -> ``dynamic``; the root package -> ``__init__``."""
    if module == package:
        return "__init__"
    return module.split(".")[1]


def layer_of(module: str, rules: Rules) -> int | None:
    unit = unit_of(module, rules.package)
    if unit == "__init__" or unit in rules.entry_points:
        return len(rules.layers)  # the root: above everything
    for index, units in enumerate(rules.layers):
        if unit in units:
            return index
    return None


def _layer_name(index: int, rules: Rules) -> str:
    if index == len(rules.layers):
        return "package root"
    if rules.layer_names:
        return rules.layer_names[index]
    return "/".join(sorted(rules.layers[index]))


def is_allowed(edge: Edge, rules: Rules) -> bool:
    """An allow-listed dependency, imported at call time."""
    return edge.where == "deferred" and any(
        edge.importer == importer and _contains(target, edge.target)
        for importer, target in rules.allowed
    )


def _describe(edge: Edge, modules: Mapping[str, Module], root: Path) -> str:
    kind = "via package __init__" if edge.implicit else edge.where
    return f"{edge.at(modules, root)} ({kind}): {edge.statement}"


def find_cycles(edges: Iterable[Edge], modules: Mapping[str, Module], rules: Rules, root: Path):
    """One line per strongly connected group of modules: a shortest cycle through it."""
    graph: dict[str, dict[str, Edge]] = {}
    for e in edges:
        if is_allowed(e, rules):
            continue
        current = graph.setdefault(e.importer, {}).get(e.target)
        if current is None or (current.implicit and not e.implicit):
            graph[e.importer][e.target] = e  # prefer an explicit statement to report
    # Tarjan's algorithm, iterative so a deep package cannot hit the recursion limit.
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    groups: list[list[str]] = []
    counter = 0
    for start in sorted(set(graph) | {t for v in graph.values() for t in v}):
        if start in index:
            continue
        work = [(start, iter(sorted(graph.get(start, {}))))]
        index[start] = low[start] = counter
        counter += 1
        stack.append(start)
        on_stack.add(start)
        while work:
            node, children = work[-1]
            child = next(children, None)
            if child is not None:
                if child not in index:
                    index[child] = low[child] = counter
                    counter += 1
                    stack.append(child)
                    on_stack.add(child)
                    work.append((child, iter(sorted(graph.get(child, {})))))
                elif child in on_stack:
                    low[node] = min(low[node], index[child])
                continue
            work.pop()
            if work:
                parent = work[-1][0]
                low[parent] = min(low[parent], low[node])
            if low[node] == index[node]:
                group = []
                while True:
                    member = stack.pop()
                    on_stack.discard(member)
                    group.append(member)
                    if member == node:
                        break
                if len(group) > 1 or node in graph.get(node, {}):
                    groups.append(sorted(group))
    lines = []
    for group in sorted(groups):
        members = set(group)
        first = group[0]
        # breadth-first search for the shortest way back to `first` inside the group
        previous: dict[str, str] = {}
        frontier = [first]
        found = None
        while frontier and found is None:
            following = []
            for node in frontier:
                for child in sorted(graph.get(node, {})):
                    if child not in members:
                        continue
                    if child == first:
                        found = node
                        break
                    if child not in previous:
                        previous[child] = node
                        following.append(child)
                if found is not None:
                    break
            frontier = following
        path = [found]
        while path[-1] != first:
            path.append(previous[path[-1]])
        path.reverse()
        path.append(first)
        hops = "\n".join(
            f"      {a} -> {b}  at {_describe(graph[a][b], modules, root)}"
            for a, b in itertools.pairwise(path)
        )
        more = "" if len(members) == len(path) - 1 else f" (group of {len(members)}: {group})"
        lines.append(f"cycle {' -> '.join(path)}{more}\n{hops}")
    return lines


def upward_imports(
    edges: Iterable[Edge],
    unresolved: Iterable[Unresolved],
    modules: Mapping[str, Module],
    rules: Rules,
    root: Path,
) -> list[str]:
    """Imports against the layer order, between kept-apart units, or to nowhere."""
    lines = []
    for name in sorted(modules):
        if layer_of(name, rules) is None:
            lines.append(f"{name}: no layer for '{unit_of(name, rules.package)}' (add it)")
    for u in unresolved:
        lines.append(
            f"{u.importer}: {modules[u.importer].path.relative_to(root)}:{u.line}: "
            f"`{u.statement}` names no module of the package"
        )
    for e in sorted(edges, key=lambda e: (e.importer, e.line, e.target)):
        if e.implicit:
            continue
        low, high = layer_of(e.importer, rules), layer_of(e.target, rules)
        if low is None or high is None:
            continue
        units = {unit_of(e.importer, rules.package), unit_of(e.target, rules.package)}
        if high > low:
            if is_allowed(e, rules):
                continue
            note = ""
            if any(e.importer == i and _contains(t, e.target) for i, t in rules.allowed):
                note = " [allow-listed only when imported inside a function]"
            lines.append(
                f"{e.importer} ({_layer_name(low, rules)}) imports {e.target} "
                f"({_layer_name(high, rules)}) at {_describe(e, modules, root)}{note}"
            )
        elif high == low and len(units) == 2 and frozenset(units) in rules.kept_apart:
            lines.append(
                f"{e.importer} imports {e.target}: {' and '.join(sorted(units))} share a layer "
                f"but are kept apart, at {_describe(e, modules, root)}"
            )
    return lines


def cli_imports(edges: Iterable[Edge], modules: Mapping[str, Module], rules: Rules, root: Path):
    """Imports of the command line from outside it (and outside the entry points)."""
    lines = []
    for e in sorted(edges, key=lambda e: (e.importer, e.line)):
        if e.implicit or unit_of(e.target, rules.package) != rules.cli:
            continue
        unit = unit_of(e.importer, rules.package)
        if unit == rules.cli or unit in rules.entry_points:
            continue
        lines.append(f"{e.importer} imports {e.target} at {_describe(e, modules, root)}")
    return lines


def _private(name: str) -> bool:
    return name.startswith("_") and not (name.startswith("__") and name.endswith("__"))


def private_imports(
    edges: Iterable[Edge], modules: Mapping[str, Module], rules: Rules, root: Path
) -> list[str]:
    """Private names taken from another module; private modules taken from another package."""
    lines = []
    for e in sorted(edges, key=lambda e: (e.importer, e.line)):
        if e.implicit:
            continue
        names = [n for n in e.names if _private(n)]
        if names:
            lines.append(
                f"{e.importer} imports private {', '.join(names)} from {e.target} "
                f"at {_describe(e, modules, root)}"
            )
        parts = e.target.split(".")
        for n in range(2, len(parts) + 1):
            owner = ".".join(parts[: n - 1])
            if _private(parts[n - 1]) and not _contains(owner, e.importer):
                lines.append(
                    f"{e.importer} imports {e.target}, private to {owner}, "
                    f"at {_describe(e, modules, root)}"
                )
                break
    return lines


def _module_names(module: Module, modules: Mapping[str, Module], package: str):
    """Local name -> the modules of the package an import statement binds it to (any scope)."""
    bound: dict[str, set[str]] = {}
    for node, _ in _imports(module.tree):
        if isinstance(node, ast.Import):
            for alias in node.names:
                if not _contains(package, alias.name) or alias.name not in modules:
                    continue
                if alias.asname:  # `import pkg.x as m` binds m to pkg.x
                    bound.setdefault(alias.asname, set()).add(alias.name)
                else:  # `import pkg.x` binds pkg
                    top = alias.name.partition(".")[0]
                    bound.setdefault(top, set()).add(top)
            continue
        base = _from_base(node, _here(module))
        if base is None or not _contains(package, base):
            continue
        for alias in node.names:
            submodule = f"{base}.{alias.name}"
            if submodule in modules:  # `from . import x`: the module x
                bound.setdefault(alias.asname or alias.name, set()).add(submodule)
    return bound


def _resolve(
    expr: ast.expr, bound: Mapping[str, set[str]], modules: Mapping[str, Module]
) -> set[str]:
    """The modules of the package ``expr`` names (``m``, ``m.sub``, ``pkg.x.y``)."""
    if isinstance(expr, ast.Name):
        return bound.get(expr.id, set())
    if isinstance(expr, ast.Attribute):
        subs = {f"{m}.{expr.attr}" for m in _resolve(expr.value, bound, modules)}
        return {m for m in subs if m in modules}
    return set()


def private_attributes(modules: Mapping[str, Module], package: str, root: Path) -> list[str]:
    """Private names reached as attributes of another module of the package (``m._x``)."""
    lines = []
    for module in sorted(modules.values(), key=lambda m: m.name):
        bound = _module_names(module, modules, package)
        if not bound:
            continue
        attributes = [n for n in ast.walk(module.tree) if isinstance(n, ast.Attribute)]
        for node in sorted(attributes, key=lambda n: (n.lineno, n.col_offset)):
            if not _private(node.attr):
                continue
            at = f"{module.path.relative_to(root)}:{node.lineno}: {ast.unparse(node)}"
            for owner in sorted(_resolve(node.value, bound, modules)):
                if owner == module.name:
                    continue
                if f"{owner}.{node.attr}" in modules:  # a private module: fine inside `owner`
                    if not _contains(owner, module.name):
                        lines.append(
                            f"{module.name} uses {owner}.{node.attr}, private to {owner}, at {at}"
                        )
                else:
                    lines.append(f"{module.name} uses private {node.attr} of {owner} at {at}")
    return lines


def code_lines(text: str, tree: ast.Module | None = None) -> int:
    """Lines that hold code: not blank, not only a comment, not part of a docstring.

    A docstring is any statement that is a bare string (module, class and function docstrings,
    and attribute docstrings below an assignment). Tokens are read with :mod:`tokenize`, so a
    ``#`` inside a string is not taken for a comment. ``tree``: the text's parse, where the
    caller has it already.
    """
    skip = {
        tokenize.COMMENT,
        tokenize.NL,
        tokenize.NEWLINE,
        tokenize.INDENT,
        tokenize.DEDENT,
        tokenize.ENCODING,
        tokenize.ENDMARKER,
    }
    lines: set[int] = set()
    for tok in tokenize.generate_tokens(io.StringIO(text).readline):
        if tok.type not in skip:
            first, last = tok.start[0], tok.end[0]
            if first == last:  # most tokens: no range to build
                lines.add(first)
            else:
                lines.update(range(first, last + 1))
    for node in _statements(ast.parse(text) if tree is None else tree):
        if (
            isinstance(node, ast.Expr)
            and isinstance(node.value, ast.Constant)
            and isinstance(node.value.value, str)
        ):
            lines.difference_update(range(node.lineno, (node.end_lineno or node.lineno) + 1))
    return len(lines)


#: The fields that hold statements (of a statement, an except clause or a match case).
_BODIES = ("body", "orelse", "finalbody", "handlers", "cases")


def _statements(tree: ast.Module) -> Iterable[ast.AST]:
    """Every statement of ``tree``, nested ones included, with the except clauses and match
    cases that hold some. A docstring is a statement and an expression holds none, so this is
    all :func:`code_lines` needs to look at, a tenth of the nodes of ``ast.walk``."""
    todo: list[ast.AST] = [tree]
    while todo:
        node = todo.pop()
        yield node
        for name in _BODIES:
            value = getattr(node, name, None)
            if isinstance(value, list):  # a lambda's or an if-expression's body is no list
                todo.extend(value)


def long_modules(modules: Mapping[str, Module], limit: int, root: Path) -> list[str]:
    return [
        f"{m.path.relative_to(root)}: {m.n_lines} lines of code (limit {limit})"
        for m in sorted(modules.values(), key=lambda m: -m.n_lines)
        if m.n_lines > limit
    ]


def _stdlib_aliases(tree: ast.Module, roots: frozenset[str]) -> dict[str, str]:
    """Local name -> dotted origin, for imports of the modules ``roots`` (any scope)."""
    aliases: dict[str, str] = {}
    for node, _ in _imports(tree):
        if isinstance(node, ast.Import):
            for a in node.names:
                if a.name in roots:
                    aliases[a.asname or a.name] = a.name
        elif node.module in roots and not node.level:
            for a in node.names:
                aliases[a.asname or a.name] = f"{node.module}.{a.name}"
    return aliases


def _origin(expr: ast.expr, aliases: Mapping[str, str]) -> str | None:
    """``name`` or ``module.name`` as its dotted origin, through the aliases."""
    if isinstance(expr, ast.Name):
        return aliases.get(expr.id)
    if isinstance(expr, ast.Attribute) and isinstance(expr.value, ast.Name):
        module = aliases.get(expr.value.id)
        if module is not None and "." not in module:
            return f"{module}.{expr.attr}"
    return None


def cache_uses(modules: Mapping[str, Module], root: Path) -> list[str]:
    """Every use of functools.lru_cache / functools.cache, through any alias."""
    lines = []
    for m in modules.values():
        aliases = _stdlib_aliases(m.tree, frozenset({"functools"}))
        if not aliases:  # no name of functools in the module: nothing to resolve to it
            continue
        for node in ast.walk(m.tree):
            if not isinstance(node, ast.Name | ast.Attribute):
                continue
            origin = _origin(node, aliases)
            if origin in CACHE_DECORATORS:
                lines.append(f"{m.path.relative_to(root)}:{node.lineno}: {origin}")
    return sorted(set(lines))


_SCOPES = (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda, ast.ClassDef)


def _own_nodes(scope: ast.AST) -> list[tuple[ast.AST, ast.stmt | None]]:
    """The nodes that run in ``scope`` (a module, function, lambda or class body), each with its
    statement. Nested scopes are not entered, but their decorators, defaults and bases (which
    run in ``scope``) are."""
    out: list[tuple[ast.AST, ast.stmt | None]] = []

    def visit(node: ast.AST, stmt: ast.stmt | None) -> None:
        here = node if isinstance(node, ast.stmt) else stmt
        out.append((node, here))
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef | ast.Lambda):
            outer: list[ast.expr | None] = [*node.args.defaults, *node.args.kw_defaults]
            if not isinstance(node, ast.Lambda):
                outer += node.decorator_list
        elif isinstance(node, ast.ClassDef):
            outer = [*node.bases, *(k.value for k in node.keywords), *node.decorator_list]
        else:
            for child in ast.iter_child_nodes(node):
                visit(child, here)
            return
        for expr in outer:
            if expr is not None:
                visit(expr, here)

    for node in [scope.body] if isinstance(scope, ast.Lambda) else scope.body:
        visit(node, None)
    return out


def _locals(scope: ast.AST, nodes: list[tuple[ast.AST, ast.stmt | None]]) -> set[str]:
    """Names local to a function or class body (those it declares ``global`` excluded)."""
    names: set[str] = set()
    if isinstance(scope, ast.FunctionDef | ast.AsyncFunctionDef | ast.Lambda):
        a = scope.args
        names |= {x.arg for x in [*a.posonlyargs, *a.args, *a.kwonlyargs]}
        names |= {x.arg for x in (a.vararg, a.kwarg) if x is not None}
    for node, _ in nodes:
        if isinstance(node, ast.Name) and isinstance(node.ctx, ast.Store | ast.Del):
            names.add(node.id)
        elif isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef | ast.ClassDef):
            names.add(node.name)
        elif isinstance(node, ast.Import | ast.ImportFrom):
            names |= {(a.asname or a.name).partition(".")[0] for a in node.names}
        elif isinstance(node, ast.ExceptHandler) and node.name:
            names.add(node.name)
    return names - _declared_global(nodes)


def _declared_global(nodes: list[tuple[ast.AST, ast.stmt | None]]) -> set[str]:
    return {n for node, _ in nodes if isinstance(node, ast.Global) for n in node.names}


def _subscript_root(expr: ast.expr) -> str | None:
    """``X`` for ``X``, ``X[a]`` and ``X[a][b]``; None otherwise."""
    while isinstance(expr, ast.Subscript):
        expr = expr.value
    return expr.id if isinstance(expr, ast.Name) else None


def _module_containers(module: Module) -> dict[str, tuple[int, str]]:
    """Module-level names bound to a mutable container -> (line, what it is)."""
    aliases = _stdlib_aliases(module.tree, frozenset({"collections"}))
    found: dict[str, tuple[int, str]] = {}
    for node, _ in _own_nodes(module.tree):
        if isinstance(node, ast.Assign):
            pairs = [(t, node.value) for t in node.targets]
        elif isinstance(node, ast.AnnAssign) and node.value is not None:
            pairs = [(node.target, node.value)]
        else:
            continue
        while pairs:
            target, value = pairs.pop()
            if isinstance(target, ast.Tuple | ast.List) and isinstance(value, ast.Tuple | ast.List):
                pairs.extend(zip(target.elts, value.elts, strict=False))  # A, B = {}, []
                continue
            if not isinstance(target, ast.Name):
                continue
            what = None
            if isinstance(value, MUTABLE_DISPLAYS):
                what = type(value).__name__.lower()  # dict, list, set, dictcomp, ...
            elif isinstance(value, ast.Call):
                origin = _origin(value.func, aliases)
                if origin is None and isinstance(value.func, ast.Name):
                    origin = value.func.id  # a builtin, unless an import rebinds the name
                if origin in MUTABLE_FACTORIES:
                    what = f"{origin}()"
            if what is not None:
                found.setdefault(target.id, (node.lineno, what))
    return found


@dataclass(frozen=True)
class Change:
    """One statement that changes module-level state."""

    name: str
    line: int
    where: str  # "at import", "in f()", "in class C"
    statement: str
    rebound: bool  # through `global name` (otherwise: the container is mutated in place)


def _may_change(tree: ast.Module, containers: set[str]) -> bool:
    """False when :func:`_changes` can find nothing: no ``global`` statement, and no container
    read (``X[k] = v``, ``del X[k]`` and ``X.append(v)`` read ``X``) or augmented (``X += v``)
    anywhere. Most modules' only container is ``__all__``, which none of them touches; one
    walk then spares the scope-by-scope scan."""
    for node in ast.walk(tree):
        if isinstance(node, ast.Global):
            return True
        if isinstance(node, ast.Name) and isinstance(node.ctx, ast.Load):
            if node.id in containers:
                return True
        elif isinstance(node, ast.AugAssign) and isinstance(node.target, ast.Name):
            if node.target.id in containers:
                return True
    return False


def _changes(module: Module, containers: set[str]) -> list[Change]:
    """Mutations of the module-level ``containers``, and every rebinding through ``global``."""
    out: list[Change] = []
    if not _may_change(module.tree, containers):
        return out

    def scan_scope(scope: ast.AST, where: str, shadowed: frozenset[str]) -> None:
        nodes = _own_nodes(scope)
        at_module = isinstance(scope, ast.Module)
        local = set() if at_module else _locals(scope, nodes)
        declared = set() if at_module else _declared_global(nodes)
        visible = (containers - local - shadowed) | (containers & declared)

        def hit(name: str, node: ast.AST, stmt: ast.stmt | None, rebound: bool = False) -> None:
            text = ast.unparse(stmt if stmt is not None else node).splitlines()[0]
            out.append(Change(name, node.lineno, where, text, rebound))

        for node, stmt in nodes:
            if isinstance(node, ast.Subscript) and isinstance(node.ctx, ast.Store | ast.Del):
                root = _subscript_root(node)  # X[k] = v, X[k] += v, del X[k], for X[k] in ...
                if root in visible:
                    hit(root, node, stmt)
            elif isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute):
                root = _subscript_root(node.func.value)  # X.append(v), X[k].add(v)
                if root in visible and node.func.attr in MUTATING_METHODS:
                    hit(root, node, stmt)
            elif isinstance(node, ast.AugAssign) and isinstance(node.target, ast.Name):
                if at_module and node.target.id in containers:  # X += [...] in place
                    hit(node.target.id, node, stmt)
            elif isinstance(node, ast.Name) and isinstance(node.ctx, ast.Store | ast.Del):
                if node.id in declared:
                    hit(node.id, node, stmt, rebound=True)
        # a function's locals shadow the module names in the functions it encloses; a class's
        # do not (its methods do not see the class body)
        inner = shadowed if isinstance(scope, ast.Module | ast.ClassDef) else shadowed | local
        for node, _ in nodes:
            if isinstance(node, _SCOPES):
                if isinstance(node, ast.ClassDef):
                    label = f"in class {node.name}"
                elif isinstance(node, ast.Lambda):
                    label = f"in a lambda {where}"
                else:
                    label = f"in {node.name}()"
                scan_scope(node, label, frozenset(inner))

    scan_scope(module.tree, "at import", frozenset())
    return out


def mutable_state(modules: Mapping[str, Module], rules: Rules, root: Path) -> list[str]:
    """Module-level containers the module mutates, names rebound through ``global``, and stale
    entries of the registry allow-list."""
    lines = []
    used: set[tuple[str, str]] = set()
    for m in sorted(modules.values(), key=lambda m: m.name):
        containers = _module_containers(m)
        path = m.path.relative_to(root)
        seen: set[tuple[str, int]] = set()
        for c in sorted(_changes(m, set(containers)), key=lambda c: (c.line, c.name)):
            if (c.name, c.line) in seen:
                continue
            seen.add((c.name, c.line))
            if (m.name, c.name) in rules.registries:
                used.add((m.name, c.name))
                continue
            if c.name in containers:
                line, what = containers[c.name]
                what = f"module-level {what} of line {line}"
            else:
                what = "module-level name"
            how = f"rebound through `global {c.name}`" if c.rebound else "mutated"
            lines.append(f"{path}:{c.line}: {c.name} ({what}) {how} {c.where}: {c.statement}")
    for module, name in sorted(set(rules.registries) - used):
        lines.append(
            f"registry allow-list names {module} {name}, which is not a module-level container "
            "the module changes (stale entry: remove it)"
        )
    return lines


@dataclass(frozen=True)
class Layout:
    """The parsed package and all its findings."""

    modules: dict[str, Module]
    edges: list[Edge]
    cycles: list[str]
    upward: list[str]
    cli: list[str]
    private: list[str]
    long: list[str]
    caches: list[str]
    state: list[str]


def check(src: Path, rules: Rules, max_lines: int = MAX_LINES) -> Layout:
    modules = scan(src, rules.package)
    edges, unresolved = collect(modules, rules.package)
    root = src.parent
    return Layout(
        modules=modules,
        edges=edges,
        cycles=find_cycles(edges, modules, rules, root),
        upward=upward_imports(edges, unresolved, modules, rules, root),
        cli=cli_imports(edges, modules, rules, root),
        private=[
            *private_imports(edges, modules, rules, root),
            *private_attributes(modules, rules.package, root),
        ],
        long=long_modules(modules, max_lines, root),
        caches=cache_uses(modules, root),
        state=mutable_state(modules, rules, root),
    )


def fail_with(title: str, lines: list[str]) -> None:
    if lines:
        pytest.fail(f"{title}: {len(lines)}\n" + "\n".join(f"  - {x}" for x in lines), False)


# --- the real package ------------------------------------------------------------------------

RULES = Rules(
    package=PACKAGE,
    layers=LAYERS,
    layer_names=LAYER_NAMES,
    kept_apart=KEPT_APART,
    allowed=ALLOWED,
    registries=REGISTRIES,
)


@pytest.fixture(scope="module")
def layout() -> Layout:
    return check(SRC, RULES)


def test_the_package_was_found(layout):
    """Guards the other tests against silently scanning nothing."""
    assert {PACKAGE, f"{PACKAGE}.materials", f"{PACKAGE}.cli"} <= set(layout.modules)
    assert any(e.where == "deferred" for e in layout.edges)


def test_no_import_cycles(layout):
    fail_with("import cycles", layout.cycles)


def test_imports_run_one_way(layout):
    fail_with("imports against the layer order", layout.upward)


def test_nothing_imports_the_cli(layout):
    fail_with("imports of contactres.cli from outside it", layout.cli)


def test_no_private_names_cross_module_borders(layout):
    fail_with("private names taken from another module", layout.private)


def test_no_module_over_the_line_limit(layout):
    fail_with(f"modules over {MAX_LINES} lines of code", layout.long)


def test_no_module_level_caches(layout):
    fail_with("functools caches (no module-level caches)", layout.caches)


def test_no_hand_written_module_level_caches(layout):
    fail_with("module-level state changed by the module (no module-level caches)", layout.state)


# --- the machinery, on a synthetic package ---------------------------------------------------

FAKE = "fake"
FAKE_RULES = Rules(
    package=FAKE,
    layers=(
        frozenset({"low", "util"}),
        frozenset({"mid", "side"}),
        frozenset({"high"}),
        frozenset({"cli"}),
    ),
    kept_apart=(frozenset({"mid", "side"}),),
    allowed={(f"{FAKE}.high", f"{FAKE}.cli"): "test", (f"{FAKE}.low", f"{FAKE}.high"): "test"},
    registries={(f"{FAKE}.mid.plugins", "PLUGINS"): "test"},
)

CLEAN = {
    "__init__.py": "from .mid import f\nfrom .high import g\n",
    "__main__.py": "from .cli import main\n",
    "low.py": "import numpy as np\n\n\ndef _hidden():\n    return np.pi\n\n\nX = 1\n",
    "util.py": "from .low import X\nfrom .low import X as _x\n",
    "mid/__init__.py": "from .core import f\nfrom . import helper\n",
    "mid/core.py": (
        "from ..low import X\nfrom . import helper\nfrom .helper import h\n\n\n"
        "def f():\n    return h() + X\n"
    ),
    "mid/helper.py": "from .. import low\n\n\ndef h():\n    return low.X\n",
    "mid/plugins.py": (
        "PLUGINS = []\nTABLE = {'a': 1}\n\n\ndef register(f):\n    PLUGINS.append(f)\n"
        "    return f\n\n\ndef lookup(key):\n    return TABLE[key]\n"
    ),
    "side.py": "from .low import X\n",
    "high.py": "from .mid import f\nfrom .mid.core import f as f2\nimport fake.side\n\n\ndef g():\n"
    "    return f() + f2()\n",
    "cli/__init__.py": "from ._app import main\nfrom . import _app\n",
    "cli/_app.py": "from ..high import g\n\n\ndef main():\n    return g()\n",
}


def write_package(tmp_path: Path, files: Mapping[str, str]) -> Path:
    src = tmp_path / "src"
    for name, text in files.items():
        path = src / FAKE / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)
    return src


def fake_layout(tmp_path: Path, rules: Rules = FAKE_RULES, **changes: str) -> Layout:
    """The clean package with files replaced or added (``mid__core_py`` -> mid/core.py)."""
    files = dict(CLEAN)
    for key, text in changes.items():
        files[key.replace("__", "/").replace("_py", ".py")] = text
    return check(write_package(tmp_path, files), rules, max_lines=20)


def everything(layout: Layout) -> list[str]:
    return [
        *layout.cycles,
        *layout.upward,
        *layout.cli,
        *layout.private,
        *layout.long,
        *layout.caches,
        *layout.state,
    ]


def test_machinery_accepts_a_clean_package(tmp_path):
    """Re-exports, siblings through the package, aliases and __main__ -> cli are all fine."""
    layout = fake_layout(tmp_path)
    assert everything(layout) == []
    targets = {(e.importer, e.target) for e in layout.edges if not e.implicit}
    assert ("fake.mid", "fake.mid.core") in targets  # the package depends on its children
    assert ("fake.mid.core", "fake.mid.helper") in targets  # `from . import helper`: sibling
    assert ("fake.mid.core", "fake.mid") not in targets  # ... not the package
    assert ("fake.mid.helper", "fake.low") in targets  # `from .. import low`: the module
    assert ("fake.high", "fake.side") in targets  # absolute `import fake.side`
    implicit = {(e.importer, e.target) for e in layout.edges if e.implicit}
    assert ("fake.high", "fake.mid") in implicit  # fake.mid.core runs fake/mid/__init__ first


def test_machinery_reports_a_cycle(tmp_path):
    layout = fake_layout(
        tmp_path, low_py="from .util import Y\nX = 1\n", util_py="from .low import X\nY = 2\n"
    )
    assert len(layout.cycles) == 1
    assert "cycle fake.low -> fake.util -> fake.low" in layout.cycles[0]
    assert "src/fake/low.py:1" in layout.cycles[0]


def test_machinery_reports_a_child_importing_through_its_package(tmp_path):
    """`from . import f` where f is re-exported by mid/__init__ from mid.core: a real cycle."""
    layout = fake_layout(tmp_path, mid__helper_py="from . import f\n\n\ndef h():\n    return 1\n")
    assert len(layout.cycles) == 1
    assert layout.cycles[0].startswith("cycle fake.mid -> fake.mid.helper -> fake.mid")
    assert "src/fake/mid/helper.py:1 (top level): from . import f" in layout.cycles[0]


def test_machinery_reports_a_cycle_through_a_package_init(tmp_path):
    """side imports mid.core; mid/__init__ runs first and imports helper, which imports side."""
    layout = fake_layout(
        tmp_path,
        mid__helper_py="from ..side import Z\n\n\ndef h():\n    return Z\n",
        side_py="from .mid.core import f\nZ = 1\n",
    )
    joined = "\n".join(layout.cycles)
    assert "via package __init__" in joined
    assert "fake.mid" in joined and "fake.side" in joined
    # and mid <-> side are kept apart although they share a layer
    assert any("kept apart" in x for x in layout.upward)


def test_machinery_reports_an_upward_import(tmp_path):
    layout = fake_layout(tmp_path, side_py="from .high import g\n")
    assert layout.upward == [
        "fake.side (mid/side) imports fake.high (high) at src/fake/side.py:1 (top level): "
        "from .high import g"
    ]


def test_machinery_reports_a_deferred_upward_import(tmp_path):
    layout = fake_layout(
        tmp_path, util_py="def late():\n    from .mid.core import f\n\n    return f()\n"
    )
    assert len(layout.upward) == 1
    assert "fake.util (low/util) imports fake.mid.core" in layout.upward[0]
    assert "src/fake/util.py:2 (deferred)" in layout.upward[0]


def test_machinery_reports_a_type_checking_import(tmp_path):
    layout = fake_layout(
        tmp_path,
        util_py="from typing import TYPE_CHECKING\n\nif TYPE_CHECKING:\n    from .high import g\n",
    )
    assert len(layout.upward) == 1 and "(type-checking only)" in layout.upward[0]


def test_machinery_honours_the_allow_list_at_call_time_only(tmp_path):
    deferred = fake_layout(
        tmp_path / "a", low_py="def w():\n    from .high import g\n\n    return g\n"
    )
    assert everything(deferred) == []  # allowed, and not counted in cycles either
    top = fake_layout(tmp_path / "b", low_py="from .high import g\n")
    assert (
        len(top.upward) == 1
        and "allow-listed only when imported inside a function" in top.upward[0]
    )
    assert top.cycles  # at module level it is a real cycle: high -> mid -> low -> high


def test_machinery_reports_cli_imports(tmp_path):
    layout = fake_layout(
        tmp_path, side_py="def run():\n    from .cli import main\n\n    return main\n"
    )
    assert len(layout.cli) == 1 and "fake.side imports fake.cli" in layout.cli[0]
    # high -> cli is allow-listed for the layer order, but the CLI rule admits no exception
    layout = fake_layout(tmp_path / "c", high_py="def run():\n    from .cli import main\n")
    assert len(layout.cli) == 1 and layout.upward == []


def test_machinery_reports_private_imports(tmp_path):
    layout = fake_layout(
        tmp_path,
        side_py=(
            "from .low import _hidden\nfrom .low import _hidden as visible\nimport fake.cli._app\n"
        ),
    )
    assert len(layout.private) == 3
    assert (
        "fake.side imports private _hidden from fake.low at src/fake/side.py:1" in layout.private[0]
    )
    assert "src/fake/side.py:2" in layout.private[1]
    assert "fake.side imports fake.cli._app, private to fake.cli" in layout.private[2]


def test_machinery_reports_unknown_units_and_unresolved_imports(tmp_path):
    layout = fake_layout(tmp_path, extra_py="X = 1\n", side_py="from .units import metre\n")
    assert "fake.extra: no layer for 'extra' (add it)" in layout.upward
    assert any("`from .units import metre` names no module" in x for x in layout.upward)


def test_machinery_reports_long_modules_and_caches(tmp_path):
    layout = fake_layout(
        tmp_path,
        # 21 lines of code among a docstring, a comment and blank lines (not counted); the
        # "#" inside a string is code
        util_py='"""A docstring\nover lines.\n"""\n\n# a comment\nx = "# text"\n' + "x = 1\n" * 20,
        side_py=(
            "import functools as ft\nfrom functools import lru_cache as memo, cache\n\n\n"
            "@memo(maxsize=None)\ndef a():\n    pass\n\n\n@ft.cache\ndef b():\n    pass\n\n\n"
            "c = cache(b)\n"
        ),
    )
    assert layout.long == ["src/fake/util.py: 21 lines of code (limit 20)"]
    assert layout.caches == [
        "src/fake/side.py:10: functools.cache",
        "src/fake/side.py:15: functools.cache",
        "src/fake/side.py:5: functools.lru_cache",
    ]


def test_machinery_reports_private_names_reached_through_a_module(tmp_path):
    layout = fake_layout(
        tmp_path,
        mid___impl_py="f = 1\n",
        mid__core_py="from . import _impl\n\n\ndef f():\n    return _impl.f\n",  # its package
        high_py=(
            "import fake.low\nimport fake.mid.core as core\nimport numpy as np\n"
            "from . import low, mid\nfrom . import low as lw\nfrom .mid import helper\n\n\n"
            "def g():\n    return (\n        low._hidden(), lw._hidden, helper._h, core._c,\n"
            "        fake.low._hidden, mid._impl.f, mid.core._c,\n"
            "        np._NoValue, low.__name__, low.X, mid.core.f, _impl._x,\n    )\n"
        ),
    )
    assert layout.private == [
        "fake.high uses private _hidden of fake.low at src/fake/high.py:11: low._hidden",
        "fake.high uses private _hidden of fake.low at src/fake/high.py:11: lw._hidden",
        "fake.high uses private _h of fake.mid.helper at src/fake/high.py:11: helper._h",
        "fake.high uses private _c of fake.mid.core at src/fake/high.py:11: core._c",
        "fake.high uses private _hidden of fake.low at src/fake/high.py:12: fake.low._hidden",
        "fake.high uses fake.mid._impl, private to fake.mid, at src/fake/high.py:12: mid._impl",
        "fake.high uses private _c of fake.mid.core at src/fake/high.py:12: mid.core._c",
    ]


def test_machinery_accepts_read_only_module_containers(tmp_path):
    """Lookup tables that are only read, and locals or parameters that shadow them, are fine."""
    layout = fake_layout(
        tmp_path,
        side_py=(
            "from collections import defaultdict as dd\n\nCONVENTIONS = {'a': 1}\n"
            "ORDER: list[str] = ['a']\nCOUNTS = dd(int)\n\n\n"
            "def f(CONVENTIONS, key):\n    CONVENTIONS[key] = 2\n    ORDER = []\n"
            "    ORDER.append(key)\n    local = dict(COUNTS)\n    local[key] = 1\n"
            "    return [CONVENTIONS['a'], *ORDER, COUNTS.get(key), *sorted(local)]\n"
        ),
    )
    assert everything(layout) == []


def test_machinery_reports_mutated_module_containers(tmp_path):
    """A hand-written cache, in all its shapes."""
    layout = fake_layout(
        tmp_path,
        side_py=(
            "import collections\n\n_TABLES: dict = {}\n_SEEN, _Q = set(), collections.deque()\n"
            "_LAST = None\nfor k in 'ab':\n    _TABLES[k] = 0\n\n\n"
            "def load(key):\n    global _LAST\n    _TABLES[key] += 1\n    del _TABLES[key]\n"
            "    _SEEN.add(key)\n    _Q[0].appendleft(key)\n    _LAST = key\n"
        ),
    )
    path = "src/fake/side.py"
    assert layout.state == [
        f"{path}:7: _TABLES (module-level dict of line 3) mutated at import: _TABLES[k] = 0",
        f"{path}:12: _TABLES (module-level dict of line 3) mutated in load(): _TABLES[key] += 1",
        f"{path}:13: _TABLES (module-level dict of line 3) mutated in load(): del _TABLES[key]",
        f"{path}:14: _SEEN (module-level set() of line 4) mutated in load(): _SEEN.add(key)",
        f"{path}:15: _Q (module-level collections.deque() of line 4) mutated in load(): "
        "_Q[0].appendleft(key)",
        f"{path}:16: _LAST (module-level name) rebound through `global _LAST` in load(): "
        "_LAST = key",
    ]


def test_machinery_reports_mutations_in_nested_scopes(tmp_path):
    """A nested function sees the module name unless an enclosing function shadows it."""
    layout = fake_layout(
        tmp_path,
        side_py=(
            "CACHE = {}\n\n\ndef outer(CACHE):\n    def inner():\n        CACHE[1] = 1\n\n"
            "    return inner\n\n\nclass C:\n    def m(self):\n        CACHE.update(a=1)\n"
        ),
    )
    assert layout.state == [
        "src/fake/side.py:13: CACHE (module-level dict of line 1) mutated in m(): CACHE.update(a=1)"
    ]


def test_machinery_honours_the_registry_allow_list(tmp_path):
    """mid/plugins.py mutates PLUGINS (allow-listed) and only reads TABLE: clean."""
    assert fake_layout(tmp_path / "a").state == []
    unlisted = dataclasses.replace(FAKE_RULES, registries={})
    assert fake_layout(tmp_path / "b", rules=unlisted).state == [
        "src/fake/mid/plugins.py:6: PLUGINS (module-level list of line 1) mutated in "
        "register(): PLUGINS.append(f)"
    ]
    stale = fake_layout(tmp_path / "c", mid__plugins_py="PLUGINS = []\n")
    assert stale.state == [
        "registry allow-list names fake.mid.plugins PLUGINS, which is not a module-level "
        "container the module changes (stale entry: remove it)"
    ]
