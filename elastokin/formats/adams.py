"""ADAMS/Car interoperability: TeimOrbit property files in, hardpoint tables and bushings out.

Pure Python/numpy (no Exudyn). The formats, the mapping file and every convention are
documented in ``docs/adams.md``; in short:

- **Reading** (:func:`read_teimorbit`): ``$`` comment lines, ``[BLOCK]`` and ``(SUB_BLOCK)``
  headers, ``KEY = value`` pairs (numbers, quoted strings) and tables (a ``{col1 col2 ...}``
  header line, then one row per line). Values of known quantities (:data:`COLUMN_QUANTITIES`,
  :data:`KEY_QUANTITIES`) are converted on reading, with the file's ``[UNITS]`` block, to
  elastokin's units: mm, N, N*mm, deg (s and kg for damping and mass). Everything remembers the
  line it started on, and every problem raises :class:`~elastokin.errors.ConfigError` naming
  the file, the line and the block.
- **Bushing property files** (``.bus``, :func:`read_bushing`) become a bushing ``stiffness``
  entry of an elastokin config: piecewise-linear curves through (0, 0), strictly increasing,
  extrapolated linearly with the end slopes beyond the table (:mod:`elastokin.laws`).
- **Hardpoint tables** (:func:`read_hardpoints`) are mapped onto an elastokin config through
  a mapping file (:func:`read_mapping`, :func:`apply_hardpoints`). ADAMS/Car's global frame is
  X rearward, Y right, Z up and a ``left/right`` pair stores its left point (Y < 0); the right
  one is its Y mirror. :func:`adams_to_config` / :func:`config_to_adams` convert explicitly to
  and from the config's ``frame``.
- **Export** (:func:`export_adams`): a hardpoint table (ADAMS frame, mm), one ``.bus`` file per
  bushing (mm, newton, degrees), the bushing preloads as ``[BUSHING_ASSEMBLY]`` blocks to paste
  into a subsystem file, and :func:`write_adams_kc_csv` renames the columns of an elastokin
  ``kc.csv`` to ADAMS-style channel names (:data:`KC_CHANNELS`). Writers are deterministic.
"""

from __future__ import annotations

import copy
import csv
import math
import re
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import yaml

from elastokin.config.loading import read_yaml
from elastokin.config.suspension import Suspension
from elastokin.errors import ConfigError
from elastokin.physics.joints import BUSHING_DIRECTIONS
from elastokin.physics.laws import DirectionLaw
from elastokin.physics.pose import euler_zxz_deg
from elastokin.version import __version__

__all__ = [
    "BUSHING_CURVES",
    "COLUMN_QUANTITIES",
    "FRAME_CHANNELS",
    "KC_CHANNELS",
    "KEY_QUANTITIES",
    "QUANTITY_UNITS",
    "UNIT_FACTORS",
    "AdamsHardpoint",
    "AdamsMapping",
    "Block",
    "BushingProperties",
    "Entry",
    "SubBlock",
    "Table",
    "TeimOrbitFile",
    "Units",
    "adams_to_config",
    "apply_bushings",
    "apply_hardpoints",
    "bushing_assembly_text",
    "bushing_file_text",
    "config_to_adams",
    "dump_config",
    "export_adams",
    "hardpoint_table_text",
    "import_adams",
    "kc_to_adams_channels",
    "mapping_text",
    "parse_teimorbit",
    "read_bushing",
    "read_bushing_assemblies",
    "read_hardpoints",
    "read_mapping",
    "read_teimorbit",
    "write_adams_kc_csv",
]

# ----------------------------------------------------------------------------------------------
# Units

_LBF = 4.4482216152605  # N (exact by definition of the pound-force)

#: ADAMS unit names (lower case; spaces read as ``_``) and their factor to the elastokin unit of
#: each base dimension: mm, N, deg, kg, s
UNIT_FACTORS: dict[str, dict[str, float]] = {
    "length": {
        "mm": 1.0, "millimeter": 1.0, "millimetre": 1.0, "cm": 10.0, "centimeter": 10.0,
        "centimetre": 10.0, "meter": 1000.0, "metre": 1000.0, "m": 1000.0, "km": 1.0e6,
        "kilometer": 1.0e6, "kilometre": 1.0e6, "inch": 25.4, "in": 25.4, "foot": 304.8,
        "ft": 304.8, "mile": 1609344.0,
    },
    "force": {
        "newton": 1.0, "n": 1.0, "kilo_newton": 1000.0, "kilonewton": 1000.0, "knewton": 1000.0,
        "kn": 1000.0, "millinewton": 1.0e-3, "centinewton": 1.0e-2, "dyne": 1.0e-5,
        "pound_force": _LBF, "lbf": _LBF, "kpound_force": 1000.0 * _LBF, "kip": 1000.0 * _LBF,
        "ounce_force": _LBF / 16.0, "ozf": _LBF / 16.0, "kilogram_force": 9.80665,
        "kg_force": 9.80665, "kgf": 9.80665, "gram_force": 9.80665e-3,
    },
    "angle": {
        "degrees": 1.0, "degree": 1.0, "deg": 1.0,
        "radians": 180.0 / math.pi, "radian": 180.0 / math.pi, "rad": 180.0 / math.pi,
    },
    "mass": {
        "kg": 1.0, "kilogram": 1.0, "gram": 1.0e-3, "g": 1.0e-3, "tonne": 1000.0,
        "megagram": 1000.0, "pound_mass": 0.45359237, "lbm": 0.45359237,
        "kpound_mass": 453.59237, "ounce_mass": 0.45359237 / 16.0, "slug": _LBF / 0.3048,
    },
    "time": {
        "second": 1.0, "sec": 1.0, "s": 1.0, "millisecond": 1.0e-3, "msec": 1.0e-3,
        "ms": 1.0e-3, "minute": 60.0, "min": 60.0, "hour": 3600.0, "hr": 3600.0, "h": 3600.0,
    },
}

_DIMENSIONS = ("length", "force", "angle", "mass", "time")

#: derived quantities: exponents of (length, force, angle, mass, time) and the elastokin unit
QUANTITY_UNITS: dict[str, tuple[tuple[int, int, int, int, int], str]] = {
    "length": ((1, 0, 0, 0, 0), "mm"),
    "force": ((0, 1, 0, 0, 0), "N"),
    "angle": ((0, 0, 1, 0, 0), "deg"),
    "mass": ((0, 0, 0, 1, 0), "kg"),
    "time": ((0, 0, 0, 0, 1), "s"),
    "torque": ((1, 1, 0, 0, 0), "N*mm"),
    "velocity": ((1, 0, 0, 0, -1), "mm/s"),
    "angular_velocity": ((0, 0, 1, 0, -1), "deg/s"),
    "damping": ((-1, 1, 0, 0, 1), "N*s/mm"),
    "rotational_damping": ((1, 1, -1, 0, 1), "N*mm*s/deg"),
}

