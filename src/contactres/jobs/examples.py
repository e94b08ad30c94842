"""Job ``examples``: the example files installed with contactres, listed or copied.

Inputs: none (pass None). Settings: which examples (all by default) and, optionally, a folder
to copy them into. The files and their descriptions are :data:`contactres.examples.EXAMPLES`;
the copy is :func:`contactres.examples.copy_examples` (each file written atomically; a file of
the same name in the folder is kept unless ``overwrite``).
"""

from __future__ import annotations

from dataclasses import dataclass
from types import MappingProxyType
from typing import TYPE_CHECKING

from ..measurements.schema import EXAMPLES_LISTING
from .contract import JobResult, Progress, say

if TYPE_CHECKING:
    import pandas as pd

__all__ = ["Result", "Settings", "run"]


@dataclass(frozen=True)
class Settings:
    """Which examples, and where to copy them.

    Parameters
    ----------
    names : tuple of str
        File names of :data:`contactres.examples.EXAMPLES`; empty: all of them.
    copy_to : str or None
        A folder to copy them into (created if missing); None: list them where they are.
    overwrite : bool
        Replace files of the same names in ``copy_to``.
    """

    names: tuple[str, ...] = ()
    copy_to: str | None = None
    overwrite: bool = False


@dataclass(frozen=True)
class Result(JobResult):
    """``table``: one row per example: name, size, description, a command that reads it, the
    optional extras that command needs, and its path (installed, or of the copy)
    (:data:`contactres.measurements.schema.EXAMPLES_LISTING`); ``copied``: whether the paths
    are copies."""

    SCHEMAS = MappingProxyType({"table": EXAMPLES_LISTING})
    NAME = "examples"

    table: pd.DataFrame
    copied: bool


def run(inputs: None = None, settings: Settings | None = None, progress: Progress | None = None):
    """The examples chosen, listed or copied (see the module docstring)."""
    import pandas as pd

    from ..examples import EXAMPLES, copy_examples, example_path

    s = settings or Settings()
    given = (s.names,) if isinstance(s.names, str) else s.names  # one name, not its letters
    names = list(dict.fromkeys(given)) or list(EXAMPLES)
    if s.copy_to is None:
        paths = [example_path(name) for name in names]  # checks every name
    else:
        say(progress, f"copying {len(names)} example file(s) into {s.copy_to}")
        paths = copy_examples(s.copy_to, names, overwrite=s.overwrite)
    table = pd.DataFrame(
        {
            "name": names,
            "size_bytes": [p.stat().st_size for p in paths],
            "description": [EXAMPLES[n].description for n in names],
            "command": [EXAMPLES[n].command for n in names],
            "extra": [EXAMPLES[n].extra for n in names],
            "path": [str(p) for p in paths],
        }
    )
    return Result(table=table, copied=s.copy_to is not None)
