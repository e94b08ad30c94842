"""What the command line runs: the demo and the reproductions of the papers' figures.

:func:`write_demo` writes the demo (``contactres demo``) into one folder
(:func:`check_demo_output` checks it first); the modules
:mod:`contactres.apps.paper1` and :mod:`contactres.apps.paper2` draw the figures of the two papers
(``contactres figures paper1`` / ``paper2``; the gallery calls their functions). The rest of the
package's modules are private (``_demo``); the public names are loaded on first use (PEP 562
module ``__getattr__``), so that ``import contactres.apps`` pays for no plotting library.
"""

from __future__ import annotations

from types import MappingProxyType

from .._lazy import attach

# Read as True by mypy and pyright (the real objects below), False at run time: no import.
TYPE_CHECKING = False

# Public name -> the module that defines it.
_EXPORTS = MappingProxyType({"check_demo_output": "._demo", "write_demo": "._demo"})

__all__ = sorted(_EXPORTS)

# What type checkers see (never run, so the import stays lazy; tests/test_public_api.py keeps
# these imports and ``_EXPORTS`` the same).
if TYPE_CHECKING:
    from ._demo import check_demo_output as check_demo_output
    from ._demo import write_demo as write_demo

__getattr__, __dir__ = attach(__name__, _EXPORTS)
