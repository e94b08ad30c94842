"""The order of the ramps comes from the table, never from where its rows stand (issue 27,
causes 4 and 9): a permutation of the rows gives the same loads, E and γ; without a ``ramp``
column the ramps are inferred in one stated way, and the result agrees with what is said."""

import re
import warnings
from importlib.resources import as_file, files

import numpy as np
import pandas as pd
import pytest

from contactres.analysis import AnalysisSettings, analyze
from contactres.analysis._flags import Flag, has
from contactres.analysis._ramps import check_ramps
from contactres.measurements._sweeps import SweepWarning, read_sweeps

SETTINGS = AnalysisSettings(bootstrap=50)


@pytest.fixture(scope="module")
def example():
    """One configuration and medium of the bundled example (4 experiments, 6 loads, 4 ramps)."""
    with as_file(files("contactres") / "data" / "example_sweeps.csv") as path:
        raw = pd.read_csv(path)
    return raw[(raw["configuration"] == "SiO2_2.2mm") & (raw["medium"] == "air")]


def _analyze(frame: pd.DataFrame, tmp_path, name: str, **kw):
    path = tmp_path / name
    frame.to_csv(path, index=False)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        table = read_sweeps(path)
    notes = [str(w.message) for w in caught if issubclass(w.category, SweepWarning)]
    return analyze(table, settings=SETTINGS, **kw), notes


@pytest.fixture(scope="module")
def base(example, tmp_path_factory):
    """The analysis of ``example`` as the file holds it: the reference of three tests below."""
    return _analyze(example, tmp_path_factory.mktemp("base"), "base.csv")[0]


def _same_results(a, b):
    keys = ["configuration", "medium", "normal_force_N"]
    la = a.loads.sort_values(keys).reset_index(drop=True)
    lb = b.loads.sort_values(keys).reset_index(drop=True)
    pd.testing.assert_frame_equal(la, lb, check_exact=False, rtol=1e-12, atol=0)
    ga, gb = a.groups[0], b.groups[0]
    for key in ("E_Pa", "gamma_J_m2"):
        assert ga[key] == pytest.approx(gb[key], rel=1e-12, abs=0), key
    for key in ("E_err_Pa", "gamma_err_J_m2"):  # the bootstrap draws by name, not by row
        assert ga[key] == pytest.approx(gb[key], rel=1e-9, abs=0), key


def test_a_permutation_of_the_rows_changes_nothing(example, base, tmp_path):
    # main took the first sweep of each load in the file as running-in, whatever its ramp
    # label: shuffled rows tested the real ramp 1 for drift and lost loads (E withheld).
    shuffled = example.sample(frac=1.0, random_state=np.random.default_rng(7))
    perm, notes = _analyze(shuffled, tmp_path, "perm.csv")
    assert np.isfinite(base.groups[0]["E_Pa"])
    _same_results(base, perm)
    assert perm.messages == base.messages and not notes
    sw = perm.sweeps
    assert sorted(sw.loc[has(sw["flags"], Flag.FIRST_RAMP), "ramp"].unique()) == [1]
    assert not has(sw["flags"], Flag.RAMP_ORDER).any()


def test_reordered_sweeps_keep_their_labelled_running_in_ramp(example, base, tmp_path):
    # Whole sweeps in reverse order (rows within each sweep kept): ramp 4 first in the file.
    order = example.groupby("sweep", sort=False).ngroup()
    reverse = example.assign(_k=-order).sort_values("_k", kind="stable").drop(columns="_k")
    rev, _ = _analyze(reverse, tmp_path, "reverse.csv")
    _same_results(base, rev)


def test_without_a_ramp_column_the_stated_inference_is_what_is_done(example, base, tmp_path):
    # main said "all sweeps are used" and then drift-flagged every load (0 used): the
    # running-in ramp, offset from the others, entered the drift test.
    res, notes = _analyze(example.drop(columns="ramp"), tmp_path, "noramp.csv")
    assert len(notes) == 1
    assert "ramps of each load are inferred as its sweeps in the order of the file" in notes[0]
    assert "the first one taken as running-in" in notes[0]
    sw = res.sweeps
    first = has(sw["flags"], Flag.FIRST_RAMP)
    # The first sweep of each load in the file: the one labelled 1 in the full table.
    assert set(sw.loc[first, "sweep"]) == set(base.sweeps.loc[base.sweeps["ramp"] == 1, "sweep"])
    assert not sw.loc[first, "used"].any()
    assert int(sw["used"].sum()) == int(base.sweeps["used"].sum()) > 0
    drift = sw.loc[has(sw["flags"], Flag.DRIFT), "sweep"]
    assert set(drift) == set(base.sweeps.loc[has(base.sweeps["flags"], Flag.DRIFT), "sweep"])
    assert res.groups[0]["E_Pa"] == pytest.approx(base.groups[0]["E_Pa"], rel=1e-12)


