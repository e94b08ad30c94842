"""``contactres demo``: the main job on bundled data, written into one folder.

The parts are computed by the ``demo`` job (:mod:`contactres.jobs.demo`); each part has a
writer here, ``write(result, out: Path) -> list[Path]``, which writes its files into ``out``
(atomically, via :mod:`contactres.fileio`) and returns the paths it wrote. The writers run in
the order of :data:`DEMO_WRITERS` (the order of the job's ``STEPS``).
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

from ..fileio import CSV_FLOAT_FORMAT, ensure_dir, write_csv
from ..jobs import demo as job

__all__ = ["DEMO_WRITERS", "run_demo", "write_demo"]


def _write_crystals(result: job.Result, out: Path) -> list[Path]:
    return [write_csv(out / "crystals.csv", result.crystals, float_format=CSV_FLOAT_FORMAT)]


def _write_qcm_analysis(result: job.Result, out: Path) -> list[Path]:
    """Paper 2's analysis of the bundled sweeps (scripts/make_example_data.py): qcm-analysis/."""
    from ..report import write_report

    return write_report(result.sweeps_analysis, ensure_dir(out / "qcm-analysis"))


def _write_qcm_spectra(result: job.Result, out: Path) -> list[Path]:
    """From the instrument: qcm-spectra/ (sweeps.csv, fits.csv and the results)."""
    from ..report import write_report

    folder = ensure_dir(out / "qcm-spectra")
    written = [
        write_csv(folder / "sweeps.csv", result.spectra_rows, float_format=CSV_FLOAT_FORMAT),
        write_csv(folder / "fits.csv", result.spectra_fits, float_format=CSV_FLOAT_FORMAT),
    ]
    return written + write_report(result.spectra_analysis, ensure_dir(folder / "analysis"))


def _write_paper2_forward(result: job.Result, out: Path) -> list[Path]:
    """Paper 2 forward model: loops (Fig. 2C-D) and Δf(u0), ΔΓ(u0) (Fig. 1D): paper2-forward/."""
    from .paper2 import write_paper2_figures

    return write_paper2_figures(out / "paper2-forward", result=result.paper2)


def _write_paper1_dcsf(result: job.Result, out: Path) -> list[Path]:
    """Paper 1: exact DCSF of built-in crystals on (001) faces (as Fig. 4): paper1-dcsf/."""
    from .paper1 import write_crystal_dcsf

    return write_crystal_dcsf(
        out / "paper1-dcsf", model=job.CRYSTAL_DCSF_MODEL, curves=result.crystal_dcsf
    )


def _write_polycrystal(result: job.Result, out: Path) -> list[Path]:
    """The bundled Cu map: the M map with the IPF-coloured legend (M_map.png) and the constants
    fitted back from the measured k* map (fit.json): polycrystal/."""
    from ..fileio import save_figure, write_text
    from ..polycrystal import folded_normals
    from ..report import modulus_map_figure

    omap = result.map_orientations
    if (
        omap is None
        or result.map_dataset is None
        or result.map_fit is None
        or result.map_triangle is None
    ):
        return []  # the step was left out (the job says why in its warnings)
    folder = ensure_dir(out / "polycrystal")
    fig = modulus_map_figure(
        result.map_dataset["M_Pa"].values,
        folded_normals(omap, "cubic"),
        "cubic",
        result.map_triangle,
        pixel_size=omap.step_x,
        material_name="Cu",
    )
    return [
        save_figure(folder / "M_map.png", fig),
        write_text(folder / "fit.json", result.map_fit["json"]),
    ]


def _write_coated_contact(result: job.Result, out: Path) -> list[Path]:
    """A sphere on a coated substrate (the ``contact`` job's table): coated-contact/contact.csv."""
    folder = ensure_dir(out / "coated-contact")
    table = result.coated_contact
    return [write_csv(folder / "contact.csv", table, float_format=CSV_FLOAT_FORMAT)]


def _write_cr_map(result: job.Result, out: Path) -> list[Path]:
    """The bundled DART image's maps (k*, M, tan δ), conventions and Dataset: cr-map/."""
    from .afm_map import write_afm_map

    if result.cr_map is None:
        return []  # the step was left out (the job says why in its warnings)
    return write_afm_map(result.cr_map, out / "cr-map")


#: The writers of the parts, in the order of :data:`contactres.jobs.demo.STEPS`.
DEMO_WRITERS: tuple[Callable[[job.Result, Path], list[Path]], ...] = (
    _write_qcm_analysis,
    _write_qcm_spectra,
    _write_crystals,
    _write_paper2_forward,
    _write_paper1_dcsf,
    _write_polycrystal,
    _write_coated_contact,
    _write_cr_map,
)


def write_demo(result: job.Result, out: str | Path) -> list[Path]:
    """Write every part of the demo's ``result`` into folder ``out``; return the files."""
    folder = ensure_dir(out)
    written: list[Path] = []
    for write in DEMO_WRITERS:
        written.extend(write(result, folder))
    return written


def run_demo(out: str | Path, progress: Callable[[str], None] | None = None) -> list[Path]:
    """Run the demo job and write its results into folder ``out``; return the files written."""
    ensure_dir(out)  # a path that cannot be the folder is refused before the work
    return write_demo(job.run(None, job.Settings(), progress), out)
