"""Shared option types and output helpers of the command line."""

from __future__ import annotations

import json
import os
import sys
from typing import TYPE_CHECKING

import click

from ..errors import ContactresInputError

if TYPE_CHECKING:  # annotations only: numpy and pandas are imported when a command runs
    import numpy as np
    import pandas as pd


def parse_range(text: str) -> np.ndarray:
    """Parse ``start:stop:num`` (numpy linspace, ``num`` points), ``a,b,c`` or one number."""
    import numpy as np

    s = str(text).strip()
    try:
        if ":" in s:
            parts = s.split(":")
            if len(parts) != 3:
                raise ValueError
            start, stop = float(parts[0]), float(parts[1])
            num = int(parts[2])
            if num < 1:
                raise ValueError
            values = np.linspace(start, stop, num)
        else:
            values = np.array([float(v) for v in s.split(",") if v.strip()])
    except ValueError:
        raise ContactresInputError(
            f"{text!r} is not a range: use START:STOP:NUM (NUM >= 1 points), "
            "a comma list or a number"
        ) from None
    if values.size == 0 or not np.all(np.isfinite(values)):
        raise ContactresInputError(f"{text!r} is not a range of finite numbers")
    return values


def _checked(quantity: str, option: str, value, ctx, **rule) -> float:
    """``value`` checked by :func:`contactres.units.check_magnitude`; its ValueError becomes a
    click usage error (one line naming the command, exit code 2)."""
    from ..units import check_magnitude

    try:
        return check_magnitude(quantity, value, option, **rule)
    except ValueError as exc:
        raise click.UsageError(str(exc), ctx) from None


def _option_name(param) -> str:
    return max(param.opts, key=len) if param is not None and param.opts else "value"


def odd_overtone(ctx, param, value):
    """Click callback: the QCM is driven at its odd harmonics only (paper 2, Eq. 1)."""
    if value is not None and value % 2 == 0:
        raise click.UsageError(
            f"--overtone {value} must be odd: a QCM resonates at n = 1, 3, 5, ...", ctx
        )
    return value


class ValueDefault(click.Option):
    """An option whose default is a plain value applied later (from a file's column or a TOML
    file, so ``default`` stays None): its help shows ``[default: 5e6]`` like any other value,
    not click's parenthesised form of a described default, ``[default: (5e6)]``."""

    def get_help_extra(self, ctx):
        extra = super().get_help_extra(ctx)
        if isinstance(self.show_default, str) and "default" in extra:
            extra["default"] = self.show_default
        return extra


class MagnitudeType(click.ParamType):
    """A click parameter for one number of a physical quantity, checked against its plausible
    range (:data:`contactres.units.QUANTITIES`): a unit slip, NaN, inf or a negative value where
    none is physical is refused in one line naming the option.

    Parameters
    ----------
    quantity : str
        A key of :data:`contactres.units.QUANTITIES`.
    integer : bool
        Parse an integer (a count, an overtone order).
    **rule
        ``allow_zero``/``signed`` of :func:`contactres.units.check_magnitude`.
    """

    def __init__(self, quantity: str, *, integer: bool = False, **rule):
        self.quantity = quantity
        self.integer = integer
        self.rule = rule
        self.name = "INTEGER" if integer else "FLOAT"

    def convert(self, value, param, ctx):
        # A string is what the user typed (quoted as such); a number is a value already parsed
        # (a programmatic call), checked the same way.
        if self.integer:
            try:
                value = int(value.strip() if isinstance(value, str) else value)
            except (TypeError, ValueError):
                self.fail(f"{value!r} is not an integer", param, ctx)
        number = _checked(self.quantity, _option_name(param), value, ctx, **self.rule)
        return value if self.integer else number


