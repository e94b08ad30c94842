"""The map computations, now in :mod:`contactres.jobs.maps`: re-exported here for the scripts,
benchmarks and gallery written against ``contactres.apps.maps``."""

from ..jobs.maps import (
    METHODS,
    TipLoad,
    fit_measured_map,
    fit_record,
    open_map,
    predict_map,
    read_value_grid,
    synthetic_map,
)

__all__ = [
    "METHODS",
    "TipLoad",
    "fit_measured_map",
    "fit_record",
    "open_map",
    "predict_map",
    "read_value_grid",
    "synthetic_map",
]
