"""CLI: ``contactres maps synthetic|predict|fit`` (polycrystal maps: EBSD -> contact stiffness,
and measured stiffness + orientations -> single-crystal constants)."""

from __future__ import annotations

import click

from ..errors import ContactresInputError
from ._app import maps
from ._common import MagnitudeType, emit_record, figure_path, format_option, step
from ._film import coating_option
from ._map_options import (
    map_material,
    map_shape,
    material_options,
    pixel_options,
    progress_callback,
    scheduler_address,
    tip_options,
)


@maps.command("synthetic")
@click.option("--out", type=click.Path(), required=True, help="Output map store (Zarr folder).")
@material_options
@tip_options(required=True)
@click.option(
    "--shape",
    default="512x512",
    show_default=True,
    callback=map_shape,
    help="Map size ROWSxCOLUMNS, pixels.",
)
@click.option(
    "--grains",
    type=click.IntRange(min=1),
    default=60,
    show_default=True,
    help="Number of Voronoi grains, dimensionless.",
)
@click.option(
    "--seed",
    type=click.IntRange(min=0),
    default=1,
    show_default=True,
    help="Seed of the random generator (grains, orientations, noise), dimensionless.",
)
@click.option(
    "--noise",
    type=click.FloatRange(0, 0.5, max_open=True),
    default=0.01,
    show_default=True,
    help="Relative noise per pixel of k*, dimensionless.",
)
@click.option(
    "--pixel-size",
    type=MagnitudeType("pixel_size"),
    default=1e-6,
    show_default=True,
    help="Pixel pitch, m.",
)
def maps_synthetic(
    out,
    crystal,
    c11,
    c12,
    c13,
    c33,
    c44,
    density,
    tip_radius,
    force,
    tip_modulus,
    shape,
    grains,
    seed,
    noise,
    pixel_size,
):
    """A seeded Voronoi polycrystal with a noisy contact-stiffness map k* (N/m), as a Zarr map
    store: Bunge Euler angles (rad), grain labels and k_star_N_per_m, ready for 'maps fit'.

    \b
    Example: contactres maps synthetic --crystal Cu --tip-radius 2e-8 --force 1e-6 --out cu.zarr
    """
    import math

    from ..jobs import maps_synthetic as job
    from ..jobs.maps import TipLoad
    from ..polycrystal import check_map_output, write_map

    check_map_output(out)
    material, lattice = map_material(crystal, c11, c12, c13, c33, c44, density)
    tipload = TipLoad(tip_radius, force, math.inf if tip_modulus is None else tip_modulus)
    settings = job.Settings(material, lattice, tipload, shape, grains, seed, noise, pixel_size)
    result = job.run(None, settings, progress=lambda text: step("maps synthetic", text))
    ds = result.dataset
    write_map(out, ds)
    k = ds["k_star_N_per_m"].values
    click.echo(
        f"{shape[0]}x{shape[1]} map, {grains} grains, noise {noise:g}: k* from "
        f"{k.min():.4g} to {k.max():.4g} N/m; wrote {out}"
    )
    for line in result.warnings:  # the Hertz flag: one line, also in the store's attributes
        click.echo(f"contactres: warning: {line}", err=True)


