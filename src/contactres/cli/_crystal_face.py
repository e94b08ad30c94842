"""Shared CLI options that choose a cubic crystal and one of its faces (``contact``, ``dcsf``)."""

from __future__ import annotations

import re
from typing import TYPE_CHECKING

import click

from ..errors import ContactresInputError
from ._common import MagnitudeType

if TYPE_CHECKING:  # annotations only: the library is imported when a command runs
    from ..materials import Material


def parse_direction(text: str, name: str = "surface") -> tuple[float, ...]:
    """Parse Miller-like indices: ``001``, ``1-10``, ``-1 1 0`` or ``1,1,1``."""
    import numpy as np

    s = str(text).strip()
    try:
        if "," in s or " " in s:
            parts = s.replace(",", " ").split()
        elif re.fullmatch(r"(-?\d){3}", s):
            parts = re.findall(r"-?\d", s)
        else:
            raise ValueError
        if len(parts) != 3:
            raise ValueError
        v = tuple(float(p) for p in parts)
    except ValueError:
        raise ContactresInputError(
            f"--{name} {text!r} is not a direction: give three indices such as 001, 1-10, "
            "'1 1 1' or 1,1,0"
        ) from None
    if not np.all(np.isfinite(v)) or not any(v):
        raise ContactresInputError(f"--{name} {text!r} must be three finite numbers, not all zero")
    return v


def material_from_options(crystal, c11, c12, c44, zener, poisson) -> Material:
    """The crystal (cube-axis frame) chosen by ``--crystal`` or the elastic-constant options."""
    from ..materials import Material

    by_constants = c11 is not None or c12 is not None
    by_ratios = zener is not None or poisson is not None
    chosen = sum([crystal is not None, by_constants, by_ratios])
    if chosen != 1:
        raise ContactresInputError(
            "give exactly one of: --crystal NAME, --c11/--c12/--c44 (Pa), or "
            "--zener/--poisson/--c44 (Pa)"
        )
    if crystal is not None:
        if c44 is not None:
            raise ContactresInputError("--c44 cannot be combined with --crystal")
        try:
            return Material.crystal(crystal)
        except ValueError as exc:  # unknown name: the library's message lists the known ones
            raise ContactresInputError(f"--crystal: {exc}") from None
    missing = [
        n
        for n, v in (
            ("--c11", c11) if by_constants else ("--zener", zener),
            ("--c12", c12) if by_constants else ("--poisson", poisson),
            ("--c44", c44),
        )
        if v is None
    ]
    if missing:
        raise ContactresInputError(f"missing {', '.join(missing)}")
    # Each option passed its own range check; what is left is their combination (stability).
    try:
        if by_constants:
            return Material.cubic(c11, c12, c44)
        return Material.cubic_from_ratios(zener, poisson, c44=c44)
    except ValueError as exc:
        options = "--c11/--c12/--c44" if by_constants else "--zener/--poisson/--c44"
        raise ContactresInputError(f"{options}: {exc}") from None


def crystal_face_options(
    c44_help: str = "Cubic elastic constant C44, Pa.",
    inplane_help: str = "Direction of the surface x axis in cube axes.",
):
    """Decorator adding --crystal, --c11/--c12/--c44, --zener/--poisson, --surface, --inplane."""
    options = [
        click.option(
            "--crystal",
            help="Built-in crystal or solid (see 'contactres crystals'), e.g. Cu, quartz.",
        ),
        click.option(
            "--c11", type=MagnitudeType("modulus"), help="Cubic elastic constant C11, Pa."
        ),
        click.option(
            "--c12",
            # C12 may be zero or negative (auxetic crystals); Material.cubic checks stability.
            type=MagnitudeType("modulus", allow_zero=True, signed=True),
            help="Cubic elastic constant C12, Pa (may be negative).",
        ),
        click.option("--c44", type=MagnitudeType("modulus"), help=c44_help),
        click.option(
            "--zener",
            type=MagnitudeType("zener"),
            help="Zener ratio A = 2 C44/(C11 - C12), dimensionless (with --poisson).",
        ),
        click.option(
            "--poisson",
            type=MagnitudeType("poisson"),
            help="ν = C12/(C11 + C12) of the cubic crystal, dimensionless.",
        ),
        click.option(
            "--surface",
            default="001",
            show_default=True,
            help="Surface normal in cube axes (Miller indices): 001, 011, 111, 1-10, '1 2 3', ...",
        ),
        click.option(
            "--inplane",
            default=None,
            show_default="[100] projected, or [010]",
            help=inplane_help,
        ),
    ]

    def decorate(f):
        for option in reversed(options):
            f = option(f)
        return f

    return decorate


#: The names of the AT-cut quartz plate (already a cut: its own surface frame).
AT_CUT_NAMES = ("quartz-at", "at-quartz", "quartz_at")


def crystal_face(crystal, c11, c12, c44, zener, poisson, surface, inplane) -> Material:
    """The chosen crystal in the frame of the chosen face (z = inward normal); ``--crystal
    quartz-AT`` is the AT-cut plate (:func:`contactres.materials.at_cut_quartz`)."""
    if crystal is not None and crystal.strip().lower() in AT_CUT_NAMES:
        from ..materials import at_cut_quartz

        if (
            surface != "001"
            or inplane is not None
            or any(v is not None for v in (c11, c12, c44, zener, poisson))
        ):
            raise ContactresInputError(
                "--crystal quartz-AT is already a cut (x = the X axis, z = the plate normal): "
                "leave out --surface, --inplane and the elastic constants"
            )
        return at_cut_quartz()
    m = material_from_options(crystal, c11, c12, c44, zener, poisson)
    normal = parse_direction(surface, "surface")
    x = None if inplane is None else parse_direction(inplane, "inplane")
    try:
        return m.rotated(normal, x)
    except ValueError as exc:  # both are valid directions: only their combination can fail
        raise ContactresInputError(f"--surface {surface} / --inplane {inplane}: {exc}") from None
