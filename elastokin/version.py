"""The elastokin version, and the Exudyn version read from the installed package's metadata
(without importing Exudyn): every result file carries both."""

from __future__ import annotations

import functools
import hashlib
from importlib import metadata
from pathlib import Path

__version__ = "0.1.0"


def exudyn_version() -> str:
    """The installed Exudyn's version ("not installed" when it is missing)."""
    try:
        return metadata.version("exudyn")
    except metadata.PackageNotFoundError:
        return "not installed"


@functools.cache
def code_sha256() -> str:
    """SHA-256 of elastokin's own code (every ``.py`` file of the installed package, by its
    path inside the package and its bytes): two runs of the same version with different code
    (a development checkout, a patched install) tell apart, so the cache never answers one
    with the other's results. Read once per process (~200 files, a few ms)."""
    root = Path(__file__).resolve().parent
    h = hashlib.sha256()
    for path in sorted(root.rglob("*.py")):
        h.update(path.relative_to(root).as_posix().encode() + b"\0")
        h.update(path.read_bytes())
        h.update(b"\0")
    return h.hexdigest()
