"""Writing the results of an analysis: tables, figures."""

from .tables import SUMMARY_GROUP_KEYS, SWEEP_COLUMNS, SWEEP_EXTRA_COLUMNS, Results

__all__ = ["SUMMARY_GROUP_KEYS", "SWEEP_COLUMNS", "SWEEP_EXTRA_COLUMNS", "Results"]
