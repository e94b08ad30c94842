"""Every table of every job's Result is bound to its schema, and has exactly its columns.

The Result classes are found by walking :mod:`contactres.jobs` (a new job is checked without a
line here). The cheap jobs run on small inputs and the columns of each table they return are
compared with the schema's names, in order; a column the schema says is written only in some
cases is named, per run, in ``absent``. The costly jobs (the demo, paper 1's figures) are
checked through the functions that make their tables, on small grids.
"""

from __future__ import annotations

import dataclasses
import importlib
import pkgutil
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pandas as pd
import pytest

import contactres.jobs
from contactres.jobs.contract import JobResult
from contactres.measurements.schema import SCHEMAS, TableSchema

DATA = Path(__file__).resolve().parents[2] / "src" / "contactres" / "data"


def job_results() -> dict[str, type[JobResult]]:
    """Job module name -> its Result class, for every module of contactres.jobs that has one."""
    found = {}
    for info in pkgutil.iter_modules(contactres.jobs.__path__):
        module = importlib.import_module(f"contactres.jobs.{info.name}")
        result = getattr(module, "Result", None)
        if isinstance(result, type) and issubclass(result, JobResult):
            found[info.name] = result
    return found


RESULTS = job_results()


def test_the_walk_finds_every_job():
    assert {"contact", "dcsf", "qcm_loop", "crystals", "paper1", "paper2", "demo"} <= set(RESULTS)
    # Every module is a job but the contract, and the map computations and the reader registry
    # the jobs share.
    modules = {info.name for info in pkgutil.iter_modules(contactres.jobs.__path__)}
    assert set(RESULTS) == modules - {"contract", "maps", "readers"}


@pytest.mark.parametrize("name", sorted(RESULTS))
def test_no_table_is_unbound(name):
    kind = RESULTS[name]
    fields = {f.name: f for f in dataclasses.fields(kind)}
    for table, schema in kind.SCHEMAS.items():
        assert table in fields, f"{name}: SCHEMAS names {table!r}, not a field of its Result"
        assert isinstance(schema, TableSchema), f"{name}: table {table!r} has no schema"
        assert any(schema is s for s in SCHEMAS), f"{name}: {schema.name!r} not in the schema"
    # The annotations are text (postponed evaluation): a table is a field declared a DataFrame.
    frames = {f for f, field in fields.items() if str(field.type).endswith("DataFrame")}
    assert frames <= set(kind.SCHEMAS), f"{name}: a DataFrame field is not in SCHEMAS"


def test_the_sweep_analysis_binds_its_own_tables():
    # qcm_sweeps carries the analysis's Results and overrides tables() (the tables of the
    # results folder): no job run needed to see which schemas it gives. The stub's empty
    # tables have the analysis's columns and one more, which the folder's tables leave out.
    from contactres.jobs import qcm_sweeps
    from contactres.measurements.schema import (
        CURVE_RESULTS,
        JKR_CURVE_RESULTS,
        LOAD_RESULTS,
        RADIATION_RESULTS,
        SWEEP_RESULTS,
    )

    def empty(schema):
        return pd.DataFrame(columns=["extra", *schema.names])

    stub = SimpleNamespace(sweeps=empty(SWEEP_RESULTS), loads=empty(LOAD_RESULTS), radiation=None)
    tables = qcm_sweeps.Result(analysis=stub, reading=None).tables()
    assert {k: s for k, (_, s) in tables.items()} == {
        "sweeps": SWEEP_RESULTS,
        "loads": LOAD_RESULTS,
    }
    with_radiation = SimpleNamespace(**{**vars(stub), "radiation": empty(RADIATION_RESULTS)})
    tables = qcm_sweeps.Result(analysis=with_radiation).tables()
    assert tables["radiation"][1] is RADIATION_RESULTS
    # The fitted curves (issue 30): tables where the analysis computed them.
    curves = pd.DataFrame(
        {"sweep": ["a", "a"], "grid_points": [30, 30], "amplitude_m": [0.0, 1e-8],
         "df_model_Hz": [1.0, 2.0], "dgamma_model_Hz": [0.1, 0.2]}
    )  # fmt: skip
    jkr = empty(JKR_CURVE_RESULTS).drop(columns="extra")
    every = SimpleNamespace(**{**vars(with_radiation), "curves": curves, "jkr": jkr})
    tables = qcm_sweeps.Result(analysis=every).tables()
    assert tables["curves"][1] is CURVE_RESULTS and tables["jkr_curves"][1] is JKR_CURVE_RESULTS
    assert set(qcm_sweeps.Result.table_names()) == set(tables)
    for frame, schema in tables.values():
        assert_columns(frame, schema)


