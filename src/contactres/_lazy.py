"""Public names of a subpackage loaded on first use (PEP 562 module ``__getattr__``).

A subpackage whose ``__init__`` re-exports names from its modules passes its mapping name ->
module to :func:`attach` and binds the two functions it returns as ``__getattr__`` and
``__dir__``: ``import contactres.normal`` then imports none of its modules, and
``contactres.normal.hertz`` imports only ``contactres.normal._isotropic``. Nothing is kept
between calls: the import system holds each module once in ``sys.modules``.
"""

from __future__ import annotations

import importlib
import sys
from collections.abc import Callable, Mapping
from types import ModuleType

TYPE_CHECKING = False
if TYPE_CHECKING:
    from typing import Any

__all__ = ["attach"]


def attach(
    package: str, exports: Mapping[str, str]
) -> tuple[Callable[[str], Any], Callable[[], list[str]]]:
    """``(__getattr__, __dir__)`` of the package ``package`` whose public names are ``exports``.

    Parameters
    ----------
    package : the package's ``__name__``
    exports : public name -> the module (relative to ``package``) that defines it
    """

    def __getattr__(name: str) -> Any:
        """Import the module behind a public name on first access."""
        if name in exports:
            return getattr(importlib.import_module(exports[name], package), name)
        raise AttributeError(f"module {package!r} has no attribute {name!r}")

    def __dir__() -> list[str]:
        """The public names and the loaded public submodules, as tab completion expects.

        Not the package's own helpers (``attach``, ``TYPE_CHECKING``, ...) nor its private
        modules: ``dir()`` shows what a user may call, as scipy's subpackages do.
        """
        loaded = vars(sys.modules[package])
        modules = (n for n, v in loaded.items() if isinstance(v, ModuleType) and n[0] != "_")
        return sorted({*exports, *modules})

    return __getattr__, __dir__
