"""The results folder of a sweep analysis: its files, their names and columns.

The folder is a report of the ``qcm_sweeps`` job's Result (:mod:`contactres.jobs.qcm_sweeps`:
its tables, :func:`sweeps_table`, :func:`loads_table`, :func:`radiation_table`, and its values,
:func:`summary`), written by :func:`contactres.report.write_report` with the figures and
the page registered for it there (:mod:`.job_figures`, :mod:`.figures`, :mod:`.html`).
:func:`write_report` writes the folder as one :class:`contactres.fileio.ResultSet`: nothing is
written if a file of the set would replace an input (the sweep table, by default) or another run
is writing into the folder, the files appear together or not at all (a killed run leaves the
earlier set), ``manifest.json`` lists them, and files of an earlier set that this one does not
write (e.g. its figures) are removed. The columns are those of
:mod:`contactres.measurements.schema` (``SWEEP_RESULTS``, ``LOAD_RESULTS``, ``GROUP_RESULTS``):

``sweeps.csv``
    one row per sweep, in the order of the schema: the 18 columns of the paper's analysis, then
    the uncertainties and derived quantities. ``model``: the amplitude class (elastic,
    cattaneo-mindlin, savkoor, plateau). ``plateau_amplitude_m`` (± ``plateau_amplitude_err_m``):
    the critical displacement d_c of a plateau sweep, from the fit of the exact plateau loop
    (the hinge of the plateau model if that fit is off or unresolved; then no error). ``df0_Hz``,
    ``dgamma0_Hz``: low-amplitude limits. ``df_slope_Hz_per_m``, ``dgamma_slope_Hz_per_m``: the
    straight line, or for a plateau the hinge slope above the plateau (descriptive only).
    ``mu_df``, ``mu_dgamma``: μ from those slopes (paper 2, Eq. 12), Cattaneo-Mindlin
    sweeps only; empty for a plateau sweep (flag ``plateau-slope``: the shifts leave a plateau
    with no linear term, so no slope formula holds). ``mu_fit``: μ from the fit of the exact
    loop (Cattaneo-Mindlin, or Cattaneo-Mindlin behind the plateau). ``flags``: ';'-separated
    (:class:`contactres.analysis.Flag`; the README explains each).
``loads.csv``
    one row per (configuration, medium, normal force): ``n_experiments``, ``n_sweeps`` and
    ``<quantity>_mean``, ``<quantity>_sd`` (standard deviation over experiments, ddof = 1) of
    Δf0, ΔΓ0 (Hz), κ, ωξ (N/m), the loss tangent ΔΓ0/Δf0 and μ (from Δf, from ΔΓ, from the fit).
``summary.json``
    ``{"groups": [...], "settings": {...}, "version": ..., "conventions": {...}}``; one group per
    (configuration, medium) with the JKR + Mindlin fit (Table 1 of paper 2); with the radiation
    table also ``"radiation": {"sphere_material", "plate_material", "file", "groups": [...]}``
    (:func:`contactres.analysis.radiation_summary`: per group the ranges of a and
    tan δ_rad, the medians of tan δ_rad and of its share of the measured loss tangent).
``radiation.csv``
    only when the analysis was given the two materials (``--sphere-material`` and
    ``--plate-material``): one row per load, the columns of
    :data:`contactres.measurements.schema.RADIATION_RESULTS` (the radiation loss of the contact
    against the measured one).
``fig4_*.png``, ``fig5_*.png``, ``fig7_*.png``, ``fig8_*.png``
    ``fig4_sweeps.png``, ``fig5_df0_vs_load.png``, ``fig7_dissipation_vs_load.png`` and
    ``fig8_friction_vs_load.png``: the figures of paper 2 for these data
    (:mod:`contactres.report.figures`; none when no sweep is used, with a
    :class:`~contactres.measurements.SweepWarning`), and with the radiation table
    ``radiation_loss.png`` (measured and radiation loss tangent per load).
``report.html``
    only when asked for (format ``html``, ``--report html``): one self-contained page of the
    analysis (:func:`contactres.report.html_report`).
``manifest.json``
    written last: the files of the set with their sizes and SHA-256 sums.

Conventions: Δf is the frequency shift (not Δf/n); ΔΓ the half-bandwidth at half height (not D);
amplitudes in m; forces per contact in N; a number that is not finite (NaN where not
applicable, an infinite slope error or loss tangent) is an empty cell in CSV and null in JSON.
"""

from __future__ import annotations

from pathlib import Path

from ..jobs.qcm_sweeps import loads_table, radiation_table, summary, sweeps_table
from ._writer import DEFAULT_FORMATS

__all__ = [
    "loads_table",
    "radiation_table",
    "summary",
    "sweeps_table",
    "write_report",
]


def write_report(results, folder, formats=DEFAULT_FORMATS, *, inputs=None) -> list[Path]:
    """Write the results folder (see the module docstring); return the paths written.

    :func:`contactres.report.write_report` for the analysis: ``results`` is what
    :func:`contactres.analyze` returned (or the ``qcm_sweeps`` job's Result).

    Parameters
    ----------
    results : what :func:`contactres.analyze` returned
    folder : the results folder, created if missing (a path that exists and is not a folder is
        an error); or a :class:`~contactres.fileio.ResultSet` opened by the caller (declared
        with :func:`contactres.report.report_set`), which moves the files into place
        when its block ends
    formats : one of :data:`~contactres.report.FORMATS`, or a sequence of them
    inputs : files that must not be overwritten (default: the sweep table the results came
        from); ignored when ``folder`` is a ResultSet (it was given its inputs)

    Returns
    -------
    list of Path : the files of the set (not ``manifest.json``), where they are once in place

    Raises
    ------
    contactres.fileio.OutputError
        Before anything is written: the folder cannot be written, a file of the set is one of
        ``inputs``, or another run is writing into the folder.
    """
    from ._writer import write_report as write

    return write(results, folder, formats, inputs=inputs)