#: table columns of a known quantity (lower-case names), converted on reading
COLUMN_QUANTITIES: dict[str, str] = {
    "disp": "length", "force": "force", "rot": "angle", "torque": "torque",
    "x_value": "length", "y_value": "length", "z_value": "length",
    "radius": "length", "width": "length", "vel": "velocity", "velocity": "velocity",
}

#: ``KEY = value`` entries of a known quantity (upper-case names), converted on reading;
#: keys of the ``[DAMPING]`` block are classified by :func:`_damping_quantity`
KEY_QUANTITIES: dict[str, str] = {
    **{f"T_PRELOAD_{a}": "force" for a in "XYZ"},
    **{f"R_PRELOAD_{a}": "torque" for a in "XYZ"},
    **{f"T_OFFSET_{a}": "length" for a in "XYZ"},
    **{f"R_OFFSET_{a}": "angle" for a in "XYZ"},
    "GEOMETRY_LENGTH": "length", "GEOMETRY_RADIUS": "length",
}


def _damping_quantity(key: str) -> str | None:
    """Translational damping (FX.., CX.., TRANS..) or rotational (TX.., CTX.., ROT..)."""
    k = key.upper()
    if re.match(r"^(F[XYZ]|C[XYZ]|TRANS)", k):
        return "damping"
    if re.match(r"^(T[XYZ]|CT[XYZ]|ROT)", k):
        return "rotational_damping"
    return None


def _unit_key(name: str) -> str:
    return re.sub(r"\s+", "_", str(name).strip().lower())


@dataclass(frozen=True)
class Units:
    """The ``[UNITS]`` of a TeimOrbit file (ADAMS names as written in the file)."""

    length: str = "mm"
    force: str = "newton"
    angle: str = "degrees"
    mass: str = "kg"
    time: str = "second"

    def factor(self, quantity: str) -> float:
        """Multiplier from this file's unit of ``quantity`` to elastokin's."""
        exponents, _ = QUANTITY_UNITS[quantity]
        f = 1.0
        for dim, e in zip(_DIMENSIONS, exponents):
            if e:
                f *= UNIT_FACTORS[dim][_unit_key(getattr(self, dim))] ** e
        return f


# ----------------------------------------------------------------------------------------------
# TeimOrbit reader


@dataclass
class Entry:
    """``KEY = value``; ``unit`` is the elastokin unit the value was converted to (None: not a
    known quantity, kept as read)."""

    key: str
    value: float | str
    line: int
    unit: str | None = None


@dataclass
class Table:
    """A ``{col1 col2 ...}`` table: ``rows`` of numbers (converted) or strings (unquoted).
    ``units`` holds per column the elastokin unit it was converted to (None: kept as read)."""

    columns: tuple[str, ...]
    line: int
    rows: list[tuple] = field(default_factory=list)
    row_lines: list[int] = field(default_factory=list)
    units: tuple[str | None, ...] = ()

    def column(self, name: str) -> list:
        i = [c.lower() for c in self.columns].index(name.lower())
        return [r[i] for r in self.rows]

    @property
    def header(self) -> str:
        return "{" + " ".join(self.columns) + "}"


@dataclass
class SubBlock:
    """A ``(SUB_BLOCK)`` inside a block: entries and tables up to the next header."""

    name: str
    line: int
    entries: dict[str, Entry] = field(default_factory=dict)
    tables: list[Table] = field(default_factory=list)


@dataclass
class Block:
    """A ``[BLOCK]``: entries and tables before its first sub-block, then its sub-blocks."""

    name: str
    line: int
    entries: dict[str, Entry] = field(default_factory=dict)
    tables: list[Table] = field(default_factory=list)
    sub_blocks: list[SubBlock] = field(default_factory=list)

    def value(self, key: str, default=None):
        e = self.entries.get(key.upper())
        return default if e is None else e.value


@dataclass
class TeimOrbitFile:
    """A parsed TeimOrbit file; ``blocks`` in file order (a name may repeat, as
    ``[BUSHING_ASSEMBLY]`` does in a subsystem file)."""

    path: str
    blocks: list[Block]
    units: Units = Units()
    units_declared: bool = False

    def blocks_named(self, name: str) -> list[Block]:
        return [b for b in self.blocks if b.name == name.upper()]

    def block(self, name: str) -> Block:
        """The one block called ``name``; ConfigError when it is missing or repeated."""
        found = self.blocks_named(name)
        if not found:
            raise ConfigError(f"{self.path}: block [{name.upper()}] is missing")
        if len(found) > 1:
            raise ConfigError(f"{self.path}, line {found[1].line}: block [{name.upper()}] "
                              f"appears again (first at line {found[0].line}); expected once")
        return found[0]

    def error(self, line: int | None, block: str | None, msg: str) -> ConfigError:
        return _error(self.path, line, block, msg)


def _error(path: str, line: int | None, block: str | None, msg: str) -> ConfigError:
    where = f"{path}" + (f", line {line}" if line else "") + (f", block [{block}]" if block
                                                               else "")
    return ConfigError(f"{where}: {msg}")


_NUMBER = re.compile(r"^[+-]?(\d+\.?\d*|\.\d+)([eEdD][+-]?\d+)?$")
_NAME = r"[A-Za-z_][A-Za-z0-9_]*"


def _strip_comment(text: str) -> tuple[str, str | None]:
    """The text before an unquoted ``$``; the second item names an unclosed quote."""
    quote = None
    for i, ch in enumerate(text):
        if quote:
            if ch == quote:
                quote = None
        elif ch in "'\"":
            quote = ch
        elif ch == "$":
            return text[:i], None
    return text, quote


def _tokens(text: str) -> list[tuple[str, bool]]:
    """Whitespace-separated tokens, quoted strings kept whole: (text, was_quoted)."""
    return [(m.group(1) if m.group(1) is not None else m.group(2) if m.group(2) is not None
             else m.group(3), m.group(3) is None)
            for m in re.finditer(r"'([^']*)'|\"([^\"]*)\"|(\S+)", text)]


def _value(token: str, quoted: bool) -> float | str:
    if quoted:
        return token.strip()
    if _NUMBER.match(token):
        return float(token.replace("d", "e").replace("D", "e"))
    return token


