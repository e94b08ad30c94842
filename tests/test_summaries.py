"""Every public parameter and result class prints compactly and renders in notebooks (issue 30).

The classes are those of the public subpackages' ``__all__`` pinned in tests/test_public_api.py:
each dataclass among them is built here from a small example (:data:`BUILDERS`; a new public
dataclass without a builder fails :func:`test_every_public_dataclass_has_an_example`). Then

* ``repr`` is at most :data:`LIMIT` characters and holds no numpy repr (``array(``);
* the classes with a summary of their own (``contactres._summary.Summarised``) also give
  ``_repr_html_``, a string in which a label such as ``<b>&`` appears escaped;
* the numbers a summary shows are the object's: each is parsed back from the text and
  compared with the field it names, to the four significant digits shown
  (:data:`KEY_NUMBERS`).

The small parameter classes (:data:`PLAIN`) keep the dataclass repr, which is short and can be
pasted back as code.
"""

from __future__ import annotations

import importlib
import inspect
import re
from dataclasses import is_dataclass

import numpy as np
import pandas as pd
import pytest

import contactres as cr
from contactres import (
    analysis,
    crystals,
    dynamic,
    examples,
    fitting,
    measurements,
    normal,
    polycrystal,
    resonators,
    tangential,
    units,
    viscoelastic,
)
from contactres._summary import Summarised
from test_public_api import PUBLIC

LIMIT = 400  # characters of a repr: a few lines on a screen
LABEL = "<b>&"  # a label that HTML would read as markup if it were not escaped
DIGITS_RTOL = 5e-4  # four significant digits shown: a relative rounding of at most 5e-4

CU = cr.Material.cubic(168.4e9, 121.4e9, 75.4e9, density=8960.0, name="Cu")
SILICA = cr.Material.isotropic(72e9, 0.17, density=2200.0, name="silica")


def _film():
    return cr.LayeredMaterial(SILICA, [(cr.Material.isotropic(3e9, 0.35, name="film"), 20e-9)])


def _particle_fit():
    p = resonators.Particle.sphere(1e-6, 2000.0)
    n = np.arange(1, 14, 2)
    df, dg = resonators.particle_shifts(5e6, n, p, 100.0, 2e-7, 2e9)
    return analysis.fit_particles(5e6, n, df, dg, p, sigma_df=0.1, sigma_dgamma=0.1)


def _film_result():
    film = cr.Material.isotropic(6e9 * (1 - 0.35**2), 0.35, name="film")
    # A 100 nm tip at 50 nN: a/R ≈ 0.085, inside Hertz's range (the inversion checks a/R).
    stack = cr.LayeredMaterial(SILICA, [(film, 20e-9)])
    k = normal.sphere_contact(stack, 100e-9, 50e-9).stiffness
    guess = cr.Material.isotropic(3e9, 0.35, name="film")
    return analysis.film_modulus_from_contact_stiffness(
        k, substrate=SILICA, film=guess, thickness=20e-9, tip_radius=100e-9, load=50e-9
    )


def _cantilever():
    return resonators.Cantilever((160e3, 1000e3), 40.0)


def _cr_result():
    lever = _cantilever()
    f = resonators.contact_frequencies(lever, np.array([10.0, 50.0]), 0.95, modes=(1, 2))
    return resonators.invert_contact_resonance(lever, f.real, 0.95)


def _synthetic():
    return polycrystal.synthetic_polycrystal((16, 16), 4, 1)


def _orientation_map(source="map.ang"):
    s = _synthetic()
    return polycrystal.OrientationMap(
        s.euler, s.step_x, s.step_y, s.phase, s.confidence, labels=s.labels, source=source
    )


def _cubic_fit():
    R = polycrystal.random_orientations(40, seed=1)
    M = polycrystal.indentation_moduli(CU, R)
    return polycrystal.fit_cubic_constants(R, M, 1e-4 * M, quantity="modulus")


def _hexagonal_fit():
    zn = np.array([165.0, 31.1, 50.0, 61.8, 39.6]) * 1e9
    R = polycrystal.random_orientations(60, seed=1)
    M = polycrystal.indentation_moduli(cr.Material.hexagonal(*zn), R)
    guess = dict(zip(("c12_c11", "c13_c11", "c33_c11", "c44_c11"), zn[1:] / zn[0], strict=True))
    return polycrystal.fit_hexagonal_constants(R, M, 1e-3 * M, quantity="modulus", guess=guess)


