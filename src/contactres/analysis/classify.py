"""The model choice of every sweep: low-amplitude limits, slopes and the amplitude class.

Every sweep is fitted with the four amplitude models of :mod:`contactres.analysis.models`
(closed form, :mod:`contactres.analysis.amplitude`):

``elastic``           Δf = Δf0,                      ΔΓ = ΔΓ0                     (k = 2)
``cattaneo-mindlin``  Δf = Δf0 + s_f u0,             ΔΓ = ΔΓ0 + s_Γ u0             (k = 4, Eq. 12)
``savkoor``           Δf = Δf0 + c_f u0²,            ΔΓ = ΔΓ0 + c_Γ u0²            (k = 4, Eq. 15)
``plateau``           Δf = Δf0 + s_f max(u0-u_c, 0), ΔΓ = ΔΓ0 + s_Γ max(u0-u_c, 0)  (k = 5)

(equations of paper 2). The Cattaneo-Mindlin candidate is the better (by BIC) of the straight
line and the exact loop (k = 3, :func:`contactres.analysis.loops.fit_cm_loops`), so that sweeps
reaching full sliding, which curve, are still recognised as such; the low-amplitude limits of
such a sweep come from the exact loop. A sweep classified ``plateau`` is refitted with the exact
plateau loop (:func:`contactres.analysis.plateau.fit_plateau_loops`), which then gives its limits
and its critical displacement.

**Model choice (the stated criterion).** With separate unknown noise levels in Δf and ΔΓ, the
Bayesian information criterion of a model with k parameters is
``BIC = n ln(RSS_f/n) + n ln(RSS_Γ/n) + k ln(2n)``. The model with the lowest BIC wins, except
that a model listed earlier in :data:`~contactres.analysis.models.AMPLITUDE_MODELS` (elastic,
cattaneo-mindlin, savkoor, plateau: simplest and most common first) is kept if its BIC is within
``delta_bic`` (default 2, "positive evidence" on the Kass-Raftery scale) of the lowest.
"""

from __future__ import annotations

from concurrent.futures import ProcessPoolExecutor
from itertools import repeat

import numpy as np
import pandas as pd

from .amplitude import BLOCK_POINTS, Block, HingeFit, LineFit, Padded, bic, fit_hinge, fit_line
from .loops import CMLoopTable, cm_loop_table, fit_cm_loops
from .models import AMPLITUDE_MODELS, N_PARAMETERS
from .plateau import PLATEAU_LOOP_COLUMNS, fit_plateau_loops

__all__ = ["LINE_FIELDS", "fit_sweeps"]

#: The arrays of a :class:`~contactres.analysis.amplitude.LineFit`, in order.
LINE_FIELDS = ("a", "b", "var_a", "var_b", "cov_ab", "rss")


def _fit_block(b: Block, exact_loop: bool, table: CMLoopTable | None) -> dict[str, np.ndarray]:
    """The per-sweep fits of one block of sweeps (arrays with the sweep as last axis)."""
    Y = np.stack([b.df, b.dg])
    n = b.n.astype(float)
    out = {"u_max": np.max(np.where(b.w > 0, b.u, 0.0), axis=1)}
    out["mean"] = (b.w * Y).sum(-1) / n  # elastic
    out["rss_el"] = (b.w * (Y - out["mean"][..., None]) ** 2).sum(-1)
    out["var_mean"] = out["rss_el"] / np.maximum(n - 1, 1) / n
    line = fit_line(b.u, Y, b.w)  # cattaneo-mindlin; its residuals give the noise levels
    parabola = fit_line(b.u**2, Y, b.w)  # savkoor: a straight line in u0²
    hinge = fit_hinge(b)  # plateau
    for name, fit in (("line", line), ("parabola", parabola), ("hinge", hinge.line)):
        out.update({f"{name}.{k}": v for k, v in zip(LINE_FIELDS, fit.fields(), strict=True)})
    out["u_c"], out["found"] = hinge.u_c, hinge.found
    if exact_loop:
        sigma = np.sqrt(line.rss / np.maximum(n - 2, 1))
        loop = fit_cm_loops(b.u, b.df, b.dg, b.w, sigma[0], sigma[1], table)
        out.update({f"cm_{col}": loop[col].to_numpy() for col in loop.columns})
    return out


def _run(fn, workers: int, first: list, *rest) -> list:
    """``[fn(a, *r) for a, *r in zip(first, *rest)]``, in ``workers`` processes if > 1."""
    if workers > 1 and len(first) > 1:
        with ProcessPoolExecutor(min(workers, len(first))) as pool:
            return list(pool.map(fn, first, *rest))
    # strict=False: ``rest`` may hold endless itertools.repeat()s; ``first`` sets the length.
    return [fn(*args) for args in zip(first, *rest, strict=False)]


