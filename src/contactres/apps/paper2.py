"""The forward figures of paper 2: loops (Fig. 2C-D) and Δf(u0), ΔΓ(u0) (Fig. 1D).

The parameters are those of the paper's experiment (glass spheres, R = 1.1 mm, ν = 0.17, a
tripod on a 5 MHz crystal, 3rd overtone) with a round E = 70 GPa, μ = 1 and a loss tangent
ωξ/κ = 0.1; the Savkoor traction is chosen so that both models slide at the same force μF_N.
Every figure is written as PNG together with the CSV of the plotted numbers, the folder as one
result set (:func:`paper2_set`, with its ``manifest.json``: a rerun replaces only what
contactres wrote).
"""

from __future__ import annotations

from pathlib import Path

from matplotlib.figure import Figure

from ..fileio import ResultSet
from ..jobs import paper2 as job
from ..jobs.paper2 import Paper2Example
from ..report.figures import key_below
from ._sets import figures_set, write_figures

__all__ = [
    "Paper2Example",
    "loops_figure",
    "paper2_set",
    "shifts_figure",
    "write_paper2_figures",
]


def loops_figure(example: Paper2Example | None = None, amplitudes=(10e-9, 20e-9)):
    """Fig. 2C-D: a viscoelastic (Voigt) loop and Cattaneo-Mindlin loops (no dashpot).

    Returns (figure, table); the table holds u (m) and F₊, F₋ (N) of every loop drawn. The full
    dots mark the turning points (Δf ∝ force/displacement there), the hatch the loop area
    (ΔΓ ∝ area/u0²).
    """
    ex = example or Paper2Example()
    table, turning = job.loops_table(ex, amplitudes)
    return _draw_loops(ex, table, turning), table


def _draw_loops(ex: Paper2Example, table, turning):
    """The two panels of Fig. 2C-D from the loops' table and turning points."""
    fig = Figure(figsize=(8, 4.2), layout="constrained")
    axes = fig.subplots(1, 2, sharey=True)
    titles = {
        "voigt": "C: viscoelastic (Voigt) contact",
        "cattaneo_mindlin": "D: partial slip (CM)",
    }
    amplitudes = list(dict.fromkeys(turning["u0_m"]))
    for ax, name in zip(axes, dict.fromkeys(turning["model"]), strict=True):
        for u0 in amplitudes:
            t = table[(table["model"] == name) & (table["u0_m"] == u0)]
            x = t.u_m * 1e9
            ax.plot(x, t.F_plus_N * 1e3, color="C0", label="branch F₊(u)")
            ax.plot(x, t.F_minus_N * 1e3, "--", color="C1", label="branch F₋(u)")
            ax.fill_between(
                x,
                t.F_minus_N * 1e3,
                t.F_plus_N * 1e3,
                hatch="//",
                color="0.5",
                alpha=0.2,
                label="loop area (ΔΓ ∝ area/u0²)",
            )
            turn = turning[(turning["model"] == name) & (turning["u0_m"] == u0)]
            Fu0 = float(turn["F_u0_N"].iloc[0])
            ax.plot(
                [u0 * 1e9, -u0 * 1e9],
                [Fu0 * 1e3, -Fu0 * 1e3],
                "ko",
                ls="none",
                label="turning points ±u0 (Δf ∝ F(u0)/u0)",
            )
        ax.set_title(titles[name], fontsize=10)
        ax.set_xlabel("displacement u (nm)")
        ax.axhline(0, color="0.7", lw=0.5)
        ax.axvline(0, color="0.7", lw=0.5)
    axes[0].set_ylabel("tangential force F (mN)")
    amps = ", ".join(f"{u0 * 1e9:g}" for u0 in amplitudes)
    fig.suptitle(
        f"u0 = {amps} nm; F_N = {ex.normal_force * 1e3:.2f} mN, κ = {ex.kappa:.3g} N/m, "
        f"μ = {ex.mu:g}, Voigt loss tangent ωξ/κ = {ex.loss_tangent:g}",
        fontsize=9,
    )
    key_below(fig, ncols=4, fontsize=7)
    return fig