def _least_squares():
    # Two problems, one parameter each: r = p - target, minimum at the target.
    target = np.array([[1.5], [-2.0]])

    def evaluate(p, rows, jacobian):
        out = {"residuals": p - target[rows]}
        if jacobian:
            out["jacobian"] = np.ones((len(rows), 1, 1))
        return out

    return fitting.levenberg_marquardt(evaluate, np.zeros((2, 1)))


def _fit_result(model_name="line"):
    model = fitting.Model(
        key=model_name,
        display="a line",
        parameters=(
            fitting.Parameter("slope", "slope", "Hz/m", "slope_Hz_m"),
            fitting.Parameter("offset", "offset", "Hz", "offset_Hz"),
        ),
        x="amplitude",
        x_unit="m",
        observable="df",
        unit="Hz",
        source="a test",
        function=lambda x, slope, offset: slope * x + offset,
    )
    x = np.linspace(0.0, 1.0, 11)
    y = 2.5 * x + 0.75 + 0.01 * np.sin(7 * x)  # not exactly a line: finite errors
    return fitting.fit(model, x, y, {"slope": 1.0, "offset": 0.0})


def _sweep_table(source=None):
    path = cr.example_path("example_sweeps.csv")
    table = measurements.read_sweeps(path)
    return table if source is None else measurements.SweepTable(table.data, source=source)


# One small example per public dataclass (name -> builder).
BUILDERS = {
    "Example": lambda: examples.EXAMPLES["example_sweeps.csv"],
    "AnalysisSettings": analysis.AnalysisSettings,
    "DartReconstruction": lambda: analysis.dart_reconstruction(
        np.array([298e3, 299e3]), np.array([302e3, 303e3]), 1.0, 1.1, 0.5, 2.0
    ),
    "FilmModulusResult": _film_result,
    "ModulusModel": lambda: analysis.ModulusModel(tip_radius=50e-9, load=1e-6),
    "ModulusResult": lambda: analysis.modulus_from_contact_stiffness(
        np.array([1262.8, 1300.0]), tip_radius=50e-9, load=1e-6
    ),
    "ParticleFit": _particle_fit,
    "Results": lambda: analysis.Results(
        pd.DataFrame({"sweep": range(10), "used": [True] * 10}),
        pd.DataFrame({"normal_force_N": [1e-3, 2e-3]}),
        pd.DataFrame(),
        [],
        {},
        "9.9.9",
    ),
    "CrystalRecord": lambda: crystals.crystal_record("quartz"),
    "CheckedDCSF": lambda: dynamic.checked_dcsf_models(CU, np.array([0.1, 0.3]), models=("R0",)),
    "KernelTable": lambda: dynamic.prepare(CU, rtol=1e-3),
    "TangentialTable": lambda: dynamic.prepare_tangential(CU, rtol=1e-3),
    "LayeredMaterial": _film,
    "Material": lambda: CU,
    "ExampleLever": measurements.ExampleLever,
    "IgorWave": lambda: measurements.read_ibw(cr.example_path("example_dart.ibw")),
    "ResonanceMaps": lambda: measurements.ResonanceMaps(
        np.full((8, 8), 300e3), np.full((8, 8), 80.0), (1e-8, 1e-8), "map.nc"
    ),
    "ParticleStudy": measurements.ParticleStudy,
    "SweepGroup": lambda: measurements.example_study().groups[0],
    "SweepStudy": measurements.example_study,
    "SweepTable": _sweep_table,
    "AnisotropicContact": lambda: normal.sphere_contact(CU.rotated((1, 1, 0)), 50e-9, 0.2e-6),
    "Contact": lambda: normal.hertz(100e9, 50e-9, np.array([0.1e-6, 0.2e-6])),  # a/R < 0.1
    "ContactEllipse": lambda: normal.contact_ellipse(CU.rotated((1, 1, 0))),
    "ContactIntegrals": lambda: normal.contact_integrals(CU),
    "LayeredContact": lambda: normal.sphere_contact(
        _film(), 20e-9, np.array([1e-6, 2e-6]), check_validity=False
    ),
    "CoatedModuli": lambda: polycrystal.coated_moduli(
        SILICA, [(SILICA, 15e-9)], np.full(3, 72e9 / (1 - 0.17**2)), None, 20e-9, 1e-6
    ),
    "ContactMap": lambda: polycrystal.contact_stiffness_map(
        np.array([120e9, 140e9, 160e9]), None, 50e-9, 1e-6
    ),
    "CubicInverseResult": _cubic_fit,
    "EbsdPhase": lambda: polycrystal.EbsdPhase("Cu", "cubic", 3.615e-10, space_group=225),
    "ExactModulus": lambda: polycrystal.ExactModulus(CU),
    "GrainOrientations": lambda: polycrystal.grain_orientations(
        _synthetic().labels, _synthetic().surface_matrices(), "cubic"
    ),
    "HexagonalInverseResult": _hexagonal_fit,
    "IPFTriangle": lambda: polycrystal.ipf_triangle("cubic", n=11),
    "IndexedPixels": lambda: polycrystal.indexed_pixels(_orientation_map()),
    "NormalTable": lambda: polycrystal.prepare_normal_table(CU, "cubic", rtol=1e-2),
    "OrientationMap": _orientation_map,
    "SyntheticPolycrystal": _synthetic,
    "TriangleModuli": lambda: polycrystal.triangle_moduli(
        "cubic",
        lambda v: polycrystal.indentation_moduli(CU, polycrystal.surface_matrices_from_normals(v)),
        n=11,
    ),
    "Cantilever": _cantilever,
    "ContactResonanceResult": _cr_result,
    "Medium": lambda: resonators.WATER,
    "Particle": lambda: resonators.Particle.sphere(1e-6, 2000.0),
    "QCM": resonators.QCM,
    "RUMOscillator": lambda: resonators.RUMOscillator(30e3, 1e5),
    "ConstantLoss": lambda: viscoelastic.ConstantLoss(3e9, 0.05),
    "ModulusTable": lambda: viscoelastic.ModulusTable(
        np.logspace(0, 6, 50), np.linspace(3e9, 5e9, 50), np.linspace(1e8, 2e8, 50)
    ),
    "PowerLaw": lambda: viscoelastic.PowerLaw(3e9, 1.0, 0.05),
    "Prony": lambda: viscoelastic.Prony(3e9, ((1e9, 1e-3), (5e8, 1e-1))),
    "ViscoelasticMaterial": viscoelastic.pmma,
    "CattaneoMindlinLoop": lambda: tangential.CattaneoMindlinLoop(1e5, 0.5, 1e-3),
    "DashpotLoop": lambda: tangential.DashpotLoop(
        tangential.CattaneoMindlinLoop(1e5, 0.5, 1e-3), 1e-3, 3e7
    ),
    "PlateauLoop": lambda: tangential.PlateauLoop(
        tangential.CattaneoMindlinLoop(1e5, 0.5, 1e-3), 1e-9
    ),
    "SavkoorLoop": lambda: tangential.SavkoorLoop(1e5, 1e6, 1e-6),
    "VoigtLoop": lambda: tangential.VoigtLoop(1e5, 1e-3, 3e7),
    "FitResult": _fit_result,
    "LMOptions": fitting.LMOptions,
    "LeastSquaresResult": _least_squares,
    "Model": lambda: analysis.REGISTRY["elastic"],
    "Parameter": lambda: analysis.REGISTRY["elastic"].parameters[0],
    "Plausible": lambda: next(iter(units.QUANTITIES.values())),
}

