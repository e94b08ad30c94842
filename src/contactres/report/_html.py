"""One self-contained HTML page of a sweep analysis: ``report.html`` (``--report html``).

The page needs nothing but itself: no network, no external CSS or JavaScript; the fit of every
sweep is drawn as inline SVG (points and the chosen model's curve, Δf and ΔΓ against u0), the
result plots are embedded PNG (data: URIs). It holds a table of contents, the input file's name
and SHA-256, the package version, how many sweeps were used and why the others were left out,
Table 1 (E and γ per configuration and medium, as printed by ``qcm analyze``), the result plots
(κ against F_N with the JKR fits and their 95 % bands, the dissipation and loss tangent, μ per
load: paper 2's Figs. 5, 7 and 8), the classification of the used sweeps (a figure of the model
classes per group and load, and a table), the statistics per load (a value whose spread is as
large as itself is marked: the data do not resolve it), every sweep with its model and flags
(filtered by configuration, medium, load and flag with a few lines of inline JavaScript), every
entry of ``summary.json`` (folded), the flags in words, the conventions and constants, and the
radiation loss where the analysis has it. Every label of the data is HTML-escaped.
"""

from __future__ import annotations

import math
from html import escape
from pathlib import Path

import numpy as np

from .._version import __version__
from ..analysis import DESCRIPTIONS, PAGE_POINTS, Flag, Results, has, render, sweep_rows
from ..fileio import write_text
from ..jobs.qcm_sweeps import summary
from ..measurements import CONSTANTS
from ..measurements.schema import CONVENTIONS
from ._console import DASH, friction_table, plus_minus, radiation_lines, table1_text, withheld_lines

__all__ = ["HTML_FILE", "UNRESOLVED_MARK", "html_report", "sweeps_page", "write_html"]

#: The file name of the page in the results folder.
HTML_FILE = "report.html"

_CSS = """
body{font-family:sans-serif;margin:1em 2em;color:#222}
table{border-collapse:collapse;margin:.5em 0;font-size:90%}
th,td{border:1px solid #bbb;padding:2px 6px;text-align:left;vertical-align:top}
th{background:#eee}
td.n{text-align:right;white-space:nowrap}
svg{background:#fff}
.filters label{margin-right:1em}
code{background:#f4f4f4}
nav ul{columns:2;max-width:40em}
img.plot{max-width:100%;border:1px solid #ddd;margin:.3em 0}
"""

#: The sections of the page, in order: (anchor, title) — the table of contents.
_SECTIONS = (
    ("input", "Input and counts"),
    ("table1", "Table 1: E and γ per configuration and medium"),
    ("plots", "Result plots"),
    ("classification", "Classification: the model of the used sweeps per medium"),
    ("loads", "Per load"),
    ("radiation", "Radiation loss"),
    ("sweeps", "Sweeps: the model chosen for each"),
    ("summary", "The summary record"),
    ("flags", "Flags"),
    ("conventions", "Conventions"),
    ("constants", "Constants"),
    ("messages", "Messages"),
)
#: Mark of a mean whose standard deviation is at least its magnitude (not resolved).
UNRESOLVED_MARK = "†"

_JS = """
function crFilter(){
 var f={};document.querySelectorAll('.filters select').forEach(function(s){f[s.name]=s.value;});
 var n=0;document.querySelectorAll('#sweeps tbody tr').forEach(function(r){
  var ok=Object.keys(f).every(function(k){return !f[k]||(k==='flag'?
   (' '+r.dataset.flag+' ').indexOf(' '+f[k]+' ')>=0:r.dataset[k]===f[k]);});
  r.style.display=ok?'':'none';if(ok)n++;});
 document.getElementById('shown').textContent=n;}
"""


def _e(value) -> str:
    return escape(str(value), quote=True)


def _table(frame, numeric=()) -> str:
    head = "".join(f"<th>{_e(c)}</th>" for c in frame.columns)
    rows = []
    for _, row in frame.iterrows():
        cells = "".join(
            f'<td class="n">{_e(v)}</td>' if c in numeric else f"<td>{_e(v)}</td>"
            for c, v in row.items()
        )
        rows.append(f"<tr>{cells}</tr>")
    return f"<table><thead><tr>{head}</tr></thead><tbody>{''.join(rows)}</tbody></table>"


