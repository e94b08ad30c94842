"""CLI: ``contactres afm map FILE... --out DIR`` (a contact-resonance map from the instrument's file
-> maps of k*, σ, tan δ, E* and M, with figures and the conventions)."""

from __future__ import annotations

import re

import click

from ..errors import ContactresInputError
from ._app import afm
from ._common import MagnitudeType, figure_format_option, step
from ._map_options import scheduler_address

# What every map's folder gets: the conventions (json), the figures (in the --figure-format
# formats, between these) and the page (the Dataset is written beside them, --map-name).
REPORT_FORMATS = ("csv", "json", "html")


def _region(ctx, param, value):
    """``Y0:Y1,X0:X1`` (pixel rows and columns, end excluded) -> (y0, y1, x0, x1)."""
    if value is None:
        return None
    m = re.fullmatch(r"\s*(\d+)\s*:\s*(\d+)\s*,\s*(\d+)\s*:\s*(\d+)\s*", str(value))
    if m is None:
        raise click.BadParameter(
            f"{value!r} is not Y0:Y1,X0:X1 (pixel rows and columns, e.g. 0:20,0:40)", ctx, param
        )
    return tuple(int(g) for g in m.groups())


def _map_name(ctx, param, value):
    """A plain file name ending in .nc or .zarr (checked before the work)."""
    from pathlib import Path

    if Path(value).name != value or Path(value).suffix.lower() not in (".nc", ".zarr"):
        raise click.BadParameter(
            f"{value!r} is not a plain file name ending in .nc (NetCDF) or .zarr (Zarr)", ctx, param
        )
    return value


