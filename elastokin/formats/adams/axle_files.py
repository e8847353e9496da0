"""The axle's scalar data in ADAMS/Car files in: a subsystem's ``[PARAMETER]`` block (the
anti-roll bar's torsional rate, the steering's ``rack_ratio`` and travel limit) and elastokin's
curve files (the bar's torque curve, the rack ratio curve).

Pure Python/numpy. A ``[PARAMETER]`` value is in the subsystem's ``[UNITS]`` (ADAMS/Car's
defaults mm, newton, deg without one), converted here by the quantity asked for, except
``rack_ratio``, which ADAMS/Car gives in S.I. whatever the units: rad of steering wheel per
metre of rack travel. Every error names the file, line and block. Conventions:
``docs/adams.md``, "Axles".
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

from elastokin.errors import ConfigError
from elastokin.formats.adams.axle import mm_per_rev
from elastokin.formats.adams.teimorbit import QUANTITY_UNITS, TeimOrbitFile, read_teimorbit
from elastokin.physics.laws import DirectionLaw

__all__ = [
    "PARAMETER_COLUMNS",
    "RACK_MM_PER_REV_RANGE",
    "Parameters",
    "rack_ratio_check",
    "read_curve",
    "read_parameters",
]

PARAMETER_COLUMNS = ("parameter_name", "symmetry", "type", "value")
#: mm of rack travel per steering-wheel revolution a rack and pinion can have (the
#: "c-factor": ~35-60 on cars, ~75-100 on quick racing racks); a ``rack_ratio`` outside gives
#: an error (a value in another unit than rad/m, e.g. deg/mm, rad/mm or m/rad, falls outside)
RACK_MM_PER_REV_RANGE = (5.0, 500.0)


@dataclass(frozen=True)
class Parameters:
    """The ``[PARAMETER]`` rows of a subsystem file: name (lower case) -> (value as written,
    line, description), and the file (for its units and errors)."""

    file: TeimOrbitFile
    rows: dict[str, tuple[float | str, int, str]]

    def value(self, name: str, what: str) -> tuple[float, int]:
        """The number of parameter ``name`` (as written) and its line."""
        row = self.rows.get(name.lower())
        if row is None:
            known = ", ".join(sorted(self.rows)) or "none"
            raise ConfigError(f"{self.file.path}: no [PARAMETER] '{name}' ({what}; the name "
                              f"is the mapping file's; parameters in the file: {known})")
        v, line, _ = row
        if not isinstance(v, float) or not math.isfinite(v):
            raise self.file.error(line, "PARAMETER", f"'{name}' = {v!r}: expected a number "
                                  f"({what})")
        return v, line

    def positive(self, name: str, quantity: str, what: str) -> float:
        """Parameter ``name`` converted from the file's units of ``quantity`` to elastokin's
        (rounded to 12 significant digits); it must be positive."""
        v, line = self.value(name, what)
        unit = QUANTITY_UNITS[quantity][1]
        if not v > 0:
            raise self.file.error(line, "PARAMETER", f"'{name}' = {v:g}: {what} must be "
                                  f"positive ({unit})")
        k = self.file.units.factor(quantity)
        return v if k == 1.0 else float(f"{v * k:.12g}")


def read_parameters(path: str | Path) -> Parameters:
    """Every row of the ``{parameter_name symmetry type value}`` tables of a subsystem file
    (values as written; :meth:`Parameters.positive` converts)."""
    f = read_teimorbit(path)
    rows: dict[str, tuple[float | str, int, str]] = {}
    for block in f.blocks_named("PARAMETER"):
        for t in block.tables:
            if tuple(c.lower() for c in t.columns) != PARAMETER_COLUMNS:
                raise f.error(t.line, block.name, f"table header {t.header}: expected "
                              f"{{{' '.join(PARAMETER_COLUMNS)}}}")
            for i, (row, line) in enumerate(zip(t.rows, t.row_lines)):
                name = str(row[0]).strip().lower()
                if name in rows:
                    raise f.error(line, block.name, f"parameter '{row[0]}' is given twice "
                                  f"(first at line {rows[name][1]})")
                rows[name] = (row[3], line, t.descriptions.get(i, ""))
    return Parameters(f, rows)


def rack_ratio_check(params: Parameters, name: str) -> float:
    """mm of rack per steering-wheel revolution from ADAMS/Car's ``rack_ratio`` (rad/m): it
    must be positive (elastokin finds the pinion's sense itself) and give a rack ratio in
    :data:`RACK_MM_PER_REV_RANGE`."""
    what = "the steering's rack ratio, steering-wheel angle per rack travel in rad/m (S.I.)"
    v, line = params.value(name, what)
    if not v > 0:
        raise params.file.error(line, "PARAMETER", f"'{name}' = {v:g}: {what} must be "
                                "positive (the sense of the pinion is found by elastokin's "
                                "steering load case, not given by the ratio's sign)")
    c = mm_per_rev(v)
    lo, hi = RACK_MM_PER_REV_RANGE
    if not lo <= c <= hi:
        raise params.file.error(line, "PARAMETER", f"'{name}' = {v:g} rad/m gives {c:.4g} mm of "
                                f"rack per steering-wheel revolution, outside {lo:g}..{hi:g}: "
                                f"expected rad/m (S.I., as ADAMS/Car's rack_ratio; 50 mm/rev is "
                                f"{2000.0 * math.pi / 50.0:.4g} rad/m), not another unit")
    return c


def read_curve(path: str | Path, columns: tuple[str, str]) -> tuple[list[float], list[float]]:
    """The ``[CURVE]`` table ``{columns}`` of an elastokin curve file, converted to deg, mm,
    N*mm; it must be an elastokin law (increasing, through (0, 0))."""
    f = read_teimorbit(path)
    block = f.block("CURVE")
    if len(block.tables) != 1:
        raise f.error(block.line, "CURVE", f"expected one table {{{' '.join(columns)}}}, "
                      f"found {len(block.tables)}")
    t = block.tables[0]
    if tuple(c.lower() for c in t.columns) != columns:
        raise f.error(t.line, "CURVE", f"table header {t.header}: expected "
                      f"{{{' '.join(columns)}}}")
    for row, line in zip(t.rows, t.row_lines):
        if not all(isinstance(v, float) and math.isfinite(v) for v in row):
            raise f.error(line, "CURVE", f"row {row}: expected two numbers")
    u, v = [float(r[0]) for r in t.rows], [float(r[1]) for r in t.rows]
    try:
        DirectionLaw(tuple(u), tuple(v))
    except ValueError as exc:
        raise f.error(t.line, "CURVE", f"{exc}") from None
    return u, v
