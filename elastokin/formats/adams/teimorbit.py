"""TeimOrbit files (the ADAMS/Car text format): parser, reader and unit conversion.

Pure Python (no Exudyn). ``$`` comments, ``[BLOCK]`` and ``(SUB_BLOCK)`` headers, ``KEY = value``
pairs and ``{col1 col2 ...}`` tables; every item remembers its line. The reader takes every file
as ADAMS/Car writes it: any bracketed block name (``[3D]``), a block name repeated (a left/right
pair written as two blocks), a description row (one quoted string) under a table row, free text
after the values of a table row or a key, a key given twice (the last value is used, with a
warning), every ADAMS unit name and unit system. What is really broken raises
:class:`~elastokin.errors.ConfigError` naming the file, the line and the block. Values of known
quantities are converted on reading, with the file's ``[UNITS]`` block (ADAMS/Car's defaults
when it has none), to elastokin units: mm, N, N*mm, deg (s and kg for damping and mass). No
frame is involved here: values stay in the file's frame. Format: ``docs/adams.md``.
"""

from __future__ import annotations

import dataclasses
import math
import re
from dataclasses import dataclass, field
from pathlib import Path

from elastokin.errors import ConfigError
from elastokin.formats.adams.teimorbit_units import (
    COLUMN_QUANTITIES,
    KEY_QUANTITIES,
    QUANTITY_UNITS,
    UNIT_FACTORS,
    UNIT_SYSTEMS,
    Units,
    damping_quantity,
    unit_factor,
)

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
    "decode_text",
    "parse_teimorbit",
    "read_teimorbit",
]


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
    ``units`` holds per column the elastokin unit it was converted to (None: kept as read);
    ``descriptions`` the description row under a row (row index -> text, as ADAMS/Car writes
    under ``[PARAMETER]`` rows); ``notes`` the free text after a row's values (row index ->
    text, ignored)."""

    columns: tuple[str, ...]
    line: int
    rows: list[tuple] = field(default_factory=list)
    row_lines: list[int] = field(default_factory=list)
    units: tuple[str | None, ...] = ()
    descriptions: dict[int, str] = field(default_factory=dict)
    notes: dict[int, str] = field(default_factory=dict)

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
    ``[BUSHING_ASSEMBLY]`` does in a subsystem file); ``warnings``: what was read tolerantly
    (a repeated key, free text), one line each naming file, line and block."""

    path: str
    blocks: list[Block]
    units: Units = Units()
    units_declared: bool = False
    warnings: list[str] = field(default_factory=list)

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
        return ConfigError(_where(self.path, line, block) + msg)

    def warn(self, line: int | None, block: str | None, msg: str) -> None:
        self.warnings.append(_where(self.path, line, block) + msg)


def _where(path: str, line: int | None, block: str | None) -> str:
    return (f"{path}" + (f", line {line}" if line else "") + (f", block [{block}]" if block
                                                              else "") + ": ")


def _show(text: str, limit: int = 60) -> str:
    """``repr`` of a line's text for a message, cut after ``limit`` characters."""
    r = repr(text)
    return r if len(r) <= limit else r[:limit] + "..."


_NUMBER = re.compile(r"^[+-]?(\d+\.?\d*|\.\d+)([eEdD][+-]?\d+)?$")
_NAME = r"[A-Za-z_][A-Za-z0-9_]*"
_KEY_LINE = re.compile(rf"({_NAME})\s*=\s*(.*)")
_BLOCK_HEADER = re.compile(r"\[\s*([^\[\]]*?)\s*\]")


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


def _is_free_text(token: tuple[str, bool]) -> bool:
    """A token that starts free text after the values: a bare word that is not a number."""
    return not token[1] and not _NUMBER.match(token[0])


def _value(token: str, quoted: bool) -> float | str:
    if quoted:
        return token.strip()
    if _NUMBER.match(token):
        x = float(token.replace("d", "e").replace("D", "e"))
        return x if math.isfinite(x) else token  # 1e999: not a number a quantity can take
    return token