# Keep the dataclass repr: a few scalars, short, and it reads back as code.
PLAIN = {
    "AnalysisSettings",
    "ModulusModel",
    "ExampleLever",
    "ParticleStudy",
    "ContactEllipse",
    "ContactIntegrals",
    "EbsdPhase",
    "ExactModulus",
    "Cantilever",
    "Medium",
    "Particle",
    "QCM",
    "RUMOscillator",
    "ConstantLoss",
    "PowerLaw",
    "Prony",
    "CattaneoMindlinLoop",
    "DashpotLoop",
    "PlateauLoop",
    "SavkoorLoop",
    "VoigtLoop",
    "LMOptions",
    "Parameter",
    "Plausible",
}


def _public_dataclasses() -> dict[str, type]:
    found = {}
    for module, names in PUBLIC.items():
        if module.startswith("jobs."):
            continue  # the jobs' Settings and Result: the contract of the CLI, not notebooks
        m = importlib.import_module(f"contactres.{module}")
        for name in names:
            obj = getattr(m, name)
            if inspect.isclass(obj) and is_dataclass(obj):
                found[name] = obj
    return found


CLASSES = _public_dataclasses()


def test_every_public_dataclass_has_an_example():
    assert set(BUILDERS) == set(CLASSES)
    assert PLAIN <= set(CLASSES)


@pytest.fixture(scope="module")
def built():
    """The examples, each built once for this module's tests (some take a second)."""
    made: dict[str, object] = {}

    def get(name: str):
        if name not in made:
            made[name] = BUILDERS[name]()
        return made[name]

    return get


