"""The installed version of contactres (from the package metadata; ``0+unknown`` in a bare tree)."""

from importlib.metadata import PackageNotFoundError, version

try:
    __version__ = version("contactres")
except PackageNotFoundError:  # pragma: no cover - running from a source tree
    __version__ = "0+unknown"

__all__ = ["__version__"]
