"""ADAMS/Car hardpoint tables in: every ``{hardpoint_name symmetry x_value y_value z_value}``
table of a subsystem (``.sub``), assembly (``.asy``) or hardpoint file, with left/right pairs
kept apart, and the lookup of a mapped name (``hpl_``/``hpr_``/``hps_`` prefixes).

Pure Python/numpy. Points stay in ADAMS/Car's global frame (X rearward, Y right, Z up), in mm
(converted from the file's ``[UNITS]`` on reading); a ``left/right`` row stores its left point
(Y < 0), the right one is its Y mirror; an asymmetric pair is two rows, ``left`` and
``right``. A name may be given once per side (names compare case-insensitively, as they are
looked up); hardpoints farther than :data:`PLAUSIBLE_MM` from the origin, or all of them within
:data:`IMPLAUSIBLE_MM` of it, mean a wrong ``[UNITS]`` block and are refused. Conventions:
``docs/adams.md``, "Hardpoint tables".
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from elastokin.errors import ConfigError
from elastokin.formats.adams.database import subsystem_file
from elastokin.formats.adams.teimorbit import TeimOrbitFile, read_teimorbit

__all__ = [
    "HARDPOINT_COLUMNS",
    "IMPLAUSIBLE_MM",
    "PLAUSIBLE_MM",
    "SYMMETRIES",
    "AdamsHardpoint",
    "lookup_hardpoint",
    "read_hardpoints",
]

Fail = Callable[[int, str], ConfigError]

#: a hardpoint farther than this from the origin (mm) is read in the wrong units (a vehicle's
#: hardpoints lie within a few metres of its origin)
PLAUSIBLE_MM = 20_000.0
#: every hardpoint of a table (of three or more) within this of the origin (mm): the values are
#: in metres (or another large unit) while the [UNITS] block says mm
IMPLAUSIBLE_MM = 10.0

HARDPOINT_COLUMNS = ("hardpoint_name", "symmetry", "x_value", "y_value", "z_value")
#: symmetry values of a hardpoint row: a pair (left point stored), a single point, or one side
#: of an asymmetric pair (each side its own row)
SYMMETRIES = ("left/right", "single", "left", "right")


@dataclass(frozen=True)
class AdamsHardpoint:
    """A hardpoint of a hardpoint table: ``position_mm`` as stored (ADAMS/Car global frame,
    mm; the left point of a ``left/right`` pair), ``symmetry`` ``left/right``, ``single``, or
    for an asymmetric pair ``left``, ``right`` or ``asymmetric`` (both rows), whose points are
    in ``sides``."""

    name: str
    symmetry: str
    position_mm: tuple[float, float, float]
    line: int
    sides: dict[str, tuple[float, float, float]] = field(default_factory=dict)

    def at(self, side: str) -> np.ndarray:
        """The point on ``side`` (left/right), ADAMS frame, mm: the right point of a pair is the
        Y mirror of the stored left one; a ``single`` point is the same on both sides; an
        asymmetric pair gives each side its own row."""
        p = np.array(self.position_mm, float)
        if self.symmetry == "single":
            return p
        if self.symmetry == "left/right":
            if side == "right":
                p[1] = -p[1]
            return p
        if side not in self.sides:
            raise ConfigError(f"hardpoint '{self.name}' (line {self.line}) has no {side} row "
                              f"(its rows: {', '.join(self.sides)})")
        return np.array(self.sides[side], float)


def _add_hardpoint(points: dict[str, AdamsHardpoint], hp: AdamsHardpoint, fail: Fail) -> None:
    """Add a row: a new name, or the other side of an asymmetric pair; a name given again
    (also in another case: names are looked up case-insensitively) is an error."""
    old = points.get(hp.name)
    if old is None:
        same = next((p for p in points.values() if p.name.lower() == hp.name.lower()), None)
        if same is not None:
            raise fail(hp.line, f"hardpoint '{hp.name}' is '{same.name}' (line {same.line}) "
                       "again: ADAMS/Car hardpoint names are case-insensitive")
        points[hp.name] = hp
        return
    if old.symmetry in ("left", "right") and hp.symmetry in ("left", "right") \
            and old.symmetry != hp.symmetry:
        points[hp.name] = AdamsHardpoint(hp.name, "asymmetric", old.position_mm, old.line,
                                         {**old.sides, **hp.sides})
        return
    raise fail(hp.line, f"hardpoint '{hp.name}' is given twice (first at line {old.line})")


def read_hardpoints(path: str | Path, warnings: list[str] | None = None
                    ) -> dict[str, AdamsHardpoint]:
    """Every row of every ``{hardpoint_name symmetry x_value y_value z_value}`` table of a
    TeimOrbit file (a subsystem ``.sub``, an assembly ``.asy`` or a hardpoint table), converted
    to mm. ``path`` may also be an ADAMS/Car database folder
    (:func:`~elastokin.formats.adams.database.subsystem_file`). What was read tolerantly is
    appended to ``warnings``."""
    f = read_teimorbit(subsystem_file(path))
    if warnings is not None:
        warnings += f.warnings
    points: dict[str, AdamsHardpoint] = {}
    tables = [(block, t) for block in f.blocks for section in (block, *block.sub_blocks)
              for t in section.tables]
    found = [(b, t) for b, t in tables if tuple(c.lower() for c in t.columns) ==
             HARDPOINT_COLUMNS]
    for block, t in found:
        for row, n in zip(t.rows, t.row_lines):
            hp = _row(f, block.name, row, n)
            _add_hardpoint(points, hp, lambda line, msg, b=block.name: f.error(line, b, msg))
    if not found:
        near = [f"{t.header} (line {t.line})" for _, t in tables
                if t.columns and t.columns[0].lower() == HARDPOINT_COLUMNS[0]]
        raise ConfigError(f"{f.path}: no hardpoint table {{{' '.join(HARDPOINT_COLUMNS)}}} in "
                          "any block" + (f"; found {', '.join(near)}" if near else ""))
    _check_units(f, points)
    return points


def _row(f: TeimOrbitFile, block: str, row: tuple, n: int) -> AdamsHardpoint:
    """One table row as a hardpoint (its name, symmetry and numbers checked)."""
    name, sym, *xyz = row
    if not isinstance(name, str) or not name:
        raise f.error(n, block, f"hardpoint name {name!r}: expected a quoted name")
    sym = str(sym).strip().lower()
    if sym not in SYMMETRIES:
        raise f.error(n, block, f"hardpoint '{name}': symmetry {row[1]!r}, expected one of "
                      f"{', '.join(SYMMETRIES)}")
    if not all(isinstance(v, float) and math.isfinite(v) for v in xyz):
        raise f.error(n, block, f"hardpoint '{name}': x y z values must be numbers, got {xyz}")
    sides = {sym: tuple(xyz)} if sym in ("left", "right") else {}
    return AdamsHardpoint(name, sym, tuple(xyz), n, sides)


def _check_units(f: TeimOrbitFile, points: Mapping[str, AdamsHardpoint]) -> None:
    """Hardpoints that no vehicle has: read in the wrong units (:data:`PLAUSIBLE_MM`,
    :data:`IMPLAUSIBLE_MM`)."""
    units = f"LENGTH '{f.units.length}'" if f.units_declared else \
        "no [UNITS] block: ADAMS/Car's default, mm"
    rows = [(p.name, xyz, p.line) for p in points.values()
            for xyz in ([p.position_mm] + list(p.sides.values()))]
    far = max(rows, key=lambda r: max(abs(v) for v in r[1]), default=None)
    if far is not None and max(abs(v) for v in far[1]) > PLAUSIBLE_MM:
        raise f.error(far[2], None, f"hardpoint '{far[0]}' is at {np.round(far[1], 1).tolist()}"
                      f" mm, more than {PLAUSIBLE_MM / 1000:g} m from the origin ({units}): "
                      "a wrong [UNITS] block?")
    if len(points) >= 3 and max(abs(v) for r in rows for v in r[1]) < IMPLAUSIBLE_MM:
        raise f.error(None, None, f"every hardpoint lies within {IMPLAUSIBLE_MM:g} mm of the "
                      f"origin ({units}): values in metres? (give the [UNITS] block's LENGTH)")


def lookup_hardpoint(points: Mapping[str, AdamsHardpoint], name: str, side: str | None,
            where: str) -> tuple[AdamsHardpoint, str | None]:
    """The table row of ``name``: exact, case-insensitive, or ``hpl_/hpr_/hps_`` + name (the
    prefix then gives the side, which must agree with an explicit one)."""
    by_lower = {k.lower(): v for k, v in points.items()}
    if name in points or name.lower() in by_lower:
        return points.get(name) or by_lower[name.lower()], side
    prefix = {"hpl_": "left", "hpr_": "right", "hps_": None}
    for pre, pside in prefix.items():
        base = name[len(pre):]
        if name.lower().startswith(pre) and base.lower() in by_lower:
            if side is not None and pside is not None and side != pside:
                raise ConfigError(f"{where}: '{name}' names the {pside} point but side is "
                                  f"{side}")
            return by_lower[base.lower()], pside or side
    known = ", ".join(sorted(points))
    raise ConfigError(f"{where}: ADAMS hardpoint '{name}' is not in the hardpoint table "
                      f"({len(points)} hardpoints: {known})")
