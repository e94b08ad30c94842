"""Writing results: any job's Result or the QCM analysis's as tables, JSON and figures
(:func:`write_report`), the HTML page of the analysis (:func:`write_html`) and the text the
command line prints.

The public names below are loaded on first use (PEP 562 module ``__getattr__``); the modules
that implement them are private (``_writer``, ``_tables``, ...). Two modules are public:
:mod:`contactres.report.figures` (the figures of the QCM analysis, and :func:`key_below
<contactres.report.figures.key_below>` shared by every figure of the package) and
:mod:`contactres.report.dictionary` (the data dictionary, generated from the schemas).
"""

from __future__ import annotations

from types import MappingProxyType

from .._lazy import attach

# Read as True by mypy and pyright (the real objects below), False at run time: no import.
TYPE_CHECKING = False

# Public name -> the module that defines it.
_EXPORTS = MappingProxyType(
    {
        "friction_table": "._console",
        "radiation_lines": "._console",
        "table1_text": "._console",
        "withheld_lines": "._console",
        "html_report": "._html",
        "write_html": "._html",
        "prediction_figure": "._job_figures",
        "modulus_map_figure": "._map_figures",
        "loads_table": "._tables",
        "summary": "._tables",
        "sweeps_table": "._tables",
        "FORMATS": "._writer",
        "report_names": "._writer",
        "report_set": "._writer",
        "write_report": "._writer",
    }
)

__all__ = sorted(_EXPORTS)

# What type checkers see: the real objects behind the public names (never run, so the imports
# stay lazy; tests/test_public_api.py keeps these imports and ``_EXPORTS`` the same).
if TYPE_CHECKING:
    # isort: off
    from ._console import (
        friction_table as friction_table,
        radiation_lines as radiation_lines,
        table1_text as table1_text,
        withheld_lines as withheld_lines,
    )
    from ._html import html_report as html_report, write_html as write_html
    from ._job_figures import prediction_figure as prediction_figure
    from ._map_figures import modulus_map_figure as modulus_map_figure
    from ._tables import (
        loads_table as loads_table,
        summary as summary,
        sweeps_table as sweeps_table,
    )
    from ._writer import (
        FORMATS as FORMATS,
        report_names as report_names,
        report_set as report_set,
        write_report as write_report,
    )

    # isort: on

__getattr__, __dir__ = attach(__name__, _EXPORTS)