def _panel(x0, u, y, uu, yy, label) -> str:
    """One panel of a sweep plot: points, model curve, the y range as text."""
    w, h, pad = 150.0, 90.0, 4.0
    ys = np.concatenate([y[np.isfinite(y)], yy[np.isfinite(yy)]])
    if not len(ys) or not len(u):
        return ""
    lo, hi = float(ys.min()), float(ys.max())
    if hi <= lo:
        lo, hi = lo - 1.0, hi + 1.0
    umax = float(max(np.nanmax(u), uu.max() if len(uu) else 0.0)) or 1.0

    def xy(a, b):
        px = x0 + pad + (a / umax) * (w - 2 * pad)
        py = 14 + pad + (hi - b) / (hi - lo) * (h - 2 * pad)
        return px, py

    marks = "".join(
        f"M{px:.0f} {py:.0f}h0"
        for px, py in (xy(a, b) for a, b in zip(u, y, strict=True))
        if math.isfinite(px) and math.isfinite(py)
    )
    dots = f'<path d="{marks}" stroke="#236" stroke-width="3" stroke-linecap="round"/>'
    line = ""
    ok = np.isfinite(yy)
    if ok.any():
        pts = " ".join(
            f"{px:.0f},{py:.0f}"
            for px, py in (xy(a, b) for a, b in zip(uu[ok], yy[ok], strict=True))
        )
        line = f'<polyline points="{pts}" fill="none" stroke="#c33" stroke-width="1"/>'
    return (
        f'<rect x="{x0}" y="14" width="{w:g}" height="{h:g}" fill="none" stroke="#999"/>'
        f'<text x="{x0 + 2}" y="11">{_e(label)} {lo:.4g}…{hi:.4g} Hz</text>'
        f"{dots}{line}"
    )


def _sweep_svg(points, curve) -> str:
    """Δf and ΔΓ against u0 (0 … u_max) with the chosen model's curve, inline SVG: the
    sweep's rows of ``Results.points`` and of ``Results.curves`` (NaN where the sweep has no
    model fitted, e.g. too few points: points only)."""
    u, df, dg = (points[c].to_numpy(float) for c in ("amplitude_m", "df_Hz", "dgamma_Hz"))
    uu, f, g = (curve[c].to_numpy(float) for c in ("amplitude_m", "df_model_Hz", "dgamma_model_Hz"))
    body = _panel(0, u, np.asarray(df, float), uu, f, "Δf") + _panel(
        160, u, np.asarray(dg, float), uu, g, "ΔΓ"
    )
    return f'<svg width="312" height="110" font-size="9" role="img">{body}</svg>'


def _marked(mean: float, sd: float, digits: int = 3) -> str:
    """``mean ± sd``, with :data:`UNRESOLVED_MARK` where the spread is as large as the value
    (e.g. μ(ΔΓ) = 2.9 ± 3.7: the data do not resolve it; issue 30)."""
    text = plus_minus(mean, sd, digits)
    if math.isfinite(mean) and math.isfinite(sd) and sd >= abs(mean) > 0:
        return f"{text} {UNRESOLVED_MARK}"
    return text


def _load_stats(results: Results):
    import pandas as pd

    loads = results.loads
    rows = []
    for _, ld in loads.iterrows():
        rows.append(
            {
                "configuration": ld["configuration"],
                "medium": ld["medium"],
                "F_N (mN)": f"{ld['normal_force_N'] * 1e3:.4g}",
                "experiments": ld["n_experiments"],
                "sweeps": ld["n_sweeps"],
                "κ (N/m)": _marked(ld["kappa_N_per_m_mean"], ld["kappa_N_per_m_sd"]),
                "loss tangent": _marked(ld["loss_tangent_mean"], ld["loss_tangent_sd"]),
                "μ (Δf)": _marked(ld["mu_df_mean"], ld["mu_df_sd"], 2),
                "μ (ΔΓ)": _marked(ld["mu_dgamma_mean"], ld["mu_dgamma_sd"], 2),
                "μ (loop fit)": _marked(ld["mu_fit_mean"], ld["mu_fit_sd"], 2),
            }
        )
    return pd.DataFrame(rows)


