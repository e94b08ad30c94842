"""Job ``afm_invert``: the contact resonances of a CR-AFM table -> contact stiffness k*, tip
position, damping and modulus, one row per point or map pixel.

Inputs: the path of the resonance table (CSV, columns
:data:`contactres.measurements.schema.AFM_TABLE`). Settings: the normalisation of the
frequencies, the tolerance between modes, and the sample for paper 1's dynamic correction of
the Hertz rows. The inversion is :func:`contactres.invert_afm_table` (Euler-Bernoulli lever,
U. Rabe et al., Rev. Sci. Instrum. 67, 3281 (1996)).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from types import MappingProxyType
from typing import TYPE_CHECKING

from ..measurements.schema import AFM_INVERT_RESULTS
from .contract import JobResult, Progress, say

if TYPE_CHECKING:
    import os

    import pandas as pd

    from ..materials import Material

__all__ = ["Result", "Settings", "run"]


@dataclass(frozen=True)
class Settings:
    """How to invert a CR-AFM table.

    Parameters
    ----------
    normalisation : str
        "global" (β_n from f1_free_Hz only) or "modewise" (each mode's own free frequency).
    mode_tolerance : float
        Relative disagreement of κ between modes, dimensionless, beyond which a row is flagged.
    sample : Material or None
        The sample in the frame of its face, for paper 1's dynamic correction of the Hertz rows
        (with its density); None: no correction.
    loss : float
        Material loss Q⁻¹ of the sample for the correction, dimensionless (0: lossless).
    """

    normalisation: str = "global"
    mode_tolerance: float = 0.05
    sample: Material | None = None
    loss: float = 0.0


@dataclass(frozen=True)
class Result(JobResult):
    """``table``: the input's columns (``input_columns``, copied) then the computed ones
    (:data:`contactres.measurements.schema.AFM_INVERT_RESULTS`, which lists the computed
    ones only)."""

    SCHEMAS = MappingProxyType({"table": AFM_INVERT_RESULTS})

    table: pd.DataFrame
    input_columns: tuple[str, ...]


def run(inputs: str | os.PathLike, settings: Settings, progress: Progress | None = None) -> Result:
    """Invert every row of the CR-AFM table ``inputs`` (see the module docstring)."""
    from ..analysis import invert_afm_table
    from ..measurements import read_resonance_table
    from ..measurements.schema import AFM_TABLE

    s = settings
    say(progress, f"reading {Path(inputs).name}")
    checked = read_resonance_table(inputs, AFM_TABLE)
    say(progress, f"inverting {len(checked)} rows")
    table = invert_afm_table(
        checked,
        str(Path(inputs)),
        normalisation=s.normalisation,
        sample=s.sample,
        loss=s.loss,
        mode_tolerance=s.mode_tolerance,
    )
    return Result(table=table, input_columns=tuple(checked.columns))
