"""``contactres demo``: the main job on bundled data, written into one folder.

The parts are computed by the ``demo`` job (:mod:`contactres.jobs.demo`); each part has a
writer here, ``write(result, out: Path) -> list[Path]``, which writes its files into ``out``
(each folder as one :class:`contactres.fileio.ResultSet`, with its ``manifest.json``) and
returns the paths it wrote. The writers run in
the order of :data:`DEMO_WRITERS` (the order of the job's ``STEPS``).
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

from ..fileio import CSV_FLOAT_FORMAT, ResultSet, write_csv
from ..jobs import demo as job

__all__ = ["DEMO_WRITERS", "check_demo_output", "run_demo", "write_demo"]


def _tables_set(folder: Path, names: tuple[str, ...], kind: str) -> ResultSet:
    """The result set of the demo's own files in ``folder`` (its subfolders are other sets)."""
    return ResultSet(folder, names=names, kind=kind)


def _crystals_set(out: Path) -> ResultSet:
    return _tables_set(out, ("crystals.csv",), "demo")


def _spectra_set(out: Path) -> ResultSet:
    return _tables_set(out / "qcm-spectra", ("sweeps.csv", "fits.csv"), "demo_spectra")


def _polycrystal_set(out: Path) -> ResultSet:
    return _tables_set(out / "polycrystal", ("M_map.png", "fit.json"), "demo_polycrystal")


def _coated_set(out: Path) -> ResultSet:
    return _tables_set(out / "coated-contact", ("contact.csv",), "demo_coated_contact")


def _write_crystals(result: job.Result, out: Path) -> list[Path]:
    with _crystals_set(out) as rs:
        write_csv(rs.path("crystals.csv"), result.crystals, float_format=CSV_FLOAT_FORMAT)
    return [rs.final("crystals.csv")]


def _write_qcm_analysis(result: job.Result, out: Path) -> list[Path]:
    """Paper 2's analysis of the bundled sweeps (scripts/make_example_data.py): qcm-analysis/."""
    from ..report import write_report

    return write_report(result.sweeps_analysis, out / "qcm-analysis")


def _write_qcm_spectra(result: job.Result, out: Path) -> list[Path]:
    """From the instrument: qcm-spectra/ (sweeps.csv, fits.csv and the results)."""
    from ..report import write_report

    with _spectra_set(out) as rs:
        write_csv(rs.path("sweeps.csv"), result.spectra_rows, float_format=CSV_FLOAT_FORMAT)
        write_csv(rs.path("fits.csv"), result.spectra_fits, float_format=CSV_FLOAT_FORMAT)
    written = [rs.final("sweeps.csv"), rs.final("fits.csv")]
    return written + write_report(result.spectra_analysis, out / "qcm-spectra" / "analysis")


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
    fig = modulus_map_figure(
        result.map_dataset["M_Pa"].values,
        folded_normals(omap, "cubic"),
        "cubic",
        result.map_triangle,
        pixel_size=omap.step_x,
        material_name="Cu",
    )
    with _polycrystal_set(out) as rs:
        save_figure(rs.path("M_map.png"), fig)
        write_text(rs.path("fit.json"), result.map_fit["json"])
    return [rs.final("M_map.png"), rs.final("fit.json")]


def _write_coated_contact(result: job.Result, out: Path) -> list[Path]:
    """A sphere on a coated substrate (the ``contact`` job's table): coated-contact/contact.csv."""
    with _coated_set(out) as rs:
        write_csv(rs.path("contact.csv"), result.coated_contact, float_format=CSV_FLOAT_FORMAT)
    return [rs.final("contact.csv")]


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


def check_demo_output(out: str | Path) -> None:
    """Check, writing nothing, that :func:`write_demo` may write into folder ``out`` (before
    the work): every result set of its parts, the ``cr-map`` folder's included.

    Raises
    ------
    contactres.fileio.OutputError
        One line naming the folder and the reason, among them a file under one of the demo's
        names that no manifest shows contactres wrote (issue 27); nothing was changed.
    """
    from ..jobs import qcm_sweeps
    from ..report import report_set
    from .afm_map import check_afm_map_output
    from .paper1 import crystal_dcsf_set
    from .paper2 import paper2_set

    folder = Path(out)
    for rs in (
        _crystals_set(folder),  # first: a path that cannot be the folder is named as given
        report_set(qcm_sweeps.Result, folder / "qcm-analysis"),
        _spectra_set(folder),
        report_set(qcm_sweeps.Result, folder / "qcm-spectra" / "analysis"),
        paper2_set(folder / "paper2-forward"),
        crystal_dcsf_set(folder / "paper1-dcsf", job.CRYSTAL_DCSF_MODEL),
        _polycrystal_set(folder),
        _coated_set(folder),
    ):
        rs.check()
    check_afm_map_output(folder / "cr-map")


def write_demo(result: job.Result, out: str | Path) -> list[Path]:
    """Write every part of the demo's ``result`` into folder ``out``; return the files.

    Each folder of the demo (``out`` itself, ``qcm-analysis``, ``qcm-spectra`` and its
    ``analysis``, ``paper2-forward``, ``paper1-dcsf``, ``polycrystal``, ``coated-contact``,
    ``cr-map``) is one :class:`contactres.fileio.ResultSet` with its ``manifest.json``: a rerun
    replaces only what contactres wrote; :func:`check_demo_output` makes the checks first.
    """
    folder = Path(out)
    written: list[Path] = []
    for write in DEMO_WRITERS:
        written.extend(write(result, folder))
    return written


def run_demo(out: str | Path, progress: Callable[[str], None] | None = None) -> list[Path]:
    """Run the demo job and write its results into folder ``out``; return the files written."""
    check_demo_output(out)  # refused before the work: a path that cannot be the folder, ...
    return write_demo(job.run(None, job.Settings(), progress), out)
