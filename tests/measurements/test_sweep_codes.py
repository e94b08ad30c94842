"""The codes of the sweep ids and labels that the sweep validator finds once and lends to the
checks of the rows (duplicates, one value per sweep, the sign of ΔΓ, too few points): each
check decides and says exactly what it does when it hashes the texts itself (issue 31, point 3:
the 10^6 sweep ids of 10^5 sweeps were hashed again by every check)."""

from __future__ import annotations

import warnings

import numpy as np
import pandas as pd
import pytest

from contactres.errors import ContactresInputError
from contactres.measurements import validate_sweeps
from contactres.measurements._sweep_checks import (
    check_dissipation_sign,
    check_per_sweep,
    drop_duplicates,
    point_keys,
    warn_sweeps,
)
from contactres.measurements._sweeps import PER_SWEEP_COLUMNS, _labels

CONST = dict(overtone=3, area_m2=2.5e-5, n_contacts=3, sphere_radius_m=1.1e-3)
IDS = ("s0", " s0", "s0 ", "s1", "s 1", "s2", "\ts1")  # white space around: one id, stripped


def _raw(rng: np.random.Generator, n: int) -> pd.DataFrame:
    """A table of text labels (ids written with and without white space around them) and
    numbers, as a reader gives it."""
    return pd.DataFrame(
        {
            "sweep": pd.Series(rng.choice(IDS, n), dtype=object),
            "experiment": pd.Series(rng.choice(["e1", " e1", "e2"], n), dtype=object),
            "configuration": pd.Series(rng.choice(["SiO2", "SiO2 ", "Si"], n), dtype=object),
            "medium": pd.Series(rng.choice(["air", "water"], n), dtype=object),
            "amplitude_m": rng.choice([1e-9, 2e-9], n),
            "df_Hz": rng.choice([50.0, 51.0], n),
            "dgamma_Hz": rng.choice([-1.0, 5.0], n),
        }
    )


def test_label_codes_are_equal_where_the_stripped_texts_are():
    """_labels' codes are pandas' own factorisation of the column it writes (the stripped
    texts): equal codes where, and only where, the texts are equal, first seen first."""
    rng = np.random.default_rng(3)
    for trial in range(50):
        raw = _raw(rng, int(rng.integers(1, 60)))
        for col in ("sweep", "experiment", "configuration", "medium"):
            out = pd.DataFrame({"line": np.arange(len(raw))})
            codes = _labels(out, raw, "<t>", col)
            np.testing.assert_array_equal(codes, pd.factorize(out[col])[0], err_msg=str(trial))


