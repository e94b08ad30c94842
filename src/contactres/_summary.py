"""Compact summaries of parameter and result objects: one line to print, a table for notebooks.

A dataclass repr prints every field in full: a 6x6 stiffness as a numpy repr, a map of 10^6
pixels, a whole sweep table. The classes a user holds in a notebook inherit :class:`Summarised`
instead (with ``@dataclass(repr=False)``, so equality and hashing stay the dataclass' own) and
say, in :meth:`Summarised._facts`, the few numbers a user wants, with their units;
``repr(x)`` is then ``Name(label: value; label: value)`` and ``x._repr_html_()`` (what Jupyter
shows) the same facts as a small HTML table, every label and value escaped.

The formatting helpers (:func:`number`, :func:`values`, :func:`plus_minus`, ...) keep the
numbers of all classes alike: four significant digits, a range for an array, NaNs counted. The
module imports only the standard library at the top (numpy where an array is summarised), so
that light modules (:mod:`contactres.crystals`) can use it.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

__all__ = [
    "Summarised",
    "clipped",
    "flagged",
    "number",
    "plus_minus",
    "summary_html",
    "summary_text",
    "table_size",
    "values",
]

DIGITS = 4  # significant digits of every number shown: enough to recognise a value


def clipped(text: str, limit: int = 80) -> str:
    """``text`` cut to ``limit`` characters, the cut marked with an ellipsis.

    Examples
    --------
    >>> clipped("Simmons and Wang, Single Crystal Elastic Constants (1971)", 20)
    'Simmons and Wang, S…'
    """
    return text if len(text) <= limit else text[: limit - 1] + "…"


def number(x, unit: str = "", scale: float = 1.0, digits: int = DIGITS) -> str:
    """One number divided by ``scale``, to ``digits`` significant digits, with its unit.

    A complex number (a lossy modulus) shows both parts; NaN shows as "nan".

    Examples
    --------
    >>> number(168.4e9, "GPa", 1e9)
    '168.4 GPa'
    >>> number(3e9 + 1.5e8j, "GPa", 1e9)
    '3+0.15j GPa'
    """
    z = complex(x)  # each part divided alone: complex(inf) / 1e9 would be inf + nan j
    re, im = z.real / scale, z.imag / scale
    text = f"{re:.{digits}g}" if im == 0 else f"{re:.{digits}g}{im:+.{digits}g}j"
    return f"{text} {unit}" if unit else text


def plus_minus(value, error, unit: str = "", scale: float = 1.0) -> str:
    """``value ± error`` (value as :func:`number`, error to two digits); NaN value: "not
    determined", NaN error: the value alone.

    Examples
    --------
    >>> plus_minus(0.7213, 0.0123)
    '0.7213 ± 0.012'
    >>> plus_minus(float("nan"), 0.1)
    'not determined'
    """
    v, e = float(value) / scale, float(error) / scale
    if not math.isfinite(v):
        return "not determined"
    text = number(v)
    text = f"{text} ± {e:.2g}" if math.isfinite(e) else text
    return f"{text} {unit}" if unit else text


def values(x, unit: str = "", scale: float = 1.0, digits: int = DIGITS) -> str:
    """A scalar as :func:`number`; an array as its shape and range (real parts), NaNs counted.

    Examples
    --------
    >>> import numpy as np
    >>> values(np.array([1.0e9, 2.5e9, np.nan]), "GPa", 1e9)
    '3 values, 1 to 2.5 GPa (1 NaN)'
    >>> values(np.zeros((2, 3)))
    'shape (2, 3), 0 to 0'
    """
    import numpy as np  # here, not at the top: the module is imported by light ones (crystals)

    a = np.asarray(x)
    if a.size == 1:
        return number(a.reshape(()).item(), unit, scale, digits)
    count = f"{a.size} values" if a.ndim == 1 else f"shape {a.shape}"
    if a.size == 0:
        return count
    real = np.real(a).astype(float) / scale
    finite = real[np.isfinite(real)]
    nans = real.size - finite.size
    if finite.size == 0:
        return f"{count}, all NaN"
    span = f"{finite.min():.{digits}g} to {finite.max():.{digits}g}"
    tail = f" ({nans} NaN)" if nans else ""
    return f"{count}, {span}{' ' + unit if unit else ''}{tail}"


def flagged(flags) -> str:
    """How many entries carry a flag: a non-zero bit mask, or a non-empty tuple of names.

    Examples
    --------
    >>> import numpy as np
    >>> flagged(np.array([0, 4, 0, 1]))
    '2 of 4'
    >>> flagged(((), ("unresolved",), ()))
    '1 of 3'
    """
    if isinstance(flags, tuple) and all(isinstance(f, tuple) for f in flags):
        return f"{sum(1 for f in flags if f)} of {len(flags)}"
    import numpy as np  # as in values()

    a = np.asarray(flags)
    return f"{int(np.count_nonzero(a))} of {a.size}"


def table_size(frame, first: int = 4) -> str:
    """Rows, columns and the first column names of a DataFrame.

    Examples
    --------
    >>> import pandas as pd
    >>> table_size(pd.DataFrame({"a": [1, 2], "b": [3, 4]}))
    '2 rows x 2 columns (a, b)'
    """
    names = [str(c) for c in frame.columns]
    shown = ", ".join(names[:first]) + (", …" if len(names) > first else "")
    return f"{len(frame)} rows x {len(names)} columns ({shown})"


def summary_text(name: str, facts: Sequence[tuple[str, str]]) -> str:
    """``name(label: value; ...)``; a fact with an empty label shows its value alone.

    Examples
    --------
    >>> summary_text("Thing", [("", "Cu"), ("C11", "168.4 GPa")])
    'Thing(Cu; C11: 168.4 GPa)'
    """
    shown = "; ".join(f"{k}: {v}" if k else v for k, v in facts)
    return f"{name}({shown})"


def summary_html(name: str, facts: Sequence[tuple[str, str]]) -> str:
    """The facts of :func:`summary_text` as HTML, all escaped: ``name`` and the unlabelled facts
    as a heading, the labelled ones as a table.

    Examples
    --------
    >>> summary_html("T", [("", "Cu"), ("a", "<b>&")])
    '<p><b>T</b> Cu</p><table><tbody><tr><th>a</th><td>&lt;b&gt;&amp;</td></tr></tbody></table>'
    """
    # Imported here: only a notebook asks for HTML (html.entities is a table of ~2,000 names).
    import html

    head = ", ".join(html.escape(v) for k, v in facts if not k)
    rows = "".join(
        f"<tr><th>{html.escape(k)}</th><td>{html.escape(v)}</td></tr>" for k, v in facts if k
    )
    return (
        f"<p><b>{html.escape(name)}</b>{' ' + head if head else ''}</p>"
        f"<table><tbody>{rows}</tbody></table>"
    )


class Summarised:
    """Mixin: ``repr`` and the notebook view (``_repr_html_``) from :meth:`_facts`.

    Use it with ``@dataclass(..., repr=False)``: the dataclass' own ``__repr__`` would
    otherwise replace the inherited one. The mixin has no fields and no ``__eq__``.
    """

    __slots__ = ()

    def _facts(self) -> list[tuple[str, str]]:
        """(label, value with unit) of the summary; each class says which."""
        raise NotImplementedError

    def __repr__(self) -> str:
        return summary_text(type(self).__name__, self._facts())

    def _repr_html_(self) -> str:
        """The facts as a small HTML table, for notebooks (every label escaped)."""
        return summary_html(type(self).__name__, self._facts())
