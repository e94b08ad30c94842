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

from dataclasses import dataclass

import numpy as np
import pandas as pd

from ._drift import LOAD_OF_EXPERIMENT

__all__ = ["RampCheck", "check_ramps"]

_WORD_UP = r"(?<![a-z])up(?![a-z])"
_WORD_DOWN = r"(?<![a-z])down(?![a-z])"


@dataclass(frozen=True)
class RampCheck:
    """What :func:`check_ramps` found, one entry per sweep where arrays.

    Attributes
    ----------
    first
        The running-in sweep of each load (first in file order; labelled 1 when the labels
        agree with the file).
    suspect
        Sweeps of loads whose labels disagree with the data.
    messages
        One line per problem, naming experiment, load, sweeps and ramps.
    """

    first: np.ndarray
    suspect: np.ndarray
    messages: tuple[str, ...]


def check_ramps(info: pd.DataFrame, first_line: np.ndarray, direction: np.ndarray) -> RampCheck:
    """Check the ramp labels of every load of every experiment against the data.

    ``info``: one row per sweep with ``sweep``, ``ramp`` and the columns of
    :data:`~contactres.analysis._drift.LOAD_OF_EXPERIMENT`; ``first_line``: the line of each
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
    # Every load at once: sweeps sorted by load, then by their first line in the file.
    load = info.groupby(LOAD_OF_EXPERIMENT, sort=False).ngroup().to_numpy()
    order = np.lexsort((first_line, load))
    lo, lab = load[order], ramp[order]
    start = np.r_[True, lo[1:] != lo[:-1]]  # first sweep of each load in the file
    same = ~start
    # Labels that do not rise in file order.
    disorder = np.zeros(load.max() + 1, bool)
    disorder[lo[1:][same[1:] & (np.diff(lab) <= 0)]] = True
    # A gap after a load's first ramp means a ramp was lost (a load may start after ramp 1).
    by_label = np.lexsort((lab, lo))
    l2, r2 = lo[by_label], lab[by_label]
    new_label = np.r_[True, (l2[1:] != l2[:-1]) | (r2[1:] != r2[:-1])]
    n_labels = np.bincount(l2[new_label], minlength=disorder.size)
    span = np.zeros(disorder.size)
    np.maximum.at(span, lo, lab)
    low = np.full(disorder.size, np.inf)
    np.minimum.at(low, lo, lab)
    gaps = (span - low + 1) > n_labels
    # The first sweep measured is the running-in one, whatever its label says.
    bad_order = disorder[lo]
    first[order[bad_order]] = False
    first[order[bad_order & start]] = True
    suspect[order] = (disorder | gaps)[lo]
    for g in np.flatnonzero(disorder | gaps):  # the loads with a problem: a few, for messages
        rows = order[lo == g]
        key = info.iloc[rows[0]]
        where = (
            f"experiment {key['experiment']!r}, {key['configuration']}/{key['medium']}, "
            f"F_N = {key['normal_force_N']:g} N"
        )
        labels = ramp[rows]
        problems = []
        if disorder[g]:
            problems.append(f"ramps in file order are {', '.join(str(r) for r in labels)}")
            sweep = info["sweep"].iloc[rows[0]]
            problems.append(f"ramp 1 taken as sweep {sweep!r}, the first in the file")
        if gaps[g]:
            missing = sorted(
                set(range(int(labels.min()), int(labels.max()) + 1)) - set(labels.tolist())
            )
            problems.append(f"ramp(s) {', '.join(map(str, missing))} missing")
        messages.append(f"{where}: {'; '.join(problems)}")
    # Up/down in a sweep's name against the order of its amplitudes in the file.
    names = info["sweep"].astype(str).str.lower()
    says_up = names.str.contains(_WORD_UP).to_numpy()
    says_down = names.str.contains(_WORD_DOWN).to_numpy()
    label = np.where(says_up & ~says_down, "up", np.where(says_down & ~says_up, "down", ""))
    direction = np.asarray(direction)
    wrong = (label != "") & np.isin(direction, ["up", "down"]) & (label != direction)
    suspect |= wrong
    for i in np.flatnonzero(wrong):
        messages.append(
            f"sweep {info['sweep'].iloc[i]!r} is labelled {str(label[i])!r} but its amplitudes "
            f"run {direction[i]} in the file"
        )
    return RampCheck(first, suspect, tuple(messages))
