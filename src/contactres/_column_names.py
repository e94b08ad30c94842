"""Column names that a table holds more than once, said in one line: the readers' messages for a
user's header (a one-line error naming the file, the name, its places and the rule) and the
writers' check of a table of ours (an internal error: :func:`contactres._csvcells.unique_written`),
and a given column named as one a run computes (:func:`refuse_computed_names`: the inversions).

Kept in the ground layer: the writers (:mod:`contactres._csvcells`) and the readers of
:mod:`contactres.measurements` and :mod:`contactres.polycrystal` say it the same way.
"""

from __future__ import annotations

from collections.abc import Callable, Collection, Iterable

from .errors import ContactresInputError

__all__ = [
    "column_place",
    "empty_places",
    "excel_letters",
    "refuse_computed_names",
    "refuse_line_name",
    "repeated_names",
    "repeats_text",
    "shown_names",
]

#: Names, and places of each, shown in one message (the rest counted): a header of 20,000
#: repeats is refused in a short line.
SHOWN_NAMES = 3
SHOWN_PLACES = 5
#: Longest name shown (a 50 MB header cell is shown by its first characters).
SHOWN_CHARS = 60


def repeated_names(names: Iterable[str], named_only: bool = False) -> dict[str, list[int]]:
    """The names that occur more than once in ``names``, each with its places (1, 2, ...: the
    first column is 1), in the order of their first repeat; with ``named_only``, empty names
    (no name, not one name) are left out. One pass, a dict lookup a name."""
    seen: dict[str, int] = {}
    repeats: dict[str, list[int]] = {}
    for i, name in enumerate(names, start=1):
        if named_only and not name:
            continue
        first = seen.setdefault(name, i)
        if first != i:
            repeats.setdefault(name, [first]).append(i)
    return repeats


def excel_letters(position: int) -> str:
    """The letters of a spreadsheet's column ``position`` (1 -> A, 26 -> Z, 27 -> AA): the
    bijective base-26 numbering spreadsheets show."""
    letters = ""
    while position > 0:
        position, rest = divmod(position - 1, 26)
        letters = chr(ord("A") + rest) + letters
    return letters


def _listed(items: list, count: int, text: Callable = str) -> str:
    """``text`` of the first ``count`` of ``items``, joined by commas, the rest counted
    (``, ... 40 in all``): the one shape of every list these messages show."""
    more = f", ... {len(items)} in all" if len(items) > count else ""
    return ", ".join(text(i) for i in items[:count]) + more


def _shown(name: str) -> str:
    text = name if len(name) <= SHOWN_CHARS else name[: SHOWN_CHARS - 1] + "…"
    return repr(text)


def shown_names(names: Iterable[str], count: int = 20) -> str:
    """``['a', 'b', ... 40 in all]``: the first ``count`` of ``names``, each shortened as in
    :func:`repeats_text`, the rest counted (an internal error's text stays one short line
    whatever the header holds)."""
    return f"[{_listed(list(names), count, _shown)}]"


def repeats_text(
    names: Iterable[str],
    place: Callable[[int], str] = str,
    word: str = "columns",
    tail: str = "",
    named_only: bool = False,
) -> str | None:
    """``'df_Hz' (columns 8, 16); 'x' (columns 2, 5)``: the repeated names of ``names`` and their
    places (``place`` gives the text of a place: a number, or a spreadsheet's letters; ``word``
    and ``tail`` what stands before and after them), at most :data:`SHOWN_NAMES` names of
    :data:`SHOWN_PLACES` places each, the rest counted; None when every name is its own.
    ``named_only``: as for :func:`repeated_names`."""
    repeats = repeated_names(names, named_only)
    if not repeats:
        return None
    parts = []
    for name, places in list(repeats.items())[:SHOWN_NAMES]:
        parts.append(f"{_shown(name)} ({word} {_listed(places, SHOWN_PLACES, place)}{tail})")
    left = len(repeats) - SHOWN_NAMES
    return "; ".join(parts) + (f"; and {left} more name(s)" if left > 0 else "")


def empty_places(names: Iterable[str], place: Callable[[int], str] = str) -> str | None:
    """``columns 2, 4`` (or ``column C``): the places of the empty names of ``names`` (``place``
    gives the text of a place: a number, or a spreadsheet's letters), at most
    :data:`SHOWN_PLACES` of them, the rest counted; None when every name is given. The readers
    of a CSV file and of a workbook say an empty header cell alike (by its number or its
    letters)."""
    empty = [i for i, name in enumerate(names, start=1) if not name]
    if not empty:
        return None
    return f"column{'' if len(empty) == 1 else 's'} {_listed(empty, SHOWN_PLACES, place)}"


def refuse_computed_names(table, computed: Collection[str], source: str) -> None:
    """One-line error for a column of ``table`` (a DataFrame or an ArrayTable; its given columns,
    ``attrs["given"]``, where the reader recorded them) named as one of ``computed``, the
    columns a run appends to it; ``source`` names the file.

    Why: a run's result is the given columns then the computed ones, each set by its name, so
    a computed column would take the place of the given one of its name: the user's values
    replaced without a word (a column ``kappa`` of the user's, or every computed column of a
    table an earlier run wrote). Only the names the run writes are refused: a column it does
    not compute is the user's to keep. Places as the file shows them: a sheet's letters."""
    given = list(table.attrs.get("given", [c for c in table.columns if c != "line"]))
    clash = [c for c in given if c in computed]
    if not clash:
        return
    shown = _listed(clash, 5, lambda c: f"{c!r} ({column_place(table, given.index(c) + 1)})")
    one = len(clash) == 1
    raise ContactresInputError(
        f"{source}: column{'' if one else 's'} {shown} "
        f"{'is a column' if one else 'are columns'} the inversion computes: the result would "
        f"replace {'its' if one else 'their'} values; rename {'it' if one else 'them'} (a table "
        "an inversion wrote: drop its computed columns first)"
    )


def column_place(table, position: int) -> str:
    """The place of a table's column as its file shows it: ``column 7`` (1 is the first), or
    the spreadsheet's letters (``column G``) for a sheet of a workbook, whose reader says so in
    ``attrs["column_letters"]``."""
    letters = getattr(table, "attrs", {}).get("column_letters", False)
    return f"column {excel_letters(position) if letters else position}"


def refuse_line_name(
    names: Iterable[str], where: str, place: Callable[[int], str], numbers: str
) -> None:
    """One-line error for a column (or array) named ``line`` among ``names``: the name the
    readers give the row numbers they add, which would replace the file's own values.
    ``where``: the file (and its header's line or row); ``place``: the text of the name at a
    position (1 is the first), e.g. ``column 'line' (column G)``; ``numbers``: what the added
    numbers are, e.g. ``line numbers of the file``."""
    names = list(names)
    if "line" in names:
        raise ContactresInputError(
            f"{where}: {place(names.index('line') + 1)} is the name contactres gives the "
            f"{numbers}; rename it (e.g. scan_line)"
        )
