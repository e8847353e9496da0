"""TeimOrbit files (the ADAMS/Car text format): parser, reader and unit conversion.

Pure Python (no Exudyn). ``$`` comments, ``[BLOCK]`` and ``(SUB_BLOCK)`` headers, ``KEY = value``
pairs and ``{col1 col2 ...}`` tables; every item remembers its line and every problem raises
:class:`~elastokin.errors.ConfigError` naming the file, the line and the block. Values of known
quantities are converted on reading, with the file's ``[UNITS]`` block (ADAMS/Car's defaults
when it has none), to elastokin units: mm, N, N*mm, deg (s and kg for damping and mass). No
frame is involved here: values stay in the file's frame. Format: ``docs/adams.md``.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from pathlib import Path

from elastokin.errors import ConfigError

__all__ = [
    "COLUMN_QUANTITIES",
    "KEY_QUANTITIES",
    "QUANTITY_UNITS",
    "UNIT_FACTORS",
    "Block",
    "Entry",
    "SubBlock",
    "Table",
    "TeimOrbitFile",
    "Units",
    "parse_teimorbit",
    "read_teimorbit",
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


def _show(text: str, limit: int = 60) -> str:
    """``repr`` of a line's text for a message, cut after ``limit`` characters."""
    r = repr(text)
    return r if len(r) <= limit else r[:limit] + "..."


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
        x = float(token.replace("d", "e").replace("D", "e"))
        return x if math.isfinite(x) else token  # 1e999: not a number a quantity can take
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
            raise _error(path, n, bname,
                         f"unclosed quote {open_quote} in {_show(raw.strip())}")
        line = line.strip()
        if not line:
            continue
        if line.startswith("["):
            m = re.fullmatch(rf"\[\s*({_NAME})\s*\]", line)
            if not m:
                raise _error(path, n, bname, f"malformed block header {_show(line)} (expected "
                             "[NAME])")
            block = Block(m.group(1).upper(), n)
            blocks.append(block)
            section, table = block, None
            continue
        if block is None:
            raise _error(path, n, None, f"{_show(line)} comes before the first [BLOCK] header")
        if line.startswith("("):
            m = re.fullmatch(rf"\(\s*({_NAME})\s*\)", line)
            if not m:
                raise _error(path, n, bname, f"malformed sub-block header {_show(line)} "
                             "(expected (NAME))")
            section = SubBlock(m.group(1).upper(), n)
            block.sub_blocks.append(section)
            table = None
            continue
        if line.startswith("{"):
            if not line.endswith("}") or line.count("}") != 1:
                raise _error(path, n, bname, f"unclosed table header {_show(line)}: expected "
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
                             f"number or a 'quoted string'), got {_show(m.group(2))}")
            key = m.group(1).upper()
            if key in section.entries:
                raise _error(path, n, bname, f"{key} is given twice (first at line "
                             f"{section.entries[key].line})")
            section.entries[key] = Entry(key, _value(*toks[0]), n)
            continue
        if table is None:
            raise _error(path, n, bname, f"unrecognised line {_show(line)} (expected a "
                         "[BLOCK], (SUB_BLOCK), KEY = value, {table header}, a table row or a $ "
                         "comment)")
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
        data = p.read_bytes()
    except OSError as exc:
        raise ConfigError(f"{p}: cannot read file ({exc.strerror})") from None
    bad = data.find(b"\0")  # a NUL byte: binary data
    if bad < 0:
        try:
            text = data.decode("utf-8").removeprefix("\ufeff")
        except UnicodeDecodeError as exc:
            bad = exc.start
    if bad >= 0:
        raise _error(str(p), data.count(b"\n", 0, bad) + 1, None, f"not a text file (byte "
                     f"{bad} is binary or not UTF-8); expected a TeimOrbit text file")
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