#: Why a sweep is left out, in the order a reason is counted: a sweep left out for several of
#: them is counted under the first (so the reasons add up to the sweeps left out).
LEAVE_OUT = (
    (Flag.FEW_POINTS, "too few points"),
    (Flag.FIRST_RAMP, "first ramp"),
    (Flag.DRIFT, "drift"),
)


def _counts(results: Results) -> str:
    """ "384 sweeps, 285 used; the 99 left out for: first ramp 96, drift 3; flags on used
    sweeps: ..." — each sweep left out is counted once, under the first of its reasons in
    :data:`LEAVE_OUT` ("other" if it has none); the flags of the used sweeps are listed apart
    (a used sweep may carry several, so those counts need not add up)."""
    sw = results.sweeps
    used = sw["used"].to_numpy(dtype=bool) if len(sw) else np.zeros(0, dtype=bool)
    line = f"{len(sw)} sweeps, {int(used.sum())} used"
    if (~used).any():
        flags = sw["flags"].to_numpy(dtype=np.int64)[~used]
        counted = np.zeros(flags.size, dtype=bool)
        reasons = []
        for flag, text in LEAVE_OUT:
            n = int((has(flags, flag) & ~counted).sum())
            counted |= has(flags, flag)
            if n:
                reasons.append(f"{text} {n}")
        if (~counted).any():
            reasons.append(f"other {int((~counted).sum())}")
        line += f"; the {int((~used).sum())} left out for: {', '.join(reasons)}"
    if used.any():
        counts: dict[str, int] = {}
        for text in render(sw["flags"].to_numpy()[used]):
            for flag in (t for t in text.split(";") if t):
                counts[flag] = counts.get(flag, 0) + 1
        if counts:
            listed = ", ".join(f"{_e(flag)} {n}" for flag, n in sorted(counts.items()))
            line += f"; flags on used sweeps: {listed}"
    return f"<p><b>{line}.</b></p>"


def _plots(results: Results) -> str:
    """Paper 2's Figs. 5, 7 and 8 of the analysis as embedded PNG (nothing when no sweep is
    used: nothing to draw); below Fig. 5 what its bands are and which groups have none."""
    from .figures import figure_dissipation, figure_friction, figure_stiffness

    if not len(results.sweeps) or not results.sweeps["used"].any():
        return "<p>No sweep is used: nothing to plot.</p>"
    parts = []
    for title, draw in (
        (
            # What is drawn is Δf0 in Hz (κ = Δf0 / P, Eq. 1 of paper 2), so the title says Δf0.
            "Δf0 (Hz, proportional to the contact stiffness κ) against the normal force, with "
            "the JKR fits and their 95 % bands (paper 2, Fig. 5)",
            figure_stiffness,
        ),
        ("ΔΓ0 and the loss tangent against the normal force (Fig. 7)", figure_dissipation),
        ("The friction coefficient μ per load (Fig. 8)", figure_friction),
    ):
        parts.append(f"<h3>{_e(title)}</h3>{_png(draw(results), title)}")
        if draw is figure_stiffness:
            parts += [f"<p>{_e(line)}</p>" for line in _band_lines(results)]
    return "".join(parts)


def _png(figure, alt: str) -> str:
    """A matplotlib figure as an embedded PNG image (90 dpi: the page's scale)."""
    import base64
    import io

    from .._png import print_png

    buffer = io.BytesIO()
    print_png(figure, buffer, 90, tight=True)  # savefig(..., bbox_inches="tight"), one draw
    data = base64.b64encode(buffer.getvalue()).decode("ascii")
    return f'<img class="plot" alt="{_e(alt)}" src="data:image/png;base64,{data}">'


