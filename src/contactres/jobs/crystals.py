"""Job ``crystals``: the built-in table of solids with the indentation moduli of their faces.

Inputs: none (pass None). Settings: none. The table is :func:`contactres.crystal_table`; the
indentation modulus M of a face (paper 1, Eq. 4: a rigid sphere sees an isotropic E* = M) is
:func:`contactres.indentation_modulus`: of the face normal to the crystal z axis (M001) for
every solid, and of the cubic (011) and (111) faces for the cubic and isotropic ones.
"""

from __future__ import annotations

from dataclasses import dataclass
from types import MappingProxyType
from typing import TYPE_CHECKING

from ..measurements.schema import CRYSTALS_LISTING
from .contract import JobResult, Progress, say

if TYPE_CHECKING:
    import pandas as pd

__all__ = ["Result", "Settings", "run"]

# Faces given by cube-axis Miller indices: meaningful for cubic (and isotropic) solids only.
_CUBIC_FACES = (("M011_GPa", (0, 1, 1)), ("M111_GPa", (1, 1, 1)))


@dataclass(frozen=True)
class Settings:
    """Nothing to choose: the table lists every built-in solid."""


@dataclass(frozen=True)
class Result(JobResult):
    """``table``: one row per solid: the columns of :func:`contactres.crystal_table`, with
    M001_GPa, M011_GPa and M111_GPa (GPa; NaN where the face does not apply) before the source
    (:data:`contactres.measurements.schema.CRYSTALS_LISTING`)."""

    SCHEMAS = MappingProxyType({"table": CRYSTALS_LISTING})
    NAME = "crystals"

    table: pd.DataFrame


def run(inputs: None = None, settings: Settings | None = None, progress: Progress | None = None):
    """The table of the built-in solids (see the module docstring)."""
    import numpy as np

    from ..crystals import crystal_table
    from ..materials import Material
    from ..normal import indentation_modulus

    table = crystal_table()
    say(progress, f"indentation moduli of {len(table)} solids")
    solids = [Material.crystal(name) for name in table["name"]]
    cubic_like = table["symmetry"].isin(["cubic", "isotropic"]).to_numpy()
    at = table.columns.get_loc("source")
    assert isinstance(at, int)  # one column of that name: get_loc gives its position
    table.insert(at, "M001_GPa", [indentation_modulus(m.rotated((0, 0, 1))) / 1e9 for m in solids])
    for label, normal in _CUBIC_FACES:
        values = [
            indentation_modulus(m.rotated(normal)) / 1e9 if ok else np.nan
            for m, ok in zip(solids, cubic_like, strict=True)
        ]
        at = table.columns.get_loc("source")
        assert isinstance(at, int)  # as above
        table.insert(at, label, values)
    return Result(table=table)
