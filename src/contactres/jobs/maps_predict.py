"""Job ``maps_predict``: an orientation map -> the indentation modulus M, the contact stiffness
k* (and, at a frequency, paper 1's DCSF) of every pixel.

Inputs: the path of an orientation map (a Zarr map store, or an EBSD export .ang/.ctf/.h5oina; Bunge
angles, sample z = inward surface normal). Settings: the crystal, the tip and load, how M is
evaluated, the frequency and model of the DCSF, the chunks and the dask scheduler. The map is
:func:`contactres.jobs.maps.predict_map`.

Besides ``progress`` (one line per stage), :func:`run` takes ``chunk_progress(done, total)``,
called after each chunk of pixels: the evaluation of a large map is long, and a bar needs
numbers, not lines.

With ``Settings(coating=...)`` (films on the sample, top first: ``"MATERIAL:THICKNESS"`` as
``contactres contact --coating``) the result adds the coated indentation modulus M_coated_Pa and
k_star_coated_N_per_m of every pixel: the static punch on the films over the grain, at the
pixel's bare Hertz contact radius (:func:`contactres.polycrystal.coated_moduli`, which states
the approximation: each grain's crystal under the films is the isotropic solid with its M and
the crystal's Voigt-Reuss-Hill Poisson ratio; < 1e-3 against the anisotropic substrate for
films softer than the grains, up to 5e-3 for much stiffer ones). The bare variables stay as
they are; a coated map at a frequency (the DCSF) is not offered: the isotropic equivalent of a
grain has its M but not its wave speeds, on which the DCSF depends, and is checked for the
static modulus only (``contactres dcsf --coating`` gives the DCSF of one coated contact on a
crystal face, with the anisotropic face itself under the films).

With ``Settings(legend=True)`` (the default) the result also holds M over the standard
triangle of surface normals (exact, paper 1's Eqs. 1-4 for each normal, on a grid of
:data:`TRIANGLE_GRID` points per axis: ~3,600 evaluations, about a second): the legend of the
map's figure (:func:`contactres.report.prediction_figure` draws it, never evaluates M). The
command line asks for it only with ``--figure``.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from .._threads import one_blas_thread
from ..errors import ContactresInputError
from .contract import JobResult, Progress, say

if TYPE_CHECKING:
    import os

    from ..materials import Material
    from ..polycrystal import TriangleModuli
    from .maps import TipLoad

__all__ = ["TRIANGLE_GRID", "Result", "Settings", "check_phase_name", "run"]

#: Grid points per axis of the standard triangle on which M is evaluated for the figure's legend.
TRIANGLE_GRID = 81


@dataclass(frozen=True)
class Settings:
    """The prediction.

    Parameters
    ----------
    material : Material
        The crystal, cube (or crystal) axes; with its density for a frequency.
    lattice : str
        "cubic" or "hexagonal".
    tipload : TipLoad
        Tip radius (m), force (N) and tip modulus (Pa; inf: rigid).
    method : str
        How M is evaluated (:data:`contactres.jobs.maps.METHODS`).
    rtol : float
        Target relative accuracy of M.
    frequency : float or None
        Frequency of the DCSF, Hz (None: static only).
    model : str
        Displacement model of the DCSF.
    chunks : int
        Pixels per side of a chunk.
    scheduler : str or None
        Address of a dask scheduler (None: in this process).
    min_confidence, max_mad, phase : float, float, int or None
        Which pixels of an EBSD map are used (:func:`contactres.polycrystal.indexed_pixels`;
        None: its defaults).
    legend : bool
        Evaluate M over the standard triangle, the legend of the map's figure (False: no
        ``triangle`` in the result, and no figure).
    coating : tuple of str
        Films on the sample, top first, ``"MATERIAL:THICKNESS"`` (thickness in m;
        :func:`contactres.jobs.contact.parse_coating`; a viscoelastic film takes its 1 Hz
        storage constants): adds M_coated_Pa and k_star_coated_N_per_m (module docstring).
        Empty: the bare map only.
    ignore_phase_name : bool
        Predict the map as ``material`` even where the EBSD export names its phase as another
        built-in crystal (:func:`check_phase_name`; default False: that is an error).
    """

    material: Material
    lattice: str
    tipload: TipLoad
    method: str = "auto"
    rtol: float = 1e-4
    frequency: float | None = None
    model: str = "exact"
    chunks: int = 256
    scheduler: str | None = None
    min_confidence: float | None = None
    max_mad: float | None = None
    phase: int | None = None
    legend: bool = True
    coating: tuple = ()
    ignore_phase_name: bool = False


@dataclass(frozen=True)
class Result(JobResult):
    """``dataset``: the map's variables plus M_Pa, E_star_Pa, contact_radius_m, k_star_N_per_m
    (and the DCSF at a frequency), an :mod:`xarray` Dataset; ``info``: how M was evaluated
    (method, stated_error, exact_evaluations; ``hertz_flag`` where the contact is wider than
    a tenth of the tip radius); ``material`` and ``lattice``: the crystal;
    ``triangle``: M (Pa) over the standard triangle, exact (the legend of the map's figure;
    None unless ``Settings.legend``); ``warnings``: lines for the user (the Hertz flag)."""

    NOT_VALUES = ("dataset", "material", "triangle", "warnings")

    dataset: object
    info: dict
    material: Material
    lattice: str
    triangle: TriangleModuli | None
    warnings: tuple[str, ...] = ()


@one_blas_thread()
def run(
    inputs: str | os.PathLike,
    settings: Settings,
    progress: Progress | None = None,
    chunk_progress: Callable[[int, int], None] | None = None,
) -> Result:
    """The predicted map of the orientations ``inputs`` (see the module docstring)."""
    from ..polycrystal import (
        indentation_moduli,
        indexed_pixels,
        surface_matrices_from_normals,
        triangle_moduli,
    )
    from .maps import check_tip_load, open_map, predict_map

    s = settings
    if s.frequency is not None and s.material.density is None:
        raise ContactresInputError("a frequency needs the density of the material (kg/m^3)")
    layers = _static_layers(s.coating)
    if layers and s.frequency is not None:
        raise ContactresInputError(
            "--coating with --frequency: the coated map is static only (its grains are "
            "isotropic solids of their M, checked for the static modulus only; the DCSF depends "
            "on their wave speeds, which M does not give): dcsf --coating gives the DCSF of one "
            "coated contact on a crystal face"
        )
    hertz_flag = check_tip_load(s.material, s.tipload)
    if not s.ignore_phase_name:
        check_phase_name(inputs, s.material, s.phase)
    say(progress, f"reading {inputs}")
    omap, _ = open_map(inputs)
    pixels = indexed_pixels(omap, min_confidence=s.min_confidence, max_mad=s.max_mad, phase=s.phase)
    say(progress, pixels.summary())
    ds, info = predict_map(
        omap,
        s.material,
        s.lattice,
        s.tipload,
        method=s.method,
        rtol=s.rtol,
        frequency=s.frequency,
        model=s.model,
        chunks=(s.chunks, s.chunks),
        scheduler=s.scheduler,
        progress=chunk_progress,
        pixels=pixels,
    )
    if layers:
        say(progress, "coated moduli (the films on each grain's equivalent isotropic solid)")
        _add_coated(ds, info, s, layers)
    triangle = None
    if s.legend:
        say(progress, "M over the standard triangle (the figure's legend)")
        triangle = triangle_moduli(
            s.lattice,
            lambda n: indentation_moduli(s.material, surface_matrices_from_normals(n)),
            TRIANGLE_GRID,
        )
    if hertz_flag:  # recorded with the map (its attributes) and in the printed record
        ds.attrs["hertz_flag"] = hertz_flag
        info["hertz_flag"] = hertz_flag
    return Result(
        dataset=ds,
        info=dict(info),
        material=s.material,
        lattice=s.lattice,
        triangle=triangle,
        warnings=(hertz_flag,) if hertz_flag else (),
    )


def _static_layers(coating) -> tuple:
    """The films of ``coating`` with static, lossless constants (a viscoelastic film's storage
    constants at 1 Hz, as the static coated contact takes them); () for none."""
    from .contact import parse_coating

    return parse_coating(coating, static=True) if coating else ()


def _add_coated(ds, info: dict, s: Settings, layers) -> None:
    """M_coated_Pa and k_star_coated_N_per_m of every pixel, with their attributes."""
    from ..layered import thickness_text
    from ..polycrystal import coated_moduli

    t = s.tipload
    rtol = min(max(s.rtol, 1e-9), 1e-6)
    c = coated_moduli(s.material, layers, ds["M_Pa"].values, t.tip, t.radius, t.force, rtol)
    label = " on ".join(f"{m.name or 'film'} {thickness_text(h)}" for m, h in layers)
    dims = ("y", "x")
    ds["M_coated_Pa"] = (
        dims,
        c.moduli,
        {"units": "Pa", "long_name": f"indentation modulus under {label}"},
    )
    ds["k_star_coated_N_per_m"] = (dims, c.stiffness, {"units": "N/m"})
    ds.attrs.update(
        coating=label,
        coating_model=(
            "static punch on the films over each grain's isotropic equivalent (its M, the "
            f"crystal's Hill Poisson ratio {c.poisson:.4g}), at the bare Hertz contact radius"
        ),
        M_coated_stated_error=f"{c.error:.2g}",
    )
    info.update(coating=label, coated_error=f"{c.error:.2g}", coated_evaluations=c.evaluations)


#: Common names of the built-in cubic crystals (``crystals.csv``), lower case, as EBSD exports
#: name their phases (EDAX writes e.g. "Copper", "Iron (Alpha)", "Nickel"; others the symbol).
_COMMON_NAMES = {
    "cu": ("copper",), "al": ("aluminium", "aluminum"), "ni": ("nickel",), "au": ("gold",),
    "ag": ("silver",), "fe": ("iron",), "w": ("tungsten", "wolfram"), "si": ("silicon",),
    "ge": ("germanium",), "pb": ("lead",), "li": ("lithium",), "na": ("sodium",),
    "nacl": ("halite", "sodium chloride"), "kcl": ("sylvite", "potassium chloride"),
    "rbbr": ("rubidium bromide",), "rbi": ("rubidium iodide",), "gaas": ("gallium arsenide",),
    "diamond": ("diamond",),
}  # fmt: skip


def _crystal_of(name: str) -> str | None:
    """The built-in crystal (lower-case symbol) a phase or material name names: its first word
    is the symbol, or it starts with a common name (case-insensitive); None if it names none."""
    words = re.findall(r"[a-z0-9]+", name.lower())
    if not words:
        return None
    text = " ".join(words)
    for symbol, common in _COMMON_NAMES.items():
        if words[0] == symbol or any(text == c or text.startswith(c + " ") for c in common):
            return symbol
    return None


def _header_phases(path: Path) -> dict[int, str]:
    """Phase id -> name of an .ang (``# Phase n``, ``# MaterialName``) or .ctf header (the
    lines after ``Phases n``: a;b;c, angles, name, ...); {} for another file."""
    suffix = path.suffix.lower()
    if suffix not in (".ang", ".ctf") or not path.is_file():
        return {}
    names: dict[int, str] = {}
    with path.open(encoding="utf-8", errors="replace") as f:
        if suffix == ".ang":
            pid = 1
            for line in f:
                if not line.startswith("#"):
                    break  # the header ends where the data begin
                field = line[1:].split(None, 1)
                if len(field) == 2 and field[0] == "Phase" and field[1].strip().isdigit():
                    pid = int(field[1])
                elif len(field) == 2 and field[0] == "MaterialName":
                    names[pid] = field[1].strip()
            return names
        count = None
        for line in f:
            cells = line.rstrip("\r\n").split("\t")
            if count is None:
                if cells[0] == "Phases" and len(cells) > 1 and cells[1].strip().isdigit():
                    count = int(cells[1])
                continue
            if len(names) >= count or len(cells) < 3:
                break
            names[len(names) + 1] = cells[2].strip()
    return names


def check_phase_name(path, material, phase: int | None = None) -> None:
    """Refuse an EBSD export (.ang or .ctf) whose phase is named as another built-in crystal
    than ``material`` (issue 27: a Li map run with ``--crystal Cu`` was predicted as Cu).

    The phase checked is ``phase`` if given, else every phase of the header. Names are compared
    case-insensitively as an element symbol or a common name (:data:`_COMMON_NAMES`: "Cu",
    "copper", "Iron (Alpha)"); a name that names no built-in crystal ("Phase 1", "Brass") or a
    material given by its constants passes, as does any map that is not an .ang or .ctf file.
    The error names both and the option that overrides it (``--ignore-phase-name``).
    """
    given = _crystal_of(str(getattr(material, "name", None) or ""))
    if given is None:
        return
    path = Path(path)
    for pid, name in _header_phases(path).items():
        if phase is not None and pid != phase:
            continue
        found = _crystal_of(name)
        if found is not None and found != given:
            raise ContactresInputError(
                f"{path.name}: phase {pid} is named {name!r} but the crystal given (--crystal) "
                f"is {material.name}: give the crystal the map was indexed as, or pass "
                f"--ignore-phase-name to predict it as {material.name} anyway"
            )