class RangeType(click.ParamType):
    """A click parameter for ``START:STOP:NUM`` ranges (numpy linspace) or comma lists.

    With a ``quantity`` (a key of :data:`contactres.units.QUANTITIES`) every value is checked
    against its plausible range; the message names the first value refused and the range typed.
    ``**rule``: ``allow_zero``/``signed`` of :func:`contactres.units.check_magnitude`.
    """

    name = "START:STOP:NUM"

    def __init__(self, quantity: str | None = None, **rule):
        self.quantity = quantity
        self.rule = rule

    def convert(self, value, param, ctx):
        import numpy as np

        if isinstance(value, np.ndarray):
            return value
        try:
            text = self._in_si(value, param)
        except ValueError as exc:  # a unit pint refused: one line naming the option, as above
            raise click.UsageError(str(exc), ctx) from None
        try:
            values = parse_range(text)
        except ValueError as exc:
            self.fail(str(exc), param, ctx)
        if self.quantity is not None:
            self._check(values, str(value).strip(), param, ctx)
        return values

    def _in_si(self, value, param):
        """``value`` with each number typed with its unit (``1.1mm``, ``0:2mN:5``'s ends, a
        comma list's items) written in SI (:func:`contactres.typed_units.to_si`); plain numbers
        as typed. Only for a quantity (its SI unit is known)."""
        from ..typed_units import has_unit

        text = str(value)
        if self.quantity is None or not any(c.isalpha() for c in text):
            return value
        from ..typed_units import to_si
        from ..units import QUANTITIES

        unit = QUANTITIES[self.quantity].unit
        option = _option_name(param)
        sep = ":" if ":" in text else ","
        parts = text.split(sep)
        ends = parts[:2] if sep == ":" else parts  # NUM of START:STOP:NUM has no unit
        typed = [has_unit(t) for t in ends]
        if any(typed) and not all(typed):
            # "1,1 mm" is a decimal comma, "1mm:2:5" an end without its unit: never guessed.
            from ..errors import ContactresInputError

            raise ContactresInputError(
                f"{option} {text.strip()!r}: give every value with its unit or none (plain "
                "numbers are SI); a decimal comma? write 1.1mm"
            )
        converted = [
            repr(to_si(t, unit, option)) if u else t for t, u in zip(ends, typed, strict=True)
        ]
        return sep.join(converted + parts[len(ends) :])

    def _check(self, values, typed: str, param, ctx) -> None:
        """Refuse an implausible value, quoted as typed: a refused end of START:STOP:NUM (the
        numbers the user wrote) before a point between them, else the first refused element."""
        import numpy as np

        from ..units import QUANTITIES, format_number

        assert self.quantity is not None  # convert checks only a quantity it was given
        bad = ~np.asarray(QUANTITIES[self.quantity].accepts(values, **self.rule))
        if not bad.any():
            return
        from ..typed_units import has_unit

        if values.size == 1:
            i, text = 0, typed
            if has_unit(typed):  # the value with its unit: no unit slip to suggest
                _checked(self.quantity, _option_name(param), typed, ctx, **self.rule)
        elif ":" in typed:
            ends = typed.split(":")[:2]
            first = [k for k in (0, values.size - 1) if bad[k]]
            i = first[0] if first else int(np.flatnonzero(bad)[0])
            number = ends[0 if i == 0 else 1].strip() if first else format_number(values[i])
            text = f"{number} (in {typed})"
        else:
            i = int(np.flatnonzero(bad)[0])
            text = f"{[t for t in typed.split(',') if t.strip()][i].strip()} (in {typed})"
        _checked(self.quantity, _option_name(param), float(values[i]), ctx, text=text, **self.rule)


RANGE = RangeType()


class MaterialType(click.ParamType):
    """A click parameter for the name of a solid in a contact (``role`` "sphere" or "plate"):
    a built-in solid (``contactres crystals``), ``glass`` (soda-lime glass) and, for the plate,
    ``quartz-AT`` (:func:`contactres.materials.at_cut_quartz`). An unknown name is refused in one
    line listing the known ones (:func:`contactres.analysis.material_by_name`)."""

    name = "NAME"

    def __init__(self, role: str):
        self.role = role

    def convert(self, value, param, ctx):
        from ..analysis import material_by_name

        try:
            material_by_name(value, self.role)
        except ValueError as exc:
            self.fail(str(exc), param, ctx)
        return str(value).strip()


FORMATS = ("plain", "csv", "json")


class _PrintFormat(click.Choice):
    """``--format``'s choices; a file format asked for here (``--format xlsx``, as a user of
    spreadsheet tools may type) is pointed to ``--save-as``, which writes it."""

    def convert(self, value, param, ctx):
        word = str(value).strip().lower().lstrip(".")
        if word in ("xlsx", "excel", "netcdf", "nc"):
            self.fail(
                f"{value!r} is a file format, not a way to print: --save-as "
                f"{'netcdf' if word in ('netcdf', 'nc') else 'xlsx'} writes the tables into OUT "
                "as one file (qcm analyze, qcm stiffness, qcm particles); --format chooses how "
                f"the table is printed ({', '.join(FORMATS)})",
                param,
                ctx,
            )
        return super().convert(value, param, ctx)


