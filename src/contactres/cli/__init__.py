"""The ``contactres`` command line (click). Argument parsing and printing only.

Each module here registers its subcommands on :data:`main` when imported.
"""

from . import materials as _materials  # noqa: F401  (registers subcommands)
from ._app import main

__all__ = ["main"]
