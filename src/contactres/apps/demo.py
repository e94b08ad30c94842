"""``contactres demo``: the main job on bundled data, written into one folder.

Each part of the package contributes a step: a function ``step(out: Path) -> list[Path]`` that
writes its results into ``out`` (atomically, via :mod:`contactres.fileio`) and returns the
paths it wrote. Steps run in the order of :data:`DEMO_STEPS`.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

from ..fileio import CSV_FLOAT_FORMAT, ensure_dir, write_csv

__all__ = ["DEMO_STEPS", "run_demo"]


def _crystals_step(out: Path) -> list[Path]:
    from ..crystals import crystal_table

    return [write_csv(out / "crystals.csv", crystal_table(), float_format=CSV_FLOAT_FORMAT)]


def _qcm_analysis_step(out: Path) -> list[Path]:
    """Paper 2's analysis of the bundled sweeps (scripts/make_example_data.py): qcm-analysis/."""
    from importlib.resources import as_file, files

    from ..analysis import analyze
    from ..measurements.sweeps import read_sweeps
    from ..report import write_report

    with as_file(files("contactres") / "data" / "example_sweeps.csv") as path:
        table = read_sweeps(path)
    return write_report(analyze(table), ensure_dir(out / "qcm-analysis"))


def _qcm_spectra_step(out: Path) -> list[Path]:
    """From the instrument: the bundled admittance spectra -> resonance fits -> sweep table ->
    paper 2's analysis: qcm-spectra/ (sweeps.csv, fits.csv and the results)."""
    from importlib.resources import as_file, files

    from ..analysis import analyze
    from ..measurements.shifts import read_spectra_sweeps
    from ..report import write_report

    folder = ensure_dir(out / "qcm-spectra")
    with as_file(files("contactres") / "data" / "example_spectra.csv") as path:
        table, rows, fits, _ = read_spectra_sweeps(path)
    written = [
        write_csv(folder / "sweeps.csv", rows, float_format=CSV_FLOAT_FORMAT),
        write_csv(folder / "fits.csv", fits, float_format=CSV_FLOAT_FORMAT),
    ]
    return written + write_report(analyze(table), ensure_dir(folder / "analysis"))


def _paper2_forward_step(out: Path) -> list[Path]:
    """Paper 2 forward model: loops (Fig. 2C-D) and Δf(u0), ΔΓ(u0) (Fig. 1D): paper2-forward/."""
    from .paper2 import write_paper2_figures

    return write_paper2_figures(out / "paper2-forward")


def _paper1_dcsf_step(out: Path) -> list[Path]:
    """Paper 1: exact DCSF of built-in crystals on (001) faces (as Fig. 4): paper1-dcsf/."""
    from .paper1 import write_crystal_dcsf

    return write_crystal_dcsf(out / "paper1-dcsf")


def _polycrystal_step(out: Path) -> list[Path]:
    """The bundled EBSD-style Cu map (scripts/make_example_map.py): predicted M and k* per
    pixel with the IPF-coloured M legend, and the constants fitted back from the bundled
    measured k* map: polycrystal/ (M_map.png, fit.json)."""
    from importlib.resources import as_file, files

    from ..fileio import save_figure, write_text
    from ..materials import Material
    from ..polycrystal.grains import folded_normals
    from ..polycrystal.moduli import indentation_moduli
    from ..polycrystal.normal_table import surface_matrices_from_normals
    from ..report.map_figures import modulus_map_figure
    from .maps import TipLoad, fit_measured_map, fit_record, open_map, predict_map, read_value_grid

    folder = ensure_dir(out / "polycrystal")
    cu = Material.crystal("Cu")
    data = files("contactres") / "data"
    with as_file(data / "example_cu_map.ang") as ang, as_file(data / "example_cu_kstar.csv") as k:
        omap, _ = open_map(ang)
        measured = read_value_grid(k)
    ds, _ = predict_map(omap, cu, "cubic", TipLoad(radius=20e-9, force=1e-6))
    fig = modulus_map_figure(
        ds["M_Pa"].values,
        folded_normals(omap, "cubic"),
        "cubic",
        lambda n: indentation_moduli(cu, surface_matrices_from_normals(n)),
        pixel_size=omap.step_x,
        material_name="Cu",
    )
    result, _, used = fit_measured_map(omap, measured, quantity="stiffness")
    record = fit_record(result, source="example_cu_map.ang + example_cu_kstar.csv", pixels=used)
    return [save_figure(folder / "M_map.png", fig), write_text(folder / "fit.json", record["json"])]


#: (title, step) pairs run by :func:`run_demo`.
DEMO_STEPS: list[tuple[str, Callable[[Path], list[Path]]]] = [
    (
        "QCM sweep analysis of the bundled example (paper 2: Table 1, Figs. 4, 5, 7, 8)",
        _qcm_analysis_step,
    ),
    (
        "from the instrument: bundled admittance spectra -> shifts -> analysis",
        _qcm_spectra_step,
    ),
    ("built-in crystals and their anisotropy", _crystals_step),
    ("paper 2 forward: partial-slip loops and QCM shifts (Figs. 1D, 2C-D)", _paper2_forward_step),
    ("paper 1: dynamic contact stiffness on crystals (exact, Fig. 4)", _paper1_dcsf_step),
    ("polycrystal map: EBSD -> M and k* per pixel, and the constants back", _polycrystal_step),
]


def run_demo(out: str | Path, progress: Callable[[str], None] | None = None) -> list[Path]:
    """Run every demo step into folder ``out``; return the files written."""
    folder = ensure_dir(out)
    written: list[Path] = []
    for title, step in DEMO_STEPS:
        if progress is not None:
            progress(title)
        written.extend(step(folder))
    return written
