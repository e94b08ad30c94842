"""One self-contained HTML page of any job's Result: :func:`job_page`.

A page a job registers in :func:`contactres.report._writer.html_registry` when it has no page
of its own: it reads only what every :class:`contactres.jobs.contract.JobResult` carries, so
it suits any of them. In order:

* the title (the job's name and the input's), the package version;
* the warnings of the Result (its ``warnings`` lines, where it has them);
* its summary, where it has a ``summary()`` method (a table: what the command prints);
* the figures registered for the Result's type (:func:`contactres.report._writer.figure_registry`,
  passed by :func:`~contactres.report._writer.html_registry`), drawn again and embedded as
  base64 PNG;
* the flags: for every table with a ``flags`` column (``;``-separated names), how many rows
  carry each flag;
* the values (:meth:`~contactres.jobs.contract.JobResult.values`: conventions, constants, the
  equation, ...), a table per mapping and one for the rest;
  except those the Result names in ``JSON_ONLY`` (per-step lists, model curves: named, left to
  its JSON);
* every table: its description, its row count, its columns with their units (from its schema)
  and its first :data:`FIRST_ROWS` rows.

The page needs nothing but itself (no network, no external CSS or script); every text from the
data (labels, file names, values) is HTML-escaped, as on the sweep analysis's page.
"""

from __future__ import annotations

import base64
import io
import math
from html import escape

__all__ = ["FIRST_ROWS", "JOB_PAGE_FILE", "LIST_ITEMS", "job_page"]

#: The file name of the page in the results folder.
JOB_PAGE_FILE = "report.html"
#: How many rows of each table the page shows.
FIRST_ROWS = 10
#: Items of a list value shown (the rest is counted and left to the JSON).
LIST_ITEMS = 20

_CSS = """
body{font-family:sans-serif;margin:1em 2em;color:#222;max-width:70em}
table{border-collapse:collapse;margin:.5em 0;font-size:90%}
th,td{border:1px solid #bbb;padding:2px 6px;text-align:left;vertical-align:top}
th{background:#eee}
td.n{text-align:right;white-space:nowrap}
code{background:#f4f4f4}
img{max-width:100%;border:1px solid #ddd}
"""


def _e(value) -> str:
    return escape(str(value), quote=True)


def _shown(value) -> str:
    """A value as the page shows it: numbers to 7 significant digits, nothing as a dash."""
    if value is None or (isinstance(value, float) and not math.isfinite(value)):
        return "—"
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, float):
        return f"{value:.7g}"
    if isinstance(value, list):
        # A per-step series (10^4 time steps) would make the page megabytes: its head only,
        # the whole of it is in the result's JSON.
        head = ", ".join(_shown(v) for v in value[:LIST_ITEMS])
        more = len(value) - LIST_ITEMS
        return head if more <= 0 else f"{head}, … ({len(value)} values; all in the JSON)"
    return str(value)


def _rows(pairs) -> str:
    body = "".join(
        f"<tr><td><code>{_e(k)}</code></td><td>{_e(_shown(v))}</td></tr>" for k, v in pairs
    )
    return (
        f"<table><thead><tr><th>name</th><th>value</th></tr></thead><tbody>{body}</tbody></table>"
    )


def _leaves(value, path: str):
    """(dotted path, value) of every leaf of a nested mapping; lists of plain values whole."""
    if isinstance(value, dict) and value:
        for k, v in value.items():
            yield from _leaves(v, f"{path}.{k}" if path else str(k))
    else:
        yield path, value


def _values_section(result) -> list[str]:
    left = tuple(getattr(result, "JSON_ONLY", ()))
    values = {k: v for k, v in result.values().items() if k not in left}
    plain = [(k, v) for k, v in values.items() if not isinstance(v, dict)]
    parts = ["<h2>Values</h2>"]
    if plain:
        parts.append(_rows(plain))
    for key, value in values.items():
        if isinstance(value, dict):
            parts.append(f"<h3>{_e(key)}</h3>")
            parts.append(_rows(list(_leaves(value, ""))) if value else "<p>none</p>")
    if left:
        name = f"{getattr(result, 'NAME', 'result')}.json"
        shown = ", ".join(f"<code>{_e(k)}</code>" for k in left)
        parts.append(f"<p>{shown}: in <code>{_e(name)}</code> (lists too long for a page).</p>")
    return parts


def _summary_section(result) -> list[str]:
    """The Result's ``summary()`` table (what its command prints), where it has one."""
    summary = getattr(result, "summary", None)
    if not callable(summary):
        return []
    frame = summary()
    head = "".join(f"<th>{_e(c)}</th>" for c in frame.columns)
    body = "".join(f"<tr>{_cells(row)}</tr>" for row in frame.itertuples(index=False))
    table = f"<table><thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>"
    return ["<h2>Summary</h2>", table]


