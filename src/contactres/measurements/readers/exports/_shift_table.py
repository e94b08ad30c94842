"""Reader plug-in for the tidy table of QCM-D shifts: ``time_s, overtone, df_Hz, dgamma_Hz``.

The table a user writes from any instrument (or from another program) when no export reader
fits: one row per time and overtone, comma, semicolon or tab separated, the columns of
:data:`contactres.measurements.schema.QCMD_SHIFTS_TABLE` with their rules. Its column names
state its conventions, so none is asked for: Δf_n not divided by n (Hz), ΔΓ_n the shift of the
half bandwidth (Hz), time in seconds, shifts against the bare sensor in the same medium as
written (baseline ``as-exported``). A blank ``dgamma_Hz`` cell is a bandwidth not measured at
that point; a table without bandwidths (no ``dgamma_Hz`` column, or every cell blank) is
refused, since Δf alone cannot tell a contact from a mass.

Of the conventions of :data:`~._base.CONVENTION_KEYS`: ``fundamental`` (Hz) is recorded (the
table holds no frequency to read it from), ``overtone`` keeps one overtone; one that contradicts
the column names (Δf divided by n, a D scale, a time unit other than s, a baseline other than
as-exported, a channel) is a one-line error.
"""

from __future__ import annotations

from pathlib import Path
from types import MappingProxyType

from ....errors import ContactresInputError
from ._base import COLUMNS, ExportReader, ExportTable, ExportWarning, check_keys, header_names

__all__ = ["CONVENTIONS", "NAME", "READER", "SUFFIXES", "detect", "load"]

NAME = "tidy"
SUFFIXES = (".csv", ".txt", ".tsv", ".xlsx")
#: The sheet of a workbook read first (else its first sheet).
SHEET = "shifts"
SOURCE = "contactres (the tidy QCM-D shift table: contactres.measurements.schema)"
CONVENTIONS = MappingProxyType(
    {
        "time": "time_s: seconds",
        "frequency": "df_Hz: Δf_n, not divided by n",
        "dissipation": "dgamma_Hz: ΔΓ_n, the half-bandwidth shift (Hz)",
        "overtones": "one row per time and overtone (column overtone)",
        "channels": "one",
    }
)

#: The conventions whose only value agreeing with the column names is this one (None: not given).
_STATED = MappingProxyType(
    {
        "df_divided_by_n": (False, "df_Hz holds Δf_n, not divided by n"),
        "dissipation_scale": (None, "the table holds ΔΓ in Hz (dgamma_Hz), no D"),
        "time_unit": ("s", "time_s is in seconds"),
        "baseline": ("as-exported", "the shifts are taken as written"),
        "channel": (None, "the table has one channel"),
    }
)


def detect(path: Path, head: str) -> bool:
    """True for a header naming ``time_s``, ``overtone`` and ``df_Hz`` (``dgamma_Hz`` is
    checked by :func:`load`, which names it when it is missing) and no ``sweep`` column (an
    amplitude-sweep table has its own reader); in an Excel workbook (``.xlsx``), the header of
    its sheet ``shifts`` (else its first sheet)."""
    if Path(path).suffix.lower() == ".xlsx":
        from .. import _excel

        try:
            names = (
                set(_excel.load_sheet(Path(path), SHEET).columns)
                if _excel.detect(Path(path), head)
                else set()
            )
        except ContactresInputError:
            return False  # not a readable sheet: the other readers are tried, then one line
    else:
        names = set(header_names(head))
    return {"time_s", "overtone", "df_Hz"} <= names and "sweep" not in names


def _option(key: str, value) -> str:
    """The command-line option that passes ``key`` (the API's keyword) as ``value``: the flag
    pair ``--df-per-overtone/--df-divided-by-n`` sets ``df_divided_by_n``."""
    if key == "df_divided_by_n":
        return "--df-divided-by-n" if value else "--df-per-overtone"
    return "--" + key.replace("_", "-")


def _check_conventions(path: Path, given: dict) -> None:
    for key, (agrees, why) in _STATED.items():
        value = given.get(key)
        if value is None or value == agrees:
            continue
        if key == "baseline" and str(value).strip().lower() == agrees:
            continue
        raise ContactresInputError(
            f"{path}: {key}={value!r} ({_option(key, value)} on the command line) does not "
            f"apply to a tidy shift table: {why} (its column names state the conventions)"
        )


