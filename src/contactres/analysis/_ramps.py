"""The ramps of one load, checked against the data rather than trusted as labelled.

Paper 2 ramps the amplitude up and down several times at every load; the first ramp is the
running-in one. Which sweep came first is read from an explicit ordering, never from where a
row stands in the file (issue 27: shuffling the rows of a table must not change its results):

* with a ``time_s`` column (in every row) the ramps of a load are ordered by the time of their
  first point, and the ``ramp`` labels are checked against that order: labels out of time order,
  missing or repeated ramp numbers, and sweeps labelled "up" or "down" whose amplitudes run the
  other way in time are reported by name, and the running-in ramp is the first sweep measured,
  not the one labelled 1 when the two disagree;
* without times the ``ramp`` labels are the order (the schema: "order of the ramps of one
  load"), checked for missing and repeated numbers (repeated labels are ordered by sweep name);
* without ``ramp`` labels (ramp 0) the ramps are inferred: the sweeps of each load in time
  order, else in the order of the file (the only order there is), the first one running-in.

A load whose ramps start after 1 (the running-in ramp left out of the table) has no running-in
sweep.
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
        The running-in sweep of each load (the first measured: labelled 1 when the labels agree
        with the times; module docstring).
    suspect
        Sweeps of loads whose labels disagree with the data.
    messages
        One line per problem, naming experiment, load, sweeps and ramps.
    """

    first: np.ndarray
    suspect: np.ndarray
    messages: tuple[str, ...]


def _says(names: pd.Series, word: str, pattern: str) -> np.ndarray:
    """Whether each of ``names`` matches ``pattern`` (the whole ``word``), searched only in the
    names that hold ``word`` at all (a match needs it): the look-around search in every name
    was ~40 % of check_ramps at 10^5 sweeps (0.32 s, now 0.19 s; issue 31, point 3)."""
    says = names.str.contains(word, regex=False).to_numpy(dtype=bool, copy=True)
    if says.any():
        says[says] = names[says].str.contains(pattern).to_numpy(dtype=bool)
    return says


def _name_ranks(info: pd.DataFrame) -> np.ndarray:
    """The rank of each sweep's name (``info["sweep"]``) among the names sorted."""
    return pd.factorize(info["sweep"].astype(str), sort=True)[0]


def check_ramps(
    info: pd.DataFrame,
    first_line: np.ndarray,
    direction: np.ndarray,
    first_time: np.ndarray | None = None,
) -> RampCheck:
    """Check the ramp labels of every load of every experiment against the data.

    ``info``: one row per sweep with ``sweep``, ``ramp`` and the columns of
    :data:`~contactres.analysis._drift.LOAD_OF_EXPERIMENT`; ``first_line``: the line of each
    sweep's first row in the file; ``direction``: ``up``, ``down`` or ``mixed`` from the order of
    its amplitudes (in time where the table has times, else in the file); ``first_time``: the
    time of each sweep's first point (s), or None for a table without times. The order of the
    ramps: module docstring.
    """
    n = len(info)
    ramp = info["ramp"].to_numpy()
    first = ramp == 1
    suspect = np.zeros(n, bool)
    messages: list[str] = []
    labelled = bool((ramp > 0).any())
    timed = first_time is not None
    # The order of measurement: time, else the labels, else (no labels) the file.
    if timed:
        position, word = np.asarray(first_time, dtype=float), "time order"
    elif labelled:
        position, word = ramp.astype(float), "label order"
    else:
        position, word = np.asarray(first_line, dtype=float), "file order"
    # Every load at once (numbered in sorted order: no file order), sweeps sorted by position;
    # ties (repeated labels) by sweep name, then line.
    load = info.groupby(LOAD_OF_EXPERIMENT, sort=True).ngroup().to_numpy()
    order = np.lexsort((position, load))
    lo, at = load[order], position[order]
    tied = (lo[1:] == lo[:-1]) & ((at[1:] == at[:-1]) | (np.isnan(at[1:]) & np.isnan(at[:-1])))
    # The rank of each sweep's name, sorted only where it decides (sorting 10^5 names cost
    # ~0.04 s, issue 31, point 3): with no tie the keys (load, position) are distinct, so the
    # order is the same without it, and the names' messages below are the few sweeps they name.
    by_name = None
    if tied.any():
        by_name = _name_ranks(info)
        order = np.lexsort((first_line, by_name, position, load))
    lo, lab = load[order], ramp[order]
    start = np.r_[True, lo[1:] != lo[:-1]]  # first sweep of each load measured
    if not labelled:  # inferred ramps: the first sweep of each load is the running-in one
        first[order[start]] = True
        return RampCheck(first, suspect, ())
    same = ~start
    # Labels that do not rise in the order of measurement.
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
            problems.append(f"ramps in {word} are {', '.join(str(r) for r in labels)}")
            sweep = info["sweep"].iloc[rows[0]]
            first_of = "the first measured" if timed else "the first by name"
            problems.append(f"ramp 1 taken as sweep {sweep!r}, {first_of}")
        if gaps[g]:
            missing = sorted(
                set(range(int(labels.min()), int(labels.max()) + 1)) - set(labels.tolist())
            )
            problems.append(f"ramp(s) {', '.join(map(str, missing))} missing")
        messages.append(f"{where}: {'; '.join(problems)}")
    # Up/down in a sweep's name against the order of its amplitudes (in time, else the file).
    names = info["sweep"].astype(str).str.lower()
    says_up, says_down = _says(names, "up", _WORD_UP), _says(names, "down", _WORD_DOWN)
    label = np.where(says_up & ~says_down, "up", np.where(says_down & ~says_up, "down", ""))
    direction = np.asarray(direction)
    wrong = (label != "") & np.isin(direction, ["up", "down"]) & (label != direction)
    suspect |= wrong
    if wrong.any():  # named in the order of their names
        ranks = _name_ranks(info) if by_name is None else by_name
        for i in np.flatnonzero(wrong)[np.argsort(ranks[wrong], kind="stable")]:
            messages.append(
                f"sweep {info['sweep'].iloc[i]!r} is labelled {str(label[i])!r} but its "
                f"amplitudes run {direction[i]} in {'time' if timed else 'the file'}"
            )
    return RampCheck(first, suspect, tuple(messages))