class _Parser:
    """Line by line: the current block, section (block or sub-block) and table."""

    def __init__(self, path: str):
        self.path = path
        self.blocks: list[Block] = []
        self.block: Block | None = None
        self.section: Block | SubBlock | None = None
        self.table: Table | None = None
        self.tables: list[tuple[Table, str]] = []
        self.warnings: list[str] = []

    def error(self, n: int, msg: str) -> ConfigError:
        return ConfigError(_where(self.path, n, self.block.name if self.block else None) + msg)

    def warn(self, n: int, msg: str) -> None:
        self.warnings.append(_where(self.path, n, self.block.name) + msg)

    def feed(self, n: int, raw: str) -> None:
        line, open_quote = _strip_comment(raw)
        if self.block is None:
            return self.before_first_block(n, line.strip(), open_quote)
        if open_quote:
            raise self.error(n, f"unclosed quote {open_quote} in {_show(raw.strip())}")
        line = line.strip()
        if not line:
            return
        if line.startswith("["):
            return self.start_block(n, line)
        if line.startswith("("):
            return self.start_sub_block(n, line)
        if line.startswith("{"):
            return self.start_table(n, line)
        m = _KEY_LINE.fullmatch(line)
        if m:
            return self.entry(n, m.group(1), m.group(2))
        if self.table is None:
            raise self.error(n, f"unrecognised line {_show(line)} (expected a [BLOCK], "
                             "(SUB_BLOCK), KEY = value, {table header}, a table row or a $ "
                             "comment)")
        self.row(n, line)

    def before_first_block(self, n: int, line: str, open_quote: str | None) -> None:
        """Up to its first ``[BLOCK]`` header a file has not shown itself to be TeimOrbit:
        an error there names the line but never shows it (the file may be anything)."""
        if not line and not open_quote:
            return
        header = _BLOCK_HEADER.fullmatch(line)
        if not open_quote and header and header.group(1):
            return self.start_block(n, line)
        what = "a malformed block header" if line.startswith("[") else \
            "a line that is neither a $ comment nor a [BLOCK] header"
        raise self.error(n, f"{what} comes before the first [BLOCK] header (expected [NAME]): "
                         "not a TeimOrbit file? (its text is not shown)")

    def start_block(self, n: int, line: str) -> None:
        m = _BLOCK_HEADER.fullmatch(line)
        if not m or not m.group(1):
            raise self.error(n, f"malformed block header {_show(line)} (expected [NAME])")
        self.block = Block(m.group(1).upper(), n)
        self.blocks.append(self.block)
        self.section, self.table = self.block, None

    def start_sub_block(self, n: int, line: str) -> None:
        m = re.fullmatch(r"\(\s*([^()]*?)\s*\)", line)
        if not m or not m.group(1):
            raise self.error(n, f"malformed sub-block header {_show(line)} (expected (NAME))")
        self.section = SubBlock(m.group(1).upper(), n)
        self.block.sub_blocks.append(self.section)
        self.table = None

    def start_table(self, n: int, line: str) -> None:
        if not line.endswith("}") or line.count("}") != 1:
            raise self.error(n, f"unclosed table header {_show(line)}: expected "
                             "'{col1 col2 ...}' on one line")
        columns = tuple(line[1:-1].split())
        if not columns:
            raise self.error(n, "table header '{}' names no columns")
        self.table = Table(columns, n)
        self.section.tables.append(self.table)
        self.tables.append((self.table, self.block.name))

    def entry(self, n: int, key: str, rest: str) -> None:
        self.table = None
        toks = _tokens(rest)
        if not toks or (len(toks) > 1 and not _is_free_text(toks[1])):
            raise self.error(n, f"{key} = ...: expected one value (a number or a 'quoted "
                             f"string'), got {_show(rest)}")
        key = key.upper()
        if len(toks) > 1:
            self.warn(n, f"{key}: free text after the value ignored: "
                      f"{_show(' '.join(t for t, _ in toks[1:]))}")
        old = self.section.entries.get(key)
        if old is not None:
            self.warn(n, f"{key} is given again (first at line {old.line}): the last value is "
                      "used")
        self.section.entries[key] = Entry(key, _value(*toks[0]), n)

    def row(self, n: int, line: str) -> None:
        t = self.table
        toks = _tokens(line)
        ncol = len(t.columns)
        if len(toks) == 1 and toks[0][1] and ncol > 1:  # a description row under a row
            if not t.rows:
                raise self.error(n, f"a description row {_show(line)} comes before the first "
                                 f"row of the table {t.header} (line {t.line})")
            i = len(t.rows) - 1
            t.descriptions[i] = (t.descriptions.get(i, "") + " " + toks[0][0].strip()).strip()
            return
        if len(toks) > ncol and _is_free_text(toks[ncol]):
            t.notes[len(t.rows)] = " ".join(tok for tok, _ in toks[ncol:])
            toks = toks[:ncol]
        if len(toks) != ncol:
            raise self.error(n, f"row has {len(toks)} values but the table {t.header} (line "
                             f"{t.line}) has {ncol} columns")
        t.rows.append(tuple(_value(tok, q) for tok, q in toks))
        t.row_lines.append(n)

    def finish(self) -> None:
        for t, block in self.tables:
            if t.notes:
                lines = [t.row_lines[i] for i in t.notes]
                first = next(iter(t.notes.values()))
                self.warnings.append(
                    _where(self.path, lines[0], block) + f"free text after the values of "
                    f"{len(lines)} row(s) of {t.header} ignored (lines "
                    f"{', '.join(map(str, lines))}): {_show(first)}")


