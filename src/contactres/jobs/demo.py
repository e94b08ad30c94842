"""Job ``demo``: the main workflows of contactres on the bundled example data.

Inputs: none (pass None; the data are the package's, ``contactres/data``). Settings: none.
:func:`run` computes every part, in the order of :data:`STEPS` (``progress`` gets each title
before its part); :func:`contactres.apps.write_demo` writes them into one folder
(``contactres demo``):

* paper 2's analysis of the bundled sweeps (:func:`contactres.analyze`);
* from the instrument: the bundled admittance spectra -> resonance fits -> sweep table -> the
  analysis;
* the built-in crystals (:func:`contactres.crystal_table`);
* paper 2's forward model (the ``paper2`` job);
* paper 1's exact DCSF of built-in crystals on (001) faces (as Fig. 4);
* the bundled EBSD-style Cu map: predicted M and k* per pixel (20 nm tip, 1 µN), and the
  constants fitted back from the bundled measured k* map;
* a coated substrate: paper 2's sphere (radius 1.1 mm) on 250 nm of PMMA on fused silica
  (the ``contact`` job with a coating, :data:`COATED_CONTACT`), static, at four forces
  (contact radii 3.8-7.4 µm, around paper 2's 3.7-5.4 µm);
* the bundled DART image (``example_dart.ibw``): the contact resonance per pixel from its two
  amplitudes and phases, then k*, σ, tan δ and M (the ``afm_map`` job, :data:`CR_MAP`: the tip
  position, tip radius, load and tip modulus the image was made with).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from importlib.resources import as_file, files
from types import MappingProxyType
from typing import TYPE_CHECKING

from .._threads import one_blas_thread
from ..errors import MissingExtraError
from ..measurements.schema import CONTACT_TABLE, CRYSTAL_TABLE, SPECTRA_FITS, SPECTRA_SWEEPS
from .contract import JobResult, Progress, say

if TYPE_CHECKING:
    import xarray as xr

    from ..polycrystal import OrientationMap, TriangleModuli
    from . import afm_map, paper2

__all__ = [
    "COATED_CONTACT",
    "CRYSTAL_DCSF_MODEL",
    "CR_MAP",
    "STEPS",
    "Result",
    "Settings",
    "run",
]

#: The titles of the parts, in the order computed and written.
STEPS = (
    "QCM sweep analysis of the bundled example (paper 2: Table 1, Figs. 4, 5, 7, 8)",
    "from the instrument: bundled admittance spectra -> shifts -> analysis",
    "built-in crystals and their anisotropy",
    "paper 2 forward: partial-slip loops and QCM shifts (Figs. 1D, 2C-D)",
    "paper 1: dynamic contact stiffness on crystals (exact, Fig. 4)",
    "polycrystal map: EBSD -> M and k* per pixel, and the constants back",
    "coated substrate: a sphere on 250 nm of PMMA on fused silica (paper 2's case)",
    "contact-resonance AFM map: the bundled DART image -> k*, tan δ and M per pixel",
)
#: The model of the crystals' DCSF: the exact rigid punch the README recommends.
CRYSTAL_DCSF_MODEL = "exact"
#: The coated contact of the demo: the face, the film (``contact --coating``), the sphere's
#: radius (m; paper 2's spheres are 2.2 mm across) and the forces (N).
COATED_CONTACT = MappingProxyType(
    {"crystal": "fused-silica", "coating": "pmma:250e-9", "radius": 1.1e-3,
     "forces": (2e-3, 8e-3, 14e-3, 20e-3)}
)  # fmt: skip


#: The CR map of the demo: the bundled DART image and how it was made
#: (scripts/make_example_dart.py): tip at r = 0.95, a 20 nm Si tip (M = 165 GPa) at 50 nN.
CR_MAP = MappingProxyType(
    {"file": "example_dart.ibw", "tip_position": 0.95, "tip_radius": 20e-9, "load": 50e-9,
     "tip_modulus": 165e9}
)  # fmt: skip


@dataclass(frozen=True)
class Settings:
    """Nothing to choose: the demo runs on the bundled data."""


@dataclass(frozen=True)
class Result(JobResult):
    """Every part of the demo: the analyses (``sweeps_analysis``; ``spectra_rows``,
    ``spectra_fits`` and ``spectra_analysis``; the tables bound to
    :data:`~contactres.measurements.schema.SPECTRA_SWEEPS` and
    :data:`~contactres.measurements.schema.SPECTRA_FITS`), the ``crystals`` table
    (:data:`~contactres.measurements.schema.CRYSTAL_TABLE`), the ``paper2`` job's
    Result, the crystals' DCSF curves (``crystal_dcsf``: label -> DCSF on the grid
    ``contactres.jobs.paper1.KLA``), the polycrystal map (``map_dataset``, the orientation
    map ``map_orientations``, the fit record ``map_fit``, M over the standard triangle for the
    legend of the map's figure ``map_triangle``) and the coated contact (``coated_contact``,
    :data:`~contactres.measurements.schema.CONTACT_TABLE`)."""

    SCHEMAS = MappingProxyType(
        {
            "crystals": CRYSTAL_TABLE,
            "spectra_rows": SPECTRA_SWEEPS,
            "spectra_fits": SPECTRA_FITS,
            "coated_contact": CONTACT_TABLE,
        }
    )
    NOT_VALUES = (
        "sweeps_analysis",
        "spectra_analysis",
        "paper2",
        "crystal_dcsf",
        "map_dataset",
        "map_orientations",
        "map_fit",
        "map_triangle",
        "cr_map",
        "warnings",
    )

    sweeps_analysis: object
    spectra_rows: object
    spectra_fits: object
    spectra_analysis: object
    crystals: object
    paper2: paper2.Result
    crystal_dcsf: dict
    map_dataset: xr.Dataset | None
    map_orientations: OrientationMap | None
    map_fit: dict | None
    map_triangle: TriangleModuli | None
    coated_contact: object
    #: The ``afm_map`` job's Result on the bundled DART image (None without its extras).
    cr_map: afm_map.Result | None = None
    #: The parts left out, one line each (the maps without the ``maps`` extra).
    warnings: tuple[str, ...] = ()


def _topic(step: str) -> str:
    """A step's topic, its title before the colon: "polycrystal map" (a line stays short)."""
    return step.split(":")[0]


