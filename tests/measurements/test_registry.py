"""The schemas and the reader recipes are complete: a walk over every one of them.

Every table schema: column names unique, a unit in the name of every column with a unit, a
rule for every required column, every rule a callable with its words. Every reader recipe:
names unique within their kind, suffixes lower case with the dot, ``detect``/``load``
callable, a known kind; and the registry is a value (adding a reader leaves it unchanged).
"""

import re

import numpy as np
import pandas as pd
import pytest

from contactres.errors import ContactresInputError
from contactres.jobs.readers import ALL_READERS, GRID_READER
from contactres.measurements import schema
from contactres.measurements.readers import (
    BUILT_IN,
    KINDS,
    RESONANCE_READERS,
    Reader,
    Readers,
    pick_reader,
)
from contactres.measurements.schema import (
    INPUTS,
    SCHEMAS,
    SWEEP_TABLE,
    Column,
    Rule,
    TableSchema,
    check_cells,
    check_value,
)

# How a unit is spelled in a column name (``kappa_N_per_m``, ``area_m2``).
SPELLINGS = {
    "m^2": ("m2",),
    "Hz/m": ("Hz_per_m",),
    "Hz/m^2": ("Hz_per_m2",),
    "N/m": ("N_per_m",),
    "J/m^2": ("J_m2",),
    "kg/m^3": ("kg_m3",),
    "Hz/(N/m)": ("Hz_per_N_per_m",),
    "N s/m": ("N_s_per_m",),
    "kg/s": ("kg_per_s",),
    "1/m^2": ("per_m2",),
}
WITHOUT_UNIT = ("-", "text")


def test_the_walk_sees_every_schema_of_the_package():
    """No TableSchema defined in the schema package is missing from SCHEMAS."""
    found = {id(v) for v in vars(schema).values() if isinstance(v, TableSchema)}
    assert found == {id(s) for s in SCHEMAS}
    assert len(SCHEMAS) == 28
    assert len({s.name for s in SCHEMAS}) == len(SCHEMAS)


@pytest.mark.parametrize("table", SCHEMAS, ids=lambda s: s.name)
def test_every_schema_is_complete(table):
    names = table.names
    assert len(set(names)) == len(names), f"{table.name}: a column name twice"
    for c in table.columns:
        assert isinstance(c, Column) and c.meaning.strip()
        if c.unit not in WITHOUT_UNIT:
            spelled = SPELLINGS.get(c.unit, (c.unit,))
            # the unit as whole words of the name (``df0_Hz_mean``: a statistic after it)
            assert any(f"_{s}_" in c.name + "_" for s in spelled), (
                f"{table.name}: column {c.name!r} has unit {c.unit!r} but not in its name"
            )
        if c.required:
            assert c.rules, f"{table.name}: required column {c.name!r} has no rule"
        for r in c.rules:
            assert isinstance(r, Rule) and callable(r.check) and r.message.strip()
            assert r.text.strip() or not r.shown, f"{c.name}: a shown rule needs its words"
    if table not in INPUTS:
        assert not any(c.rules or c.required for c in table.columns), "outputs are not read"


def test_rule_words_in_the_dictionary_are_the_shown_rules():
    amplitude = SWEEP_TABLE.column("amplitude_m")
    assert amplitude.rule == ">= 0, 0 or >= 1e-13, <= 1e-06"
    assert SWEEP_TABLE.column("df_Hz").rule == ""  # only the unsaid "a finite number"


def test_the_validator_names_file_line_column_value_and_rule():
    """check_cells against messages written out here by hand."""
    table = pd.DataFrame({"x": ["1", "-2", "-3"], "line": [2, 3, 5]})
    positive = Rule("positive", lambda v: v > 0, "> 0", ": must be > 0")
    values = np.array([1.0, -2.0, -3.0])
    with pytest.raises(ContactresInputError) as err:
        check_cells(table, "t.csv", "x", (positive,), values)
    assert str(err.value) == (
        "t.csv, line 3, column 'x' (2 such rows: lines 3, 5): value '-2': must be > 0"
    )
    # blank cells are not given: no rule applies to them
    check_cells(table, "t.csv", "x", (positive,), values, given=values > 0)
    with pytest.raises(ContactresInputError, match=r"^argument x: x = -1 must be > 0$"):
        check_value("x", -1.0, "argument x", "-1", (Rule("", lambda v: v > 0, "", " must be > 0"),))


def test_rules_run_in_order_the_first_broken_is_reported():
    low = Rule("low", lambda v: v >= 0, ">= 0", " is negative")
    high = Rule("high", lambda v: v <= 1, "<= 1", " is above 1")
    table = pd.DataFrame({"x": [5.0, -1.0], "line": [2, 3]})
    with pytest.raises(ContactresInputError, match=r"line 3.* is negative$"):
        check_cells(table, "t", "x", (low, high))


# --- the reader recipes -----------------------------------------------------------------------