def _band_lines(results: Results) -> list[str]:
    """What the bands of the JKR fits are, and which groups have none (and why)."""
    jkr = results.jkr
    lines = [
        "Shaded: the 95 % pointwise band of each JKR fit: the errors of E and γ that Table 1 "
        "prints (the spread between experiments where a bootstrap gives them), with their "
        "correlation (E_gamma_corr in summary.json), propagated linearly, t95 of Table 1 wide; "
        "jkr_curves.csv holds it."
    ]
    for g in results.groups:
        where = f"{g['configuration']}, {g['medium']}"
        if not np.isfinite(g["E_Pa"]):
            lines.append(f"{where}: no JKR fit, so no curve and no band (see Table 1's note).")
            continue
        if jkr is None or "kappa_lo_N_per_m" not in jkr:
            continue
        mine = (jkr["configuration"] == g["configuration"]) & (jkr["medium"] == g["medium"])
        if not np.isfinite(jkr.loc[mine, "kappa_lo_N_per_m"].to_numpy(float)).any():
            lines.append(f"{where}: no band (Table 1's errors of E and γ give no covariance).")
    return lines


def _classification(results: Results) -> str:
    """The model class of the used sweeps per group and load as a figure (stacked bars), then
    how many used sweeps each model was chosen for, per medium (one row per medium, one
    column per model, a total column)."""
    import pandas as pd

    from .figures import figure_classification

    sw = results.sweeps
    if not len(sw) or not sw["used"].any():
        return "<p>No sweep is used: nothing classified.</p>"
    figure = figure_classification(results)
    alt = "The model class of the used sweeps per configuration, medium and load"
    plot = "" if figure is None else f"<h3>{_e(alt)}</h3>{_png(figure, alt)}"
    used = sw[sw["used"]]
    table = pd.crosstab(used["medium"], used["model"].fillna(DASH)).sort_index()
    table["all models"] = table.sum(axis=1)
    table = table.reset_index()
    table.columns = [str(c) for c in table.columns]
    note = (
        "<p>Number of used sweeps for which each model was chosen (the sweeps section lists them "
        "one by one).</p>"
    )
    return plot + _table(table, numeric=tuple(table.columns[1:])) + note


def _constants(results: Results):
    sw = results.sweeps
    names = [c for c in CONSTANTS if c in sw.columns]
    if not len(sw) or not names:
        return ""
    table = sw.groupby(["configuration", "medium"], sort=True)[names].agg(
        # pandas-stubs: the overloads of agg leave mypy no type for a lambda (a def has one)
        lambda s: ", ".join(f"{v:.6g}" for v in sorted(set(s.dropna())))  # type: ignore[misc]
    )
    table = table.reset_index()
    table.columns = ["configuration", "medium"] + [f"{c} ({CONSTANTS[c][0]})" for c in names]
    return _table(table)


def _select(name: str, values) -> str:
    opts = "".join(f'<option value="{_e(v)}">{_e(v)}</option>' for v in values)
    return (
        f'<label>{_e(name)} <select name="{_e(name)}" onchange="crFilter()">'
        f'<option value="">all</option>{opts}</select></label>'
    )


def _sweeps_section(results: Results) -> str:
    sw = results.sweeps
    if not len(sw):
        return "<p>No sweeps.</p>"
    points, curves = results.points, results.curves
    index: dict = {}
    curve: dict = {}
    # Results built by hand (not by analyze) may carry no curves: their sweeps are listed
    # without plots.
    if points is not None and curves is not None:
        curves = curves[curves["grid_points"] == PAGE_POINTS]
        index, curve = sweep_rows(points), sweep_rows(curves)
    flags = render(sw["flags"].to_numpy())
    loads = [f"{f * 1e3:.4g}" for f in sw["normal_force_N"]]
    used_flags = sorted({t for text in flags for t in text.split(";") if t})
    filters = (
        '<p class="filters">'
        + _select("configuration", sorted(sw["configuration"].astype(str).unique()))
        + _select("medium", sorted(sw["medium"].astype(str).unique()))
        + _select("load", sorted(set(loads), key=float))
        + _select("flag", used_flags)
        + f' shown: <span id="shown">{len(sw)}</span> of {len(sw)}</p>'
    )
    rows = []
    for (_, row), text, load in zip(sw.iterrows(), flags, loads, strict=True):
        i = index.get(row["sweep"])
        plot = DASH
        if i is not None and points is not None and curves is not None:
            plot = _sweep_svg(points.iloc[i], curves.iloc[curve[row["sweep"]]])
        model = row["model"] if isinstance(row["model"], str) and row["model"] else DASH
        rows.append(
            f'<tr data-configuration="{_e(row["configuration"])}" data-medium="{_e(row["medium"])}"'
            f' data-load="{_e(load)}" data-flag="{_e(text.replace(";", " "))}">'
            f"<td>{_e(row['sweep'])}</td><td>{_e(row['configuration'])}</td>"
            f'<td>{_e(row["medium"])}</td><td class="n">{_e(load)}</td>'
            f"<td>{_e(row['experiment'])}</td><td>{_e(row['ramp'])}</td>"
            f"<td>{'yes' if row['used'] else 'no'}</td><td>{_e(model)}</td>"
            f"<td>{_e(text.replace(';', ', ')) or DASH}</td><td>{plot}</td></tr>"
        )
    head = "".join(
        f"<th>{h}</th>"
        for h in (
            "sweep", "configuration", "medium", "F_N (mN)", "experiment", "ramp", "used",
            "model", "flags", "Δf, ΔΓ (Hz) against u0 (points; line: model)",
        )
    )  # fmt: skip
    return (
        filters + f'<table id="sweeps"><thead><tr>{head}</tr></thead><tbody>{"".join(rows)}</tbody>'
        "</table>"
    )


