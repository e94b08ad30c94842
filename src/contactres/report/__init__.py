"""Writing results: any job's Result or the QCM analysis's as tables, JSON and figures
(:func:`write_report`, :mod:`contactres.report.writer`) and the HTML page of the analysis
(:func:`write_html`)."""

from .html import html_report, write_html
from .map_figures import modulus_map_figure
from .tables import FORMATS, loads_table, report_files, summary, sweeps_table
from .writer import write_report

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