def test_times_order_the_ramps_and_the_points(example, tmp_path):
    # With time_s the order of measurement is the times', whatever the file's order: a table
    # whose rows are shuffled but whose times follow the measurement is read as measured.
    timed = example.assign(time_s=np.arange(len(example), dtype=float))
    base, _ = _analyze(timed, tmp_path, "timed.csv")
    shuffled = timed.sample(frac=1.0, random_state=np.random.default_rng(3))
    perm, _ = _analyze(shuffled, tmp_path, "timed_perm.csv")
    _same_results(base, perm)
    assert list(perm.sweeps.sort_values("sweep")["direction"]) == list(
        base.sweeps.sort_values("sweep")["direction"]
    )


def test_up_and_down_in_names_are_whole_words_as_the_plain_search_finds_them():
    # check_ramps searches the look-around pattern only in names holding "up"/"down" at all:
    # the verdict must be that of the pattern searched in every name (written here with re).
    names = [
        "s-up", "S_UP_2", "setup", "upward", "pushup/down", "Down", "downhill", "r1 down",
        "ramp-up-labelled", "x", "u p", "UP", "cup-down", "lookup-2", "DOWN-up", "sweep_7",
    ]  # fmt: skip
    n = len(names)
    info = pd.DataFrame(
        {
            "sweep": names,
            "experiment": "e1",
            "configuration": "c",
            "medium": "air",
            "normal_force_N": 1e-3,
            "ramp": np.arange(1, n + 1),
        }
    )
    rng = np.random.default_rng(3)
    direction = rng.choice(np.array(["up", "down", "mixed"], dtype=object), n)
    got = check_ramps(info, np.arange(n), direction)
    up = [re.search(r"(?<![a-z])up(?![a-z])", s.lower()) is not None for s in names]
    down = [re.search(r"(?<![a-z])down(?![a-z])", s.lower()) is not None for s in names]
    label = [
        "up" if u and not d else "down" if d and not u else ""
        for u, d in zip(up, down, strict=True)
    ]
    wrong = [
        bool(lab) and dr in ("up", "down") and lab != dr
        for lab, dr in zip(label, direction, strict=True)
    ]
    assert got.suspect.tolist() == wrong
    said = sorted(m.split("'")[1] for m in got.messages if "is labelled" in m)
    assert said == sorted(s for s, w in zip(names, wrong, strict=True) if w)
    assert any(wrong) and not all(wrong)


@pytest.mark.parametrize("times", [None, [3.0, 3.0, 5.0, 9.0], [np.nan] * 4])
def test_tied_ramps_are_ordered_by_sweep_name_then_line(times):
    # Repeated ramp labels (or equal or missing first times) of one load: the running-in
    # sweep is the first of the tie by name, whatever the order of the rows. The reference
    # sorts the sweeps in Python by (position, name, line), missing times last.
    names = ["z", "a", "m", "b"]
    info = pd.DataFrame(
        {
            "sweep": names,
            "ramp": [1, 1, 2, 3],
            "experiment": "e1",
            "configuration": "c",
            "medium": "air",
            "normal_force_N": 1e-3,
        }
    )
    lines = np.array([2, 14, 26, 38])
    times = None if times is None else np.array(times)
    got = check_ramps(info, lines, np.array(["up"] * 4), times)
    position = info["ramp"].to_numpy(float) if times is None else times
    key = [
        (np.isnan(p), 0.0 if np.isnan(p) else p, n, ln)
        for p, n, ln in zip(position, names, lines, strict=True)
    ]
    first = min(range(4), key=lambda i: key[i])
    assert names[first] == "a"
    assert got.first.tolist() == [i == first for i in range(4)]
