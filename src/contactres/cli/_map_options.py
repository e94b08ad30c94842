"""Shared options of ``contactres maps``: the crystal (cubic or hexagonal), the tip and its
load, which pixels of an EBSD map are used, the scheduler address, the map shape and a progress
callback."""

from __future__ import annotations

import re

import click

from ..errors import ContactresInputError
from ._common import MagnitudeType, progress_stream


def material_options(f):
    options = [
        click.option(
            "--crystal",
            help="Built-in cubic crystal (see 'contactres crystals'), e.g. Cu; or give the "
            "constants.",
        ),
        click.option("--c11", type=MagnitudeType("modulus"), help="Elastic constant C11, Pa."),
        click.option(
            "--c12",
            type=MagnitudeType("modulus", allow_zero=True, signed=True),
            help="Elastic constant C12, Pa.",
        ),
        click.option(
            "--c13",
            type=MagnitudeType("modulus", allow_zero=True, signed=True),
            help="Hexagonal C13, Pa (with --c33: a hexagonal crystal, c axis = crystal z).",
        ),
        click.option("--c33", type=MagnitudeType("modulus"), help="Hexagonal C33, Pa."),
        click.option("--c44", type=MagnitudeType("modulus"), help="Elastic constant C44, Pa."),
        click.option(
            "--density",
            type=MagnitudeType("density"),
            help="Density, kg/m^3 (needed with --frequency when the constants are given).",
        ),
    ]

    for option in reversed(options):
        f = option(f)
    return f


def _finite(ctx, param, value):
    """click's FloatRange lets NaN through (every comparison with NaN is false)."""
    if value is not None and value != value:
        raise click.BadParameter("must be a finite number, not nan", ctx, param)
    return value


def pixel_options(f):
    """--min-confidence, --max-mad, --phase: which pixels of an EBSD map are used
    (:func:`contactres.polycrystal.indexed_pixels`)."""
    options = [
        click.option(
            "--min-confidence",
            type=click.FloatRange(-1.0, 1.0),
            callback=_finite,
            show_default="0.1",
            help="Lowest confidence index CI of a used .ang pixel, dimensionless (CI = -1: not "
            "indexed). Pixels below it are left out and counted.",
        ),
        click.option(
            "--max-mad",
            type=click.FloatRange(0.0, 180.0, min_open=True),
            callback=_finite,
            show_default="no limit",
            help="Largest mean angular deviation MAD of a used .ctf/.h5oina pixel, degrees "
            "(phase 0 is always left out: not indexed).",
        ),
        click.option(
            "--phase",
            type=click.IntRange(0),
            show_default="the map's one phase",
            help="Phase id whose pixels are used, dimensionless (needed when the map holds "
            "several phases).",
        ),
    ]
    for option in reversed(options):
        f = option(f)
    return f


def map_material(crystal, c11, c12, c13, c33, c44, density):
    """(Material, lattice) from --crystal or the constants."""
    from ..crystals import crystal_record
    from ..materials import Material

    constants = {"--c11": c11, "--c12": c12, "--c13": c13, "--c33": c33, "--c44": c44}
    given = [k for k, v in constants.items() if v is not None]
    if crystal is not None:
        if given:
            raise ContactresInputError(
                f"give --crystal or the constants, not both ({', '.join(given)})"
            )
        try:
            record = crystal_record(crystal)
        except ValueError as exc:
            raise ContactresInputError(f"--crystal: {exc}") from None
        if record.symmetry not in ("cubic", "isotropic"):
            raise ContactresInputError(
                f"--crystal {crystal}: maps handle cubic and hexagonal crystals; {record.name} "
                f"is {record.symmetry}"
            )
        m = Material.crystal(crystal)
        return (m if density is None else Material.from_voigt(m.C, density, m.name)), "cubic"
    hexagonal = c13 is not None or c33 is not None
    need = ["--c11", "--c12", "--c44"] + (["--c13", "--c33"] if hexagonal else [])
    missing = [k for k in need if constants[k] is None]
    if not given:
        raise ContactresInputError(
            "give --crystal NAME, or --c11/--c12/--c44 (cubic, Pa), or "
            "--c11/--c12/--c13/--c33/--c44 (hexagonal, Pa)"
        )
    if missing:
        raise ContactresInputError(f"missing {', '.join(missing)}")
    try:
        if hexagonal:
            return Material.hexagonal(c11, c12, c13, c33, c44, density=density), "hexagonal"
        return Material.cubic(c11, c12, c44, density=density), "cubic"
    except ValueError as exc:
        raise ContactresInputError(f"{'/'.join(need)}: {exc}") from None


def tip_options(required: bool):
    def decorate(func):
        for option in reversed(
            [
                click.option(
                    "--tip-radius",
                    type=MagnitudeType("tip_radius"),
                    required=required,
                    help="Radius R of the spherical tip, m.",
                ),
                click.option(
                    "--force",
                    type=MagnitudeType("force"),
                    required=required,
                    help="Static normal force F on the tip, N.",
                ),
                click.option(
                    "--tip-modulus",
                    type=MagnitudeType("modulus"),
                    show_default="rigid",
                    help="Plane-strain modulus of the tip E/(1 - ν²), Pa (diamond: 1.14e12).",
                ),
            ]
        ):
            func = option(func)
        return func

    return decorate


def scheduler_address(ctx, param, value):
    if value is not None and not re.fullmatch(r"[a-z]+://\S+", value):
        raise click.BadParameter(
            f"{value!r} is not a scheduler address: give tcp://HOST:PORT", ctx, param
        )
    return value


def map_shape(ctx, param, value):
    m = re.fullmatch(r"\s*(\d+)\s*[xX,]\s*(\d+)\s*", str(value))
    if m is None or min(int(m.group(1)), int(m.group(2))) < 1:
        raise click.BadParameter(f"{value!r} is not ROWSxCOLUMNS, e.g. 512x512", ctx, param)
    return int(m.group(1)), int(m.group(2))


def progress_callback(label: str):
    """A click progress bar (drawn on a terminal only) and its ``progress(done, total)``."""
    state = {}

    def progress(done: int, total: int) -> None:
        if "bar" not in state:
            bar = click.progressbar(length=total, label=label, file=progress_stream())
            state["bar"] = bar.__enter__()
        state["bar"].update(done - state["bar"].pos)
        if done == total:
            state["bar"].__exit__(None, None, None)

    return progress
