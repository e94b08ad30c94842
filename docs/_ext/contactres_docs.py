"""Build-time pages of the contactres docs: the data dictionary, generated from the schema.

Each table of :func:`contactres.report.dictionary.dictionary_tables` is written to
``_generated/<name>.md`` when the build starts; ``dictionary.md`` includes them, so the page
cannot drift from the columns the package reads and writes.
"""

from __future__ import annotations

from pathlib import Path


def _write_dictionary(app) -> None:
    from contactres.report.dictionary import dictionary_tables

    out = Path(app.srcdir) / "_generated"
    out.mkdir(exist_ok=True)
    for name, table in dictionary_tables().items():
        path = out / f"{name}.md"
        text = table + "\n"
        # Rewrite only on change, so an incremental build does not re-read every page.
        if not path.exists() or path.read_text(encoding="utf-8") != text:
            path.write_text(text, encoding="utf-8")


def setup(app):
    app.connect("builder-inited", _write_dictionary)
    return {"version": "1", "parallel_read_safe": True, "parallel_write_safe": True}