@maps.command("predict")
@click.argument("map_path", metavar="MAP", type=click.Path(exists=True))
@click.option("--out", type=click.Path(), required=True, help="Output map store (Zarr folder).")
@material_options
@tip_options(required=True)
@click.option(
    "--method",
    type=click.Choice(["auto", "interpolated", "exact", "grains"]),
    default="auto",
    show_default=True,
    help="M per pixel: tabulated over the fundamental triangle and interpolated, "
    "exact per pixel, or exact per grain (labelled maps); auto: grains if labelled.",
)
@click.option(
    "--rtol",
    type=click.FloatRange(1e-8, 1e-2),
    default=1e-4,
    show_default=True,
    help="Interpolation tolerance of M, relative, dimensionless (1e-8 to 1e-2).",
)
@click.option(
    "--frequency",
    type=MagnitudeType("frequency"),
    help="Hz: add paper 1's DCSF and the dynamic contact stiffness of every pixel.",
)
@click.option(
    "--model",
    type=click.Choice(["exact", "WA2D"]),
    default="exact",
    show_default=True,
    help="DCSF model (with --frequency).",
)
@click.option(
    "--chunks",
    type=click.IntRange(min=1),
    default=256,
    show_default=True,
    help="Square chunk size in pixels, dimensionless (the unit of work on a cluster).",
)
@click.option(
    "--scheduler",
    callback=scheduler_address,
    show_default="this machine",
    help="Dask scheduler address tcp://HOST:PORT: evaluate M on that cluster.",
)
@click.option(
    "--figure",
    type=click.Path(dir_okay=False),
    callback=figure_path,
    help="Figure file, PNG, SVG or PDF by its suffix (.png, .svg, .pdf): M map, IPF-Z map and "
    "the M legend over the standard triangle.",
)
@coating_option(
    "Adds M_coated_Pa and k_star_coated_N_per_m: the static punch on the films over each "
    "grain at the pixel's bare Hertz contact radius, each grain's crystal taken as the "
    "isotropic solid with its M and the crystal's Voigt-Reuss-Hill Poisson ratio (< 0.1 % off "
    "the anisotropic grain for films softer than it, up to 0.5 % for much stiffer ones). "
    "Static only (not with --frequency: a grain's isotropic equivalent has its M but not "
    "its wave speeds, on which the DCSF depends; 'contactres dcsf --coating' gives one coated "
    "contact's DCSF)."
)
@pixel_options
@click.option(
    "--ignore-phase-name",
    is_flag=True,
    help="Predict the map as the crystal given even where the .ang/.ctf header names its phase "
    "as another built-in crystal (symbol or common name, case-insensitive; without this option "
    "that is an error).",
)
@format_option()
def maps_predict(
    map_path,
    out,
    crystal,
    c11,
    c12,
    c13,
    c33,
    c44,
    density,
    tip_radius,
    force,
    tip_modulus,
    method,
    rtol,
    frequency,
    model,
    chunks,
    scheduler,
    figure,
    min_confidence,
    max_mad,
    phase,
    ignore_phase_name,
    coating,
    fmt,
):
    """Predicted indentation modulus M (Pa) and contact stiffness k* (N/m) of every pixel of an
    orientation map (a Zarr map store, or an EBSD export .ang/.ctf/.h5oina; Bunge angles, sample
    z = inward surface normal). Writes MAP's variables plus M_Pa, E_star_Pa,
    contact_radius_m, k_star_N_per_m (and the DCSF with --frequency; M_coated_Pa and
    k_star_coated_N_per_m with --coating) to OUT atomically. A tip and force whose Hertz
    contact on the softest orientation is wider than half the tip radius are refused before
    any work (most likely a unit slip); wider than a tenth of it, a warning says Hertz is
    approximate (recorded as hertz_flag in OUT's attributes and the printed record).

    The example files: 'contactres examples --copy .' copies them into this folder.

    \b
    Example: contactres maps predict example_cu_map.ang --crystal Cu \\
        --tip-radius 2e-8 --force 1e-6 --out cu_predicted.zarr
    """
    import math

    import numpy as np

    from ..jobs import maps_predict as job
    from ..jobs.maps import TipLoad
    from ..polycrystal import check_map_output, write_map

    check_map_output(out, inputs=[map_path])
    if figure is not None:
        from ..fileio import check_output_file

        check_output_file(figure, inputs=[map_path])
    material, lattice = map_material(crystal, c11, c12, c13, c33, c44, density)
    if frequency is not None and material.density is None:
        raise ContactresInputError("--frequency needs the density: give --density (kg/m^3)")
    tipload = TipLoad(tip_radius, force, math.inf if tip_modulus is None else tip_modulus)
    settings = job.Settings(
        material,
        lattice,
        tipload,
        method,
        rtol,
        frequency,
        model,
        chunks,
        scheduler,
        min_confidence=min_confidence,
        max_mad=max_mad,
        phase=phase,
        legend=figure is not None,
        coating=tuple(coating),
        ignore_phase_name=ignore_phase_name,
    )
    result = job.run(
        map_path,
        settings,
        progress=lambda text: step("maps predict", text),
        chunk_progress=progress_callback("M per chunk"),
    )
    ds, info = result.dataset, result.info
    for line in result.warnings:  # the Hertz flag: one line, also in the store's attributes
        click.echo(f"contactres: warning: {line}", err=True)
    write_map(out, ds, chunks=(chunks, chunks))
    if figure is not None:
        from ..fileio import save_figure
        from ..report import prediction_figure

        save_figure(figure, prediction_figure(result))
    M, k = ds["M_Pa"].values, ds["k_star_N_per_m"].values
    record = {
        "pixels": int(np.isfinite(M).sum()),
        "method": info["method"],
        "M_stated_error": info["stated_error"],
        "exact_evaluations": info["exact_evaluations"],
        "pixels_left_out": info["pixels_left_out"],
        "M_min_Pa": float(np.nanmin(M)),
        "M_max_Pa": float(np.nanmax(M)),
        "k_star_min_N_per_m": float(np.nanmin(k)),
        "k_star_max_N_per_m": float(np.nanmax(k)),
        "out": str(out),
        **({"hertz_flag": info["hertz_flag"]} if "hertz_flag" in info else {}),
    }
    if coating:
        Mc, kc = ds["M_coated_Pa"].values, ds["k_star_coated_N_per_m"].values
        record.update(
            coating=info["coating"],
            M_coated_stated_error=info["coated_error"],
            M_coated_min_Pa=float(np.nanmin(Mc)),
            M_coated_max_Pa=float(np.nanmax(Mc)),
            k_star_coated_min_N_per_m=float(np.nanmin(kc)),
            k_star_coated_max_N_per_m=float(np.nanmax(kc)),
        )
    if fmt != "plain":
        emit_record(record, fmt)
        return
    if info["pixels_left_out"]:
        click.echo(info["pixels"])
    click.echo(
        f"{record['pixels']} pixels, M {info['method']} ({info['exact_evaluations']} exact "
        f"evaluations, error {info['stated_error']}): M from {record['M_min_Pa'] / 1e9:.4g} to "
        f"{record['M_max_Pa'] / 1e9:.4g} GPa, k* from {record['k_star_min_N_per_m']:.4g} to "
        f"{record['k_star_max_N_per_m']:.4g} N/m; wrote {out}"
    )
    if coating:
        click.echo(
            f"under {record['coating']}: M_coated from {record['M_coated_min_Pa'] / 1e9:.4g} to "
            f"{record['M_coated_max_Pa'] / 1e9:.4g} GPa, k* from "
            f"{record['k_star_coated_min_N_per_m']:.4g} to "
            f"{record['k_star_coated_max_N_per_m']:.4g} N/m (grains as isotropic solids of "
            f"their M, at the bare contact radius; interpolation error "
            f"{record['M_coated_stated_error']})"
        )


