"""Every command prints its warnings and notes with the same prefix, ``contactres: warning: ``
and ``contactres: note: `` (as its errors say ``contactres: error: ``), so that a user or a
script can pick them out of any command's stderr alike. Before, ``afm invert``, ``afm map`` and
``rum invert`` said ``warning: `` and ``contact`` printed its job's warnings as ``note: ``."""

from __future__ import annotations

import re
from pathlib import Path

import contactres.cli

# A message text that starts with a bare kind: an f-string or string literal opening with it.
_BARE = re.compile(r"""(?<![\w:])f?["'](warning|note|error): """)


def test_no_command_prints_a_bare_warning_or_note():
    cli = Path(contactres.cli.__file__).parent
    found = [
        f"{path.name}:{n}: {line.strip()}"
        for path in sorted(cli.glob("*.py"))
        for n, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1)
        if _BARE.search(line)
    ]
    assert not found, "\n".join(found)


def test_the_pattern_catches_the_old_forms():
    assert _BARE.search('click.echo(f"warning: {message}", err=True)')
    assert _BARE.search('line = f"note: {message}"')
    assert not _BARE.search('click.echo(f"contactres: warning: {line}", err=True)')
