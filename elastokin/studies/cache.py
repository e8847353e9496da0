"""A cache of a K&C run's expensive results (the geometric identification, the stiffness fit),
keyed by the content of everything they depend on: the config (and rig) bytes, the CMM or K&C
test files' bytes, the elastokin and Exudyn versions. A result is reused only when every input
is the same; a corrupt or foreign entry is ignored with a warning, never trusted.

Entries live in the results folder (``results/<name>/.cache/``): a run reads the entries of the
previous results and writes its own into the new folder, which replaces the old one as a whole
only when the run succeeded, so concurrent runs never see half-written entries.
"""

from __future__ import annotations

import hashlib
import pickle
import warnings
from pathlib import Path

from elastokin.version import __version__, exudyn_version

#: bumped when what an entry holds changes
CACHE_FORMAT = 5


class CacheWarning(UserWarning):
    """A cache entry was unreadable or foreign and was ignored."""


def content_key(*parts) -> str:
    """SHA-256 of the parts (bytes, strings, files as their bytes) and of the versions."""
    h = hashlib.sha256(f"{CACHE_FORMAT} {__version__} {exudyn_version()}".encode())
    for part in parts:
        if isinstance(part, Path):
            h.update(str(part.name).encode())
            h.update(part.read_bytes() if part.is_file() else b"<missing>")
        elif isinstance(part, bytes):
            h.update(part)
        else:
            h.update(repr(part).encode())
        h.update(b"\0")
    return h.hexdigest()


class ResultCache:
    """Results read from ``source`` (a previous run's ``.cache`` folder, if any) and written to
    ``target``; ``enabled`` False ignores what is stored (``--refit``) but still writes."""

    def __init__(self, source: Path | None, target: Path | None, enabled: bool = True):
        self.source, self.target, self.enabled = source, target, enabled
        self.reused: list[str] = []

    def get(self, name: str, key: str):
        """The stored value of ``name`` when its key is ``key``, else None."""
        if not self.enabled or self.source is None:
            return None
        path = self.source / f"{name}.pkl"
        if not path.is_file():
            return None
        try:
            with open(path, "rb") as fh:
                entry = pickle.load(fh)
            if not isinstance(entry, dict) or entry.get("format") != CACHE_FORMAT:
                raise ValueError("not an elastokin cache entry")
        except Exception as exc:  # noqa: BLE001 - anything wrong with an entry: recompute
            warnings.warn(CacheWarning(f"{path}: cache entry ignored ({type(exc).__name__}: "
                                       f"{str(exc)[:80]}); recomputing"), stacklevel=2)
            return None
        if entry.get("key") != key:
            return None
        self.reused.append(name)
        return entry["value"]

    def put(self, name: str, key: str, value) -> None:
        """Store ``value`` under ``name`` (into the new results folder)."""
        if self.target is None:
            return
        self.target.mkdir(parents=True, exist_ok=True)
        with open(self.target / f"{name}.pkl", "wb") as fh:
            pickle.dump({"format": CACHE_FORMAT, "key": key, "value": value}, fh,
                        protocol=pickle.HIGHEST_PROTOCOL)
