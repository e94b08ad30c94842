"""A reader recipe and a registry of them: immutable values, never module state.

A :class:`Reader` is what it takes to read one file format: a name, the suffixes it is tried for
first, ``detect`` (is this file in my format?), ``load`` and the ``kind`` of input it reads
(:data:`KINDS`, which also says what ``load`` returns). A :class:`Readers` is an ordered tuple
of recipes; :meth:`Readers.with_reader` returns a new registry with one more recipe (tried
before the others of its kind), so a user adds a format without changing anything shared:

>>> from contactres.measurements.readers import BUILT_IN
>>> BUILT_IN.of_kind("sweeps")[0].name
'csv'

The built-in registry is :data:`contactres.measurements.readers.BUILT_IN`.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from dataclasses import dataclass
from pathlib import Path
from types import MappingProxyType
from typing import Any, TypeVar

from ...errors import ContactresInputError

__all__ = ["KINDS", "Reader", "Readers", "first_detected", "read_head"]

#: The kinds of input, and what ``load`` of a reader of that kind returns.
KINDS = MappingProxyType(
    {
        "sweeps": (
            "load(path) -> DataFrame: a sweep table as string cells and a `line` column (float64 "
            "columns named in attrs['number_columns'] are numbers read from their text)"
        ),
        "spectra": (
            "load(path, *, layout=None, reference_impedance=50.0, two_port=None) -> DataFrame: "
            "tidy spectra "
            "rows as string cells and a `line` column"
        ),
        "export": "load(path, **conventions) -> ExportTable: an instrument's QCM-D export",
        "resonances": (
            "load(path) -> DataFrame: a CR-AFM or RUM table as string cells and a `line` column"
        ),
        "ebsd": "load(path) -> OrientationMap: an EBSD map",
        "grid": "load(path) -> 2-D float array: a measured value per pixel (NaN: not measured)",
        "afm_map": (
            "load(path) -> IgorWave (an Asylum image: its layers, labels and note) or "
            "ResonanceMaps (contact-resonance frequency and Q maps, y by x, and the pixel size)"
        ),
    }
)

#: How many characters of a file ``detect`` sees.
HEAD_CHARS = 4096


@dataclass(frozen=True)
class Reader:
    """The recipe of one file format.

    Attributes
    ----------
    name : str
        Short name of the format (unique within its kind).
    suffixes : tuple of str
        File suffixes (lower case, with the dot) this reader is tried for first.
    detect : callable(path, head: str) -> bool
        True if the file, whose first :data:`HEAD_CHARS` characters are ``head`` ("" for a
        folder), is in this format.
    load : callable
        Reads the file; its arguments and what it returns depend on ``kind`` (:data:`KINDS`).
    kind : str
        The kind of input, a key of :data:`KINDS`.
    """

    name: str
    suffixes: tuple[str, ...]
    detect: Callable[[Path, str], bool]
    # What load returns depends on the kind (KINDS: a DataFrame, an ExportTable, an
    # OrientationMap, an array): only the caller, which picked the kind, knows the type.
    load: Callable[..., Any]
    kind: str

    def __post_init__(self):
        if self.kind not in KINDS:
            raise ContactresInputError(
                f"reader {self.name!r}: kind {self.kind!r} is not one of {list(KINDS)}"
            )
        if isinstance(self.suffixes, str) or not all(
            isinstance(s, str) and s.startswith(".") and s == s.lower() for s in self.suffixes
        ):
            raise ContactresInputError(
                f"reader {self.name!r}: suffixes must be a tuple of lower-case suffixes with the "
                f"dot ('.csv'), got {self.suffixes!r}"
            )
        if not (callable(self.detect) and callable(self.load)):
            raise ContactresInputError(f"reader {self.name!r}: detect and load must be callable")


def read_head(path: Path) -> str:
    """The first :data:`HEAD_CHARS` characters of a file ("" for a folder); an empty file is a
    one-line error.

    When those characters are all comment lines (``#``) or blank, the header lies further down
    (a long preamble): the whole lines read are kept and the first :data:`HEAD_CHARS`
    characters from the first line that is neither are added, so that ``detect`` sees the
    header (issue 27: a valid table after 6 kB of comments was "recognised by no reader").
    """
    if path.is_dir():
        return ""
    with path.open(encoding="utf-8-sig", errors="replace") as fh:
        head = fh.read(HEAD_CHARS)
        if len(head) == HEAD_CHARS and all(_preamble(ln) for ln in head.splitlines()):
            head = head[: head.rfind("\n") + 1]
            fh.seek(0)
            rest = next((ln for ln in fh if not _preamble(ln)), "")
            head += (rest + fh.read(HEAD_CHARS))[:HEAD_CHARS]
    if not head.strip():
        raise ContactresInputError(
            f"{path}: the file is empty (expected a header line and data rows)"
        )
    return head


def _preamble(line: str) -> bool:
    """A blank line or a comment line (first non-blank character ``#``)."""
    return not line.strip() or line.lstrip().startswith("#")


def _first_line(head: str) -> str:
    """The first line of ``head`` that is neither blank nor a comment (what ``detect`` saw)."""
    return next((ln for ln in head.splitlines() if not _preamble(ln)), "")


def _shown(text: str, limit: int = 80) -> str:
    """A line of a file in a message: quoted, cut at ``limit`` characters."""
    return repr(text if len(text) <= limit else text[: limit - 1] + "…")


# first_detected returns one of the readers it is given, with their type (an ExportReader of
# export readers).
_R = TypeVar("_R", bound=Reader)


def first_detected(readers: Iterable[_R], path: Path, head: str) -> _R | None:
    """The first of ``readers`` that recognises the file: those whose suffix matches are tried
    first, then the others, each group in order. None if none does."""
    readers = tuple(readers)
    by_suffix = [r for r in readers if path.suffix.lower() in r.suffixes]
    for reader in by_suffix + [r for r in readers if r not in by_suffix]:
        if reader.detect(path, head):
            return reader
    return None


@dataclass(frozen=True)
class Readers:
    """An ordered, immutable registry of :class:`Reader` recipes."""

    readers: tuple[Reader, ...] = ()

    def __post_init__(self):
        object.__setattr__(self, "readers", tuple(self.readers))
        seen = set()
        for r in self.readers:
            if (r.kind, r.name) in seen:
                raise ContactresInputError(
                    f"a {r.kind} reader named {r.name!r} is already registered"
                )
            seen.add((r.kind, r.name))

    def __iter__(self):
        return iter(self.readers)

    def __len__(self) -> int:
        return len(self.readers)

    def with_reader(self, *readers: Reader) -> Readers:
        """A new registry with ``readers`` tried before the others of their kind (each name new
        within its kind); this one is unchanged."""
        return Readers((*readers, *self.readers))

    def of_kind(self, kind: str) -> tuple[Reader, ...]:
        """The readers of ``kind``, in the order they are tried."""
        if kind not in KINDS:
            raise ContactresInputError(f"kind {kind!r} is not one of {list(KINDS)}")
        return tuple(r for r in self.readers if r.kind == kind)

    def named(self, name: str, kind: str) -> Reader:
        """The reader of ``kind`` called ``name`` (one-line error listing the known names)."""
        wanted = str(name).strip().lower()  # names compare case-insensitively, both sides
        found = [r for r in self.of_kind(kind) if r.name.lower() == wanted]
        if not found:
            known = ", ".join(r.name for r in self.of_kind(kind))
            raise ContactresInputError(f"no {kind} reader is called {str(name)!r}; known: {known}")
        return found[0]

    def for_suffix(self, path, kind: str) -> Reader | None:
        """The first reader of ``kind`` whose suffixes hold ``path``'s (None if none does).

        For formats told apart by their suffix alone (EBSD exports, value grids): the file is
        not opened, so the reader chosen gives its own precise error for a file that is not
        right, where :meth:`pick` would only say that no reader recognises it.
        """
        suffix = Path(path).suffix.lower()
        return next((r for r in self.of_kind(kind) if suffix in r.suffixes), None)

    def pick(self, path, kind: str) -> Reader:
        """The reader of ``kind`` that recognises ``path`` (its suffix first, then the others);
        a one-line error naming the file and the known formats if none does."""
        path = Path(path)
        candidates = self.of_kind(kind)
        head = read_head(path)
        found = first_detected(candidates, path, head)
        if found is None:
            names = ", ".join(f"{r.name} ({'/'.join(r.suffixes)})" for r in candidates)
            first = _first_line(head)
            seen = (
                f"its first line that is not a comment is {_shown(first)}"
                if first
                else "it holds only comment lines ('#') and blank lines"
            )
            raise ContactresInputError(
                f"{path}: no reader recognises this file ({seen}); formats known: {names}"
            )
        return found
