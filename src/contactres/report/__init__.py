"""Writing results: any job's Result or the QCM analysis's as tables, JSON and figures
(:func:`write_report`, :mod:`contactres.report.writer`) and the HTML page of the analysis
(:func:`write_html`)."""

from .html import html_report, write_html
from .map_figures import modulus_map_figure
from .tables import loads_table, summary, sweeps_table
from .writer import FORMATS, report_names, write_report

__all__ = [
    "FORMATS",
    "html_report",
    "loads_table",
    "modulus_map_figure",
    "report_names",
    "summary",
    "sweeps_table",
    "write_html",
    "write_report",
]