def parse_teimorbit(text: str, path: str = "<text>") -> TeimOrbitFile:
    """Parse TeimOrbit text into blocks, sub-blocks, entries and tables (no unit conversion).

    Errors name ``path``, the line and the block."""
    blocks: list[Block] = []
    block: Block | None = None
    section: Block | SubBlock | None = None
    table: Table | None = None
    for n, raw in enumerate(text.splitlines(), start=1):
        bname = block.name if block else None
        line, open_quote = _strip_comment(raw)
        if open_quote:
            raise _error(path, n, bname, f"unclosed quote {open_quote} in {raw.strip()!r}")
        line = line.strip()
        if not line:
            continue
        if line.startswith("["):
            m = re.fullmatch(rf"\[\s*({_NAME})\s*\]", line)
            if not m:
                raise _error(path, n, bname, f"malformed block header {line!r} (expected "
                             "[NAME])")
            block = Block(m.group(1).upper(), n)
            blocks.append(block)
            section, table = block, None
            continue
        if block is None:
            raise _error(path, n, None, f"{line!r} comes before the first [BLOCK] header")
        if line.startswith("("):
            m = re.fullmatch(rf"\(\s*({_NAME})\s*\)", line)
            if not m:
                raise _error(path, n, bname, f"malformed sub-block header {line!r} (expected "
                             "(NAME))")
            section = SubBlock(m.group(1).upper(), n)
            block.sub_blocks.append(section)
            table = None
            continue
        if line.startswith("{"):
            if not line.endswith("}") or line.count("}") != 1:
                raise _error(path, n, bname, f"unclosed table header {line!r}: expected "
                             "'{col1 col2 ...}' on one line")
            columns = tuple(line[1:-1].split())
            if not columns:
                raise _error(path, n, bname, "table header '{}' names no columns")
            table = Table(columns, n)
            section.tables.append(table)
            continue
        m = re.fullmatch(rf"({_NAME})\s*=\s*(.*)", line)
        if m:
            table = None
            toks = _tokens(m.group(2))
            if len(toks) != 1:
                raise _error(path, n, bname, f"{m.group(1)} = ...: expected one value (a "
                             f"number or a 'quoted string'), got {m.group(2)!r}")
            key = m.group(1).upper()
            if key in section.entries:
                raise _error(path, n, bname, f"{key} is given twice (first at line "
                             f"{section.entries[key].line})")
            section.entries[key] = Entry(key, _value(*toks[0]), n)
            continue
        if table is None:
            raise _error(path, n, bname, f"unrecognised line {line!r} (expected a [BLOCK], "
                         "(SUB_BLOCK), KEY = value, {table header}, a table row or a $ comment)")
        row = tuple(_value(t, q) for t, q in _tokens(line))
        if len(row) != len(table.columns):
            raise _error(path, n, bname, f"row has {len(row)} values but the table "
                         f"{table.header} (line {table.line}) has {len(table.columns)} columns")
        table.rows.append(row)
        table.row_lines.append(n)
    return TeimOrbitFile(path, blocks)


def read_teimorbit(path: str | Path, convert: bool = True) -> TeimOrbitFile:
    """Read a TeimOrbit file; with ``convert`` the values of known quantities are converted
    to elastokin units (mm, N, N*mm, deg, kg, s) with the file's ``[UNITS]`` block (ADAMS/Car's
    defaults mm, newton, degrees, kg, second when the file has none)."""
    p = Path(path)
    try:
        text = p.read_text(encoding="utf-8-sig", errors="strict")
    except OSError as exc:
        raise ConfigError(f"{p}: cannot read file ({exc.strerror})") from None
    except UnicodeDecodeError as exc:
        raise ConfigError(f"{p}: not a text file (byte {exc.start} is not UTF-8)") from None
    f = parse_teimorbit(text, str(p))
    units_blocks = f.blocks_named("UNITS")
    if units_blocks:
        f.units = _units(f, f.block("UNITS"))
        f.units_declared = True
    if convert:
        _convert(f)
    return f


def _units(f: TeimOrbitFile, block: Block) -> Units:
    given = {}
    for key, e in block.entries.items():
        dim = key.lower()
        if dim not in UNIT_FACTORS:
            raise f.error(e.line, "UNITS", f"unknown unit kind {key} (expected LENGTH, FORCE, "
                          "ANGLE, MASS, TIME)")
        if _unit_key(e.value) not in UNIT_FACTORS[dim]:
            raise f.error(e.line, "UNITS", f"unknown {dim} unit {e.value!r} (known: "
                          f"{', '.join(UNIT_FACTORS[dim])})")
        given[dim] = str(e.value)
    return Units(**given)


def _scaled(value: float, factor: float) -> float:
    """``value * factor``, rounded to 12 significant digits when the factor is not 1 (drops the
    binary noise of factors such as 180/pi; far below the precision of any property file)."""
    return value if factor == 1.0 else float(f"{value * factor:.12g}")


def _convert(f: TeimOrbitFile) -> None:
    for block in f.blocks:
        if block.name == "UNITS":
            continue
        for section in (block, *block.sub_blocks):
            for key, e in section.entries.items():
                q = (_damping_quantity(key) if block.name == "DAMPING"
                     else KEY_QUANTITIES.get(key))
                if q is None:
                    continue
                if not isinstance(e.value, float):
                    raise f.error(e.line, block.name, f"{key} = {e.value!r}: expected a number "
                                  f"({q})")
                e.value = _scaled(e.value, f.units.factor(q))
                e.unit = QUANTITY_UNITS[q][1]
            for t in section.tables:
                qs = [COLUMN_QUANTITIES.get(c.lower()) for c in t.columns]
                factors = [None if q is None else f.units.factor(q) for q in qs]
                for i, (row, n) in enumerate(zip(t.rows, t.row_lines)):
                    new = list(row)
                    for j, k in enumerate(factors):
                        if k is None:
                            continue
                        if not isinstance(row[j], float):
                            raise f.error(n, block.name, f"column {t.columns[j]} of "
                                          f"{t.header}: {row[j]!r} is not a number")
                        new[j] = _scaled(row[j], k)
                    t.rows[i] = tuple(new)
                t.units = tuple(None if q is None else QUANTITY_UNITS[q][1] for q in qs)


# ----------------------------------------------------------------------------------------------
# Bushing property files

#: elastokin direction, ADAMS curve block, its table columns
BUSHING_CURVES: tuple[tuple[str, str, tuple[str, str]], ...] = (
    ("x", "FX_CURVE", ("disp", "force")),
    ("y", "FY_CURVE", ("disp", "force")),
    ("z", "FZ_CURVE", ("disp", "force")),
    ("rx", "TX_CURVE", ("rot", "torque")),
    ("ry", "TY_CURVE", ("rot", "torque")),
    ("rz", "TZ_CURVE", ("rot", "torque")),
)


