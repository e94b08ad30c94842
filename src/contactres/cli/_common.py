"""Shared option types and output helpers of the command line."""

from __future__ import annotations

import json
import sys
from typing import TYPE_CHECKING

import click

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
        raise ValueError(
            f"{text!r} is not a range: use START:STOP:NUM (NUM >= 1 points), "
            "a comma list or a number"
        ) from None
    if values.size == 0 or not np.all(np.isfinite(values)):
        raise ValueError(f"{text!r} is not a range of finite numbers")
    return values


class RangeType(click.ParamType):
    """A click parameter for ``START:STOP:NUM`` ranges (numpy linspace) or comma lists."""

    name = "START:STOP:NUM"

    def convert(self, value, param, ctx):
        import numpy as np

        if isinstance(value, np.ndarray):
            return value
        try:
            return parse_range(value)
        except ValueError as exc:
            self.fail(str(exc), param, ctx)


RANGE = RangeType()

FORMATS = ("plain", "csv", "json")


def format_option(default: str = "plain"):
    """The ``--format plain|csv|json`` option every printing subcommand takes."""
    return click.option(
        "--format",
        "fmt",
        type=click.Choice(FORMATS),
        default=default,
        show_default=True,
        help="Output format: aligned text, CSV or JSON (records).",
    )


def emit(table: pd.DataFrame, fmt: str, stream=None) -> None:
    """Print a table in the chosen format to ``stream`` (stdout)."""
    out = stream or sys.stdout
    if fmt == "csv":
        table.to_csv(out, index=False)
    elif fmt == "json":
        json.dump(json.loads(table.to_json(orient="records", double_precision=15)), out, indent=1)
        out.write("\n")
    else:
        out.write(table.to_string(index=False, float_format=lambda v: f"{v:.6g}") + "\n")


def emit_record(record: dict, fmt: str, stream=None) -> None:
    """Print one record (a dict of scalars) in the chosen format."""
    import pandas as pd

    emit(pd.DataFrame([record]), fmt, stream)
