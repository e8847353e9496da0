"""The elastokin version, and the Exudyn version read from the installed package's metadata
(without importing Exudyn): every result file carries both."""

from __future__ import annotations

from importlib import metadata

__version__ = "0.1.0"


def exudyn_version() -> str:
    """The installed Exudyn's version ("not installed" when it is missing)."""
    try:
        return metadata.version("exudyn")
    except metadata.PackageNotFoundError:
        return "not installed"