@dataclass(frozen=True)
class BushingProperties:
    """A ``.bus`` file in elastokin form.

    ``stiffness``: a bushing ``stiffness`` entry of an elastokin config, per direction
    ``{"deflection": [...], "load": [...]}`` in mm -> N (x, y, z) and deg -> N*mm (rx, ry, rz),
    bushing frame. ``damping``: the ``[DAMPING]`` constants as (value, elastokin unit); elastokin
    is quasi-static and does not use them.
    """

    path: str
    stiffness: dict[str, dict[str, list[float]]]
    damping: dict[str, tuple[float, str | None]]
    units: Units
    warnings: tuple[str, ...] = ()

    def laws(self) -> tuple[DirectionLaw, ...]:
        return tuple(DirectionLaw(tuple(self.stiffness[d]["deflection"]),
                                  tuple(self.stiffness[d]["load"])) for d in BUSHING_DIRECTIONS)


def read_bushing(path: str | Path) -> BushingProperties:
    """Read a bushing property file (``.bus``) into an elastokin bushing stiffness.

    Each of ``[FX_CURVE]`` ... ``[TZ_CURVE]`` must hold one table ``{disp force}`` (or
    ``{rot torque}``) of at least two rows, strictly increasing in deflection and in load and
    through (0, 0) (the law elastokin inverts; a load at zero deflection is a preload, given in
    the bushing assembly). Beyond the table elastokin extrapolates linearly with the end slopes.
    """
    f = read_teimorbit(path)
    warnings = []
    stiffness = {}
    for direction, name, columns in BUSHING_CURVES:
        block = f.block(name)
        tables = block.tables + [t for sb in block.sub_blocks for t in sb.tables]
        if len(tables) != 1:
            raise f.error(block.line, name, f"expected one table {{{' '.join(columns)}}}, "
                          f"found {len(tables)}")
        t = tables[0]
        if tuple(c.lower() for c in t.columns) != columns:
            raise f.error(t.line, name, f"table header {t.header}: expected "
                          f"{{{' '.join(columns)}}}")
        if len(t.rows) < 2:
            raise f.error(t.line, name, f"table {t.header} has {len(t.rows)} rows; a curve "
                          "needs at least two (an empty or unclosed table?)")
        for row, n in zip(t.rows, t.row_lines):
            for v, c in zip(row, t.columns):
                if not isinstance(v, float) or not math.isfinite(v):
                    raise f.error(n, name, f"{c} {v!r} is not a finite number")
        what = {"disp": "deflection", "rot": "rotation"}[columns[0]]
        u = np.array(t.column(columns[0]))
        load = np.array(t.column(columns[1]))
        unit_u, unit_f = t.units
        for i in range(1, len(u)):
            if u[i] <= u[i - 1]:
                raise f.error(t.row_lines[i], name, f"{what} {u[i]:.6g} {unit_u} does not "
                              f"increase on {u[i - 1]:.6g} {unit_u} (line {t.row_lines[i - 1]}):"
                              " the curve must be monotonic in deflection")
        for i in range(1, len(u)):
            if load[i] <= load[i - 1]:
                raise f.error(t.row_lines[i], name, f"{columns[1]} {load[i]:.6g} {unit_f} does "
                              f"not increase on {load[i - 1]:.6g} {unit_f} (line "
                              f"{t.row_lines[i - 1]}): elastokin needs a strictly increasing "
                              "(invertible) law")
        law_at_zero = _at_zero(u, load)
        if abs(law_at_zero) > 1e-9 * np.max(np.abs(load)):
            zero = np.flatnonzero(u == 0.0)
            if zero.size:
                line = t.row_lines[zero[0]]
                rows = f"line {line}"
            else:
                i = int(np.clip(np.searchsorted(u, 0.0), 1, len(u) - 1))
                line = t.row_lines[i - 1]
                rows = f"extrapolated from lines {line} and {t.row_lines[i]}"
            raise f.error(line, name, f"the curve gives "
                          f"{law_at_zero:.6g} {unit_f} at zero {what} ({rows}); it must "
                          "pass through (0, 0): give a load at zero deflection as the preload "
                          "(T_PRELOAD / R_PRELOAD) of the bushing assembly")
        try:
            DirectionLaw(tuple(u), tuple(load))
        except ValueError as exc:  # pragma: no cover - the checks above are the law's
            raise f.error(t.line, name, str(exc)) from None
        stiffness[direction] = {"deflection": [_clean(x) for x in u],
                                "load": [_clean(x) for x in load]}
    damping = {}
    for block in f.blocks_named("DAMPING"):
        for key, e in block.entries.items():
            damping[key] = (e.value, e.unit)
            if e.unit is None:
                warnings.append(f"{f.path}, line {e.line}, block [DAMPING]: {key} kept as read "
                                "(not a known damping key: unit not converted)")
        if block.tables:
            warnings.append(f"{f.path}, line {block.tables[0].line}, block [DAMPING]: damping "
                            "tables are not read (elastokin is quasi-static)")
    return BushingProperties(f.path, stiffness, damping, f.units, tuple(warnings))


def _at_zero(u: np.ndarray, load: np.ndarray) -> float:
    """The piecewise-linear law at zero deflection, extrapolated with the end slopes."""
    if u[0] <= 0.0 <= u[-1]:
        return float(np.interp(0.0, u, load))
    i = 0 if u[0] > 0 else len(u) - 2
    return float(load[i] + (load[i + 1] - load[i]) / (u[i + 1] - u[i]) * (0.0 - u[i]))


def _clean(x: float) -> float:
    """A plain float, without the sign of a negative zero."""
    x = float(x)
    return 0.0 if x == 0.0 else x


# ----------------------------------------------------------------------------------------------
# Hardpoints, frames and the mapping file

HARDPOINT_COLUMNS = ("hardpoint_name", "symmetry", "x_value", "y_value", "z_value")
SYMMETRIES = ("left/right", "single")


@dataclass(frozen=True)
class AdamsHardpoint:
    """A row of a hardpoint table: ``position_mm`` as stored (ADAMS/Car global frame, mm; the
    left point of a ``left/right`` pair)."""

    name: str
    symmetry: str
    position_mm: tuple[float, float, float]
    line: int

    def at(self, side: str) -> np.ndarray:
        """The point on ``side`` (left/right), ADAMS frame, mm: the right point of a pair is the
        Y mirror of the stored left one; a ``single`` point is the same on both sides."""
        p = np.array(self.position_mm, float)
        if self.symmetry == "left/right" and side == "right":
            p[1] = -p[1]
        return p