def parse_teimorbit(text: str, path: str = "<text>") -> TeimOrbitFile:
    """Parse TeimOrbit text into blocks, sub-blocks, entries and tables (no unit conversion).

    Errors name ``path``, the line and the block; what was read tolerantly is in the file's
    ``warnings``."""
    p = _Parser(path)
    for n, raw in enumerate(text.splitlines(), start=1):
        p.feed(n, raw)
    p.finish()
    return TeimOrbitFile(path, p.blocks, warnings=p.warnings)


def decode_text(data: bytes, path: str, what: str = "a TeimOrbit text file"
                ) -> tuple[str, list[str]]:
    """The text of a file and its warnings: UTF-8 (a byte-order mark dropped); a file whose only
    non-UTF-8 bytes are in ``$`` comments (Windows-1252, as ADAMS on Windows writes a degree
    sign) is read as Windows-1252 with a warning; anything else is an error naming the line."""
    if data[:2] in (b"\xff\xfe", b"\xfe\xff"):  # a UTF-16 byte-order mark (Windows Notepad)
        raise ConfigError(f"{path}: UTF-16 text; expected {what} in UTF-8 (or Windows-1252): "
                          "save it as UTF-8")
    bad = data.find(b"\0")  # a NUL byte: binary data
    if bad < 0:
        try:
            return data.decode("utf-8").removeprefix("\ufeff"), []
        except UnicodeDecodeError as exc:
            bad = exc.start
        text = data.decode("cp1252", errors="replace")
        if all(_strip_comment(ln)[0].isascii() for ln in text.splitlines()):
            line = data.count(b"\n", 0, bad) + 1
            return text, [f"{path}, line {line}: not UTF-8 (byte {bad}); read as Windows-1252 "
                          "(its non-ASCII characters are all in $ comments)"]
    line = data.count(b"\n", 0, bad) + 1
    raise ConfigError(f"{path}, line {line}: not a text file (byte {bad} is binary or not "
                      f"UTF-8); expected {what}")