def assert_columns(frame: pd.DataFrame, schema: TableSchema, absent=(), before=()) -> None:
    """``frame`` has the schema's columns in order, less ``absent`` (columns written only in
    other cases), after the copied input columns ``before``."""
    assert set(absent) <= set(schema.names), f"{schema.name}: {set(absent) - set(schema.names)}"
    expected = [*before, *(n for n in schema.names if n not in absent)]
    assert list(frame.columns) == expected, schema.name


def check_result(result: JobResult, absent: dict | None = None, before=()) -> None:
    """Every table of ``result`` against its schema (``absent``: table -> columns not written
    in this run)."""
    absent = absent or {}
    for f in dataclasses.fields(result):
        if isinstance(getattr(result, f.name), pd.DataFrame):
            assert f.name in result.SCHEMAS, f"{type(result).__module__}: {f.name} is unbound"
    for name, (frame, schema) in result.tables().items():
        assert_columns(frame, schema, absent.get(name, ()), before)


STATIC_TANGENTIAL = ("tangential_stiffness_N_per_m",)
DYNAMIC = (
    "frequency_Hz",
    "ks_a",
    "dynamic_stiffness_real_N_per_m",
    "dynamic_stiffness_imag_N_per_m",
)
DYNAMIC_TANGENTIAL = (
    "tangential_stiffness_real_N_per_m",
    "tangential_stiffness_imag_N_per_m",
    "tangential_loss_tangent",
)
COATED = ("coating", "film_share")
# Only when a contact is wider than Hertz allows (a/R > 0.1; none of these contacts).
FLAGGED = ("flags",)
# The contact ellipse: a bare face only (the coated contact is the axisymmetric approximation).
ELLIPSE = ("semi_major_m", "semi_minor_m", "ellipticity", "orientation_deg")
# The columns afm invert and rum invert add with a coating (the film's modulus).
FILM = ("coating", "M_film_Pa", "film_contact_radius_m", "film_weight", "film_verdict")


@pytest.mark.parametrize(
    "frequency, tangential, coating, absent",
    [
        (None, False, (), COATED + STATIC_TANGENTIAL + DYNAMIC + DYNAMIC_TANGENTIAL),
        (None, True, (), COATED + DYNAMIC + DYNAMIC_TANGENTIAL),
        (1e6, False, (), COATED + STATIC_TANGENTIAL + DYNAMIC_TANGENTIAL),
        (1e6, True, (), COATED + STATIC_TANGENTIAL),
        (None, False, ("Si3N4:1e-6",), ELLIPSE + STATIC_TANGENTIAL + DYNAMIC + DYNAMIC_TANGENTIAL),
        (None, True, ("Si3N4:1e-6",), ELLIPSE + DYNAMIC + DYNAMIC_TANGENTIAL),
        (1e6, False, ("Si3N4:1e-6",), ELLIPSE + STATIC_TANGENTIAL + DYNAMIC_TANGENTIAL),
    ],
)
def test_contact_table_columns(frequency, tangential, coating, absent):
    from contactres.jobs import contact
    from contactres.materials import Material

    # A coating goes on an isotropic glass: the layered solution of a cubic face needs a θ
    # average over many angles, slower and beside the point here.
    face = Material.crystal("soda-lime-glass" if coating else "Cu").rotated((0, 0, 1))
    freq = None if frequency is None else np.array([frequency])
    s = contact.Settings(np.array([1e-3]), np.array([0.5, 1.0]), freq, tangential, 0.0, coating)
    check_result(contact.run(face, s), {"table": absent + FLAGGED})


PHYSICAL = (
    "radius_m",
    "force_N",
    "frequency_Hz",
    "contact_radius_m",
    "stiffness_N_per_m",
    "K_re_N_per_m",
    "K_im_N_per_m",
)


def test_dcsf_table_columns():
    from contactres.jobs import dcsf
    from contactres.materials import Material

    cu = Material.crystal("Cu").rotated((0, 0, 1))
    ka = dcsf.run(cu, dcsf.Settings(ka=np.array([0.1, 0.5]), models=("exact", "WA")))
    check_result(ka, {"table": (*PHYSICAL, "coating")})
    one = np.array([1.0])
    contacts = dcsf.Settings(radius=one * 1e-3, force=one, frequency=one * 1e6)
    check_result(dcsf.run(cu, contacts), {"table": ("coating",)})
    # A coated face: the same columns and the coating.
    silica = Material.crystal("fused-silica")
    coated = dataclasses.replace(contacts, coating=("fused-silica:1e-7",))
    check_result(dcsf.run(silica, coated))


