"""Column names that a table holds more than once, said in one line: the readers' messages for a
user's header (a one-line error naming the file, the name, its places and the rule) and the
writers' check of a table of ours (an internal error: :func:`contactres._csvcells.unique_written`).

Kept in the ground layer: the writers (:mod:`contactres._csvcells`) and the readers of
:mod:`contactres.measurements` and :mod:`contactres.polycrystal` say it the same way.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable

__all__ = ["excel_letters", "repeated_names", "repeats_text"]

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


def _shown(name: str) -> str:
    text = name if len(name) <= SHOWN_CHARS else name[: SHOWN_CHARS - 1] + "…"
    return repr(text)


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
        shown = ", ".join(place(p) for p in places[:SHOWN_PLACES])
        more = f", ... {len(places)} in all" if len(places) > SHOWN_PLACES else ""
        parts.append(f"{_shown(name)} ({word} {shown}{more}{tail})")
    left = len(repeats) - SHOWN_NAMES
    return "; ".join(parts) + (f"; and {left} more name(s)" if left > 0 else "")