def _said(check, *args) -> tuple[str | None, list[str]]:
    """(the error ``check(*args)`` raises, or None; the warnings it gives), as text."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            check(*args)
            error = None
        except ContactresInputError as exc:
            error = str(exc)
    return error, [str(w.message) for w in caught]


def test_checks_with_the_codes_decide_and_say_what_they_do_without():
    """Each check of the rows, given the codes, raises the error and gives the warnings it
    gives when it hashes the texts itself, on random tables of ids that differ by white space
    only, conflicting labels, repeated points, short sweeps and negative ΔΓ."""
    rng = np.random.default_rng(8)
    seen = {"error": 0, "warning": 0, "quiet": 0}
    for trial in range(200):
        raw = _raw(rng, int(rng.integers(2, 40)))
        out = pd.DataFrame({"line": np.arange(2, len(raw) + 2)})
        codes = {c: _labels(out, raw, "<t>", c) for c in ("sweep", "experiment")}
        codes |= {c: _labels(out, raw, "<t>", c) for c in ("configuration", "medium")}
        for c in ("amplitude_m", "df_Hz", "dgamma_Hz"):
            out[c] = raw[c].to_numpy()
        out["normal_force_N"] = 2e-3
        out["ramp"] = 1
        for c in ("fundamental_Hz", "overtone", "area_m2", "n_contacts"):
            out[c] = 1.0
        out["sphere_radius_m"] = np.where(rng.random() < 0.2, rng.choice([1e-3, 2e-3]), 1e-3)
        out["poisson"] = 0.17
        out["time_s"] = np.nan
        with_codes = _said(drop_duplicates, out, "<t>", codes["sweep"])
        assert with_codes == _said(drop_duplicates, out, "<t>"), trial
        kept = drop_duplicates(out, "<t>") if not with_codes[1] else None
        if kept is None:  # rows dropped: the validator hashes the texts again
            continue
        per_sweep = tuple(c for c in PER_SWEEP_COLUMNS if c in out)
        said = _said(check_per_sweep, out, "<t>", per_sweep, codes)
        assert said == _said(check_per_sweep, out, "<t>", per_sweep), trial
        for check in (check_dissipation_sign, warn_sweeps):
            said = _said(check, out, "<t>", codes["sweep"])
            assert said == _said(check, out, "<t>"), (trial, check)
            seen["error" if said[0] else "warning" if said[1] else "quiet"] += 1
    assert min(seen.values()) > 0, seen  # every outcome met


def test_ids_that_differ_by_white_space_are_one_sweep_in_every_check():
    """A sweep written as ``s1`` and `` s1 ``, its experiment as ``e1`` and ``e1 ``, is one sweep
    of one experiment (the stripped text): no conflict; its repeated point is dropped as one
    row; a second experiment within it is a conflict."""
    base = dict(configuration="SiO2", medium="air", ramp=1, normal_force_N=2e-3)
    rows = [
        dict(sweep=s, experiment=e, amplitude_m=2e-9 * (k + 1), df_Hz=60.0, dgamma_Hz=5.0, **base)
        for k, (s, e) in enumerate([("s1", "e1"), (" s1 ", "e1 ")] * 3)
    ]
    table = pd.DataFrame(rows)
    assert validate_sweeps(table, constants=CONST).data["sweep"].unique().tolist() == ["s1"]
    repeated = pd.concat([table, table.iloc[[2]].assign(sweep="s1 ")], ignore_index=True)
    with pytest.warns(UserWarning, match=r"1 duplicated row\(s\) dropped"):
        assert len(validate_sweeps(repeated, constants=CONST).data) == len(table)
    other = table.assign(experiment=["e1", "e1 ", "e1", "e2", "e1", "e1"])
    with pytest.raises(ContactresInputError, match=r"sweep 's1': conflicting values in column"):
        validate_sweeps(other, constants=CONST)


def test_rows_that_pandas_finds_repeated_have_one_key_and_are_dropped_alike():
    """point_keys gives rows that pandas' ``duplicated`` pairs (0.0 and -0.0 one value, NaN
    with NaN) one key, so that no repeated point is missed; and drop_duplicates drops the rows
    and says the lines it does without the codes, on random tables of few values."""
    rng = np.random.default_rng(21)
    for trial in range(300):
        n = int(rng.integers(1, 30))
        values = [0.0, -0.0, 1.5, 2.5] + ([np.nan] if trial % 4 == 0 else [])
        ids = pd.Series(rng.choice(["a", "b", "c"], n), dtype=object)
        out = pd.DataFrame(
            {
                "line": np.arange(2, n + 2),
                "sweep": ids,
                "amplitude_m": rng.choice(values, n),
                "df_Hz": rng.choice(values[:3], n),
                "dgamma_Hz": rng.choice([1.0, 2.0], n),
                "ramp": rng.choice([1, 2], n),
            }
        )
        codes = pd.factorize(ids)[0]
        numbers = [out[c].to_numpy() for c in ("amplitude_m", "df_Hz", "dgamma_Hz")]
        keys = point_keys(codes, numbers)
        point = ["sweep", "amplitude_m", "df_Hz", "dgamma_Hz"]
        for _, rows in out.groupby(point, dropna=False, sort=False).groups.items():
            assert len(set(keys[np.asarray(rows)].tolist())) == 1, (trial, out)
        kept, said = _kept_and_said(out, codes), _kept_and_said(out, None)
        assert said[1] == kept[1], trial
        pd.testing.assert_frame_equal(said[0], kept[0])


def _kept_and_said(out: pd.DataFrame, codes) -> tuple[pd.DataFrame, list[str]]:
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        kept = drop_duplicates(out, "<t>", codes)
    return kept, [str(w.message) for w in caught]


def test_distinct_points_have_distinct_keys():
    """The keys of 10^5 distinct points of a sweep table's kind (a few amplitudes and loads,
    noisy shifts) do not collide, so that the rows are not compared again."""
    rng = np.random.default_rng(2)
    n = 100_000
    codes = np.repeat(np.arange(n // 10), 10)
    amplitude = np.tile(np.linspace(1e-9, 1e-8, 10), n // 10)
    numbers = [amplitude, rng.normal(50.0, 1.0, n), rng.normal(5.0, 0.1, n)]
    assert not pd.Series(point_keys(codes, numbers)).duplicated().any()


@pytest.mark.parametrize("order", ["runs", "shuffled"])
def test_distinct_cells_are_numbered_by_first_appearance_as_each_cell_would_be(order):
    """stripped_codes hashes the first cell of each run of equal cells only (issue 31,
    point 3): its codes and distinct texts are those a dictionary of first appearances gives
    over every cell's text (white space stripped after), for cells in runs (a sweep's id on its
    rows) and shuffled (runs of one cell). A cell's text is pandas' ``astype(str)`` of it, one
    cell at a time: pandas 3 keeps None and NaN missing (one text of their own), pandas 2
    writes "None" and "nan" (pyproject allows pandas >= 2.0)."""
    from contactres.measurements._cell_text import stripped_codes

    rng = np.random.default_rng(29)
    labels = [*IDS, None, np.nan, "", "  "]
    pick = np.repeat(rng.integers(0, len(labels), 400), 3)
    if order == "shuffled":
        pick = pick[rng.permutation(pick.size)]
    cells = np.array(labels, dtype=object)[pick]
    codes, distinct, _ = stripped_codes(pd.Series(cells, dtype=object))
    text_of = []  # each label's text, converted alone (no runs)
    for label in labels:
        t = pd.Series([label], dtype=object).astype(str).iloc[0]
        text_of.append("<missing>" if t != t else t)
    assert "<missing>" in text_of or {"None", "nan"} <= set(text_of)
    keys = [text_of[i] for i in pick]
    first: dict = {}
    for key in keys:
        first.setdefault(key, len(first))
    assert codes.tolist() == [first[k] for k in keys]
    texts = [k.strip() if k != "<missing>" else None for k in first]
    assert [None if d != d else d for d in distinct.tolist()] == texts


def test_a_column_varies_within_a_group_where_pandas_counts_two_values():
    """_varies (the grouping's runs given or not) against pandas' nunique per group: groups
    that are runs of rows (a sweep's points) or scattered, rows in no group (-1), floats with
    NaN and -0.0, integers (negative ones too), text with missing cells, codes given."""
    from contactres.measurements._sweep_checks import _varies, _within_runs

    rng = np.random.default_rng(12)
    outcomes = set()
    for trial in range(400):
        n_groups = int(rng.integers(1, 6))
        sizes = rng.integers(1, 5, n_groups)
        group = np.repeat(np.arange(n_groups), sizes)
        if trial % 3 == 1:
            group = rng.permutation(group)
        if trial % 5 == 2:
            group[rng.random(group.size) < 0.2] = -1
        n = group.size
        pick = rng.random(n) < (0.85 if trial % 2 else 0.999)  # mostly the group's own value
        base = rng.integers(-2, 2, n_groups)[np.maximum(group, 0)]
        ints = np.where(pick, base, rng.integers(-2, 2, n))
        floats = ints.astype(float) * 0.5
        floats[floats == 0] = np.where(rng.random(np.count_nonzero(floats == 0)) < 0.5, 0.0, -0.0)
        if trial % 4 == 3:
            floats[rng.random(n) < 0.2] = np.nan
        text = pd.Series(np.where(np.isnan(floats), None, floats.astype(str)), dtype=object)
        inner = _within_runs(group)
        if trial % 3 != 1 and trial % 5 != 2:
            assert inner is not None  # runs of rows, every row in a group
        for cells in (pd.Series(ints), pd.Series(floats), text):
            frame = pd.DataFrame({"g": np.where(group >= 0, group, np.nan), "v": cells})
            want = bool((frame.groupby("g")["v"].nunique() > 1).any())
            codes = pd.factorize(cells)[0] if cells.dtype == object else None
            for given in (None, codes):
                assert _varies(group, cells, given, inner) == want, trial
                assert _varies(group, cells, given, None) == want, trial
            outcomes.add((want, inner is not None))
    assert len(outcomes) == 4  # each outcome, with and without runs


@pytest.mark.parametrize("spread", [1, 3, 100])  # mostly distinct cells, or runs of them
def test_stripped_cells_and_codes_are_pandas_own(spread):
    """stripped (its cells stripped one by one where most are distinct, else each distinct
    text once) against pandas stripping every cell; stripped_codes' codes, where it says they
    need no second hashing, against pandas' factorisation of the stripped texts; and its
    flag false where a strip made two texts one or a cell is missing."""
    from contactres.measurements._cell_text import stripped_codes
    from contactres.measurements.schema import stripped

    rng = np.random.default_rng(spread)
    flags = set()
    for trial in range(60):
        words = [f"w{i}" for i in range(int(rng.integers(1, 40)))]
        if trial % 3 == 1:
            words += [" w0", "w1 "]  # one text once stripped
        if trial % 5 == 2:
            words += [None, np.nan]
        cells = pd.Series(
            np.repeat(np.array(words, dtype=object)[rng.integers(0, len(words), 50)], spread),
            dtype=object,
        )
        want = cells.astype(str).str.strip().to_numpy(dtype=object)
        got = stripped(cells)
        assert [x if x == x else None for x in got] == [x if x == x else None for x in want]
        codes, distinct, exact = stripped_codes(cells)
        if exact:
            np.testing.assert_array_equal(codes, pd.factorize(distinct[codes])[0])
        else:
            assert trial % 3 == 1 or trial % 5 == 2, trial
        flags.add(exact)
    assert flags == {True, False}