def _sweeps():
    from ..analysis import analyze
    from ..measurements import read_sweeps

    with as_file(files("contactres") / "data" / "example_sweeps.csv") as path:
        table = read_sweeps(path)
    return analyze(table)


def _spectra():
    from ..analysis import analyze
    from ..measurements import read_spectra_sweeps

    with as_file(files("contactres") / "data" / "example_spectra.csv") as path:
        table, rows, fits, _ = read_spectra_sweeps(path)
    return rows, fits, analyze(table)


def _polycrystal():
    """The predicted map of the bundled Cu orientations (with M over the standard triangle, the
    legend of its figure) and the fit of the measured map."""
    from ..materials import Material
    from ..polycrystal import indentation_moduli, surface_matrices_from_normals, triangle_moduli
    from .maps import TipLoad, fit_measured_map, fit_record, open_map, predict_map
    from .maps_predict import TRIANGLE_GRID
    from .readers import read_grid_file

    cu = Material.crystal("Cu")
    data = files("contactres") / "data"
    with as_file(data / "example_cu_map.ang") as ang, as_file(data / "example_cu_kstar.csv") as k:
        omap, _ = open_map(ang)
        measured = read_grid_file(k)
    ds, _ = predict_map(omap, cu, "cubic", TipLoad(radius=20e-9, force=1e-6))
    result, _, used = fit_measured_map(omap, measured, quantity="stiffness")
    record = fit_record(result, source="example_cu_map.ang + example_cu_kstar.csv", pixels=used)
    triangle = triangle_moduli(
        "cubic",
        lambda n: indentation_moduli(cu, surface_matrices_from_normals(n)),
        TRIANGLE_GRID,
    )
    return ds, omap, record, triangle


@one_blas_thread()
def run(inputs: None = None, settings: Settings | None = None, progress: Progress | None = None):
    """Every part of the demo (see the module docstring)."""
    from ..crystals import crystal_table
    from . import paper1, paper2

    say(progress, STEPS[0])
    sweeps_analysis = _sweeps()
    say(progress, STEPS[1])
    rows, fits, spectra_analysis = _spectra()
    say(progress, STEPS[2])
    crystals = crystal_table()
    say(progress, STEPS[3])
    forward = paper2.run()
    say(progress, STEPS[4])
    curves = paper1.crystal_curves(model=CRYSTAL_DCSF_MODEL)
    say(progress, STEPS[5])
    # The map needs the optional extra (xarray, Zarr): without it the step is left out, said in
    # one line, and the other parts are written.
    skipped: list[str] = []
    try:
        ds, omap, record, triangle = _polycrystal()
    except MissingExtraError as exc:
        ds = omap = record = triangle = None
        skipped.append(f"step 6 left out ({_topic(STEPS[5])}): {exc}")
    say(progress, STEPS[6])
    coated = _coated_contact()
    say(progress, STEPS[7])
    try:  # the reader (igor2) and the Dataset (xarray) are optional extras, as for step 6
        cr_map = _cr_map()
    except MissingExtraError as exc:
        cr_map = None
        skipped.append(f"step 8 left out ({_topic(STEPS[7])}): {exc}")
    return Result(
        sweeps_analysis=sweeps_analysis,
        spectra_rows=rows,
        spectra_fits=fits,
        spectra_analysis=spectra_analysis,
        crystals=crystals,
        paper2=forward,
        crystal_dcsf=curves,
        map_dataset=ds,
        map_orientations=omap,
        map_fit=record,
        map_triangle=triangle,
        coated_contact=coated,
        cr_map=cr_map,
        warnings=tuple(skipped),
    )


def _coated_contact():
    """The table of the ``contact`` job for :data:`COATED_CONTACT`."""
    import numpy as np

    from ..materials import Material
    from . import contact

    c = COATED_CONTACT
    settings = contact.Settings(
        radius=np.array([c["radius"]]), force=np.array(c["forces"]), coating=(c["coating"],)
    )
    return contact.run(Material.crystal(c["crystal"]), settings).table


def _cr_map():
    """The ``afm_map`` job on the bundled DART image (:data:`CR_MAP`)."""
    from ..analysis import ModulusModel
    from . import afm_map

    c = CR_MAP
    settings = afm_map.Settings(
        tip_position=c["tip_position"],
        modulus=ModulusModel(
            tip_radius=c["tip_radius"], load=c["load"], tip_modulus=c["tip_modulus"]
        ),
    )
    with as_file(files("contactres") / "data" / c["file"]) as path:
        data = afm_map.read_input(path)
    # The file by its name, as the other parts of the demo name theirs (not where it is installed).
    return afm_map.run(replace(data, source=c["file"]), settings)