def _fit_blocks(
    p: Padded, exact_loop: bool, table: CMLoopTable | None, workers: int
) -> dict[str, np.ndarray]:
    """:func:`_fit_block` on every block of ``p``, put together in the order of the sweeps."""
    S = len(p.n)
    out: dict[str, np.ndarray] = {}
    groups = p.blocks()  # <= BLOCK_POINTS points each: the fits' temporaries stay at a few MB
    blocks = [p.block(rows) for rows in groups]
    parts = _run(_fit_block, workers, blocks, repeat(exact_loop), repeat(table))
    for rows, part in zip(groups, parts, strict=True):
        for key, v in part.items():
            if key not in out:
                dtype = object if v.dtype.kind in "OUS" else v.dtype
                out[key] = np.empty((*v.shape[:-1], S), dtype=dtype)
            out[key][..., rows] = v
    return out


def fit_sweeps(
    p: Padded,
    delta_bic: float = 2.0,
    exact_loop: bool = True,
    table: CMLoopTable | None = None,
    workers: int = 1,
) -> pd.DataFrame:
    """Fit the four amplitude models to every sweep and choose one (see the module docstring).

    Parameters
    ----------
    p : the sweeps as padded arrays (:func:`contactres.analysis.amplitude.pad_sweeps`)
    delta_bic : BIC margin within which the simpler model is kept
    exact_loop : let the exact Cattaneo-Mindlin loop compete (and refit plateau sweeps with the
        exact plateau loop)
    table : the Cattaneo-Mindlin loop table (:func:`contactres.analysis.loops.cm_loop_table`;
        built here if None and ``exact_loop``)
    workers : processes for the fits of the blocks of sweeps (1: none, in this process). More
        than one pays from ~10^4 sweeps on (both cores of a 2-core machine: ~1.8x faster at
        10^5 sweeps); it starts a process pool, so a script calling it must be importable
        (``if __name__ == "__main__":``) where processes are spawned (Windows, macOS).

    Returns
    -------
    DataFrame
        One row per sweep (order of first appearance) with the low-amplitude limits, slopes and
        curvatures with standard errors, the critical amplitude of a plateau, the BIC of each
        model, the noise levels (from the straight line), the chosen ``model``, ``limits_from``
        (``mean``, ``cm-loop``, ``line``, ``parabola``, ``plateau-loop`` or ``plateau``) and,
        with ``exact_loop``, the loop fit of every sweep (columns of ``fit_cm_loops`` prefixed
        ``cm_``) and of plateau sweeps (columns of ``fit_plateau_loops`` prefixed ``pl_``).
    """
    n = p.n.astype(float)
    S = len(n)
    if exact_loop and table is None:
        table = cm_loop_table()
    f = _fit_blocks(p, exact_loop, table, workers)
    mean, rss_el, var_mean = f["mean"], f["rss_el"], f["var_mean"]
    line, parabola = (LineFit(*(f[f"{m}.{k}"] for k in LINE_FIELDS)) for m in ("line", "parabola"))
    hinge = HingeFit(LineFit(*(f[f"hinge.{k}"] for k in LINE_FIELDS)), f["u_c"], f["found"])
    sigma = np.sqrt(line.rss / np.maximum(n - 2, 1))
    rows = {"sweep": p.sweeps, "n_points": p.n, "direction": p.direction, "u_max_m": f["u_max"]}

    bic_line = bic(line.rss, n, N_PARAMETERS["cattaneo-mindlin"])
    bic_cm = bic_line
    use_loop = np.zeros(S, bool)
    if exact_loop:
        loop = {col[3:]: f[col] for col in f if col.startswith("cm_")}
        rss_loop = np.stack([loop["rss_df"], loop["rss_dgamma"]])
        ok = (loop["edge"] == "") & (loop["df0_Hz"] > 0)
        bic_loop = np.where(ok, bic(rss_loop, n, N_PARAMETERS["cattaneo-mindlin-loop"]), np.inf)
        use_loop = bic_loop < bic_line
        bic_cm = np.minimum(bic_line, bic_loop)
        rows["bic_cattaneo-mindlin-line"] = bic_line
        rows["bic_cattaneo-mindlin-loop"] = bic_loop
        # The whole loop fit (cm_df0_Hz, cm_theta_per_m, ...): μ_fit of the analysis reuses it.
        for col, values in loop.items():
            rows[f"cm_{col}"] = values
    criteria = {
        "elastic": bic(rss_el, n, N_PARAMETERS["elastic"]),
        "cattaneo-mindlin": bic_cm,
        "savkoor": bic(parabola.rss, n, N_PARAMETERS["savkoor"]),
        "plateau": np.where(hinge.found, bic(hinge.line.rss, n, N_PARAMETERS["plateau"]), np.inf),
    }
    by_model = np.stack([criteria[m] for m in AMPLITUDE_MODELS])  # (4, S)
    choice = np.argmax(
        by_model <= by_model.min(axis=0) + delta_bic, axis=0
    )  # first model within delta_bic
    for m in AMPLITUDE_MODELS:
        rows[f"bic_{m}"] = criteria[m]

    # Low-amplitude limits and their errors from the chosen model.
    is_el, is_cm, is_sv, is_pl = (choice == i for i in range(len(AMPLITUDE_MODELS)))
    cases = [is_el, is_cm, is_sv, is_pl]
    from_cm_loop = is_cm & use_loop
    for c, name in enumerate(("df", "dgamma")):
        a = np.select(cases, [mean[c], line.a[c], parabola.a[c], hinge.line.a[c]])
        va = np.select(cases, [var_mean[c], line.var_a[c], parabola.var_a[c], hinge.line.var_a[c]])
        if exact_loop:
            a = np.where(from_cm_loop, loop[f"{name}0_Hz"], a)
            va = np.where(from_cm_loop, loop[f"{name}0_err_Hz"] ** 2, va)
        rows[f"{name}0_Hz"] = a
        rows[f"{name}0_err_Hz"] = np.sqrt(va)
        # Slope of the linear part: the hinge slope for a plateau, the straight line otherwise.
        rows[f"{name}_slope_Hz_per_m"] = np.where(is_pl, hinge.line.b[c], line.b[c])
        rows[f"{name}_slope_err_Hz_per_m"] = np.sqrt(
            np.where(is_pl, hinge.line.var_b[c], line.var_b[c])
        )
        cov = np.where(is_pl, hinge.line.cov_ab[c], line.cov_ab[c])
        rows[f"{name}0_slope_cov"] = np.where(from_cm_loop, 0.0, cov)
        rows[f"{name}_curvature_Hz_per_m2"] = parabola.b[c]
        rows[f"{name}_curvature_err_Hz_per_m2"] = np.sqrt(parabola.var_b[c])
        rows[f"sigma_{name}_Hz"] = sigma[c]
    rows["plateau_amplitude_m"] = np.where(is_pl, hinge.u_c, np.nan)
    rows["plateau_amplitude_err_m"] = np.full(S, np.nan)
    from_pl = np.zeros(S, bool)
    if exact_loop:
        from_pl = _refit_plateaus(p, rows, is_pl, hinge, n, table, workers)
    rows["model"] = np.asarray(AMPLITUDE_MODELS)[choice]
    rows["limits_from"] = np.select(
        [is_el, from_cm_loop, is_cm, is_sv, is_pl & from_pl, is_pl],
        ["mean", "cm-loop", "line", "parabola", "plateau-loop", "plateau"],
        default="",
    )
    return pd.DataFrame(rows)


