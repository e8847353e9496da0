"""Where the files of an ADAMS/Car database are: the database that holds a file, the subsystem
file of a database folder, and the files a subsystem or assembly names (``mdids://<alias>/...``,
``<alias>/...``, relative or absolute), confined to the databases the user gave.

ADAMS/Car keeps a database as a folder (``front.cdb``) of table folders (``subsystems.tbl``,
``bushings.tbl``...); files name each other by ``mdids://<alias>/<table>/<file>``, the alias
resolved by ADAMS' configuration file (``.acar.cfg``), which elastokin does not read: every alias
is taken as the database that holds the naming file. Every path is resolved (``..`` and links
followed) by :func:`elastokin.config.confined.confined_path` and must lie inside the
:class:`~elastokin.config.confined.Roots` given (by default the naming file's database);
otherwise the error names the file, line, block and USAGE and the path, and nothing outside is
opened. Conventions: ``docs/adams.md``, "Paths inside the database".
"""

from __future__ import annotations

import re
from collections.abc import Iterable
from pathlib import Path

from elastokin.config.confined import Roots, confined_path
from elastokin.errors import ConfigError

__all__ = ["database_file", "database_root", "input_roots", "subsystem_file"]

_DATABASE_REFERENCE = re.compile(r"^(?:mdids://([^/\\]*)|<([^>]*)>)[/\\]+(.*)$")


def database_root(path: str | Path) -> Path:
    """The database that holds ``path``: for a file in a table folder
    (``front.cdb/subsystems.tbl/x.sub``) the folder above it, for another file its folder; for
    a folder, itself (a table folder: the folder above)."""
    p = Path(path)
    folder = p if p.is_dir() else p.parent
    return folder.parent if folder.name.lower().endswith(".tbl") else folder


def input_roots(paths: Iterable[str | Path | None]) -> Roots:
    """The databases of the files and folders the user gave (``None`` left out): where the
    paths their files name may lead (:func:`database_root` of each)."""
    return Roots.of((database_root(p) for p in paths if p is not None),
                    "the ADAMS/Car databases and folders given")


def _own_roots(path: str | Path, roots: Roots | None) -> Roots:
    if roots is not None:
        return roots
    root = database_root(path)
    return Roots.of([root], f"the database {root}")


def subsystem_file(path: str | Path, name: str | None = None, roots: Roots | None = None
                   ) -> Path:
    """``path`` itself, or for a folder (an ADAMS/Car database ``.cdb`` or one of its table
    folders ``*.tbl``) the subsystem file in the database's ``subsystems.tbl``: the one there,
    or ``<name>.sub`` (the mapping's subsystem name) when it holds several; a file found so
    must lie inside ``roots`` (default: that database) after its links are followed."""
    p = Path(path)
    if not p.is_dir():
        return p
    db = p.parent if p.name.lower().endswith(".tbl") else p
    table = db / "subsystems.tbl"
    subs = sorted(table.glob("*.sub")) if table.is_dir() else []
    if len(subs) > 1 and name and (table / f"{name}.sub") in subs:
        subs = [table / f"{name}.sub"]
    if len(subs) != 1:
        raise ConfigError(f"{p}: a folder; expected a subsystem file, or an ADAMS/Car database "
                          f"(or one of its .tbl folders) whose subsystems.tbl holds one .sub "
                          f"file or the mapping's subsystem (found {len(subs)}: "
                          f"{', '.join(s.name for s in subs) or 'none'})")
    return confined_path(subs[0].name, table, _own_roots(db, roots), f"{p}", "subsystem file")


def database_file(reference: str, naming_file: str | Path, where: str,
                  roots: Roots | None = None, what: str = "file",
                  must_exist: bool = True) -> Path:
    """The file a subsystem or assembly file names (``reference``:
    ``mdids://<alias>/bushings.tbl/x.bus``, ``<alias>/bushings.tbl/x.bus``, or a path relative
    to the naming file's folder, or absolute), resolved and confined to ``roots`` (default: the
    database that holds the naming file). A database reference is taken in the database that
    holds the naming file, whatever the alias; ``/`` and ``\\`` both separate. With
    ``must_exist`` the file must exist. ``where`` names the file, line, block and USAGE that
    give the path (errors)."""
    text = reference.strip()
    m = _DATABASE_REFERENCE.match(text)
    if m:
        base, parts = database_root(naming_file), m.group(3)
        alias = m.group(1) if m.group(1) is not None else m.group(2)
        note = (f" (alias '{alias}' taken as the database that holds "
                f"{Path(naming_file).name}: {base}; elastokin does not read .acar.cfg)")
    else:
        base, parts, note = Path(naming_file).parent, text, ""
    relative = Path(*re.split(r"[/\\]+", parts)) if parts else Path(".")
    if text.startswith(("/", "\\")):
        relative = Path("/") / relative
    path = confined_path(relative, base, _own_roots(naming_file, roots), where, what,
                         written=text)
    if must_exist and not path.is_file():
        exists = "is a folder, not a file" if path.is_dir() else "does not exist"
        raise ConfigError(f"{where}: {what} {text!r} {exists} ({path}{note})")
    return path
