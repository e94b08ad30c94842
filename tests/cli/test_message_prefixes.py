"""Every command prints its warnings and notes with the same prefix, ``contactres: warning: ``
and ``contactres: note: `` (as its errors say ``contactres: error: ``), so that a user or a
script can pick them out of any command's stderr alike. Before, ``afm invert``, ``afm map`` and
``rum invert`` said ``warning: `` and ``contact`` printed its job's warnings as ``note: ``."""

from __future__ import annotations

import io
import re
import tokenize
from pathlib import Path

import contactres.cli

# A message that starts with a bare kind, in any case: the body of a string token of any
# prefix (f, rf, F, ...), or, from Python 3.12 on, an f-string's first literal part.
_START = re.compile(r"^\s*(warning|note|error): ", re.I)
_OPENING = re.compile(r"^[rRfFbBuU]*(\"\"\"|\'\'\'|\"|\')")
_FSTRING = (getattr(tokenize, "FSTRING_START", None), getattr(tokenize, "FSTRING_MIDDLE", None))


def _bare_messages(source: str) -> list[str]:
    """The string tokens of ``source`` whose text starts with a bare kind (comments are not
    strings; ``{prog}: error:`` is the prefix made another way)."""
    found, previous = [], None
    for t in tokenize.generate_tokens(io.StringIO(source).readline):
        if t.type == tokenize.STRING:
            opening = _OPENING.match(t.string)
            if _START.match(t.string[opening.end() if opening else 0 :]):
                found.append(t.string)
        elif _FSTRING[1] is not None and (previous, t.type) == _FSTRING and _START.match(t.string):
            found.append(t.string)
        previous = t.type
    return found


def test_no_command_prints_a_bare_warning_or_note():
    cli = Path(contactres.cli.__file__).parent
    found = [
        f"{path.name}: {text}"
        for path in sorted(cli.glob("*.py"))
        for text in _bare_messages(path.read_text(encoding="utf-8"))
    ]
    assert not found, "\n".join(found)


def test_the_scan_catches_the_old_forms_and_passes_the_new():
    for bare in (
        'click.echo(f"warning: {message}", err=True)\n',
        'line = f"note: {message}"\n',
        'x = rf"Warning: {m}"\n',
        'x = F"  warning: {m}"\n',
        'x = "warning: " + m\n',
    ):
        assert _bare_messages(bare), bare
    for fine in (
        'click.echo(f"contactres: warning: {line}", err=True)\n',
        'line = f"contactres: {kind}: {message}"\n',
        'line = f"{prog}: error: {text}"\n',
        "# a comment: warning: not printed\n",
    ):
        assert not _bare_messages(fine), fine