def _refit_plateaus(p: Padded, rows: dict, is_pl, hinge, n, table, workers: int) -> np.ndarray:
    """Fit the exact plateau loop to the plateau sweeps, weighted by the noise of the hinge fit.

    Adds the ``pl_*`` columns to ``rows`` and, where the fit is resolved, replaces the limits
    and the critical amplitude of those sweeps by its values. Returns which sweeps it replaced.
    """
    S = len(n)
    for col in PLATEAU_LOOP_COLUMNS:
        rows[f"pl_{col}"] = np.full(S, np.nan)
    rows["pl_edge"] = np.full(S, "", dtype=object)
    replaced = np.zeros(S, bool)
    idx = np.flatnonzero(is_pl)
    if idx.size == 0:
        return replaced
    sig_h = np.sqrt(hinge.line.rss / np.maximum(n - 3, 1))
    # One block per worker at least (the plateau sweeps are few: often a single block).
    share = int(p.n[idx].sum()) // max(workers, 1) + int(p.n[idx].max())
    parts = p.blocks(idx, max_points=min(BLOCK_POINTS, share))
    blocks = [p.block(part) for part in parts]
    args = [(b.u, b.df, b.dg, b.w) for b in blocks]
    fits = _run(
        fit_plateau_loops,
        workers,
        *zip(*args, strict=True),
        [sig_h[0, part] for part in parts],
        [sig_h[1, part] for part in parts],
        [hinge.u_c[part] for part in parts],
        repeat(table),
    )
    for part, fit in zip(parts, fits, strict=True):
        for col in fit.columns:
            rows[f"pl_{col}"][part] = fit[col].to_numpy()
    pl = {col: rows[f"pl_{col}"][idx] for col in (*PLATEAU_LOOP_COLUMNS, "edge")}
    ok = (pl["edge"] == "") & (pl["df0_Hz"] > 0)
    replaced[idx[ok]] = True
    for name in ("df", "dgamma"):
        rows[f"{name}0_Hz"][idx[ok]] = pl[f"{name}0_Hz"][ok]
        rows[f"{name}0_err_Hz"][idx[ok]] = pl[f"{name}0_err_Hz"][ok]
        rows[f"{name}0_slope_cov"][idx[ok]] = 0.0
    rows["plateau_amplitude_m"][idx[ok]] = pl["d_c_m"][ok]
    rows["plateau_amplitude_err_m"][idx[ok]] = pl["d_c_err_m"][ok]
    return replaced