def _leaves(value, path: str):
    """(dotted path, value) of every number and text of a JSON record, lists by index."""
    if isinstance(value, dict):
        for k, v in value.items():
            yield from _leaves(v, f"{path}.{k}" if path else str(k))
    elif isinstance(value, list):
        for i, v in enumerate(value):
            yield from _leaves(v, f"{path}[{i}]")
    else:
        yield path, value


def _number(value, scale: float = 1.0) -> str:
    """A number of ``summary.json`` times ``scale`` to 4 digits (``—`` where missing)."""
    if value is None or not math.isfinite(float(value)):
        return DASH
    return f"{float(value) * scale:.4g}"


def _groups_table(results: Results) -> str:
    """The fit of each group in the units a reader uses: E (GPa) and γ (mJ/m²) with the fit's
    own errors and the bootstrap's, the sphere, the points fitted and the rms misfit."""
    import pandas as pd

    rows = [
        {
            "configuration": g["configuration"],
            "medium": g["medium"],
            "E (GPa)": plus_minus(g["E_Pa"] / 1e9, g["E_err_Pa"] / 1e9),
            "γ (mJ/m²)": plus_minus(g["gamma_J_m2"] * 1e3, g["gamma_err_J_m2"] * 1e3),
            "E fit error (GPa)": _number(g.get("E_fit_err_Pa"), 1e-9),
            "γ fit error (mJ/m²)": _number(g.get("gamma_fit_err_J_m2"), 1e3),
            "sphere radius (mm)": _number(g.get("sphere_radius_m"), 1e3),
            "ν": _number(g.get("poisson")),
            "loads fitted": g.get("n_points_fitted", DASH),
            "rms misfit (N/m)": _number(g.get("fit_rms_N_per_m")),
        }
        for g in results.groups
    ]
    if not rows:
        return "<p>No group is fitted.</p>"
    frame = pd.DataFrame(rows)
    return _table(frame, numeric=tuple(frame.columns[2:]))


def _summary_section(results: Results) -> str:
    """The fitted groups as a table in readers' units, then every entry of ``summary.json``
    (numbers to 7 digits, SI units), one row each, folded."""
    rows = []
    for key, value in _leaves(summary(results), ""):
        if isinstance(value, bool) or value is None or isinstance(value, str):
            shown = DASH if value is None else str(value)
        else:
            shown = f"{value:.7g}"
        rows.append(
            f'<tr data-key="{_e(key)}"><td><code>{_e(key)}</code></td><td>{_e(shown)}</td></tr>'
        )
    return _groups_table(results) + (
        "<details><summary>Every entry of <code>summary.json</code> as written, in SI units "
        "(groups in the order of Table 1)</summary>"
        "<table><thead><tr><th>key</th><th>value</th></tr></thead>"
        f"<tbody>{''.join(rows)}</tbody></table></details>"
    )