@pytest.mark.parametrize("name", sorted(BUILDERS))
def test_repr_is_short_and_holds_no_numpy_repr(name, built):
    obj = built(name)
    assert isinstance(obj, CLASSES[name])
    text = repr(obj)
    assert len(text) <= LIMIT, text
    assert "array(" not in text
    if name in PLAIN:
        assert not isinstance(obj, Summarised)
        return
    assert text.startswith(name)
    page = obj._repr_html_()
    assert isinstance(page, str) and page.startswith(f"<p><b>{name}</b>")


# An object of each class whose summary shows a label, with LABEL in it.
LABELLED = {
    "Material": lambda: cr.Material.isotropic(70e9, 0.2, name=LABEL),
    "LayeredMaterial": lambda: cr.LayeredMaterial(
        cr.Material.isotropic(70e9, 0.2, name=LABEL), [(SILICA, 1e-8)]
    ),
    "ViscoelasticMaterial": lambda: viscoelastic.ViscoelasticMaterial.isotropic(
        viscoelastic.ConstantLoss(3e9, 0.1), poisson=0.3, name=LABEL
    ),
    "SweepTable": lambda: _sweep_table(source=LABEL),
    "SweepGroup": lambda: measurements.SweepGroup(LABEL, "air", 1e-3, 70e9, 0.1, (1e-9,), 1.0, 0.1),
    "ResonanceMaps": lambda: measurements.ResonanceMaps(
        np.ones((2, 2)), np.ones((2, 2)), None, LABEL
    ),
    "CrystalRecord": lambda: crystals.CrystalRecord(LABEL, 1e11, 5e10, 3e10, 5000.0, LABEL),
    "Example": lambda: examples.Example(LABEL, LABEL, "contactres demo", LABEL),
    "FitResult": lambda: _fit_result(LABEL),
    "OrientationMap": lambda: _orientation_map(source=LABEL),
}


@pytest.mark.parametrize("name", sorted(LABELLED))
def test_repr_html_escapes_labels(name):
    obj = LABELLED[name]()
    assert LABEL in repr(obj)  # the label is shown ...
    page = obj._repr_html_()
    assert LABEL not in page and "&lt;b&gt;&amp;" in page  # ... and escaped in HTML


def shown(text: str, label: str) -> list[float]:
    """The numbers a summary shows for ``label``: one value, or the two ends of a range
    ("2 values, 81.93 to 85.58 GPa"), read back from the text."""
    match = re.search(rf"(?:\(|; ){re.escape(label)}: ([^;]*)", text)
    assert match, f"{label!r} not in {text!r}"
    last = match.group(1).split(", ")[-1]  # the value, or the range after the count
    return [float(x) for x in re.findall(r"[-+]?\d+(?:\.\d*)?(?:e[-+]?\d+)?", last)]


def _ends(x, scale=1.0) -> list[float]:
    a = np.real(np.asarray(x, dtype=complex)).ravel() / scale
    return [float(a[0])] if a.size == 1 else [float(np.nanmin(a)), float(np.nanmax(a))]