def load(path, **conventions) -> ExportTable:
    """Read a tidy shift table (see the module docstring); one-line errors name the file, the
    line, the column, the value and the rule."""
    import warnings

    import numpy as np
    import pandas as pd

    from ...schema import QCMD_SHIFTS_TABLE as SCHEMA
    from ...schema import check_cells, rule
    from .. import _excel
    from .._delimited import line_ranges
    from .._delimited import load as read_table

    path = Path(path)
    check_keys(path, NAME, conventions)
    given = {k: v for k, v in conventions.items() if v is not None}
    _check_conventions(path, given)
    workbook = path.suffix.lower() == ".xlsx"
    raw = _excel.load_sheet(path, SHEET) if workbook else read_table(path)
    where = str(raw.attrs.get("source", path))  # a workbook's cells: its sheet named too
    SCHEMA.check_names(raw.columns, where)  # a misspelt column would be left out unseen
    absent = [c for c in SCHEMA.required if c not in raw.columns]
    if "dgamma_Hz" in absent:
        raise ContactresInputError(
            f"{path}: no column 'dgamma_Hz': the bandwidth shifts ΔΓ_n (Hz, half width) are "
            "needed beside Δf_n to tell the particles' contact from their mass"
        )
    if absent:
        raise ContactresInputError(
            f"{path}: missing column(s) {', '.join(map(repr, absent))}; a tidy shift table has "
            f"{', '.join(SCHEMA.required)}"
        )
    if raw.empty:
        raise ContactresInputError(f"{path}: no data rows below the header")
    decimal = raw.attrs.get("decimal", ".")
    values = {}
    for name in SCHEMA.required:
        text = raw[name].astype(str).str.strip()
        if decimal == ",":
            text = text.str.replace(",", ".", regex=False)
        blank = (text == "").to_numpy()
        number = pd.to_numeric(text.where(~blank, "nan"), errors="coerce").to_numpy(float)
        not_number = ~blank & np.isnan(number) & (text.str.lower() != "nan").to_numpy()
        if not_number.any():
            words = rule("number", lambda v: v.astype(bool), "", " is not a number", shown=False)
            check_cells(raw, where, name, (words,), values=~not_number, given=not_number)
        if name != "dgamma_Hz" and blank.any():
            words = rule(
                "not empty",
                lambda v: v.astype(bool),
                "",
                " is empty; every row needs a time, an overtone and a Δf",
                shown=False,
            )
            check_cells(raw, where, name, (words,), values=~blank, given=blank)
        SCHEMA.check_cells(raw, where, name, values=number, given=~blank)
        values[name] = number
    if not np.isfinite(values["dgamma_Hz"]).any():
        raise ContactresInputError(
            f"{path}: every dgamma_Hz cell is blank: the bandwidth shifts ΔΓ_n (Hz, half width) "
            "are needed beside Δf_n to tell the particles' contact from their mass"
        )
    keys = np.stack([values["time_s"], values["overtone"]], axis=1)
    _, first, counts = np.unique(keys, axis=0, return_index=True, return_counts=True)
    if (counts > 1).any():
        twice = np.zeros(len(raw), bool)
        for k in first[counts > 1]:
            twice |= (keys == keys[k]).all(axis=1)
        lines = raw["line"].to_numpy()[twice]
        raise ContactresInputError(
            f"{where}: time {values['time_s'][twice][0]:g} s and overtone "
            f"{int(values['overtone'][twice][0])} appear more than once "
            f"({'rows' if workbook else 'lines'} {line_ranges(lines)}): one row per time and "
            "overtone"
        )
    data = pd.DataFrame(
        {
            "time_s": values["time_s"],
            "overtone": values["overtone"].astype(int),
            "df_Hz": values["df_Hz"],
            "dgamma_Hz": values["dgamma_Hz"],
        }
    )
    held = sorted(int(n) for n in data["overtone"].unique())
    if "overtone" in given:
        data = data[data["overtone"] == int(given["overtone"])]
        if data.empty:
            raise ContactresInputError(
                f"{path}: overtone {given['overtone']} (--overtone) is not in the table; it "
                f"holds {', '.join(map(str, held))}"
            )
    notes = []
    if comments := raw.attrs.get("comment_lines", ()):
        notes.append(
            f"{len(comments)} comment line(s) among the rows skipped (first character '#'): "
            f"line(s) {line_ranges(comments)}"
        )
    for note in notes:
        warnings.warn(f"{path}: {note}", ExportWarning, stacklevel=3)
    data = data.sort_values(["time_s", "overtone"], kind="stable").reset_index(drop=True)
    fundamental = given.get("fundamental")
    record = {
        "source_file": str(path),
        "reader": NAME,
        "layout": "tidy shift table: time_s, overtone, df_Hz, dgamma_Hz",
        "channel": "",
        "overtones": sorted(int(n) for n in data["overtone"].unique()),
        "time_unit_as_read": "s",
        "frequency_as_read": "shift",
        "df_as_read": "per overtone (Δf_n)",
        "dissipation_as_read": "Gamma (Hz)",
        "dissipation_scale": None,
        "dissipation_scale_source": None,
        "baseline": "as exported (the reference the table's author chose)",
        "reference_frequency_Hz": None,
        "reference_gamma_Hz": None,
        "shift_offsets_removed_Hz": None,
        "fundamental_Hz": None if fundamental is None else float(fundamental),
        "fundamental_source": None if fundamental is None else "given",
        "gamma_rule": "Γ read from the file (Hz)",
        "empty_cells_skipped": int(np.isnan(values["dgamma_Hz"]).sum()),
        "left_out": notes,
        "given_by_user": sorted(given),
    }
    return ExportTable(data[list(COLUMNS)], record)


#: The recipe (kind ``export``): tried before the instrument readers by ``qcm particles``.
READER = ExportReader(NAME, SUFFIXES, detect, load, conventions=CONVENTIONS, source=SOURCE)