def html_report(results: Results) -> str:
    """The page as text (see the module docstring)."""
    source = None if results.table is None else results.table.source
    path = Path(source) if source and source != "<table>" else None
    name = path.name if path is not None else "table in memory"
    # The checksum taken when the input was read: the file may have changed since.
    digest = None if results.table is None else results.table.source_sha256
    checksum = digest or DASH
    sections = [
        (anchor, title)
        for anchor, title in _SECTIONS
        if (anchor != "radiation" or results.radiation is not None)
        and (anchor != "messages" or results.messages)
    ]
    titles = dict(sections)
    toc = "".join(f'<li><a href="#{a}">{_e(t)}</a></li>' for a, t in sections)
    parts = [
        "<!DOCTYPE html>",
        '<html lang="en"><head><meta charset="utf-8">',
        f"<title>contactres report: {_e(name)}</title>",
        f"<style>{_CSS}</style><script>{_JS}</script></head><body>",
        f"<h1>QCM sweep analysis: {_e(name)}</h1>",
        f"<nav><h2>Contents</h2><ul>{toc}</ul></nav>",
        f'<h2 id="input">{titles["input"]}</h2>',
        f"<p>Input: <code>{_e(name)}</code>, SHA-256 <code>{_e(checksum)}</code>; "
        f"contactres {_e(__version__)}.</p>",
        _counts(results),
        f'<h2 id="table1">{titles["table1"]}</h2>',
    ]
    table1 = table1_text(results)
    if table1.empty:
        parts.append("<p>No configuration to fit (no sweep is used).</p>")
    else:
        parts.append(_table(table1, numeric=("E (GPa)", "γ (mJ/m²)", "t95")))
        parts.append(
            "<p>± standard errors; 95 % interval: value ± t95 × error (Student t, few repeats).</p>"
        )
        parts += [f"<p><b>Note:</b> {_e(line)}</p>" for line in withheld_lines(results)]
    parts.append(f'<h2 id="plots">{titles["plots"]}</h2>')
    parts.append(_plots(results))
    parts.append(f'<h2 id="classification">{titles["classification"]}</h2>')
    parts.append(_classification(results))
    parts.append(f'<h2 id="loads">{titles["loads"]}</h2>')
    if len(results.loads):
        parts.append(_table(_load_stats(results), numeric=("F_N (mN)",)))
        parts.append(
            f"<p>mean ± standard deviation over experiments; {UNRESOLVED_MARK}: the spread is "
            "as large as the value (not resolved by the data).</p>"
        )
        parts.append("<h3>Friction coefficient per load (median over experiments)</h3>")
        parts.append(_table(friction_table(results)))
    else:
        parts.append("<p>No loads.</p>")
    if results.radiation is not None:
        parts.append(f'<h2 id="radiation">{titles["radiation"]}</h2><ul>')
        parts += [f"<li>{_e(line)}</li>" for line in radiation_lines(results)]
        parts.append("</ul>")
    parts.append(f'<h2 id="sweeps">{titles["sweeps"]}</h2>')
    parts.append(_sweeps_section(results))
    parts.append(f'<h2 id="summary">{titles["summary"]}</h2>')
    parts.append(_summary_section(results))
    parts.append(f'<h2 id="flags">{titles["flags"]}</h2><dl>')
    parts += [f"<dt><code>{_e(f.text)}</code></dt><dd>{_e(DESCRIPTIONS[f])}</dd>" for f in Flag]
    parts.append(f'</dl><h2 id="conventions">{titles["conventions"]}</h2><ul>')
    parts += [f"<li><code>{_e(k)}</code>: {_e(v)}</li>" for k, v in CONVENTIONS.items()]
    parts.append(f'</ul><h2 id="constants">{titles["constants"]}</h2>')
    parts.append(_constants(results))
    if results.messages:
        parts.append(f'<h2 id="messages">{titles["messages"]}</h2><ul>')
        parts += [f"<li>{_e(' '.join(str(m).split()))}</li>" for m in results.messages]
        parts.append("</ul>")
    parts.append("</body></html>\n")
    return "\n".join(parts)


def write_html(results: Results, path) -> Path:
    """Write :func:`html_report` to ``path`` atomically; return the path."""
    return write_text(path, html_report(results))


def sweeps_page(result) -> str:
    """The page of a :class:`contactres.jobs.qcm_sweeps.Result` (its analysis's
    :func:`html_report`), as :func:`contactres.report._writer.html_registry` registers it."""
    return html_report(result.analysis)
