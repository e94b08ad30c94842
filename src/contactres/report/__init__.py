"""Writing the results of an analysis: tables, JSON and figures (:func:`write_report`) and the
HTML page (:func:`write_html`)."""

from .html import html_report, write_html
from .map_figures import modulus_map_figure
from .tables import FORMATS, loads_table, report_files, summary, sweeps_table, write_report

__all__ = [
    "FORMATS",
    "html_report",
    "loads_table",
    "modulus_map_figure",
    "report_files",
    "summary",
    "sweeps_table",
    "write_html",
    "write_report",
]