def read_teimorbit(path: str | Path, convert: bool = True) -> TeimOrbitFile:
    """Read a TeimOrbit file; with ``convert`` the values of known quantities are converted
    to elastokin units (mm, N, N*mm, deg, kg, s) with the file's ``[UNITS]`` block (ADAMS/Car's
    defaults mm, newton, degrees, kg, second when the file has none)."""
    p = Path(path)
    try:
        data = p.read_bytes()
    except OSError as exc:
        raise ConfigError(f"{p}: cannot read file ({exc.strerror})") from None
    text, warnings = decode_text(data, str(p))
    f = parse_teimorbit(text, str(p))
    if not f.blocks:
        raise ConfigError(f"{p}: " + ("empty file" if not text.strip() else "only $ comments")
                          + ": no [BLOCK] (expected a TeimOrbit file)")
    f.warnings[:0] = warnings
    if f.blocks_named("UNITS"):
        f.units = _units(f, f.block("UNITS"))
        f.units_declared = True
    if convert:
        _convert(f)
    return f


def _units(f: TeimOrbitFile, block: Block) -> Units:
    """The units a ``[UNITS]`` block gives: a unit system (``UNITS = 'Imperial'``) and/or
    single units (which override the system's); other keys are warned about and ignored."""
    base, given = Units(), {}
    for key, e in block.entries.items():
        dim = key.lower()
        if dim in ("units", "unit_system", "system"):
            system = Units.system(str(e.value))
            if system is None:
                raise f.error(e.line, "UNITS", f"unknown unit system {e.value!r} (known: "
                              f"{', '.join(UNIT_SYSTEMS)})")
            base = system
        elif dim not in UNIT_FACTORS:
            f.warn(e.line, "UNITS", f"{key} = {e.value!r}: not a unit elastokin converts "
                   "(LENGTH, FORCE, ANGLE, MASS, TIME): ignored")
        elif unit_factor(dim, e.value) is None:
            raise f.error(e.line, "UNITS", f"unknown {dim} unit {e.value!r} (known: "
                          f"{', '.join(UNIT_FACTORS[dim])}, and their plurals)")
        else:
            given[dim] = str(e.value)
    return dataclasses.replace(base, **given)


def _scaled(value: float, factor: float) -> float:
    """``value * factor``, rounded to 12 significant digits when the factor is not 1 (drops the
    binary noise of factors such as 180/pi; far below the precision of any property file)."""
    return value if factor == 1.0 else float(f"{value * factor:.12g}")


def _convert_entries(f: TeimOrbitFile, block: Block, section: Block | SubBlock) -> None:
    for key, e in section.entries.items():
        q = damping_quantity(key) if block.name == "DAMPING" else KEY_QUANTITIES.get(key)
        if q is None:
            continue
        if not isinstance(e.value, float):
            raise f.error(e.line, block.name, f"{key} = {e.value!r}: expected a number ({q})")
        e.value = _scaled(e.value, f.units.factor(q))
        e.unit = QUANTITY_UNITS[q][1]


def _convert_table(f: TeimOrbitFile, block: Block, t: Table) -> None:
    qs = [COLUMN_QUANTITIES.get(c.lower()) for c in t.columns]
    factors = [None if q is None else f.units.factor(q) for q in qs]
    for i, (row, n) in enumerate(zip(t.rows, t.row_lines)):
        new = list(row)
        for j, k in enumerate(factors):
            if k is None:
                continue
            if not isinstance(row[j], float):
                named = f"row '{row[0]}': " if isinstance(row[0], str) and j else ""
                raise f.error(n, block.name, f"{named}column {t.columns[j]} of {t.header}: "
                              f"{row[j]!r} is not a number")
            new[j] = _scaled(row[j], k)
        t.rows[i] = tuple(new)
    t.units = tuple(None if q is None else QUANTITY_UNITS[q][1] for q in qs)


def _convert(f: TeimOrbitFile) -> None:
    for block in f.blocks:
        if block.name == "UNITS":
            continue
        for section in (block, *block.sub_blocks):
            _convert_entries(f, block, section)
            for t in section.tables:
                _convert_table(f, block, t)
