"""The QCM sweep-analysis job through its Python API: the same analysis as the library's
``analyze``, its stages counted ahead, its tables bound to their schemas."""

import pytest

from contactres import AnalysisSettings, analyze, read_sweeps
from contactres.errors import ContactresInputError
from contactres.jobs import crystals, qcm_sweeps
from contactres.measurements.schema import LOAD_RESULTS, SWEEP_RESULTS

SWEEPS = "src/contactres/data/example_sweeps.csv"


def test_the_job_is_the_library_analysis_within_its_stages():
    settings = qcm_sweeps.Settings(bootstrap=0)
    reading = qcm_sweeps.read(SWEEPS, settings)
    calls = []
    result = qcm_sweeps.run(reading, settings, progress=calls.append)
    # The bar's length covers every call of the analysis, and the writing after it.
    assert len(calls) < qcm_sweeps.stages(reading, settings)
    groups = {c for c in calls if c.startswith("JKR fit")}
    assert len(groups) == reading.table.data.groupby(["configuration", "medium"]).ngroups
    direct = analyze(read_sweeps(SWEEPS), settings=AnalysisSettings(bootstrap=0))
    assert result.analysis.table1().equals(direct.table1())
    tables = result.tables()
    assert tables["sweeps"][1] is SWEEP_RESULTS and tables["loads"][1] is LOAD_RESULTS


def test_the_radiation_loss_needs_both_bodies():
    with pytest.raises(ContactresInputError, match="both bodies"):
        qcm_sweeps.run(SWEEPS, qcm_sweeps.Settings(sphere_material="glass"))


def test_crystals_job_moduli_of_an_isotropic_solid_are_e_over_one_minus_nu2():
    table = crystals.run().table.set_index("name")
    iso = table[table["symmetry"] == "isotropic"].iloc[0]
    # A rigid sphere on an isotropic solid: M = E/(1 − ν²) on every face.
    expected = iso["E_GPa"] / (1 - iso["nu"] ** 2)
    for face in ("M001_GPa", "M011_GPa", "M111_GPa"):
        assert iso[face] == pytest.approx(expected, rel=1e-6)
