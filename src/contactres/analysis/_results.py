"""What :func:`contactres.analyze` found: plain data, written by :func:`contactres.write_report`."""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from ..measurements import SweepTable

__all__ = ["Results"]


def _count(n: int, noun: str) -> str:
    """ "1 experiment", "4 experiments": a count with its noun in the right number."""
    return f"{n} {noun}" if n == 1 else f"{n} {noun}s"


def _pm(value: float, error: float, digits: int = 3) -> str:
    """``value ± error`` to ``digits`` significant digits of the value (NaN: a dash)."""
    if not math.isfinite(value):
        return "—"
    text = f"{value:.{digits}g}"
    return f"{text} ± {error:.2g}" if math.isfinite(error) else text


class Table1(pd.DataFrame):
    """Table 1 as a plain :class:`pandas.DataFrame` that prints every column.

    At pandas' default width of 80 characters a wide frame hides its middle columns behind
    "...", here E and γ themselves (issue 30). Printed, this one wraps its columns onto
    further lines instead; everything derived from it (a selection, ``.copy()``) is a plain
    DataFrame again.
    """

    def __repr__(self) -> str:
        with pd.option_context("display.max_columns", None, "display.expand_frame_repr", True):
            return super().__repr__()


# repr=False: the dataclass repr would print every table in full (~10,000 characters); the
# class gives a summary of its own (__repr__, _repr_html_ for notebooks).
@dataclass(frozen=True, repr=False)
class Results:
    """Everything :func:`contactres.analyze` found.

    Attributes
    ----------
    sweeps : one row per sweep: the columns of ``sweeps.csv``
        (:data:`contactres.measurements.schema.SWEEP_RESULTS`), the sweep's labels and constants
        from the input, and what the model choice used (``n_points``, ``u_max_m``, the noise
        levels ``sigma_df_Hz``, ``sigma_dgamma_Hz``, ``bic_<class>``, ``limits_from``,
        ``P_Hz_per_N_per_m``, ``block``, ...); ``flags`` is a bit mask of
        :class:`contactres.analysis.Flag` (text only when written)
    fits : one table per registered model fitted to every sweep (key of
        :data:`contactres.analysis.REGISTRY` -> DataFrame, one row per sweep in the order
        of ``sweeps``): ``sweep``, the parameters under their keys with their standard errors
        (``<key>_err``), the residual sums ``rss_df``, ``rss_dgamma`` and the fit's other fields
        (:func:`contactres.analysis._models.fit_tables`); the exact loops only with
        ``exact_loop``
    loads : one row per (configuration, medium, normal force)
    experiments : one row per (configuration, medium, normal force, experiment): the means of
        its used sweeps (the points of the JKR fit)
    groups : one dict per (configuration, medium): JKR + Mindlin fit and counts
    settings : the settings used
    version : contactres version
    table : the input sweep table
    points : one row per point as the analysis fitted it (after any drift correction):
        ``sweep``, ``amplitude_m``, ``df_Hz``, ``dgamma_Hz``
        (:func:`contactres.analysis._curves.sweep_points`)
    curves : the model chosen for each sweep on the grids the report draws (those of
        :func:`contactres.analyze`'s ``curve_grids``: by default the page's for every sweep
        and Fig. 4's for the sweeps it draws, :func:`contactres.analysis.figure_examples`):
        ``sweep``, ``grid_points``, ``amplitude_m``, ``df_model_Hz``, ``dgamma_model_Hz``
        (:func:`contactres.analysis._curves.fitted_curves`)
    messages : what the analysis found odd in the input, one line each (e.g. ramp labels that
        disagree with the times)
    blocks : one row per load block judged jointly (:mod:`contactres.analysis._blocks`)
    block_fits : every model's joint fit of every load block, like ``fits`` with ``block`` in
        place of ``sweep`` (the Coulomb loops' with ``bic_shared``, their shared criterion);
        the plateau loop's also with ``mu_marginal`` and ``mu_marginal_err``: its μ with d_c
        integrated over the plateau prior (:mod:`contactres.analysis._plateau_evidence`),
        NaN but where the plateau was undecided and that μ is resolved; where given they
        replace the loop fit's μ in the block's model-averaged μ
        (:func:`contactres.analysis._friction.model_averaged_mu`)
    radiation : one row per load: the radiation loss of the contact against the measured one
        (:func:`contactres.analysis.radiation_loss`; None: no materials were given)
    jkr : the fitted JKR + Mindlin curve κ(F_N) of every group on the grid Fig. 5 draws
        (:func:`contactres.analysis._curves.jkr_curves`)
    """

    sweeps: pd.DataFrame
    loads: pd.DataFrame
    experiments: pd.DataFrame
    groups: list[dict]
    settings: dict
    version: str
    table: SweepTable | None = None
    fits: Mapping[str, pd.DataFrame] = field(default_factory=dict, repr=False)
    points: pd.DataFrame | None = field(default=None, repr=False)
    curves: pd.DataFrame | None = field(default=None, repr=False)
    messages: tuple[str, ...] = ()
    blocks: pd.DataFrame | None = None
    block_fits: Mapping[str, pd.DataFrame] = field(default_factory=dict, repr=False)
    radiation: pd.DataFrame | None = None
    jkr: pd.DataFrame | None = field(default=None, repr=False)

    def table1(self) -> pd.DataFrame:
        """Table 1 of paper 2 for these data: E (GPa) and γ (mJ/m²) per configuration/medium.

        ``errors`` says how the errors were found, ``t95`` the Student-t factor of their 95 %
        interval; where a check withholds E and γ they are NaN
        and ``note`` says why and which input to check.
        """
        rows = []
        for g in self.groups:
            rows.append(
                {
                    "configuration": g["configuration"],
                    "medium": g["medium"],
                    "E_GPa": g["E_Pa"] / 1e9,
                    "E_err_GPa": g["E_err_Pa"] / 1e9,
                    "gamma_mJ_m2": g["gamma_J_m2"] * 1e3,
                    "gamma_err_mJ_m2": g["gamma_err_J_m2"] * 1e3,
                    "n_exp": g["n_experiments"],
                    "n_sweeps": g["n_sweeps_used"],
                    "t95": g.get("t95", np.nan),
                    "note": g.get("note", ""),
                    # Last: the longest text (~60 characters), after the numbers.
                    "errors": g.get("error_method", ""),
                }
            )
        return Table1(rows)

    def _group_rows(self) -> list[tuple[str, str, str]]:
        """(configuration, medium, the fitted E and γ or why they are withheld) per group."""
        rows = []
        for g in self.groups:
            if g.get("checks"):
                text = f"E and γ withheld ({', '.join(g['checks'])}): {g.get('note', '')}"
            else:
                text = (
                    f"E = {_pm(g['E_Pa'] / 1e9, g['E_err_Pa'] / 1e9)} GPa, "
                    f"γ = {_pm(g['gamma_J_m2'] * 1e3, g['gamma_err_J_m2'] * 1e3)} mJ/m² "
                    f"({_count(g['n_experiments'], 'experiment')}, "
                    f"{_count(g['n_sweeps_used'], 'sweep')})"
                )
            rows.append((str(g["configuration"]), str(g["medium"]), text))
        return rows

    def _counts(self) -> str:
        used = int(self.sweeps["used"].sum()) if "used" in self.sweeps else len(self.sweeps)
        coating = self.settings.get("coating") if isinstance(self.settings, Mapping) else None
        on = f"; fitted on the coated plate ({coating.get('label', '')})" if coating else ""
        return (
            f"{len(self.sweeps)} sweeps ({used} used), {len(self.loads)} loads, "
            f"{_count(len(self.groups), 'configuration/medium group')}{on}"
        )

    def __repr__(self) -> str:
        """A summary: the counts and Table 1 (E and γ per group, errors as in ``table1``)."""
        lines = [f"Results (contactres {self.version}): {self._counts()}"]
        lines += [f"  {c}, {m}: {text}" for c, m, text in self._group_rows()]
        lines.append(
            "  tables: .sweeps, .loads, .experiments, .table1(); write them with "
            "contactres.write_report(results, folder)"
        )
        return "\n".join(lines)

    def _repr_html_(self) -> str:
        """The summary of :meth:`__repr__` as HTML, for notebooks (every label escaped)."""
        # Imported here: only a notebook asks for HTML (html.entities is a table of ~2,000 names).
        import html

        rows = "".join(
            f"<tr><td>{html.escape(c)}</td><td>{html.escape(m)}</td><td>{html.escape(t)}</td></tr>"
            for c, m, t in self._group_rows()
        )
        return (
            f"<p><b>Results</b> (contactres {html.escape(self.version)}): "
            f"{html.escape(self._counts())}</p>"
            "<table><thead><tr><th>configuration</th><th>medium</th><th>E and γ (Table 1)</th>"
            f"</tr></thead><tbody>{rows}</tbody></table>"
        )