@afm.command("map")
@click.argument("files", nargs=-1, required=True, type=click.Path(exists=True))
@click.option(
    "--out",
    type=click.Path(file_okay=False),
    required=True,
    help="Output folder: afm_map.json (conventions, summary), afm_maps.png, afm_histograms.png, "
    "report.html (one self-contained page) and the map Dataset (--map-name); a series of "
    "files: one subfolder per file.",
)
@click.option(
    "--map-name",
    default="afm_map.nc",
    show_default=True,
    callback=_map_name,
    help="File name of the map Dataset in the folder: .nc (NetCDF, listed in the folder's "
    "manifest.json) or .zarr (a Zarr store written beside the report, not in the manifest).",
)
@click.option(
    "--frequency-width",
    type=click.FloatRange(0, min_open=True),
    show_default="the note's DFRTFrequencyWidth",
    help="DART drive separation Δf, Hz: the drives are at f_c ∓ Δf/2.",
)
@click.option(
    "--spring-constant",
    type=MagnitudeType("lever_stiffness"),
    show_default="the note's SpringConstant",
    help="Lever's spring constant k_c at the free end, N/m (wins over the note's).",
)
@click.option(
    "--free-frequency",
    type=MagnitudeType("frequency"),
    show_default="the note's ThermalFrequency",
    help="Free lever's mode-1 resonance, Hz (wins over the note's).",
)
@click.option(
    "--free-q",
    type=click.FloatRange(0, min_open=True),
    show_default="the note's ThermalQ, else none",
    help="Free lever's mode-1 Q, dimensionless: its damping is taken out of σ.",
)
@click.option(
    "--tip-position",
    type=click.FloatRange(0, 1, min_open=True),
    default=1.0,
    show_default=True,
    help="Tip position r = L1/L along the lever, dimensionless.",
)
@click.option(
    "--lateral-ratio",
    type=click.FloatRange(0),
    default=0.0,
    show_default=True,
    help="Lateral to normal contact stiffness α, dimensionless (with --tip-height).",
)
@click.option(
    "--tip-height",
    type=click.FloatRange(0),
    default=0.0,
    show_default=True,
    help="Tip height over the lever's length h/L, dimensionless.",
)
@click.option(
    "--tilt",
    type=click.FloatRange(0, 45),
    default=0.0,
    show_default=True,
    help="Tilt φ of the lever, degrees: the angle from the sample's surface to the lever, "
    "positive with the free end nearer the sample (the only mounting modelled); usual "
    "mounting 10-12°.",
)
@click.option("--tip-radius", type=MagnitudeType("tip_radius"), help="Hertz: tip radius, m.")
@click.option("--force", type=MagnitudeType("force"), help="Hertz: static load on the tip, N.")
@click.option(
    "--punch-radius", type=MagnitudeType("contact_radius"), help="Flat punch: its radius, m."
)
@click.option(
    "--reference",
    callback=_region,
    help="Reference region Y0:Y1,X0:X1 (pixel rows, columns; end excluded) of known modulus: "
    "each map is calibrated against it (tip wear across a series).",
)
@click.option(
    "--reference-modulus",
    type=MagnitudeType("modulus"),
    help="Indentation modulus of the reference region, Pa.",
)
@click.option(
    "--exponent",
    type=click.FloatRange(0, min_open=True),
    show_default="1.5 (Hertz)",
    help="m of E* = E*_ref (k*/k*_ref)^m with --reference (1: flat punch).",
)
@click.option(
    "--tip-modulus",
    type=MagnitudeType("modulus"),
    show_default="rigid",
    help="Indentation modulus of the tip, Pa (Si [001]: 1.65e11).",
)
@click.option(
    "--phase-sign",
    type=click.Choice(["auto", "lag", "lead"]),
    default="auto",
    show_default=True,
    help="DART: the file's phases are the lag of the response (lag) or its opposite (lead); "
    "auto: the sign under which the phase rises from f1 to f2 on most pixels.",
)
@click.option(
    "--scheduler",
    callback=scheduler_address,
    show_default="this machine",
    help="Dask scheduler address tcp://HOST:PORT: a series of maps on that cluster.",
)
@figure_format_option()
def afm_map(
    files,
    out,
    map_name,
    frequency_width,
    spring_constant,
    free_frequency,
    free_q,
    tip_position,
    lateral_ratio,
    tip_height,
    tilt,
    tip_radius,
    force,
    punch_radius,
    reference,
    reference_modulus,
    exponent,
    tip_modulus,
    phase_sign,
    scheduler,
    figure_formats,
):
    """Maps of contact stiffness k*, contact damping σ, loss tangent tan δ, E* and the
    indentation modulus M from a contact-resonance map: an Asylum DART image (.ibw: the
    resonance per pixel from its two amplitudes and phases), a band-excitation SHO fit (.h5,
    BGlib) or a grid of frequency_Hz and q_factor (.nc, .zarr).

    Mode 1, the tip at --tip-position (Euler-Bernoulli lever, U. Rabe et al., Rev. Sci.
    Instrum. 67, 3281 (1996)); tan δ = ωσ/k* (Yuya, Hurley & Turner 2008; Hurley et al.
    2013: one contact geometry for storage and loss). The modulus: Hertz (--tip-radius and
    --force), a flat punch (--punch-radius) or a reference region of the map
    (--reference and --reference-modulus), with --tip-modulus in series; none of them:
    k*, σ and tan δ only. The lever's constants come from the file's note where it has
    them (SpringConstant, ThermalFrequency, ThermalQ, DFRTFrequencyWidth); an option wins,
    and afm_map.json gives both. It needs the extras afm (igor2, h5py) and maps (xarray):
    pip install 'contactres[afm,maps]'.

    The example files: 'contactres examples --copy .' copies them into this folder.

    \b
    Example: contactres afm map example_dart.ibw --tip-position 0.95 --tip-radius 2e-8 \\
        --force 5e-8 --tip-modulus 1.65e11 --out cr-map
    """
    from pathlib import Path

    import numpy as np

    from ..analysis import ModulusModel
    from ..apps.afm_map import check_afm_map_output, write_afm_map
    from ..jobs import afm_map as job

    modulus = ModulusModel(
        tip_radius=tip_radius,
        load=force,
        punch_radius=punch_radius,
        reference=reference,
        reference_modulus=reference_modulus,
        exponent=exponent,
        tip_modulus=tip_modulus,
    )
    if exponent is not None and reference is None:
        raise ContactresInputError("--exponent goes with --reference (the calibration's m)")
    settings = job.Settings(
        spring_constant=spring_constant,
        free_frequency=free_frequency,
        free_q=free_q,
        tip_position=tip_position,
        lateral_ratio=lateral_ratio,
        tip_height=tip_height,
        tilt=tilt,
        modulus=modulus,
        frequency_width=frequency_width,
        phase_sign=phase_sign,
    )

    stems = [Path(f).stem for f in files]
    if len(files) > 1 and len(set(stems)) < len(stems):
        twice = sorted({s for s in stems if stems.count(s) > 1})
        raise ContactresInputError(
            f"a series writes one subfolder per file name: {', '.join(twice)} occurs twice"
        )

    def progress(text):
        step("afm map", text)

    folders = [Path(out) / Path(f).stem for f in files] if len(files) > 1 else [Path(out)]
    formats = (*REPORT_FORMATS[:2], *figure_formats, *REPORT_FORMATS[2:])
    for path, folder in zip(files, folders, strict=True):  # all checked before the work
        check_afm_map_output(folder, map_name=map_name, formats=formats, inputs=(path,))
    results = job.series(list(files), settings, scheduler=scheduler, progress=progress)
    for path, folder, result in zip(files, folders, results, strict=True):
        write_afm_map(result, folder, map_name=map_name, formats=formats, progress=progress)
        s, ds = result.summary, result.dataset
        line = f"{Path(path).name}: {s['shape'][0]}x{s['shape'][1]} pixels, "
        line += f"{s['pixels_with_k_star']} with k*"
        if s["median_k_star_N_per_m"] is not None:
            line += f" (median {s['median_k_star_N_per_m']:.4g} N/m)"
        if s["median_M_Pa"] is not None:
            line += f", M median {s['median_M_Pa'] / 1e9:.4g} GPa"
        if s["median_tan_delta"] is not None:
            line += f", tan δ median {s['median_tan_delta']:.3g}"
        ref = result.conventions["modulus"].get("reference_k_star_N_per_m")
        if ref is not None:
            line += f", reference k* {ref:.4g} N/m"
        line += f"; {s['pixels_flagged']} flagged"
        if s["pixels_modulus_flagged"]:
            line += f", {s['pixels_modulus_flagged']} modulus-flagged"
        if "dart_flags" in ds:
            line += f", {int(np.count_nonzero(ds['dart_flags'].values))} DART-flagged"
        click.echo(f"{line}; wrote {folder}")
        for warning in result.warnings:
            click.echo(f"contactres: warning: {warning}", err=True)
