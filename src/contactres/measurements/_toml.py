"""A TOML file's table, its faults said in one line: a key given twice named as the file writes it.

tomllib says where a key given twice ends (``Cannot overwrite a value (at line 3, column 9)``)
but not which key it is; a user with a file of constants looks for a name. The key is read
from the file's text: the statement that ends on that line (a value may take several lines: a
multi-line string or array) is the last line at or above it that starts like a statement (a key
then ``=``, or a table header) and from which the text to that line is TOML of its own, the
text above it also being TOML (a line inside a multi-line string is neither). Keys are shown as
written (bare, quoted or dotted), with the table they are under. Where no such statement is
found, tomllib's own text stands.
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

from ..errors import ContactresInputError

__all__ = ["toml_table"]

# TOML 1.0 keys: bare, "basic" (with escapes) or 'literal', joined by dots.
_BARE = r"[A-Za-z0-9_-]+"
_SIMPLE = rf"""(?:{_BARE}|"(?:[^"\\\n]|\\.)*"|'[^'\n]*')"""
_KEY = rf"{_SIMPLE}(?:[ \t]*\.[ \t]*{_SIMPLE})*"
#: The start of a statement: a table header (``[t]``, ``[[t]]``) or a key and its ``=``.
_STATEMENT = re.compile(
    rf"[ \t]*(?:(?P<header>\[\[?[ \t]*{_KEY}[ \t]*\]\]?)|(?P<key>{_KEY})[ \t]*=)"
)
#: tomllib's (and tomli's, the same code) texts for a key or a table given again.
_AGAIN = ("Cannot overwrite a value", "Cannot declare", "Cannot mutate immutable namespace")
_WHERE = re.compile(r"\(at line (\d+), column \d+\)$")
#: Statements tried above the line tomllib names (each a parse of the text above it): a file of
#: constants has a few lines, a huge one is not parsed again and again.
_TRIED = 20
#: A key put where the statement stands, to find the table it is under (a file holding this
#: key makes it clash: the statement is not found, tomllib's text stands; a file holding it
#: elsewhere gets no table named, which could be the wrong one).
_PROBE = '"contactres: where"'
#: Longest text searched (characters): a file of constants holds a few lines, and each
#: statement tried is a parse of the text above it (~0.4 s a parse at 1.7 MB; review R32b).
_LONGEST = 100_000


def _tomllib():
    # imported when a file is read: a table without a TOML beside it (the first call of the
    # analysis, issue 31, point 3) needs no TOML parser
    if sys.version_info >= (3, 11):
        import tomllib
    else:  # pragma: no cover - Python 3.10
        import tomli as tomllib
    return tomllib


def toml_table(text: str, path: Path) -> dict:
    """The table of the TOML document ``text`` (the file ``path``). Invalid TOML is one line
    naming the file; a key or table given twice (tomllib: ``Cannot overwrite a value``,
    ``Cannot declare ... twice``) names it as written, its table and its line."""
    tomllib = _tomllib()
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        message = str(exc)
        again = (
            _given_again(text, message, getattr(exc, "lineno", None))
            if message.startswith(_AGAIN)
            else None
        )
        raise ContactresInputError(
            f"{path}: not valid TOML ({message})" if again is None else f"{path}, {again}"
        ) from None


def _given_again(text: str, message: str, lineno: int | None) -> str | None:
    """``line 3: key sphere_radius_m clashes with ...``: the statement of a key given
    again, whose value ends on the line tomllib names, or None where it is not found."""
    if len(text) > _LONGEST:
        return None
    lines = [line.removesuffix("\r") for line in text.split("\n")]  # a CRLF file's too
    if lineno is None:  # tomllib before 3.14 gives the place in its text only
        where = _WHERE.search(message)
        # "at end of document": a last line without a line break
        lineno = int(where.group(1)) if where else len(lines)
    tomllib = _tomllib()
    tried = 0
    for start in range(min(lineno, len(lines)) - 1, -1, -1):
        statement = _STATEMENT.match(lines[start])
        if statement is None:
            continue
        tried += 1
        if tried > _TRIED:
            return None
        try:
            tomllib.loads("\n".join(lines[start:lineno]))
            above = tomllib.loads("\n".join([*lines[:start], f"{_PROBE} = 0"]))
        except tomllib.TOMLDecodeError:
            continue  # a line inside a multi-line value, not a statement
        if statement.group("header"):
            shown = f"table {statement.group('header').strip()}"
        else:
            shown = f"key {statement.group('key').strip()}"
            if _PROBE.strip('"') not in text and (table := _table_of(above)):
                shown += f" of table {table}"
        # "clashes", not "is defined": in `room = 1` then `room.door = 2` it is a key on the
        # statement's dotted path that is defined above, not the statement's own key.
        return (
            f"line {start + 1}: {shown} clashes with a key or table defined above (itself or one "
            "on its dotted path); a TOML file defines each key and table once"
        )
    return None


def _table_of(document: dict) -> str:
    """The header of the table holding :data:`_PROBE` in ``document`` (``[a.b]``, or ``[[a]]``
    for the last table of an array of tables; ``""`` at the top)."""
    probe = _PROBE.strip('"')
    tables: list[tuple[list[str], dict, bool]] = [([], document, False)]
    while tables:  # depth first: a document of constants holds a table or two
        names, table, listed = tables.pop()
        if probe in table:
            if not names:
                return ""
            dotted = ".".join(n if re.fullmatch(_BARE, n) else _quoted(n) for n in names)
            return f"[[{dotted}]]" if listed else f"[{dotted}]"
        for name, value in table.items():
            if isinstance(value, list):
                tables.extend(([*names, name], t, True) for t in value[-1:] if isinstance(t, dict))
            elif isinstance(value, dict):
                tables.append(([*names, name], value, False))
    return ""  # not reached: the probe is in the document


def _quoted(name: str) -> str:
    """``name`` as a TOML basic string (its backslashes and quotes escaped)."""
    return '"' + name.replace("\\", "\\\\").replace('"', '\\"') + '"'