def format_option(default: str = "plain"):
    """The ``--format plain|csv|json`` option every printing subcommand takes."""
    return click.option(
        "--format",
        "fmt",
        type=_PrintFormat(FORMATS),
        default=default,
        show_default=True,
        help="Output format: aligned text, CSV or JSON (records).",
    )


#: The figure formats a command that writes figures offers (those of the report writer,
#: ``contactres.report.FIGURE_FORMATS``, spelled here: the command line starts without it).
FIGURE_FORMATS = ("png", "svg", "pdf")


#: The one-file exports of a results folder (``contactres.report.FORMATS``): an Excel workbook
#: and a NetCDF file.
EXPORT_FORMATS = ("xlsx", "netcdf")


def _words(ctx, param, value, known: tuple[str, ...], what: str) -> tuple[str, ...]:
    """An option's values (repeated and/or comma lists) as a tuple of ``known`` words, each
    once; a word not in ``known``: one line naming it and the choices."""
    chosen: list[str] = []
    for given in value:
        for word in str(given).split(","):
            fmt = word.strip().lower().lstrip(".")
            if fmt not in known:
                raise click.BadParameter(
                    f"{word.strip()!r} is not {what}: choose from {', '.join(known)} (repeat "
                    "the option or give a comma list)",
                    ctx,
                    param,
                )
            if fmt not in chosen:
                chosen.append(fmt)
    return tuple(chosen)


def _figure_formats(ctx, param, value) -> tuple[str, ...]:
    """``--figure-format`` values; PNG when none is given."""
    return _words(ctx, param, value, FIGURE_FORMATS, "a figure format") or ("png",)


def _save_as(ctx, param, value) -> tuple[str, ...]:
    """``--save-as`` values; none when none is given."""
    return _words(ctx, param, value, EXPORT_FORMATS, "a format to save the tables as")


def save_as_option():
    """The ``--save-as xlsx|netcdf`` option of the QCM commands that write a results folder: the
    tables also as one Excel workbook (``results.xlsx``) and/or one NetCDF file
    (``results.nc``). Not ``--format``, which chooses how the command prints (and
    ``export`` names an instrument's file in these commands)."""
    return click.option(
        "--save-as",
        "save_as",
        multiple=True,
        callback=_save_as,
        metavar="xlsx|netcdf",
        help="Also write the tables as one file in OUT: xlsx (results.xlsx, one sheet per table "
        "and a conventions sheet; extra 'excel') or netcdf (results.nc, NetCDF 3; extra "
        "'maps'); repeat the option or give a comma list.",
    )


def figure_path(ctx, param, value):
    """A callback for an option naming one figure file: its suffix must be a figure format
    (``.png``, ``.svg``, ``.pdf``), checked before any work (matplotlib would fail after it)."""
    if value is None:
        return None
    suffix = os.path.splitext(str(value))[1].lower().lstrip(".")
    if suffix not in FIGURE_FORMATS:
        raise click.BadParameter(
            f"{value!r}: the suffix names the figure format; choose from "
            f"{', '.join('.' + f for f in FIGURE_FORMATS)}",
            ctx,
            param,
        )
    return value


def figure_format_option():
    """The ``--figure-format png|svg|pdf`` option of every command that writes figures:
    repeatable or a comma list (``--figure-format png,svg``); default PNG only."""
    return click.option(
        "--figure-format",
        "figure_formats",
        multiple=True,
        callback=_figure_formats,
        metavar="png|svg|pdf",
        show_default="png",
        help="Format of the figure files: png, svg or pdf; repeat the option or give a comma "
        "list (png,pdf) for several. The HTML page embeds PNG.",
    )


def _json_scalar(value):
    """numpy scalars (and anything else with ``.item()``) as Python values for json."""
    if hasattr(value, "item"):
        value = value.item()
        return None if isinstance(value, float) and value != value else value
    return str(value)


