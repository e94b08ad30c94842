"""The ``contactres`` command line (click). Argument parsing and printing only.

Each command module here registers its subcommands on a group of :mod:`._app` when imported;
the groups import a command's module when that command is looked up
(:class:`._app.LazyCommands`, where :data:`._app.COMMAND_MODULES` says which module defines
which command), so a command's start imports no other command's module.
"""

from ._app import main

__all__ = ["main"]