@pytest.mark.parametrize("registry", [BUILT_IN, ALL_READERS], ids=["built-in", "all"])
def test_every_reader_recipe_is_complete(registry):
    seen = set()
    for r in registry:
        assert isinstance(r, Reader)
        assert r.kind in KINDS
        assert (r.kind, r.name) not in seen, f"two {r.kind} readers named {r.name!r}"
        seen.add((r.kind, r.name))
        assert re.fullmatch(r"[a-z0-9-]+", r.name)
        assert all(re.fullmatch(r"\.[a-z0-9]+", s) for s in r.suffixes)
        assert callable(r.detect) and callable(r.load)


def test_the_resonance_readers_are_the_built_in_ones_of_their_kind():
    # read_resonance_table picks from RESONANCE_READERS by default: the very recipes of
    # BUILT_IN of kind "resonances", in the order BUILT_IN tries them, and no other.
    assert RESONANCE_READERS.readers == BUILT_IN.of_kind("resonances")
    assert all(
        a is b for a, b in zip(RESONANCE_READERS, BUILT_IN.of_kind("resonances"), strict=True)
    )
    assert {r.kind for r in RESONANCE_READERS} == {"resonances"}


def test_every_kind_has_a_reader():
    assert {r.kind for r in ALL_READERS} == set(KINDS)


@pytest.mark.parametrize(
    "bad",
    [
        dict(kind="pictures"),
        dict(suffixes=(".CSV",)),
        dict(suffixes=("csv",)),
        dict(suffixes=".csv"),
        dict(load=None),
    ],
)
def test_a_malformed_recipe_is_refused(bad):
    fields = dict(name="x", suffixes=(".x",), detect=lambda p, h: True, load=len, kind="sweeps")
    with pytest.raises(ContactresInputError):
        Reader(**{**fields, **bad})


def test_adding_a_reader_gives_a_new_registry(tmp_path):
    path = tmp_path / "a.dat"
    path.write_text("MAGIC\n1 2\n")
    mine = Reader("magic", (".dat",), lambda p, head: head.startswith("MAGIC"), len, "sweeps")
    grown = BUILT_IN.with_reader(mine)
    assert isinstance(grown, Readers) and len(grown) == len(BUILT_IN) + 1
    assert mine not in BUILT_IN.readers
    assert grown.pick(path, "sweeps") is mine
    assert pick_reader(path, "sweeps", extra=(mine,)) is mine
    known = r"formats known: csv \(.csv/.txt/.tsv\), xlsx \(.xlsx\)$"
    with pytest.raises(ContactresInputError, match=known):
        pick_reader(path, "sweeps")
    with pytest.raises(ContactresInputError, match="already registered"):
        grown.with_reader(mine)
    # the same name in another kind is another reader
    assert grown.with_reader(Reader("magic", (), mine.detect, len, "grid")).named("magic", "grid")


def test_pick_tries_the_matching_suffix_first(tmp_path):
    path = tmp_path / "t.csv"
    path.write_text("a,b\n1,2\n")
    either = [
        Reader(n, s, lambda p, head: True, len, "sweeps")
        for n, s in (("first", (".txt",)), ("second", (".csv",)))
    ]
    assert Readers(tuple(either)).pick(path, "sweeps").name == "second"
    empty = tmp_path / "e.csv"
    empty.write_text("  \n")
    with pytest.raises(ContactresInputError, match="the file is empty"):
        pick_reader(empty)


def test_the_ebsd_and_grid_recipes_recognise_their_files(tmp_path):
    from contactres.polycrystal._ebsd import write_ang, write_ctf
    from contactres.polycrystal._synthetic import synthetic_polycrystal

    m = synthetic_polycrystal((5, 7), n_grains=3, seed=2, pixel_size=0.5e-6)
    ang, ctf = write_ang(tmp_path / "m.ang", m), write_ctf(tmp_path / "m.ctf", m)
    assert ALL_READERS.pick(ang, "ebsd").name == "ang"
    assert ALL_READERS.pick(ctf, "ebsd").name == "ctf"
    back = ALL_READERS.pick(ang, "ebsd").load(ang)
    np.testing.assert_array_equal(back.euler, m.euler)  # radians with 17 digits
    grid = tmp_path / "k.csv"
    grid.write_text("1.5,2\n,3e2\n")
    assert ALL_READERS.pick(grid, "grid") is GRID_READER
    np.testing.assert_array_equal(GRID_READER.load(grid), [[1.5, 2.0], [np.nan, 300.0]])
    npy = tmp_path / "k.npy"
    np.save(npy, np.ones((2, 3)))
    assert ALL_READERS.pick(npy, "grid") is GRID_READER
    table = tmp_path / "t.csv"
    table.write_text("sweep,amplitude_m\ns,1e-9\n")
    with pytest.raises(ContactresInputError, match="no reader recognises"):
        ALL_READERS.pick(table, "grid")