def read_hardpoints(path: str | Path) -> dict[str, AdamsHardpoint]:
    """Every row of every ``{hardpoint_name symmetry x_value y_value z_value}`` table of a
    TeimOrbit file (a subsystem ``.sub`` or a hardpoint table), converted to mm."""
    f = read_teimorbit(path)
    points: dict[str, AdamsHardpoint] = {}
    found = False
    for block in f.blocks:
        for section in (block, *block.sub_blocks):
            for t in section.tables:
                if tuple(c.lower() for c in t.columns) != HARDPOINT_COLUMNS:
                    continue
                found = True
                for row, n in zip(t.rows, t.row_lines):
                    name, sym, *xyz = row
                    if not isinstance(name, str) or not name:
                        raise f.error(n, block.name, f"hardpoint name {name!r}: expected a "
                                      "quoted name")
                    sym = str(sym).strip().lower()
                    if sym not in SYMMETRIES:
                        raise f.error(n, block.name, f"hardpoint '{name}': symmetry {row[1]!r},"
                                      " expected 'left/right' or 'single'")
                    if not all(isinstance(v, float) and math.isfinite(v) for v in xyz):
                        raise f.error(n, block.name, f"hardpoint '{name}': x y z values must "
                                      f"be numbers, got {xyz}")
                    if name in points:
                        raise f.error(n, block.name, f"hardpoint '{name}' is given twice "
                                      f"(first at line {points[name].line})")
                    points[name] = AdamsHardpoint(name, sym, tuple(xyz), n)
    if not found:
        raise ConfigError(f"{f.path}: no hardpoint table "
                          f"{{{' '.join(HARDPOINT_COLUMNS)}}} in any block")
    return points


def _frame_signs(frame) -> np.ndarray:
    """Diagonal of the (self-inverse) map between the config frame and ADAMS/Car's."""
    if isinstance(frame, Mapping):
        x, y = frame.get("x"), frame.get("y")
    else:
        x, y = getattr(frame, "x", None), getattr(frame, "y", None)
    if (x, y) == ("rearward", "right"):
        return np.array([1.0, 1.0, 1.0])
    if (x, y) == ("forward", "left"):
        return np.array([-1.0, -1.0, 1.0])
    raise ConfigError(f"frame x {x} / y {y}: expected x rearward, y right (ADAMS/Car) or x "
                      "forward, y left (ISO 8855), z up")


def adams_to_config(point, frame) -> np.ndarray:
    """A point (mm) or direction from ADAMS/Car's global frame (X rearward, Y right, Z up) to
    the config frame ``frame`` (``{x: rearward|forward, y: right|left}``, same origin)."""
    return _frame_signs(frame) * np.asarray(point, float)


def config_to_adams(point, frame) -> np.ndarray:
    """A point (mm) or direction from the config frame ``frame`` to ADAMS/Car's global frame."""
    return _frame_signs(frame) * np.asarray(point, float)


@dataclass(frozen=True)
class AdamsMapping:
    """A mapping file: elastokin hardpoint -> (ADAMS hardpoint, side or None for the default);
    elastokin bushing -> ``.bus`` file (resolved against the mapping file's folder)."""

    path: str
    side: str | None
    hardpoints: dict[str, tuple[str, str | None]]
    bushings: dict[str, Path]


_MAPPING_KEYS = ("elastokin_adams_mapping", "side", "hardpoints", "bushings")


def read_mapping(path: str | Path) -> AdamsMapping:
    """Read a mapping file (YAML, see ``docs/adams.md``)."""
    data, _ = read_yaml(path)
    p = str(path)

    def fail(key: str, msg: str) -> ConfigError:
        return ConfigError(f"{p}: key '{key}': {msg}")

    for key in data:
        if key not in _MAPPING_KEYS:
            raise fail(str(key), f"unknown key (expected {', '.join(_MAPPING_KEYS)})")
    if data.get("elastokin_adams_mapping") != 1:
        raise fail("elastokin_adams_mapping", "expected 1 (the mapping file format version)")
    side = data.get("side")
    if side not in (None, "left", "right"):
        raise fail("side", f"expected left or right, got {side!r}")
    hps = data.get("hardpoints")
    if not isinstance(hps, dict) or not hps:
        raise fail("hardpoints", "expected a mapping 'elastokin name: ADAMS name'")
    hardpoints = {}
    for name, spec in hps.items():
        key = f"hardpoints.{name}"
        hp_side = None
        if isinstance(spec, dict):
            extra = set(spec) - {"adams", "side"}
            if extra:
                raise fail(f"{key}.{sorted(extra)[0]}", "unknown key (expected adams, side)")
            hp_side = spec.get("side")
            if hp_side not in (None, "left", "right"):
                raise fail(f"{key}.side", f"expected left or right, got {hp_side!r}")
            spec = spec.get("adams")
        if not isinstance(spec, str) or not spec.strip():
            raise fail(key, "expected an ADAMS hardpoint name or {adams: NAME, side: left|right}")
        hardpoints[str(name)] = (spec.strip(), hp_side)
    bus = data.get("bushings") or {}
    if not isinstance(bus, dict):
        raise fail("bushings", "expected a mapping 'elastokin bushing: FILE.bus'")
    bushings = {}
    for name, file in bus.items():
        if not isinstance(file, str) or not file.strip():
            raise fail(f"bushings.{name}", "expected a .bus file name")
        bushings[str(name)] = Path(path).parent / file.strip()
    return AdamsMapping(p, side, hardpoints, bushings)


