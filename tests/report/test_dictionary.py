"""The one schema: README tables, validator, writers and flags all agree with it."""

from pathlib import Path

import numpy as np
import pytest

from contactres.analysis._flags import DESCRIPTIONS, Flag, has, render
from contactres.measurements._sweeps import VALIDATED_COLUMNS
from contactres.measurements.schema import SWEEP_TABLE
from contactres.report.dictionary import (
    AFM_INVERT_RESULTS,
    BLOCK,
    DOCS_ONLY,
    RESONANCE_FLAGS,
    RUM_INVERT_RESULTS,
    SPECTRA_FITS,
    STIFFNESS_CSV,
    TABLE_FLAGS,
    dictionary_tables,
    update_blocks,
)

ROOT = Path(__file__).resolve().parents[2]
README = ROOT / "README.md"
DATA = ROOT / "src" / "contactres" / "data"


def test_readme_tables_are_the_schema():
    text = README.read_text(encoding="utf-8")
    found = {m.group("name"): m.group("body").strip() for m in BLOCK.finditer(text)}
    tables = {k: v for k, v in dictionary_tables().items() if k not in DOCS_ONLY}
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


def test_docs_page_includes_every_table():
    page = (ROOT / "docs" / "dictionary.md").read_text(encoding="utf-8")
    for name in dictionary_tables():
        assert f"_generated/{name}.md" in page, f"docs/dictionary.md does not show {name!r}"


def test_spectra_fits_columns_and_flags_are_the_code():
    from contactres.measurements._spectra import COLUMNS, FLAGS

    assert SPECTRA_FITS.names == COLUMNS
    table = dictionary_tables()["spectra-fit-flags"]
    assert [line.split("`")[1] for line in table.splitlines()[2:]] == list(FLAGS)


def test_stiffness_csv_columns_are_the_code():
    from contactres.cli.qcm_stiffness import COLUMN_UNITS

    assert STIFFNESS_CSV.names == tuple(COLUMN_UNITS)


def test_resonance_flags_are_the_code():
    from contactres.analysis._inversion import ModulusFlag
    from contactres.resonators._cantilever_inversion import flag_names

    names = [n.replace("_", "-") for n in flag_names(~0)]
    assert list(RESONANCE_FLAGS) == names
    table = dictionary_tables()["resonance-flags"]
    listed = [line.split("`")[1] for line in table.splitlines()[2:]]
    modulus = [f.name.lower().replace("_", "-") for f in ModulusFlag]
    assert listed == names + modulus + list(TABLE_FLAGS)


def test_invert_outputs_append_exactly_the_listed_columns():
    from contactres.analysis._resonance_tables import invert_afm_table, invert_rum_table
    from contactres.materials import Material
    from contactres.measurements._resonances import AFM_TABLE, RUM_TABLE, read_resonance_table

    afm = read_resonance_table(DATA / "example_afm.csv", AFM_TABLE)
    sample = Material.crystal("Cu").rotated((0, 0, 1))
    out = invert_afm_table(afm, "example_afm.csv", sample=sample)
    given = [c for c in out.columns if c in afm.columns]
    # The film columns are the jobs' (with a coating: tests/jobs/test_job_schemas.py), last.
    film = ("coating", "M_film_Pa", "film_contact_radius_m", "film_weight", "film_verdict")
    assert AFM_INVERT_RESULTS.names[-len(film) :] == RUM_INVERT_RESULTS.names[-len(film) :] == film
    assert tuple(c for c in out.columns if c not in given) == AFM_INVERT_RESULTS.names[: -len(film)]
    rum = read_resonance_table(DATA / "example_rum.csv", RUM_TABLE)
    out = invert_rum_table(rum, "example_rum.csv")
    appended = tuple(c for c in out.columns if c not in rum.columns)
    assert appended == RUM_INVERT_RESULTS.names[: -len(film)]