# (class, label in the summary, the field's value(s) in the unit shown).
KEY_NUMBERS = [
    ("Material", "C11", lambda m: [m.C[0, 0] / 1e9]),
    ("Material", "C12", lambda m: [m.C[0, 1] / 1e9]),
    ("Material", "C44", lambda m: [m.C[3, 3] / 1e9]),
    ("Material", "ρ", lambda m: [m.density]),
    ("LayeredMaterial", "total thickness", lambda s: [s.thicknesses.sum() / 1e-9]),
    ("ViscoelasticMaterial", "ρ", lambda m: [m.density]),
    ("ModulusTable", "M'", lambda t: _ends(t.storage, 1e9)),
    ("ModulusTable", "f", lambda t: _ends(t.frequency)),
    ("SweepTable", "sweeps", lambda t: [t.data["sweep"].nunique()]),
    ("SweepGroup", "E", lambda g: [g.E / 1e9]),
    ("SweepGroup", "R", lambda g: [g.radius / 1e-3]),
    ("SweepStudy", "F_N", lambda s: _ends(s.normal_forces, 1e-3)),
    ("IgorWave", "data", lambda w: _ends(w.data)),
    ("ResonanceMaps", "f", lambda r: _ends(r.frequency_Hz, 1e3)),
    ("Contact", "a", lambda c: _ends(c.contact_radius, 1e-9)),
    ("Contact", "k", lambda c: _ends(c.stiffness)),
    ("Contact", "p0", lambda c: _ends(c.peak_pressure, 1e9)),
    ("AnisotropicContact", "δ", lambda c: _ends(c.depth, 1e-9)),
    ("AnisotropicContact", "M", lambda c: _ends(c.indentation_modulus, 1e9)),
    ("AnisotropicContact", "b/a", lambda c: [c.ellipticity]),
    ("LayeredContact", "M", lambda c: _ends(c.indentation_modulus, 1e9)),
    ("ModulusResult", "E*", lambda r: _ends(r.E_star, 1e9)),
    ("ModulusResult", "a", lambda r: _ends(r.contact_radius, 1e-9)),
    ("FilmModulusResult", "M_film", lambda r: _ends(r.M_film, 1e9)),
    ("ParticleFit", "κ", lambda f: _ends(f.kappa)),
    ("ParticleFit", "N", lambda f: _ends(f.coverage)),
    ("ParticleFit", "f_coupled", lambda f: _ends(f.f_coupled, 1e6)),
    ("DartReconstruction", "f0", lambda r: _ends(r.f0, 1e3)),
    ("DartReconstruction", "Q", lambda r: _ends(r.Q)),
    ("ContactResonanceResult", "k*", lambda r: _ends(r.k_star)),
    ("ContactResonanceResult", "κ", lambda r: _ends(r.kappa)),
    ("CheckedDCSF", "R0", lambda c: _ends(c.values["R0"])),
    ("KernelTable", "C44", lambda t: [t.constants[3, 3].real / 1e9]),
    ("TangentialTable", "C11", lambda t: [t.constants[0, 0].real / 1e9]),
    ("CoatedModuli", "M_c", lambda c: _ends(c.moduli, 1e9)),
    ("ContactMap", "k*", lambda c: _ends(c.stiffness)),
    ("ContactMap", "E*", lambda c: _ends(c.effective_modulus, 1e9)),
    ("GrainOrientations", "pixels per grain", lambda g: _ends(g.pixels)),
    ("TriangleModuli", "M", lambda t: _ends(t.moduli[t.triangle.inside], 1e9)),
    ("NormalTable", "M", lambda t: _ends(t.moduli, 1e9)),
    ("CubicInverseResult", "C12/C11", lambda r: [r.c12_c11, r.c12_c11_error]),
    ("CubicInverseResult", "C44/C11", lambda r: [r.c44_c11, r.c44_c11_error]),
    (
        "CubicInverseResult",
        "strong combination",
        lambda r: [r.strong_combination, r.strong_combination * r.strong_error],
    ),
    # (a modulus map fixes 3 of the 4 combinations of Zn's ratios: the ratios are NaN, and
    # shown as "not determined", test_undetermined_values_are_said_so)
    ("HexagonalInverseResult", "combinations determined", lambda r: [r.n_identified, 4]),
    ("HexagonalInverseResult", "χ²/dof", lambda r: [r.chi2_dof]),
    ("FitResult", "slope", lambda f: [f.values["slope"], f.errors["slope"]]),
    ("LeastSquaresResult", "χ²", lambda r: _ends(r.chi2)),
    ("CrystalRecord", "C14", lambda c: [c.c14 / 1e9]),
]


# Ids from the class and the label only: a lambda's text holds its address, which differs
# between the xdist workers (they must collect the same test names).
@pytest.mark.parametrize(
    ("name", "label", "expected"), KEY_NUMBERS, ids=[f"{n}-{lab}" for n, lab, _ in KEY_NUMBERS]
)
def test_summary_shows_the_objects_numbers(name, label, expected, built):
    obj = built(name)
    got = shown(repr(obj), label)
    want = [float(v) for v in expected(obj)]
    assert len(got) == len(want), (repr(obj), want)
    # each value to four significant digits; an error (the second number of "v ± e") to two
    error = "±" in repr(obj).partition(f"{label}: ")[2].partition(";")[0]
    for k, (g, w) in enumerate(zip(got, want, strict=True)):
        assert g == pytest.approx(w, rel=5e-2 if error and k == 1 else DIGITS_RTOL), repr(obj)


def test_every_summarised_class_has_its_numbers_checked():
    checked = {name for name, _, _ in KEY_NUMBERS}
    summarised = {n for n in BUILDERS if n not in PLAIN}
    # Shown as words or counts only (tested above for length, escaping and their labels).
    # (OrientationMap and SyntheticPolycrystal: tests/polycrystal/test_ebsd.py.)
    words = {"Results", "Example", "IndexedPixels", "IPFTriangle", "Model"}
    words |= {"OrientationMap", "SyntheticPolycrystal"}
    assert summarised - words <= checked


def test_undetermined_values_are_said_so(built):
    res = built("HexagonalInverseResult")
    assert np.isnan(res.ratios).all()  # the premise: Zn's ratios are not determined here
    text = repr(res)
    assert "C33/C11: not determined" in text and "nan" not in text.lower()