def shifts_figure(example: Paper2Example | None = None, u0=None):
    """Fig. 1D: Δf(u0) and ΔΓ(u0) for Cattaneo-Mindlin (linear) and Savkoor (parabolic).

    Both with the same dashpot (loss tangent ``example.loss_tangent``). Returns (figure, table)
    with u0 (m) and the shifts (Hz) of both models.
    """
    ex = example or Paper2Example()
    table = job.shifts_table(ex, u0)
    return _draw_shifts(ex, table), table


def _draw_shifts(ex: Paper2Example, table):
    """The two panels of Fig. 1D from the shifts' table."""
    u0 = table["u0_m"].to_numpy()
    df_cm, dg_cm = table["df_cm_Hz"].to_numpy(), table["dgamma_cm_Hz"].to_numpy()
    df_sv, dg_sv = table["df_savkoor_Hz"].to_numpy(), table["dgamma_savkoor_Hz"].to_numpy()
    fig = Figure(figsize=(8, 4.0), layout="constrained")
    ax1, ax2 = fig.subplots(1, 2, sharex=True)
    x = u0 * 1e9
    ax1.plot(x, df_cm, label="Cattaneo-Mindlin")
    ax1.plot(x, df_sv, "--", label="Savkoor")
    ax2.plot(x, dg_cm, label="Cattaneo-Mindlin")
    ax2.plot(x, dg_sv, "--", label="Savkoor")
    ax1.set_ylabel("Δf (Hz)")
    ax2.set_ylabel("ΔΓ (Hz)")
    for ax, tag in ((ax1, "(a)"), (ax2, "(b)")):
        ax.set_xlabel("amplitude u0 (nm)")
        ax.set_title(tag, fontsize=9, loc="left")
    fig.suptitle(
        f"{ex.qcm.fundamental / 1e6:g} MHz QCM, n = {ex.qcm.overtone}, {ex.n_contacts} contacts; "
        f"F_N = {ex.normal_force * 1e3:.2f} mN, κ = {ex.kappa:.3g} N/m, μ = {ex.mu:g}, "
        f"loss tangent ωξ/κ = {ex.loss_tangent:g}",
        fontsize=9,
    )
    key_below(fig, ncols=2, fontsize=8)
    return fig


# The figures write_paper2_figures writes, each as STEM.csv and STEM.png (or the formats asked).
_STEMS = ("paper2_fig2_loops", "paper2_fig1d_shifts")


def paper2_set(out, figure_formats=("png",)) -> ResultSet:
    """The :class:`~contactres.fileio.ResultSet` of :func:`write_paper2_figures` in folder
    ``out`` (``figure_formats`` as there): open it, or :meth:`~contactres.fileio.ResultSet.check`
    it, before the work, so that a file of the user's under one of the names is refused first
    (issue 27)."""
    return figures_set(out, _STEMS, figure_formats, kind="paper2")


def write_paper2_figures(
    out,
    example: Paper2Example | None = None,
    result: job.Result | None = None,
    figure_formats=("png",),
) -> list[Path]:
    """Write Fig. 2C-D and Fig. 1D of paper 2 into folder ``out``; return the paths.

    ``out``: the folder (written as :func:`paper2_set`: with a ``manifest.json``; a file there
    under one of the names that contactres cannot show it wrote is refused,
    :class:`contactres.fileio.OutputError`, and nothing is changed), or that set opened by the
    caller. Each figure is written in every format of ``figure_formats`` (PNG only by default;
    ``png``, ``svg``, ``pdf``: the CLI's ``--figure-format``), and its data as CSV beside it.
    ``result``: what :func:`contactres.jobs.paper2.run` returned (else it runs, for
    ``example``).
    """
    if not isinstance(out, ResultSet):
        with paper2_set(out, figure_formats) as rs:
            return write_paper2_figures(rs, example, result, figure_formats)
    if result is None:
        result = job.run(None, job.Settings(example=example))
    drawn = (
        (_STEMS[0], _draw_loops(result.example, result.loops, result.turning), result.loops),
        (_STEMS[1], _draw_shifts(result.example, result.shifts), result.shifts),
    )
    return write_figures(out, drawn, figure_formats)
