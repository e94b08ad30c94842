"""The one schema: README tables, validator, writers and flags all agree with it."""

from pathlib import Path

import numpy as np
import pytest

from contactres.analysis.flags import DESCRIPTIONS, Flag, has, render
from contactres.measurements.schema import SWEEP_TABLE
from contactres.measurements.sweeps import VALIDATED_COLUMNS
from contactres.report.dictionary import BLOCK, dictionary_tables, update_blocks

README = Path(__file__).resolve().parents[2] / "README.md"


def test_readme_tables_are_the_schema():
    text = README.read_text(encoding="utf-8")
    found = {m.group("name"): m.group("body").strip() for m in BLOCK.finditer(text)}
    tables = dictionary_tables()
    assert set(found) == set(tables), "README blocks and schema tables differ in name"
    for name, table in tables.items():
        assert found[name] == table, f"README block {name!r} is stale: run scripts/update_readme.py"
    assert update_blocks(text) == text


def test_validated_table_has_exactly_the_schema_columns():
    assert set(VALIDATED_COLUMNS) == {*SWEEP_TABLE.names, "line"}


def test_every_flag_is_documented_and_rendered_in_order():
    assert set(DESCRIPTIONS) == set(Flag)
    assert all(DESCRIPTIONS[f].strip() for f in Flag)
    texts = [f.text for f in Flag]
    assert len(set(texts)) == len(texts)
    mask = np.array([0, int(Flag.DRIFT | Flag.FIRST_RAMP), int(Flag.PLATEAU_SLOPE)])
    assert list(render(mask)) == ["", "first-ramp;drift", "plateau-slope"]
    assert list(has(mask, Flag.DRIFT)) == [False, True, False]


@pytest.mark.parametrize("flag", list(Flag))
def test_every_flag_is_explained_in_the_readme(flag):
    text = README.read_text(encoding="utf-8")
    assert f"| `{flag.text}` | {DESCRIPTIONS[flag]} |" in text


def test_flags_table_has_two_cells_per_row():
    from contactres.report.dictionary import flags_markdown

    assert all(line.count("|") == 3 for line in flags_markdown().splitlines())