def _lookup(points: Mapping[str, AdamsHardpoint], name: str, side: str | None,
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


def apply_hardpoints(config: dict, points: Mapping[str, AdamsHardpoint],
                     mapping: AdamsMapping, source: str = "template config"
                     ) -> tuple[dict, list[str]]:
    """A copy of ``config`` (an elastokin config dict) whose mapped ``hardpoints`` are the ADAMS
    points: the side chosen (hardpoint's, else mapping's, else the config's ``side``), then
    converted from the ADAMS frame to the config's ``frame``. ``source`` names the config in
    errors. Returns (config, warnings)."""
    cfg = copy.deepcopy(config)
    if not isinstance(cfg.get("hardpoints"), dict):
        raise ConfigError(f"{source}: key 'hardpoints': expected a mapping")
    if not isinstance(cfg.get("frame"), dict) or cfg.get("side") not in ("left", "right"):
        raise ConfigError(f"{source}: keys 'frame' and 'side' (left or right) are needed to "
                          "place the ADAMS hardpoints")
    default_side = mapping.side or cfg["side"]
    warnings = []
    for name, (adams_name, side) in mapping.hardpoints.items():
        where = f"{mapping.path}: key 'hardpoints.{name}'"
        if name not in cfg["hardpoints"]:
            raise ConfigError(f"{where}: '{name}' is not a hardpoint of {source} "
                              f"({', '.join(cfg['hardpoints'])})")
        hp, side = _lookup(points, adams_name, side, where)
        side = side or default_side
        if hp.symmetry == "left/right" and side != cfg["side"]:
            warnings.append(f"{where}: takes the {side} point of '{hp.name}' for a "
                            f"{cfg['side']} corner")
        p = adams_to_config(hp.at(side), cfg["frame"])
        cfg["hardpoints"][name] = [_clean(v) for v in p]
    unmapped = [n for n in cfg["hardpoints"] if n not in mapping.hardpoints]
    if unmapped:
        warnings.append(f"{mapping.path}: template hardpoints not in the mapping, kept as they "
                        f"were: {', '.join(unmapped)}")
    return cfg, warnings


def apply_bushings(config: dict, bushings: Mapping[str, BushingProperties],
                   source: str = "template config") -> dict:
    """A copy of ``config`` with the ``stiffness`` of each named bushing replaced (``source``
    names the config in errors)."""
    cfg = copy.deepcopy(config)
    conns = cfg.get("connections") or {}
    for name, props in bushings.items():
        spec = conns.get(name)
        if not isinstance(spec, dict) or spec.get("type") != "bushing":
            names = [n for n, c in conns.items() if isinstance(c, dict)
                     and c.get("type") == "bushing"]
            raise ConfigError(f"{props.path}: given for '{name}', which is not a bushing of "
                              f"{source} (bushings: {', '.join(names) or 'none'})")
        spec["stiffness"] = copy.deepcopy(props.stiffness)
    return cfg


def import_adams(template: dict, hardpoints_file: str | Path, mapping_file: str | Path,
                 bushing_files: Mapping[str, str | Path] | None = None,
                 source: str = "template config") -> tuple[dict, list[str]]:
    """An elastokin config dict: ``template`` with its hardpoints taken from an ADAMS hardpoint
    table through a mapping file, and the stiffness of the named bushings from ``.bus`` files
    (the mapping file's ``bushings``, overridden by ``bushing_files``). Not yet validated: pass
    it to :func:`elastokin.config.suspension_from_dict`. ``source`` names the template in
    errors. Returns (config, warnings)."""
    mapping = read_mapping(mapping_file)
    cfg, warnings = apply_hardpoints(template, read_hardpoints(hardpoints_file), mapping,
                                     source)
    files = {**mapping.bushings, **{k: Path(v) for k, v in (bushing_files or {}).items()}}
    props = {name: read_bushing(file) for name, file in files.items()}
    for p in props.values():
        warnings += p.warnings
    return apply_bushings(cfg, props, source), warnings


def dump_config(config: dict, header: str, flow: bool | None = None) -> str:
    """A config dict as YAML text with a ``#`` comment header (deterministic); ``flow`` as
    PyYAML's ``default_flow_style`` (None: lists of numbers inline)."""
    text = yaml.safe_dump(config, sort_keys=False, default_flow_style=flow, width=100)
    return "".join(f"# {ln}\n".replace("# \n", "#\n") for ln in header.splitlines()) + text


# ----------------------------------------------------------------------------------------------
# Writers (deterministic: the same input gives the same bytes)

_UNITS_BLOCK = ("[UNITS]", " LENGTH  =  'mm'", " FORCE  =  'newton'", " ANGLE  =  'degrees'",
                " MASS  =  'kg'", " TIME  =  'second'")


def _num(x: float) -> str:
    """Shortest text that reads back as the same float; no negative zero."""
    return repr(_clean(x))


def _rule(name: str) -> str:
    return "$" + name.rjust(79, "-")


def _quoted(s: str, width: int = 0) -> str:
    return f"'{s}'".ljust(width)


def _provenance(s: Suspension) -> str:
    return f"$ elastokin {__version__}: '{s.name}' (config sha256 {s.sha256[:12]})"


def _safe_name(name: str) -> str:
    return re.sub(r"[^A-Za-z0-9_.-]", "_", name)


def hardpoint_table_text(s: Suspension) -> str:
    """A TeimOrbit hardpoint table: every config hardpoint as a ``left/right`` row, converted to
    the ADAMS/Car frame (X rearward, Y right, Z up), mm; the left point is stored (a right
    corner is mirrored)."""
    width = max([len(n) for n in s.hardpoints] + [14]) + 4
    lines = [_provenance(s),
             "$ ADAMS/Car global frame (X rearward, Y right, Z up), mm; 'left/right' rows store",
             f"$ the left point (Y < 0); this config is a {s.side} corner"
             + (" (mirrored to the left)." if s.side == "right" else "."),
             _rule("MDI_HEADER"), "[MDI_HEADER]", " FILE_TYPE  =  'sub'",
             " FILE_VERSION  =  4.0", " FILE_FORMAT  =  'ASCII'",
             _rule("UNITS"), *_UNITS_BLOCK, _rule("HARDPOINT"), "[HARDPOINT]",
             "{" + "hardpoint_name".ljust(width - 1) + "symmetry      "
             + "".join(c.rjust(22) for c in ("x_value", "y_value", "z_value")) + "}"]
    for name, p in s.hardpoints.items():
        q = config_to_adams(p, s.frame)
        if s.side == "right":
            q[1] = -q[1]
        lines.append(" " + _quoted(name, width - 1) + _quoted("left/right", 14)
                     + "".join(_num(v).rjust(22) for v in q))
    return "\n".join(lines) + "\n"


def _curve_points(law: DirectionLaw, half_range: float) -> tuple[list[float], list[float]]:
    """Table points of a law: a linear rate as 5 points over +-half_range; a curve as given,
    extended with its end slopes to +-half_range when the table is narrower."""
    if law.is_linear and len(law.deflection) == 2:
        k = law.slopes[0]
        u = [-half_range, -half_range / 2, 0.0, half_range / 2, half_range]
        return u, [k * x for x in u]
    u, f = list(law.deflection), list(law.load)
    if u[0] > -half_range:
        u.insert(0, -half_range)
        f.insert(0, float(law(-half_range)))
    if u[-1] < half_range:
        u.append(half_range)
        f.append(float(law(half_range)))
    return u, f


def bushing_file_text(s: Suspension, bushing: str, range_mm: float = 10.0,
                      range_deg: float = 10.0) -> str:
    """A ``.bus`` bushing property file (mm, newton, degrees) with the six curves of a bushing:
    a linear rate as a straight table over +-``range_mm`` / +-``range_deg``, a curve as given
    (extended with its end slopes to that range when narrower). Damping: zero."""
    b = next(x for x in s.bushings if x.name == bushing)
    lines = [_provenance(s),
             f"$ bushing {b.name}: {b.parts[0]} -> {b.parts[1]}; curves in the bushing frame "
             "(z axial, x main radial),",
             "$ mm -> N and deg -> N*mm; beyond a table elastokin extrapolates linearly with the "
             "end slopes.",
             _rule("MDI_HEADER"), "[MDI_HEADER]", " FILE_TYPE  =  'bus'", " FILE_VERSION  =  4.0",
             " FILE_FORMAT  =  'ASCII'", " (COMMENTS)", " {comment_string}",
             " '" + f"elastokin bushing {b.name} of {s.name}".replace("'", "`") + "'",
             _rule("UNITS"), *_UNITS_BLOCK,
             _rule("SHAPE"), "[SHAPE]",
             "$ graphics only: nominal sleeve (elastokin has no bushing geometry)",
             "{radius      width}", " 25.0        50.0", " 25.0        50.0",
             _rule("DAMPING"), "[DAMPING]",
             "$ elastokin is quasi-static: no damping"]
    lines += [f" {k}_DAMPING  =  0.0" for k in ("FX", "FY", "FZ", "TX", "TY", "TZ")]
    for (direction, name, columns), law in zip(BUSHING_CURVES, b.laws):
        rng = range_mm if direction in ("x", "y", "z") else range_deg
        u, f = _curve_points(law, rng)
        lines += [_rule(name), f"[{name}]", "{" + columns[0].rjust(21) + columns[1].rjust(24)
                  + "}"]
        lines += [" " + _num(a).rjust(21) + _num(c).rjust(24) for a, c in zip(u, f)]
    return "\n".join(lines) + "\n"


def bushing_assembly_text(s: Suspension, preload: Mapping[str, Iterable[float]],
                          property_files: Mapping[str, str] | None = None) -> str:
    """``[BUSHING_ASSEMBLY]`` blocks (mm, newton, degrees) to paste into a subsystem file.

    ``T_PRELOAD_*`` (N) / ``R_PRELOAD_*`` (N*mm) are the loads each bushing carries at the
    design position, bushing frame (elastokin's +K*u convention): the force and torque on
    ``parts[0]`` (ADAMS I marker) when ``parts[1]`` (J marker) is not deflected from it."""
    lines = [_provenance(s),
             "$ Bushing assemblies to paste into the subsystem file (.sub). Preloads: loads "
             "carried at the",
             "$ design position (the hardpoints), in the bushing frame, on the I part (first "
             "part); with",
             "$ them the hardpoints are the static equilibrium under the design wheel load "
             f"({s.design.wheel_load_N:g} N).",
             "$ Locations and orientations (body-313 Euler angles of the bushing frame) in the "
             "ADAMS/Car",
             "$ global frame (X rearward, Y right, Z up), mm and deg.",
             _rule("UNITS"), *_UNITS_BLOCK]
    signs = np.diag(_frame_signs(s.frame))
    for b in s.bushings:
        if b.name not in preload:
            raise ConfigError(f"{s.source}: no preload given for bushing '{b.name}'")
        p = [_clean(round(float(v), 6)) for v in preload[b.name]]
        loc = config_to_adams(b.position_mm, s.frame)
        euler = euler_zxz_deg(signs @ b.frame)
        pf = (property_files or {}).get(b.name, f"{_safe_name(b.name)}.bus")
        lines += [_rule("BUSHING_ASSEMBLY"), "[BUSHING_ASSEMBLY]",
                  f"$ {b.name}: I part {b.parts[0]}, J part {b.parts[1]} ({s.side} corner)",
                  "$   location " + " ".join(_num(round(v, 9)) for v in loc) + " mm",
                  "$   orientation body-313 " + " ".join(_num(round(v, 9)) for v in euler)
                  + " deg",
                  f" USAGE  =  '{b.name}'", " SYMMETRY  =  'left/right'",
                  f" PROPERTY_FILE  =  '{pf}'"]
        lines += [f" T_PRELOAD_{a}  =  {_num(v)}" for a, v in zip("XYZ", p[:3])]
        lines += [f" R_PRELOAD_{a}  =  {_num(v)}" for a, v in zip("XYZ", p[3:])]
    for sp in s.springs:
        lines.append(f"$ spring {sp.name}: rate {sp.rate_N_per_mm:g} N/mm, installed length "
                     f"{sp.installed_length_mm:.3f} mm (not exported)")
    return "\n".join(lines) + "\n"


def read_bushing_assemblies(path: str | Path) -> dict[str, np.ndarray]:
    """The preloads of every ``[BUSHING_ASSEMBLY]`` block: USAGE -> (Fx Fy Fz N, Tx Ty Tz
    N*mm), bushing frame (missing keys are zero)."""
    f = read_teimorbit(path)
    out = {}
    for b in f.blocks_named("BUSHING_ASSEMBLY"):
        usage = b.value("USAGE")
        if not isinstance(usage, str):
            raise f.error(b.line, b.name, "USAGE = 'name' is missing")
        out[usage] = np.array([b.value(f"{k}_PRELOAD_{a}", 0.0) for k in "TR" for a in "XYZ"],
                              float)
    return out


def mapping_text(s: Suspension, bus_files: Mapping[str, str]) -> str:
    """The mapping file that imports the exported hardpoint table back into ``s``'s config."""
    data = {"elastokin_adams_mapping": 1, "side": s.side,
            "hardpoints": {n: n for n in s.hardpoints}, "bushings": dict(bus_files)}
    head = [f"elastokin {__version__}: mapping of the ADAMS/Car files exported from "
            f"'{s.name}'", "(docs/adams.md): elastokin hardpoint: ADAMS hardpoint; elastokin "
            "bushing: .bus file"]
    return dump_config(data, "\n".join(head), flow=False)


def export_adams(s: Suspension, out_dir: str | Path,
                 bushing_preload: Mapping[str, Iterable[float]] | None = None,
                 range_mm: float = 10.0, range_deg: float = 10.0) -> list[Path]:
    """Write ``hardpoints.tbl``, one ``<bushing>.bus`` per bushing, ``bushing_assembly.txt``
    (preloads) and ``mapping.yaml`` into ``out_dir``; returns the paths written.

    ``bushing_preload``: loads at the design position per bushing (N, N*mm, bushing frame),
    e.g. :attr:`elastokin.model.DesignState.bushing_preload`; needed when the config balances
    them (``design.balance_bushing_preloads``), else taken from its preload or initial
    deflection."""
    if not (range_mm > 0 and range_deg > 0):
        raise ConfigError(f"table range must be positive, got {range_mm} mm / {range_deg} deg")
    if bushing_preload is None:
        if s.design.balance_bushing_preloads and s.bushings:
            raise ConfigError(f"{s.source}: design.balance_bushing_preloads: the bushing "
                              "preloads must be solved first (elastokin.model.design_state)")
        bushing_preload = {b.name: [law(u) for law, u in zip(b.laws, b.initial_deflection)]
                           for b in s.bushings}
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    written = []

    def write(name: str, text: str) -> None:
        (out / name).write_text(text, encoding="utf-8", newline="\n")
        written.append(out / name)

    write("hardpoints.tbl", hardpoint_table_text(s))
    bus_files = {}
    for b in s.bushings:
        bus_files[b.name] = f"{_safe_name(b.name)}.bus"
        if list(bus_files.values()).count(bus_files[b.name]) > 1:
            raise ConfigError(f"{s.source}: bushing names give the same file name "
                              f"{bus_files[b.name]}")
        write(bus_files[b.name], bushing_file_text(s, b.name, range_mm, range_deg))
    write("bushing_assembly.txt", bushing_assembly_text(s, bushing_preload, bus_files))
    write("mapping.yaml", mapping_text(s, bus_files))
    return written


# ----------------------------------------------------------------------------------------------
# K&C results with ADAMS-style channel names

#: elastokin kc.csv column -> (ADAMS-style channel, unit, meaning); springs and bushings by
#: pattern (:func:`_channel`). Units and signs are elastokin's (README, sign conventions), except
#: the components in :data:`FRAME_CHANNELS`.
KC_CHANNELS: dict[str, tuple[str, str, str]] = {
    "model": ("model", "", "elastokin model label"),
    "load_case": ("load_case", "", "elastokin load case"),
    "step": ("step", "", "step number"),
    "branch": ("branch", "", "sweep branch"),
    "pad_z_mm": ("pad_vertical_displacement", "mm", "rig pad height from design, + up"),
    "wheel_travel_mm": ("wheel_travel", "mm", "wheel-centre vertical travel, + bump"),
    "toe_deg": ("toe_angle", "deg", "toe angle, + toe-in"),
    "camber_deg": ("camber_angle", "deg", "camber angle, + top of the wheel outboard"),
    "wheel_centre_longitudinal_mm": ("wheel_travel_base", "mm",
                                     "wheel-centre longitudinal displacement, + forward"),
    "wheel_centre_lateral_mm": ("wheel_travel_track", "mm",
                                "wheel-centre lateral displacement, + to the vehicle's left"),
    "wheel_centre_x_mm": ("wheel_center_x", "mm", "wheel-centre x, ADAMS/Car frame"),
    "wheel_centre_y_mm": ("wheel_center_y", "mm", "wheel-centre y, ADAMS/Car frame"),
    "wheel_centre_z_mm": ("wheel_center_z", "mm", "wheel-centre z, ADAMS/Car frame"),
    "contact_patch_fx_N": ("tire_force_x", "N", "rig force on the tyre, x, ADAMS frame"),
    "contact_patch_fy_N": ("tire_force_y", "N", "rig force on the tyre, y, ADAMS frame"),
    "contact_patch_fz_N": ("tire_force_z", "N", "rig force on the tyre, z, ADAMS frame"),
    "vertical_force_N": ("vertical_force", "N", "rig vertical force on the tyre, + up"),
    "lateral_force_N": ("lateral_force", "N", "rig lateral force on the tyre, + left"),
    "longitudinal_force_N": ("longitudinal_force", "N",
                             "rig longitudinal force on the tyre, + forward"),
    "aligning_torque_Nmm": ("aligning_torque", "N*mm", "rig torque about the vertical, + up"),
}

#: config-frame components, converted to the ADAMS/Car frame (X rearward, Y right, Z up)
FRAME_CHANNELS = {f"wheel_centre_{a}_mm": a for a in "xyz"} | {
    f"contact_patch_f{a}_N": a for a in "xyz"}


def _channel(column: str) -> tuple[str, str, str]:
    if column in KC_CHANNELS:
        return KC_CHANNELS[column]
    m = re.fullmatch(r"spring_(.+)_force_N", column)
    if m:
        return f"{m.group(1)}_spring_force", "N", "spring force, + compression"
    m = re.fullmatch(r"bushing_(.+)_(r?)([xyz])_(mm|deg)", column)
    if m:
        kind = "rot" if m.group(2) else "disp"
        return (f"bushing_{m.group(1)}_{kind}_{m.group(3)}", m.group(4),
                "bushing deflection, part 2 rel. part 1, bushing frame")
    return column, "", "not an elastokin column: kept as is"


def kc_to_adams_channels(header: list[str], rows: Iterable[list[str]], frame
                         ) -> tuple[list[str], list[str], list[list[str]]]:
    """Rename elastokin ``kc.csv`` columns to ADAMS-style channels (:data:`KC_CHANNELS`) and
    convert the config-frame components (wheel-centre coordinates, contact-patch forces) to the
    ADAMS/Car frame. Returns (channel names, units, rows); values are text, units unchanged
    (mm, N, N*mm, deg)."""
    signs = _frame_signs(frame)
    chans = [_channel(c) for c in header]
    flip = [c in FRAME_CHANNELS and signs["xyz".index(FRAME_CHANNELS[c])] < 0 for c in header]
    out = []
    for row in rows:
        new = []
        for v, neg in zip(row, flip):
            if neg and v not in ("", None):
                x = -float(v)
                v = repr(_clean(x))
            new.append(v)
        out.append(new)
    return [c[0] for c in chans], [c[1] for c in chans], out


def write_adams_kc_csv(kc_csv: str | Path, out: str | Path, frame) -> None:
    """Write an elastokin ``kc.csv`` with ADAMS-style channel names (``#`` header lines carry
    the source's provenance and each channel's unit)."""
    src = Path(kc_csv)
    try:
        lines = src.read_text(encoding="utf-8").splitlines()
    except OSError as exc:
        raise ConfigError(f"{src}: cannot read K&C results ({exc.strerror})") from None
    comments = [ln for ln in lines if ln.startswith("#") and not ln.startswith("# units:")]
    body = list(csv.reader([ln for ln in lines if ln and not ln.startswith("#")]))
    if not body or "toe_deg" not in body[0]:
        raise ConfigError(f"{src}: not an elastokin kc.csv (no header with toe_deg)")
    header, rows = body[0], body[1:]
    for i, r in enumerate(rows):
        if len(r) != len(header):
            raise ConfigError(f"{src}: data row {i + 1} has {len(r)} cells, header "
                              f"{len(header)}")
    names, units, rows = kc_to_adams_channels(header, rows, frame)
    with open(out, "w", newline="", encoding="utf-8") as fh:
        fh.write(f"# ADAMS-style channel names (elastokin {__version__}) from {src.name}\n")
        for c in comments:
            fh.write(c + "\n")
        fh.write("# frame of wheel_center_* and tire_force_*: ADAMS/Car global (X rearward, "
                 "Y right, Z up)\n")
        fh.write("# channel units: "
                 + ", ".join(f"{n} {u}" for n, u in zip(names, units) if u) + "\n")
        w = csv.writer(fh, lineterminator="\n")
        w.writerow(names)
        w.writerows(rows)
