"""Writing the results of an analysis: tables, JSON and figures (:func:`write_report`)."""

from .tables import FORMATS, loads_table, report_files, summary, sweeps_table, write_report

__all__ = [
    "FORMATS",
    "loads_table",
    "report_files",
    "summary",
    "sweeps_table",
    "write_report",
]
