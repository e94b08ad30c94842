"""The ramps of one load, checked against the data rather than trusted as labelled.

Paper 2 ramps the amplitude up and down several times at every load; the first ramp is the
running-in one. The ``ramp`` labels of a table are checked against the order of the rows in the
file (the order of measurement) and the amplitudes themselves: labels out of file order, missing
or repeated ramp numbers, and sweeps labelled "up" or "down" whose amplitudes run the other way
are reported by name, and the running-in ramp is the first sweep of the load in the file, not
the one labelled 1 when the two disagree. A load whose ramps start after 1 (the running-in ramp
left out of the table) has no running-in sweep.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

import numpy as np
import pandas as pd

from .drift import LOAD_OF_EXPERIMENT

__all__ = ["RampCheck", "check_ramps"]

_WORD = re.compile(r"(?<![a-z])(up|down)(?![a-z])")


@dataclass(frozen=True)
class RampCheck:
    """What :func:`check_ramps` found, one entry per sweep where arrays.

    Attributes
    ----------
    first : the running-in sweep of each load (first in file order; labelled 1 when the
        labels agree with the file)
    suspect : sweeps of loads whose labels disagree with the data
    messages : one line per problem, naming experiment, load, sweeps and ramps
    """

    first: np.ndarray
    suspect: np.ndarray
    messages: tuple[str, ...]


def check_ramps(info: pd.DataFrame, first_line: np.ndarray, direction: np.ndarray) -> RampCheck:
    """Check the ramp labels of every load of every experiment against the data.

    ``info``: one row per sweep with ``sweep``, ``ramp`` and the columns of
    :data:`~contactres.analysis.drift.LOAD_OF_EXPERIMENT`; ``first_line``: the line of each
    sweep's first row in the file; ``direction``: ``up``, ``down`` or ``mixed`` from the order of
    its amplitudes in the file. A table without ramp labels (ramp 0) is not checked.
    """
    n = len(info)
    ramp = info["ramp"].to_numpy()
    first = ramp == 1
    suspect = np.zeros(n, bool)
    messages: list[str] = []
    if not (ramp > 0).any():
        return RampCheck(first, suspect, ())
    frame = info[[*LOAD_OF_EXPERIMENT, "sweep", "ramp"]].assign(_line=first_line, _pos=np.arange(n))
    for key, part in frame.groupby(LOAD_OF_EXPERIMENT, sort=False):
        part = part.sort_values("_line")
        where = f"experiment {key[0]!r}, {key[1]}/{key[2]}, F_N = {key[3]:g} N"
        labels = part["ramp"].to_numpy()
        pos = part["_pos"].to_numpy()
        problems = []
        if np.any(np.diff(labels) <= 0):
            shown = ", ".join(str(r) for r in labels)
            problems.append(f"ramps in file order are {shown}")
            # The first sweep measured is the running-in one, whatever its label says.
            first[pos] = False
            first[pos[0]] = True
            problems.append(
                f"ramp 1 taken as sweep {part['sweep'].iloc[0]!r}, the first in the file"
            )
        # A load may start after ramp 1 (running-in left out of the table); a gap after its first
        # ramp means a ramp was lost.
        missing = sorted(
            set(range(int(labels.min()), int(labels.max()) + 1)) - set(labels.tolist())
        )
        if missing:
            problems.append(f"ramp(s) {', '.join(map(str, missing))} missing")
        if problems:
            suspect[pos] = True
            messages.append(f"{where}: {'; '.join(problems)}")
    sweep_names = info["sweep"].astype(str).str.lower().to_numpy()
    for i, name in enumerate(sweep_names):
        words = set(_WORD.findall(name))
        if len(words) == 1 and direction[i] in ("up", "down") and direction[i] not in words:
            suspect[i] = True
            messages.append(
                f"sweep {info['sweep'].iloc[i]!r} is labelled {words.pop()!r} but its amplitudes "
                f"run {direction[i]} in the file"
            )
    return RampCheck(first, suspect, tuple(messages))
