"""Paths that one input file names on behalf of another, confined to the folders the user
pointed elastokin at (README "Which paths may point anywhere").

A file read from someone else (an ADAMS/Car database, a mapping file, a config and the CMM and
K&C test files it names) may name other files: ``mdids://db/../../x``, ``../x``, ``/x``, a
link. Every such path is taken here, in one place: resolved with every ``..`` and every
symbolic link followed, and refused unless it lies inside one of the :class:`Roots` (the
folders the user gave). The check only asks the file system where the path leads; nothing
outside is opened, and the error names the file (and line or key) that named the path, the
path as written and where it leads. A path the user types on the command line is taken as
typed: it is not named by a file.
"""

from __future__ import annotations

import contextlib
import os
import stat
from collections.abc import Iterable, Iterator
from contextvars import ContextVar
from dataclasses import dataclass
from pathlib import Path

from elastokin.config.suspension import Suspension
from elastokin.errors import ConfigError, ElastokinError

__all__ = ["Roots", "config_roots", "confined_path", "data_file", "data_folder", "data_folders",
           "resolved", "typed_folders"]


def resolved(path: str | Path) -> Path:
    """``path`` absolute, with every ``..`` and symbolic link followed (the file system is
    asked where it leads; nothing is opened)."""
    try:
        return Path(os.path.realpath(path))
    except (ValueError, OSError) as exc:  # a NUL byte in the name, a name too long
        raise ConfigError(f"{str(path)!r}: not a usable path ({exc})") from None


@dataclass(frozen=True)
class Roots:
    """The folders files may name paths inside (resolved) and what they are, for messages
    (e.g. ``"the database /data/front.cdb"``)."""

    folders: tuple[Path, ...]
    what: str

    @classmethod
    def of(cls, folders: Iterable[str | Path], what: str) -> Roots:
        found = dict.fromkeys(resolved(f) for f in folders)
        return cls(tuple(found), what)

    def including(self, folders: Iterable[str | Path], what: str) -> Roots:
        """These roots and ``folders`` (described together as ``what``)."""
        return Roots.of((*self.folders, *folders), what)

    def hold(self, path: Path) -> bool:
        """``path`` (resolved) lies inside one of the folders."""
        return any(path == f or path.is_relative_to(f) for f in self.folders)


def confined_path(named: str | Path, base: str | Path, roots: Roots, where: str,
                  what: str = "path", error: type[ElastokinError] = ConfigError,
                  written: str | None = None, remedy: str = "copy the file into them") -> Path:
    """The path ``named`` in an input file (relative to the folder ``base``, or absolute) as
    ``base / named``, when it leads (resolved) inside ``roots``; otherwise ``error`` naming
    ``where`` (the file and line or key that names it), ``what`` it is, the path as written
    (``written``, default ``named``), where it leads and the ``remedy``. An existing path that
    is neither a file nor a folder (a FIFO, a device) is refused too: reading it could block or
    never end."""
    path = Path(base) / named
    target = resolved(path)
    shown = str(named) if written is None else written
    if not roots.hold(target):
        inside = ", ".join(str(f) for f in roots.folders)
        raise error(f"{where}: {what} {shown!r} leads to {target}, outside {roots.what} "
                    f"({inside}); elastokin reads no file outside the folders it was given "
                    f"(README, 'Which paths may point anywhere'): {remedy}")
    try:
        mode = os.stat(target).st_mode
    except OSError:
        return path  # does not exist (yet): the reader says so
    if not (stat.S_ISREG(mode) or stat.S_ISDIR(mode)):
        raise error(f"{where}: {what} {shown!r} ({target}) is not a regular file (a FIFO or a "
                    "device: reading it could block)")
    return path


# ----------------------------------------------------------------------------------------------
# A config's data: the CMM files (measurements) and the K&C test files (kc_test)


#: the folders typed with ``--data`` for the command running (:func:`data_folders`)
_TYPED: ContextVar[tuple[Path, ...]] = ContextVar("elastokin_data_folders", default=())

#: what to do about a config's data outside its folders
DATA_REMEDY = ("copy it beside the config, or give its folder with --data FOLDER (in Python: "
               "elastokin.data_folders) if you trust the config")


@contextlib.contextmanager
def data_folders(folders: Iterable[str | Path]) -> Iterator[None]:
    """Inside this block, a config's data may also lie in ``folders`` (typed by the user:
    ``--data``), besides the config's own folder."""
    token = _TYPED.set(tuple(resolved(f) for f in folders))
    try:
        yield
    finally:
        _TYPED.reset(token)


def typed_folders() -> tuple[Path, ...]:
    """The folders typed with ``--data`` for the command running (:func:`data_folders`)."""
    return _TYPED.get()


def config_roots(s: Suspension, folders: Iterable[str | Path] = ()) -> Roots:
    """Where a config's data may lie: the config's folder, the folders typed with ``--data``
    (:func:`data_folders`) and ``folders`` typed on the command line (e.g. ``synthesize
    --out``). Not the working folder: a config from someone else, run from the home folder,
    must not reach into it."""
    typed = (*_TYPED.get(), *folders)
    return Roots.of((Path(s.source).parent, *typed),
                    "the config's folder" + (" and the folders given" if typed else ""))


def data_folder(s: Suspension, section: str) -> Path:
    """The ``folder`` of the config's ``measurements`` or ``kc_test`` section (relative to the
    config), confined to :func:`config_roots`."""
    spec = getattr(s, section)
    return confined_path(spec.folder, Path(s.source).parent, config_roots(s),
                         f"{s.source}: key '{section}.folder'", "folder", remedy=DATA_REMEDY)


def data_file(s: Suspension, section: str, name: str, key: str,
              folder: str | Path | None = None) -> Path:
    """File ``name`` of the config's ``section`` (named at config key ``key``): in the
    section's folder, or in ``folder`` (typed on the command line), confined to
    :func:`config_roots` (and ``folder``)."""
    typed = () if folder is None else (folder,)
    base = data_folder(s, section) if folder is None else Path(folder)
    return confined_path(name, base, config_roots(s, typed), f"{s.source}: key '{key}'",
                         "file", remedy=DATA_REMEDY)
