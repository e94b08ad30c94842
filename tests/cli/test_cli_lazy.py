"""The command groups import a command's module only when that command is needed
(``contactres.cli._app.LazyCommands``): the table of which module defines which command must
match what the modules register, and a command's start must not import the others."""

from __future__ import annotations

import json
import pkgutil
import subprocess
import sys

import click

import contactres.cli
from contactres.cli._app import COMMAND_MODULES, main

GROUPS = {"qcm", "afm", "rum", "maps", "figures"}


def _group(path: str) -> click.Group:
    group = main if path == "" else main.commands[path]
    assert isinstance(group, click.Group)
    return group


def test_every_command_module_is_in_the_table():
    # A command module left out of the table would never be imported: its commands would vanish.
    modules = {
        info.name
        for info in pkgutil.iter_modules(contactres.cli.__path__)
        if not info.name.startswith("_")
    }
    named = {module for table in COMMAND_MODULES.values() for module in table.values()}
    assert named == modules


def test_the_table_says_where_each_command_is_registered():
    assert set(COMMAND_MODULES) == {"", *GROUPS}
    for path, table in COMMAND_MODULES.items():
        group = _group(path)
        listed = set(group.commands)  # a listing imports every module of the group
        assert listed == set(table) | (GROUPS if path == "" else set())
        for name, module in table.items():
            command = group.commands[name]
            assert command.callback is not None
            assert command.callback.__module__ == f"contactres.cli.{module}", (path, name)


def _fresh(code: str) -> list:
    """What ``code`` prints (JSON) in a fresh interpreter, where ``loaded()`` is the set of
    command modules imported so far."""
    prelude = (
        "import json, sys\n"
        "from contactres.cli import main\n"
        "def loaded():\n"
        "    return sorted(m.rsplit('.', 1)[1] for m in sys.modules\n"
        "                  if m.startswith('contactres.cli.') and '._' not in m)\n"
    )
    run = subprocess.run(
        [sys.executable, "-c", prelude + code], capture_output=True, text=True, check=True
    )
    return json.loads(run.stdout)


def test_a_name_imports_its_module_only_and_a_listing_all():
    steps = _fresh(
        "afm = main.commands['afm']\n"
        "steps = [loaded()]\n"
        "steps.append([afm.commands['invert'].name, loaded()])\n"
        "steps.append(['nosuch' in afm.commands, afm.commands.get('nosuch'), loaded()])\n"
        "steps.append([len(afm.commands), loaded()])\n"
        "steps.append([sorted(main.commands), loaded()])\n"
        "print(json.dumps(steps))\n"
    )
    top = sorted(COMMAND_MODULES[""])
    assert steps == [
        [],
        ["invert", ["afm_invert"]],
        [False, None, ["afm_invert"]],
        [2, ["afm_invert", "afm_map"]],
        [sorted([*top, *GROUPS]), sorted(["afm_invert", "afm_map", *top])],
    ]


def test_a_commands_start_imports_no_other_command_module():
    exit_code, loaded = _fresh(
        "from click.testing import CliRunner\n"
        "r = CliRunner().invoke(main, ['afm', 'invert', '--help'])\n"
        "print(json.dumps([r.exit_code, loaded()]))\n"
    )
    assert exit_code == 0 and loaded == ["afm_invert"]
