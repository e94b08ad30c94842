"""The figures of ``qcm particles`` (a :class:`contactres.jobs.qcm_particles.Result`),
registered by :func:`contactres.report._writer.figure_registry`.

The figures a QCM-D user reads attached particles from (Pomorska et al., Anal. Chem. 82, 2237
(2010); Olsson et al., Anal. Chem. 84, 4504 (2012)):

* :func:`overtones_figure`: Δf_n/n and ΔΓ_n/n against n at a few time steps, points read and
  the fitted model's line on a fine grid of continuous n (the result's ``model_curves``; a
  coupled resonance inside the comb: Δf_n/n changes sign and ΔΓ_n/n peaks near it);
* :func:`plane_figure`: ΔΓ_n against −Δf_n, one series per overtone over time (the ratio
  −ΔΓ/Δf a mass cannot have);
* :func:`time_figure`: κ, ξ, the coverage and f_coupled against time with their standard errors
  (a step whose value the data do not identify has no point).

Each returns a matplotlib Figure (Agg canvas, no pyplot state), or None when there is nothing to
draw.
"""

from __future__ import annotations

import numpy as np

__all__ = ["overtones_figure", "plane_figure", "time_figure"]

#: How many time steps the overtone figure shows (evenly spread over those with a model).
SHOWN_STEPS = 4


def _blank(width: float, height: float):
    """An empty figure, constrained layout (a key outside the panels), Agg canvas."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width, height), layout="constrained")
    FigureCanvasAgg(fig)
    return fig


def _title(result, what: str) -> str:
    label = " ".join(str(result.source).split()) or "data"
    label = (label if len(label) <= 50 else label[:49] + "…").replace("$", r"\$")
    return f"{label}: {what}"


def _shown_times(shifts) -> np.ndarray:
    """Up to :data:`SHOWN_STEPS` times spread over the run, those with a model first."""
    modelled = shifts.loc[np.isfinite(shifts["df_model_Hz"]), "time_s"].unique()
    times = np.sort(modelled if modelled.size else shifts["time_s"].unique())
    if times.size <= SHOWN_STEPS:
        return times
    pick = np.unique(np.round(np.linspace(0, times.size - 1, SHOWN_STEPS)).astype(int))
    return times[pick]


def overtones_figure(result):
    """Δf_n/n and ΔΓ_n/n against the overtone order n with the fitted model, at a few time
    steps (the first, the last and evenly between)."""
    from .figures import key_below

    shifts = result.shifts
    if not len(shifts):
        return None
    fig = _blank(7.5, 3.6)
    ax_f, ax_g = fig.subplots(1, 2)
    # the model on a fine grid of continuous n where the result has it (a resonance between
    # two odd overtones peaks between them), else through the overtones' model points
    curves = getattr(result, "model_curves", None) or {}
    curve_times = np.asarray(curves.get("time_s", []), float)
    for k, t in enumerate(curve_times if curve_times.size else _shown_times(shifts)):
        part = shifts[shifts["time_s"] == t].sort_values("overtone")
        n = part["overtone"].to_numpy(float)
        color = f"C{k % 10}"
        for ax, read, model in (
            (ax_f, "df_Hz", "df_model_Hz"),
            (ax_g, "dgamma_Hz", "dgamma_model_Hz"),
        ):
            ax.plot(n, part[read] / n, "o", color=color, ms=4, label=f"t = {t:.4g} s")
            if curve_times.size:
                n_fine = np.asarray(curves["overtone"], float)
                fitted = np.asarray(curves[model], float)[k]
                ax.plot(n_fine, fitted / n_fine, "-", color=color, lw=1)
                continue
            fitted = part[model].to_numpy(float)
            if np.isfinite(fitted).any():
                ax.plot(n, fitted / n, "-", color=color, lw=1)
    for ax, label in ((ax_f, "Δf_n/n (Hz)"), (ax_g, "ΔΓ_n/n (Hz)")):
        ax.axhline(0.0, color="0.6", lw=0.6)
        ax.set_xlabel("overtone order n")
        ax.set_ylabel(label)
    from matplotlib.lines import Line2D

    proxy = Line2D([], [], color="0.3", lw=1)
    key_below(fig, [(proxy, "line: fitted model")], ncols=5)
    fig.suptitle(_title(result, "shifts over the overtones"), fontsize=9)
    return fig


def plane_figure(result):
    """ΔΓ_n against −Δf_n, one series per overtone over time, with the fitted model's."""
    from .figures import key_below

    shifts = result.shifts
    if not len(shifts):
        return None
    fig = _blank(5.5, 4.4)
    ax = fig.subplots()
    for k, (n, part) in enumerate(shifts.groupby("overtone")):
        color = f"C{k % 10}"
        ax.plot(-part["df_Hz"], part["dgamma_Hz"], ".", color=color, ms=3, label=f"n = {n}")
        fitted = np.isfinite(part["df_model_Hz"].to_numpy(float))
        if fitted.any():
            ax.plot(-part["df_model_Hz"][fitted], part["dgamma_model_Hz"][fitted], "-", color=color)
    ax.axvline(0.0, color="0.6", lw=0.6)
    ax.set_xlabel("−Δf_n (Hz)")
    ax.set_ylabel("ΔΓ_n (Hz)")
    from matplotlib.lines import Line2D

    proxy = Line2D([], [], color="0.3", lw=1)
    key_below(fig, [(proxy, "line: fitted model")], ncols=4)
    fig.suptitle(_title(result, "the ΔΓ versus −Δf plane"), fontsize=9)
    return fig


_QUANTITIES = (
    ("kappa_N_per_m", "kappa_err_N_per_m", "κ per particle (N/m)"),
    ("xi_kg_per_s", "xi_err_kg_per_s", "ξ per particle (kg/s)"),
    ("coverage_per_m2", "coverage_err_per_m2", "coverage (1/m²)"),
    # f_coupled's error is in particles.json (steps), not among the contract's CSV columns
    ("f_coupled_Hz", "f_coupled_err_Hz", "f_coupled (Hz)"),
)


def _error(result, name, size):
    """The standard errors of a column of particles.csv, or of particles.json's ``steps``."""
    if name in result.particles:
        return result.particles[name].to_numpy(float)
    steps = getattr(result, "steps", {}) or {}
    values = np.asarray(steps.get(name, np.full(size, np.nan)), float)
    return values if values.shape == (size,) else np.full(size, np.nan)


def time_figure(result):
    """κ, ξ, the coverage and f_coupled against time with their standard errors; a panel
    whose quantity no step identifies says so."""
    table = result.particles
    if not len(table):
        return None
    fig = _blank(7.5, 5.6)
    axes = fig.subplots(2, 2, sharex=True).ravel()
    t = table["time_s"].to_numpy(float)
    for ax, (value, error, label) in zip(axes, _QUANTITIES, strict=True):
        y = table[value].to_numpy(float)
        ok = np.isfinite(y)
        if ok.any():
            err = _error(result, error, len(t))[ok]
            err = np.where(np.isfinite(err), err, 0.0)
            ax.errorbar(t[ok], y[ok], yerr=err, fmt=".", ms=3, lw=0.8, capsize=1.5)
        else:
            ax.text(0.5, 0.5, "not identified", ha="center", va="center", transform=ax.transAxes)
        ax.set_ylabel(label)
    for ax in axes[2:]:
        ax.set_xlabel("time (s)")
    shown = int(np.isfinite(table["kappa_N_per_m"].to_numpy(float)).sum())
    fig.suptitle(
        _title(result, f"particles against time (κ identified at {shown} of {len(t)} steps)"),
        fontsize=9,
    )
    return fig
