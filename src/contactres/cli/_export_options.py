"""The options of the commands that read a QCM-D file (``qcm stiffness``, ``qcm particles``):
which reader, and what the file does not say (the conventions of
:func:`contactres.measurements.readers.exports.read_export`).

:func:`export_options` adds them to a command, in one order and with one wording;
:func:`conventions` turns their values into the keywords of ``read_export``. Nothing of the
library is imported here at start-up (tests/test_startup.py): the reader names are read from
the registry when a help is shown or an option is checked.
"""

from __future__ import annotations

import math

import click

from ._common import MagnitudeType, odd_overtone

__all__ = [
    "Baseline",
    "DissipationScale",
    "ReaderName",
    "ReaderOption",
    "conventions",
    "export_options",
    "reader_names",
    "shift_reader_names",
]


def reader_names() -> tuple[str, ...]:
    """The names of the export readers, in the order they are tried: those of the registry
    (``contactres.measurements.readers.exports.EXPORT_READERS``; imported without pandas)."""
    from ..measurements.readers.exports import EXPORT_READERS

    return tuple(r.name for r in EXPORT_READERS)


def shift_reader_names() -> tuple[str, ...]:
    """The names of the readers of QCM-D shifts (the tidy table, then the exports:
    ``contactres.measurements.readers.exports.SHIFT_READERS``)."""
    from ..measurements.readers.exports import SHIFT_READERS

    return tuple(r.name for r in SHIFT_READERS)


class ReaderName(click.ParamType):
    """The name of a reader, checked against the registry when given (``shifts``: the tidy
    table's reader is one of them)."""

    name = "NAME"

    def __init__(self, shifts: bool = False):
        self.shifts = shifts

    def convert(self, value, param, ctx):
        from ..measurements.readers.exports import EXPORT_READERS, SHIFT_READERS, export_reader

        try:
            return export_reader(value, SHIFT_READERS if self.shifts else EXPORT_READERS).name
        except ValueError as exc:
            self.fail(str(exc), param, ctx)


class ReaderOption(click.Option):
    """``--reader``, whose help names the readers of the registry, read when the help is shown
    (building the command imports no reader)."""

    @property
    def help(self) -> str:
        shifts = isinstance(self.type, ReaderName) and self.type.shifts
        names = shift_reader_names() if shifts else reader_names()
        return f"Export format: {', '.join(names)}."

    @help.setter
    def help(self, value) -> None:
        """click sets the help when it builds the option; the text is the registry's."""


class DissipationScale(click.ParamType):
    """What one unit of a D column is: a number in (0, 1] (1e-6 for ppm) or ``ppm``."""

    name = "SCALE"

    def convert(self, value, param, ctx):
        text = str(value).strip().lower()
        try:
            scale = 1e-6 if text == "ppm" else float(text)
        except ValueError:
            self.fail(f"{value!r} is not a number: use 1e-6 (D in ppm) or 1 (D plain)", param, ctx)
        if not (math.isfinite(scale) and 0 < scale <= 1):
            self.fail(
                f"{value!r} is outside (0, 1]: the scale of D is 1e-6 for ppm or 1 for a plain "
                "number",
                param,
                ctx,
            )
        return scale


class Baseline(click.ParamType):
    """``first``, ``as-exported`` or ``window:T0:T1`` (seconds)."""

    name = "BASELINE"

    def convert(self, value, param, ctx):
        from ..measurements.readers.exports import parse_baseline

        try:
            parse_baseline(value)
        except ValueError as exc:
            self.fail(str(exc), param, ctx)
        return str(value).strip().lower()


def export_options(*, shifts: bool = False):
    """Decorator: ``--reader``, ``--df-per-overtone/--df-divided-by-n``,
    ``--dissipation-scale``, ``--baseline``, ``--time-unit``, ``--channel`` and ``--overtone``,
    in this order (``shifts``: ``--reader`` also takes the tidy table's reader)."""
    options = (
        click.option(
            "--reader",
            cls=ReaderOption,
            type=ReaderName(shifts),
            show_default="recognised from the header",
        ),
        click.option(
            "--df-per-overtone/--df-divided-by-n",
            "df_per_overtone",
            default=None,
            help="The file's frequency shifts are Δf_n, Hz, or Δf_n/n, Hz (where its header "
            "does not say; not for absolute frequencies).",
        ),
        click.option(
            "--dissipation-scale",
            type=DissipationScale(),
            help="What one unit of the file's D column is, dimensionless: 1e-6 (or ppm) for D "
            "in 10^-6, 1 for D as a plain number (where the header does not say).",
        ),
        click.option(
            "--baseline",
            type=Baseline(),
            help="Reference of the shifts: first (first point of each overtone), window:T0:T1 "
            "(mean over T0 <= t <= T1, s) or as-exported (files of shifts).",
            show_default="as-exported for shifts; absolute frequencies need one",
        ),
        click.option(
            "--time-unit",
            type=click.Choice(["s", "min", "h"]),
            help="Unit of the file's time column: seconds, minutes or hours (where the header "
            "does not say).",
        ),
        click.option(
            "--channel",
            help="Sensor or channel to read from a multi-sensor export (QSense 1-4, QCM-I A-D).",
        ),
        click.option(
            "--overtone",
            type=MagnitudeType("overtone", integer=True),
            callback=odd_overtone,
            help="Overtone order n, dimensionless (odd): that of a single-overtone openQCM log, "
            "or the one to keep.",
            show_default="all in the file",
        ),
    )

    def decorate(command):
        for option in reversed(options):
            command = option(command)
        return command

    return decorate


def conventions(df_per_overtone, dissipation_scale, baseline, time_unit, channel, overtone) -> dict:
    """The values of :func:`export_options` as the conventions of ``read_export`` (None: not
    given; the fundamental is each command's own option)."""
    return {
        "df_divided_by_n": None if df_per_overtone is None else not df_per_overtone,
        "dissipation_scale": dissipation_scale,
        "baseline": baseline,
        "time_unit": time_unit,
        "channel": channel,
        "overtone": overtone,
    }
