"""Sphinx configuration of the contactres documentation (``make docs`` builds it, warnings fail)."""

from __future__ import annotations

import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE / "_ext"))

from contactres import __version__  # noqa: E402

project = "contactres"
author = "the contactres developers"
copyright = "2026, the contactres developers"
version = release = __version__

extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.napoleon",
    "sphinx.ext.mathjax",
    # MathJax copied into the site, so the theory pages render without a network.
    "sphinx-mathjax-offline",
    "sphinx.ext.viewcode",
    "matplotlib.sphinxext.plot_directive",
    "contactres_docs",
]

source_suffix = {".md": "markdown", ".rst": "restructuredtext"}
root_doc = "index"
exclude_patterns = ["_build", "_generated", "Thumbs.db", ".DS_Store"]
nitpicky = False

myst_enable_extensions = ["dollarmath", "amsmath", "colon_fence", "deflist"]
myst_heading_anchors = 3
myst_dmath_double_inline = True

# The API pages: numpy-style docstrings through napoleon; type hints in the description.
autosummary_generate = True
autodoc_typehints = "description"
autodoc_member_order = "bysource"
# A page lists what its module defines, not what it re-exports, except the page of a subpackage
# whose modules are private (scipy's rule): it lists the names of its __all__, documented there
# only (docs/_ext/contactres_docs.py adds ``:ignore-module-all:`` to every other page).
autodoc_default_options = {"members": True}
napoleon_numpy_docstring = True
napoleon_google_docstring = False
napoleon_use_rtype = False

# Figures made at build time (gallery, validation): PNG only, at a readable size.
plot_formats = [("png", 110)]
plot_html_show_formats = False
plot_html_show_source_link = True
plot_include_source = False
plot_rcparams = {"figure.autolayout": False}

# Option names (--remove-drift) and code-like text stay as typed: no en dashes or curly quotes.
smartquotes = False

html_theme = "furo"
html_title = f"contactres {release}"
html_static_path: list[str] = []