@maps.command("fit")
@click.argument("map_path", metavar="MAP", type=click.Path(exists=True))
@click.option(
    "--out",
    type=click.Path(dir_okay=False),
    required=True,
    help="Output JSON: the constants, their errors, the identifiability, warnings.",
)
@click.option(
    "--values",
    "values_path",
    type=click.Path(exists=True, dir_okay=False),
    help="The measured map: .npy, or .csv with ROWS lines of COLUMNS numbers (no "
    "header; empty = not measured), on MAP's grid.",
)
@click.option(
    "--variable",
    default="k_star_N_per_m",
    show_default=True,
    help="Variable of the MAP store holding the measured map (without --values).",
)
@click.option(
    "--quantity",
    type=click.Choice(["stiffness", "modulus"]),
    default="stiffness",
    show_default=True,
    help="The measured map: k* (N/m) or M (Pa).",
)
@click.option(
    "--lattice",
    type=click.Choice(["cubic", "hexagonal"]),
    default="cubic",
    show_default=True,
    help="Crystal symmetry of the constants fitted.",
)
@click.option(
    "--tolerance-deg",
    type=click.FloatRange(0, 30, min_open=True),
    default=2.0,
    show_default=True,
    help="Grains of an unlabelled map: largest angle between "
    "neighbouring pixels' normals within one grain, degrees.",
)
@click.option(
    "--tip-radius",
    type=MagnitudeType("tip_radius"),
    help="Tip radius R, m (with --force: fixes the calibration of a k* map).",
)
@click.option("--force", type=MagnitudeType("force"), help="Static normal force F, N.")
@click.option(
    "--tip-modulus",
    type=MagnitudeType("modulus"),
    show_default="rigid",
    help="Plane-strain modulus of the tip E/(1 - ν²), Pa.",
)
@pixel_options
@format_option()
def maps_fit(
    map_path,
    out,
    values_path,
    variable,
    quantity,
    lattice,
    tolerance_deg,
    tip_radius,
    force,
    tip_modulus,
    min_confidence,
    max_mad,
    phase,
    fmt,
):
    """Single-crystal constants (ratios to C11, and C11 when the calibration is known) from a
    measured contact-stiffness or modulus map and the orientations, with uncertainties and the
    identifiability (the weak combination of the ratios and its error).

    The example files: 'contactres examples --copy .' copies them into this folder.

    \b
    Example: contactres maps fit example_cu_map.ang --values \\
        example_cu_kstar.csv --out cu_fit.json
    """
    import os

    from ..fileio import check_output_file, write_text
    from ..jobs import maps_fit as job
    from ..jobs.maps import TipLoad

    check_output_file(out, inputs=[map_path] + ([values_path] if values_path else []))
    suffix = os.path.splitext(out)[1]
    if suffix.lower() not in ("", ".json"):  # the fit is written as JSON only
        raise click.BadParameter(
            f"{out!r}: the fit is written as JSON, not {suffix}; name it with .json",
            param_hint="'--out'",
        )
    if (tip_radius is None) != (force is None):
        raise click.UsageError("give --tip-radius and --force together (or neither)")
    settings = job.Settings(
        values_path=values_path,
        variable=variable,
        quantity=quantity,
        lattice=lattice,
        tolerance_deg=tolerance_deg,
        tipload=None if tip_radius is None else TipLoad(tip_radius, force),
        tip_modulus=tip_modulus,
        min_confidence=min_confidence,
        max_mad=max_mad,
        phase=phase,
    )
    done = job.run(map_path, settings, progress=lambda text: step("maps fit", text))
    result, used, record = done.fit, done.pixels, done.record
    write_text(out, record["json"])
    if fmt != "plain":
        emit_record(record["flat"], fmt)
        for line in result.warnings:  # the plain summary prints them; here on stderr
            click.echo(f"contactres: warning: {line}", err=True)
        return
    click.echo(result.summary())
    if record["flat"].get("pixels_left_out"):
        click.echo(record["flat"]["pixel_rule"])
    click.echo(f"{used} pixels in {result.n_grains} grains; wrote {out}")
