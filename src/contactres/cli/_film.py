"""The options of a coated sample: ``--coating`` (films on the sample, parsed by
:func:`contactres.jobs.contact.parse_coating`; :func:`coating_option`), and the set shared by
``afm invert`` and ``rum invert`` (the film's modulus on a known substrate:
:func:`contactres.analysis.film_modulus_from_contact_stiffness`; :func:`coating_options`)."""

from __future__ import annotations

import math

import click

from ..errors import ContactresInputError
from ._common import MagnitudeType


def coating_option(what: str):
    """``--coating MATERIAL:THICKNESS`` (repeatable, top first), its help ending in ``what``
    (what the films add to the command's output)."""
    return click.option(
        "--coating",
        multiple=True,
        metavar="MATERIAL:THICKNESS",
        help="A film on the sample, thickness in m or with its unit (e.g. pmma:250e-9 or "
        "pmma:250nm); repeat for more layers, "
        "top first. MATERIAL: pmma (its 1 Hz storage modulus) or an isotropic solid of "
        f"`contactres crystals` (fused-silica, soda-lime-glass, Si3N4). {what}",
    )


def coating_options():
    """--coating, --substrate, --film-range and --min-film-weight, in that order."""

    def decorate(f):
        for option in reversed(
            (
                click.option(
                    "--coating",
                    multiple=True,
                    metavar="MATERIAL:THICKNESS",
                    help="One film on the sample, thickness in m or with its unit (e.g. "
                    "pmma:250e-9 or pmma:250nm): adds the "
                    "film's modulus M_film_Pa (needs --substrate). MATERIAL as in 'contactres "
                    "contact --coating' (pmma: its 1 Hz storage constants give the Poisson "
                    "ratio); its modulus is the unknown.",
                ),
                click.option(
                    "--substrate",
                    default=None,
                    help="The solid under the coating: a built-in solid (see 'contactres "
                    "crystals'), e.g. fused-silica, Si.",
                ),
                click.option(
                    "--film-range",
                    default=None,
                    metavar="LOW:HIGH",
                    show_default="the film material's modulus / 10 to x 10",
                    help="Search range of the film's indentation modulus, Pa (e.g. 1e9:2e10); "
                    "outside it: film_verdict below-range or above-range.",
                ),
                click.option(
                    "--min-film-weight",
                    type=MagnitudeType("mode_tolerance"),
                    default="0.1",
                    show_default=True,
                    help="Film weight (the film's share of the sensitivity of k*, dimensionless) "
                    "below which the film is too thin for the tip: no modulus.",
                ),
            )
        ):
            f = option(f)
        return f

    return decorate


def parse_film_range(text: str | None) -> tuple[float, float] | None:
    """``LOW:HIGH`` (Pa) as two floats, or None; one line naming --film-range otherwise."""
    if text is None:
        return None
    low, colon, high = text.partition(":")
    try:
        values = (float(low), float(high))
    except ValueError:
        values = (math.nan, math.nan)
    if not colon or not all(math.isfinite(v) and v > 0 for v in values) or values[0] >= values[1]:
        raise ContactresInputError(
            f"--film-range must be LOW:HIGH, two moduli 0 < LOW < HIGH in Pa, got {text!r}"
        )
    from ..units import check_magnitude  # here: the CLI imports no library module at start-up

    for v, part in zip(values, (low, high), strict=True):  # a modulus typed in GPa is caught
        check_magnitude("modulus", v, "--film-range", text=part.strip())
    return values


def film_summary(table, coating: dict) -> str:
    """One line on the film's moduli of an inverted table (``coating``: the job's record)."""
    import numpy as np

    verdicts = table["film_verdict"]
    counts = ", ".join(f"{int((verdicts == v).sum())} {v}" for v in sorted(set(verdicts) - {""}))
    M = np.asarray(table["M_film_Pa"], dtype=float)  # a DataFrame's column or numpy's
    line = f"film {coating['label']} on {coating['substrate']}: {counts or 'no row with k*'}"
    if np.isfinite(M).any():
        line += f"; M_film median {np.nanmedian(M) / 1e9:.4g} GPa"
    if coating["film_range_Pa"] is not None:
        low, high = coating["film_range_Pa"]
        line += f" (searched {low / 1e9:.4g} to {high / 1e9:.4g} GPa)"
    return line
