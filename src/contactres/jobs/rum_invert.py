"""Job ``rum_invert``: the contact resonance of a RUM table -> contact stiffness k*, one row per
point or map pixel.

Inputs: the path of the resonance table (CSV, columns
:data:`contactres.measurements.schema.RUM_TABLE`): f0_Hz, fc_Hz and the calibration,
K_eff_N_per_m (lumped oscillator, (f/f0)² = 1 + k*/K_eff) or mass_kg (a rod free at one end,
k* = (EA/L)(kL) tan(kL)). Settings: none (the calibration columns choose the model). The
inversion is :func:`contactres.invert_rum_table`.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from types import MappingProxyType
from typing import TYPE_CHECKING

from ..measurements.schema import RUM_INVERT_RESULTS
from .contract import JobResult, Progress, say

if TYPE_CHECKING:
    import os

    import pandas as pd

__all__ = ["Result", "Settings", "run"]


@dataclass(frozen=True)
class Settings:
    """How to invert a RUM table: nothing to choose (the calibration columns decide)."""


@dataclass(frozen=True)
class Result(JobResult):
    """``table``: the input's columns (``input_columns``, copied), then rum_model and
    k_star_N_per_m (:data:`contactres.measurements.schema.RUM_INVERT_RESULTS`, which lists the
    computed ones only)."""

    SCHEMAS = MappingProxyType({"table": RUM_INVERT_RESULTS})

    table: pd.DataFrame
    input_columns: tuple[str, ...]


def run(
    inputs: str | os.PathLike, settings: Settings | None = None, progress: Progress | None = None
) -> Result:
    """k* of every row of the RUM table ``inputs`` (see the module docstring)."""
    from ..analysis import invert_rum_table
    from ..measurements import read_resonance_table
    from ..measurements.schema import RUM_TABLE

    say(progress, f"reading {Path(inputs).name}")
    checked = read_resonance_table(inputs, RUM_TABLE)
    say(progress, f"inverting {len(checked)} rows")
    table = invert_rum_table(checked, str(Path(inputs)))
    return Result(table=table, input_columns=tuple(checked.columns))
