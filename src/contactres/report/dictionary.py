"""The data dictionary: every column of every table and every flag, as Markdown.

Generated from :mod:`contactres.measurements.schema`, :mod:`contactres.analysis.flags` and (for
``radiation.csv``) :data:`contactres.analysis.radiation.RADIATION_RESULTS`; the
README's blocks between ``<!-- dictionary:NAME -->`` and ``<!-- /dictionary -->`` are these
tables (``python scripts/update_readme.py`` rewrites them; a test fails when they differ).
"""

from __future__ import annotations

import re

from ..analysis.flags import DESCRIPTIONS, Flag
from ..analysis.radiation import RADIATION_RESULTS
from ..measurements.resonances import AFM_TABLE, RUM_TABLE
from ..measurements.schema import GROUP_RESULTS, LOAD_RESULTS, SWEEP_RESULTS, SWEEP_TABLE
from ..measurements.spectra_table import SPECTRA_TABLE

__all__ = ["BLOCK", "dictionary_tables", "flags_markdown", "update_blocks"]

#: A README block: its name, its body and the end marker.
BLOCK = re.compile(
    r"(<!-- dictionary:(?P<name>[\w-]+) -->\n)(?P<body>.*?)(<!-- /dictionary -->)", re.S
)


def flags_markdown() -> str:
    """The flags of ``sweeps.csv`` and what each means, as a Markdown table."""
    lines = ["| flag | meaning |", "|---|---|"]
    lines += [f"| `{flag.text}` | {DESCRIPTIONS[flag]} |" for flag in Flag]
    return "\n".join(lines)


def dictionary_tables() -> dict[str, str]:
    """Block name -> Markdown table, for every table contactres reads or writes and the flags."""
    return {
        "sweep-table": SWEEP_TABLE.markdown(with_required=True),
        "sweeps-csv": SWEEP_RESULTS.markdown(),
        "loads-csv": LOAD_RESULTS.markdown(),
        "summary-json": GROUP_RESULTS.markdown(),
        "radiation-csv": RADIATION_RESULTS.markdown(),
        "spectra-table": SPECTRA_TABLE.markdown(with_required=True),
        "flags": flags_markdown(),
        "afm-table": AFM_TABLE.markdown(with_required=True),
        "rum-table": RUM_TABLE.markdown(with_required=True),
    }


def update_blocks(text: str) -> str:
    """``text`` with the body of every dictionary block replaced by the current table.

    Raises KeyError for a block whose name is not one of :func:`dictionary_tables`.
    """
    tables = dictionary_tables()

    def body(m: re.Match) -> str:
        return f"{m.group(1)}{tables[m.group('name')]}\n{m.group(4)}"

    return BLOCK.sub(body, text)