def test_qcm_loop_and_crystals_columns():
    from contactres.jobs import crystals, qcm_loop

    s = qcm_loop.Settings(kappa=1e5, mu=0.5, normal_force=1e-3, u0=np.array([1e-9, 5e-9]))
    check_result(qcm_loop.run(None, s))
    check_result(crystals.run())


def test_inversion_tables_are_the_input_then_the_schema():
    from contactres.jobs import afm_invert, rum_invert
    from contactres.materials import Material

    sample = Material.crystal("Cu").rotated((0, 0, 1))
    afm = afm_invert.run(DATA / "example_afm.csv", afm_invert.Settings(sample=sample))
    rum = rum_invert.run(DATA / "example_rum.csv")
    # A coated sample (the film's modulus): the film columns, without the dynamic correction.
    # The substrates are chosen for the cost of the layered contact, which the columns do not
    # depend on: a trigonal one (sapphire's (001) face: 4 s) and an isotropic one (1 s); a cubic
    # (001) face, not axisymmetric, took 15-22 s a table.
    coated = dict(coating=("fused-silica:50e-9",), substrate=Material.crystal("sapphire"))
    afm_film = afm_invert.run(DATA / "example_afm.csv", afm_invert.Settings(**coated))
    on_silica = dict(coating=("pmma:50e-9",), substrate=Material.crystal("fused-silica"))
    rum_film = rum_invert.run(
        DATA / "example_rum.csv", rum_invert.Settings(**on_silica, tip_radius=1e-6, force=1e-3)
    )
    runs = (
        (afm, "example_afm.csv", FILM),
        (rum, "example_rum.csv", FILM),
        (afm_film, "example_afm.csv", ("k_static_N_per_m", "k_a", "dcsf_real", "dcsf_imag")),
        (rum_film, "example_rum.csv", ()),
    )
    for result, name, absent in runs:
        # The columns the file gave are copied first (the optional ones it lacks are not).
        given = pd.read_csv(DATA / name).columns
        copied = [c for c in result.table.columns if c in set(given)]
        assert set(copied) <= set(result.input_columns)
        check_result(result, {"table": absent}, before=copied)
    assert afm.coating is None and afm_film.coating["label"] == "fused-silica 50 nm"
    assert rum_film.coating["label"] == "PMMA 50 nm"


def test_stiffness_and_spectra_columns():
    from contactres.jobs import qcm_spectra, qcm_stiffness
    from contactres.measurements.schema import SPECTRA_FITS, SPECTRA_SWEEPS, SWEEP_TABLE

    conventions = {"dissipation_scale": 1e-6, "fundamental": 4.95e6}
    settings = qcm_stiffness.Settings(area=2e-5, n_contacts=3, conventions=conventions)
    check_result(qcm_stiffness.run(DATA / "example_qcmd.csv", settings))
    # The bundled spectra carry no time: the table leaves time_s out, and the job drops Q.
    spectra = qcm_spectra.run(DATA / "example_spectra.csv")
    check_result(spectra, {"sweeps": ("time_s", "quality")})
    assert set(SWEEP_TABLE.required) <= set(SPECTRA_SWEEPS.names)
    # The demo's tables: the same reading, which keeps Q, and the built-in solids.
    from contactres.crystals import crystal_table
    from contactres.jobs import demo
    from contactres.measurements._shifts import read_spectra_sweeps

    _, rows, fits, _ = read_spectra_sweeps(DATA / "example_spectra.csv")
    assert demo.Result.SCHEMAS["spectra_rows"] is SPECTRA_SWEEPS
    assert demo.Result.SCHEMAS["spectra_fits"] is SPECTRA_FITS
    assert_columns(rows, SPECTRA_SWEEPS, ("time_s",))
    assert_columns(fits, SPECTRA_FITS)
    assert_columns(crystal_table(), demo.Result.SCHEMAS["crystals"])


def test_paper_tables_columns():
    from contactres.jobs import paper1, paper2

    short = paper2.Settings(amplitudes=(1e-8,), u0=np.array([0.0, 1e-8]))
    check_result(paper2.run(None, short))
    # paper 1's job is costly (every figure): its one table is ranking_table's.
    ranking = paper1.ranking_table(np.linspace(0.0, 1.0, 3), zeners=(1.0,))
    assert_columns(ranking, paper1.Result.SCHEMAS["ranking"])


def test_particles_columns():
    from contactres.jobs import qcm_particles

    settings = qcm_particles.Settings(5e-7, 2200.0, fundamental=5e6, medium="water")
    check_result(qcm_particles.run(DATA / "example_particles.csv", settings))