def _flags_section(result) -> list[str]:
    counts: dict[tuple[str, str], int] = {}
    totals: dict[str, int] = {}
    for name, (frame, _) in result.tables().items():
        if "flags" not in frame.columns:
            continue
        totals[name] = len(frame)
        for text in frame["flags"].astype(str):
            for flag in (f.strip() for f in text.split(";")):
                if flag and flag != "nan":
                    counts[(name, flag)] = counts.get((name, flag), 0) + 1
    if not totals:
        return []
    parts = ["<h2>Flags</h2>"]
    if not counts:
        return [*parts, "<p>No row carries a flag.</p>"]
    rows = "".join(
        f"<tr><td><code>{_e(t)}</code></td><td>{_e(f)}</td>"
        f'<td class="n">{k} of {totals[t]}</td></tr>'
        for (t, f), k in counts.items()
    )
    head = "<tr><th>table</th><th>flag</th><th>rows</th></tr>"
    return [*parts, f"<table><thead>{head}</thead><tbody>{rows}</tbody></table>"]


def _cell(value) -> str:
    if isinstance(value, float):
        return "" if not math.isfinite(value) else f"{value:.6g}"
    return str(value)


def _cells(row) -> str:
    """The cells of a table row, numbers right-aligned."""
    return "".join(
        f'<td class="n">{_e(_cell(v))}</td>'
        if isinstance(v, int | float) and not isinstance(v, bool)
        else f"<td>{_e(_cell(v))}</td>"
        for v in row
    )


def _table_section(name: str, frame, schema) -> list[str]:
    units = {} if schema is None else {c.name: c.unit for c in schema.columns}
    head = "".join(
        f"<th>{_e(c)}" + (f" ({_e(units[c])})" if units.get(c, "text") != "text" else "") + "</th>"
        for c in frame.columns
    )
    body = []
    for row in frame.head(FIRST_ROWS).itertuples(index=False):
        body.append(f"<tr>{_cells(row)}</tr>")
    about = "" if schema is None else f"{_e(schema.description)}; "
    shown = min(len(frame), FIRST_ROWS)
    return [
        f"<h3><code>{_e(name)}</code></h3>",
        f"<p>{about}{len(frame)} rows (the first {shown} shown; all in "
        f"<code>{_e(name)}.csv</code>).</p>",
        f"<table><thead><tr>{head}</tr></thead><tbody>{''.join(body)}</tbody></table>",
    ]


def _figures_section(result, figures) -> list[str]:
    from .._png import print_png  # matplotlib: imported when a page has figures

    parts = []
    for name, draw in figures:
        figure = draw(result)
        if figure is None:
            continue
        buffer = io.BytesIO()
        print_png(figure, buffer, 100, tight=True)  # savefig(..., bbox_inches="tight"), one draw
        data = base64.b64encode(buffer.getvalue()).decode("ascii")
        parts.append(
            f'<figure><img alt="{_e(name)}" src="data:image/png;base64,{data}">'
            f"<figcaption><code>{_e(name)}</code></figcaption></figure>"
        )
    return ["<h2>Figures</h2>", *parts] if parts else []


def job_page(result, figures=()) -> str:
    """The page of ``result``, any job's Result (see the module docstring), as text.

    ``figures``: (file name, drawing function) pairs, those
    :func:`contactres.report._writer.figure_registry` holds for the Result's type (the
    registry passes them: this module does not import it).
    """
    from .._version import __version__

    job = type(result).__module__.rsplit(".", 1)[-1].replace("_", " ")
    source = getattr(result, "source", "") or ""
    title = f"contactres {job}" + (f": {source}" if source else "")
    parts = [
        "<!DOCTYPE html>",
        '<html lang="en"><head><meta charset="utf-8">',
        f"<title>{_e(title)}</title>",
        f"<style>{_CSS}</style></head><body>",
        f"<h1>{_e(title)}</h1>",
        f"<p>contactres {_e(__version__)}"
        + (f"; input <code>{_e(source)}</code>" if source else "")
        + ".</p>",
    ]
    lines = getattr(result, "warnings", ()) or ()
    if lines:
        parts.append("<h2>Warnings</h2><ul>")
        parts += [f"<li>{_e(' '.join(str(line).split()))}</li>" for line in lines]
        parts.append("</ul>")
    parts += _summary_section(result)
    parts += _figures_section(result, figures)
    parts += _flags_section(result)
    parts += _values_section(result)
    parts.append("<h2>Tables</h2>")
    for name, (frame, schema) in result.tables().items():
        parts += _table_section(name, frame, schema)
    parts.append("</body></html>\n")
    return "\n".join(parts)