def emit(table: pd.DataFrame, fmt: str, stream=None) -> None:
    """Print a table in the chosen format to ``stream`` (stdout). A column name twice is a
    ValueError (a fault of the command: JSON records would keep one of the two columns)."""
    from ..fileio import neutralised, unique_written

    # The writers' check of the names, for the JSON records and the plain table too (through
    # fileio: the command line imports no module below it, tests/cli/test_cli_thin.py).
    unique_written(table)
    out = stream or sys.stdout
    if fmt == "csv":
        # 15 significant digits: read back by scripts to 5e-15, yet without the float noise of
        # the 17-digit repr (0.1 + 0.2 prints as 0.3, not 0.30000000000000004).
        neutralised(table).to_csv(out, index=False, float_format="%.15g")
    elif fmt == "json":
        # Python's own float repr (shortest exact), not pandas' to_json, which rounds to a
        # number of decimals and so writes 1.23e-12 m as 0.0.
        import numpy as np  # here: the command line starts without numpy

        # Non-finite values have no JSON form: null, as the CSV outputs leave them empty.
        finite = table.replace([np.inf, -np.inf], np.nan)
        records = finite.astype(object).where(finite.notna(), None).to_dict(orient="records")
        json.dump(records, out, indent=1, allow_nan=False, default=_json_scalar)
        out.write("\n")
    else:
        text = table.to_string(index=False, float_format=lambda v: f"{v:.6g}")
        if len(table) == 1 and max(map(len, text.splitlines())) > _WIDE:
            # One row of many columns reads as a list, one quantity per line (a 350-character
            # line wraps into noise in a terminal); several rows stay a table.
            width = max(len(str(c)) for c in table.columns)
            row = table.iloc[0]
            lines = [f"{c!s:<{width}}  {_cell_text(row[c])}" for c in table.columns]
            text = "\n".join(lines)
        out.write(text + "\n")


#: Widest text table printed as a table; one row wider than this is printed as a list.
_WIDE = 120


def _cell_text(value) -> str:
    """One cell as the text table prints it: floats to 6 significant digits, missing empty."""
    import math

    if isinstance(value, float):
        return "" if math.isnan(value) else f"{value:.6g}"
    if hasattr(value, "dtype") and getattr(value.dtype, "kind", "") == "f":
        return "" if value != value else f"{float(value):.6g}"
    return str(value)


def emit_record(record: dict, fmt: str, stream=None) -> None:
    """Print one record (a dict of scalars) in the chosen format."""
    import pandas as pd

    emit(pd.DataFrame([record]), fmt, stream)


def _interactive() -> bool:
    """True when stderr is a terminal (progress lines would not land in a pipe or a log)."""
    isatty = getattr(sys.stderr, "isatty", None)
    return bool(isatty and isatty())


def progress_stream():
    """Where a progress bar draws: stderr on a terminal, else a sink (a pipe or a log gets
    neither the bar nor its label)."""
    import io

    return sys.stderr if _interactive() else io.StringIO()


def step(command: str, text: str) -> None:
    """One progress line ``contactres COMMAND: step TEXT`` on stderr, on a terminal only: the
    stages of a command that takes more than a second, as 'contactres qcm analyze' shows its
    progress bar; piped or captured output (a CSV on stdout, one-line errors) stays clean."""
    if _interactive():
        click.echo(f"contactres {command}: step {text}", err=True)


def wrote_line(written, out) -> str:
    """The closing line of a command that wrote a report set: the files of the set, and the
    ``manifest.json`` beside them (which lists them with their digests), counted apart so that
    the number is that of the files in the folder."""
    # `--out results/` is typed with its slash often: print it once, not "results//".
    folder = str(out).rstrip("/\\") or str(out)
    return f"wrote {len(written)} files and manifest.json into {folder}/"


def computed_rounded(result, copied) -> object:
    """``result`` (DataFrame) with its computed float columns as text to 10 significant
    digits (no floating-point noise) and the ``copied`` input columns untouched (the user's
    values, written back exactly)."""
    out = result.copy()
    kept = set(copied)
    # By position: a column name twice (a fault of the job) is then the writer's to name, not
    # an AttributeError here (out[name] would be a frame of both).
    for i, col in enumerate(out.columns):
        values = out.iloc[:, i]
        if col not in kept and values.dtype.kind == "f":
            # Python floats (tolist), not numpy scalars: the same text, formatted ~1.5x faster.
            out.isetitem(i, [("" if v != v else f"{v:.10g}") for v in values.to_numpy().tolist()])
    return out
