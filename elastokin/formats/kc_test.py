"""K&C rig test files, one CSV file per load case: reader and writer (``docs/kc_test_data.md``).

UTF-8 text: optional ``#`` comment lines (one may be ``# load_case: <name>``, the others are kept
as notes), a header row of ``name [unit]`` cells, then one numeric row per rig step; the first
column is the load case's input channel. A file holds one wheel (``toe``) or both wheels of an
axle (per-wheel channels suffixed ``_left`` / ``_right``, per-axle ones such as ``roll_angle``
once; :mod:`elastokin.formats.kc_test_channels`). Known channels (:data:`CHANNELS`) are
converted once, here, to elastokin units (mm, N, N*mm, deg, ``-``); unknown ones are kept
unconverted and reported in :attr:`KCTest.warnings`. Frame: per wheel
(``docs/characteristics.md``): longitudinal forward, lateral outboard, vertical up; toe-in +,
camber top outboard +; forces and the aligning torque (toe-in sense +) are those the rig
applies to the wheel. Problems raise
:class:`~elastokin.errors.MeasurementError` naming the file and the column or line;
:func:`write_kc_test` writes deterministic bytes.
"""

from __future__ import annotations

import csv
import math
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from elastokin.errors import MeasurementError
from elastokin.formats.kc_test_channels import (
    CHANNELS,
    LOAD_CASES,
    SIDES,
    UNITS,
    Channel,
    LoadCase,
    check_layout,
    column_side,
    input_columns,
)
from elastokin.formats.text import read_text

__all__ = [
    "CHANNELS",
    "DEFAULT_JITTER_TOLERANCE",
    "LOAD_CASES",
    "MAX_BRANCHES",
    "SIDES",
    "UNITS",
    "Channel",
    "KCTest",
    "LoadCase",
    "monotonic_branches",
    "read_kc_test",
    "write_kc_test",
]

#: spellings read as the unit on the right (after removing spaces)
_UNIT_ALIASES = {"Nmm": "N*mm", "Nm": "N*m", "kNm": "kN*m", "°": "deg", "degree": "deg",
                 "degrees": "deg", "radian": "rad", "radians": "rad"}

#: a sweep may have at most this many monotonic branches (e.g. 0 -> +max -> -max -> 0)
MAX_BRANCHES = 3
#: reversals of the input smaller than this fraction of its range are jitter, not turning points
DEFAULT_JITTER_TOLERANCE = 0.01


@dataclass
class KCTest:
    """One load case measured on a K&C rig, in elastokin units.

    ``channels``: column name -> values per rig step (file order; the input channel first,
    ``input_channel`` its column, e.g. ``wheel_travel`` or ``wheel_travel_left``);
    ``units``: name -> unit of the values (the elastokin unit for known channels, the file's
    unit, possibly ``""``, for unknown ones); ``branches``: the monotonic branches of the input
    as slices (neighbours share their turning point); ``notes``: the file's free-text comment
    lines; ``warnings``: what a user should be told (unknown channels); ``sides``: the wheels
    of a file with both (``("left", "right")``, file order), ``()`` for a one-wheel file.
    """

    load_case: str
    input_channel: str
    channels: dict[str, np.ndarray]
    units: dict[str, str]
    source: str
    notes: list[str] = field(default_factory=list)
    unknown_channels: tuple[str, ...] = ()
    branches: tuple[slice, ...] = ()
    warnings: list[str] = field(default_factory=list)
    sides: tuple[str, ...] = ()

    def wheel(self, side: str = "") -> dict[str, np.ndarray]:
        """One wheel's known channels under their channel names (``toe_left`` -> ``toe``), with
        the per-axle ones; ``side`` "" for a one-wheel file (then every channel, as read)."""
        if not self.sides:
            if side:
                raise KeyError(f"{self.source}: a one-wheel file has no '{side}' channels")
            return dict(self.channels)
        if side not in self.sides:
            raise KeyError(f"{self.source}: no '{side}' channels (sides: "
                           f"{', '.join(self.sides)})")
        out = {}
        for name, values in self.channels.items():
            base, s = column_side(name)
            if s == side or (base in CHANNELS and CHANNELS[base].per_axle):
                out[base] = values
        return out

    @property
    def input(self) -> np.ndarray:
        """The input channel's values."""
        return self.channels[self.input_channel]

    @property
    def steps(self) -> int:
        """Number of rig steps (data rows)."""
        return int(self.input.size)


# ------------------------------------------------------------------------------------ helpers


def _normalise_name(name: str) -> str:
    return re.sub(r"[\s\-]+", "_", name.strip()).lower()


def _normalise_unit(unit: str) -> str:
    u = re.sub(r"\s+", "", unit)
    u = re.sub(r"[·⋅.]", "*", u)
    return _UNIT_ALIASES.get(u, u)


def _accepted(quantity: str) -> str:
    return ", ".join(UNITS[quantity])


_HEADER = re.compile(r"^(?P<name>[^\[\]]*?)\s*(?:\[(?P<unit>[^\[\]]*)\])?$")


def _parse_header_cell(path: Path, cell: str, column: int) -> tuple[str, str | None]:
    text = cell.strip()
    m = _HEADER.match(text)
    if m is None:
        raise MeasurementError(f"{path}: header, column {column} '{text}': malformed column "
                               "name (expected 'name [unit]', e.g. 'toe [deg]')")
    name = m.group("name")
    if not name:
        raise MeasurementError(f"{path}: header, column {column}: empty column name "
                               "(expected 'name [unit]', e.g. 'toe [deg]')")
    paren = re.match(r"^(.*?)\s*\(([^()]*)\)$", name)
    if m.group("unit") is None and paren:
        raise MeasurementError(f"{path}: header, column {column} '{text}': units go in square "
                               f"brackets: '{paren.group(1)} [{paren.group(2)}]'")
    return _normalise_name(name), m.group("unit")


def _load_case_from_name(path: Path) -> str | None:
    stem = path.stem.lower()
    hits = [n for n in LOAD_CASES if stem == n or re.search(rf"[_\-.]{n}$", stem)]
    return max(hits, key=len) if hits else None


def monotonic_branches(x, jitter_tolerance: float = DEFAULT_JITTER_TOLERANCE) -> list[int]:
    """Turning points of a sweep: indices where the input reverses by more than
    ``jitter_tolerance`` times its range (peak detection with hysteresis; smaller reversals
    are jitter and ignored). ``len(result) + 1`` is the number of monotonic branches."""
    x = np.asarray(x, float)
    tol = jitter_tolerance * float(np.ptp(x)) if x.size else 0.0
    turns: list[int] = []
    direction = 0  # +1 rising, -1 falling, 0 not yet away from the start by more than tol
    ext = 0  # index of the extreme reached in the current direction
    for i in range(1, x.size):
        if direction == 0:
            if abs(x[i] - x[0]) > tol:
                direction, ext = (1 if x[i] > x[0] else -1), i
        elif direction * (x[i] - x[ext]) >= 0:
            ext = i
        elif direction * (x[ext] - x[i]) > tol:
            turns.append(ext)
            direction, ext = -direction, i
    return turns


def _branches(turns: list[int], n: int) -> tuple[slice, ...]:
    edges = [0, *turns, n - 1]
    return tuple(slice(a, b + 1) for a, b in zip(edges[:-1], edges[1:]))


def _check_sweep(path, column: str, x: np.ndarray, lines: Sequence[int],
                 jitter_tolerance: float) -> tuple[slice, ...]:
    if x.size < 2:
        raise MeasurementError(f"{path}: {x.size} data row(s); a sweep needs at least 2")
    if np.ptp(x) == 0:
        raise MeasurementError(f"{path}: column '{column}': the input channel is constant "
                               f"({x[0]:g}); a sweep must vary its input")
    turns = monotonic_branches(x, jitter_tolerance)
    if len(turns) + 1 > MAX_BRANCHES:
        where = ", ".join(str(lines[i]) for i in turns[:6]) + (", ..." if len(turns) > 6 else "")
        raise MeasurementError(
            f"{path}: column '{column}': the input channel is not monotonic within its branches: "
            f"it reverses at lines {where} ({len(turns) + 1} monotonic branches; a sweep may "
            f"have at most {MAX_BRANCHES}, e.g. 0 -> +max -> -max -> 0, and reversals up to "
            f"{100 * jitter_tolerance:g}% of the input range are ignored as jitter)")
    return _branches(turns, x.size)


def _check_other_inputs(path, load_case: str, names, display, channels) -> None:
    """The other wheel's input column (a per-wheel input given for both wheels) varies as the
    first does: a constant one is a wheel the load case does not drive, which only single
    wheel travel has (its held wheel)."""
    if load_case == "single_wheel_travel":
        return
    for name in input_columns(load_case, names)[1:]:
        x = channels[name]
        if np.ptp(x) == 0:
            k = names.index(name)
            raise MeasurementError(
                f"{path}: column '{display[k]}': the input of this wheel is constant "
                f"({x[0]:g}) while '{display[0]}' sweeps; in {load_case} the rig drives both "
                "wheels (only single_wheel_travel holds one): check the column")


# --------------------------------------------------------------------------------------- read


def _read_comments(p: Path, lines: Sequence[str]
                   ) -> tuple[list[str], tuple[str, int] | None, int]:
    """The ``#`` lines before the header: (free-text notes, the ``# load_case:`` value and its
    line or None, the header's line number)."""
    notes: list[str] = []
    declared: tuple[str, int] | None = None
    header_at = None
    for n, line in enumerate(lines, start=1):
        s = line.strip()
        if not s:
            continue
        if not s.startswith("#"):
            header_at = n
            break
        body = s[1:].strip()
        m = re.match(r"^load_case\s*:\s*(.*)$", body, re.IGNORECASE)
        if m:
            if declared is not None:
                raise MeasurementError(f"{p}: line {n}: a second '# load_case:' line (the first "
                                       f"is line {declared[1]})")
            declared = (m.group(1).strip(), n)
        else:
            notes.append(body)
    if header_at is None:
        raise MeasurementError(f"{p}: no header row (expected e.g. 'wheel_travel [mm],toe [deg]' "
                               "after the '#' comment lines)")
    return notes, declared, header_at


def _resolve_load_case(p: Path, declared: tuple[str, int] | None) -> str:
    """The load case: the ``# load_case:`` line, else the file name (both must agree)."""
    from_name = _load_case_from_name(p)
    if declared is not None:
        load_case = declared[0]
        if load_case not in LOAD_CASES:
            raise MeasurementError(f"{p}: line {declared[1]}: unknown load case '{load_case}' "
                                   f"(expected one of {', '.join(LOAD_CASES)})")
        if from_name is not None and from_name != load_case:
            raise MeasurementError(f"{p}: line {declared[1]}: load case '{load_case}' "
                                   f"contradicts the file name, which names '{from_name}'")
        return load_case
    if from_name is not None:
        return from_name
    raise MeasurementError(f"{p}: cannot tell the load case: add a line "
                           "'# load_case: <name>' before the header or name the file "
                           f"'<name>.csv' (load cases: {', '.join(LOAD_CASES)})")


@dataclass
class _Header:
    """The header row: channel names in file order, their units, each column's factor to the
    elastokin unit, the unknown channels and the cells as written (for messages)."""

    names: list[str]
    units: dict[str, str]
    factors: list[float]
    unknown: list[str]
    display: list[str]


def _cells(p: Path, line: str, n: int) -> list[str]:
    try:
        return next(csv.reader([line]))
    except csv.Error as exc:  # e.g. a cell over the csv module's size limit
        raise MeasurementError(f"{p}: line {n}: unreadable CSV row ({exc})") from None


def _parse_header(p: Path, header_line: str, header_at: int) -> _Header:
    """Names, units and conversion factors of the header row (line ``header_at``)."""
    if ";" in header_line and "," not in header_line:
        raise MeasurementError(f"{p}: line {header_at}: the header is separated by ';'; save "
                               "the file as comma-separated CSV with '.' as decimal point")
    raw = _cells(p, header_line, header_at)
    names, units, factors, unknown = [], {}, [], []
    for k, cell in enumerate(raw, start=1):
        name, unit = _parse_header_cell(p, cell, k)
        if name in names:
            raise MeasurementError(f"{p}: header, column {k} '{cell.strip()}': channel "
                                   f"'{name}' appears twice (first in column "
                                   f"{names.index(name) + 1})")
        names.append(name)
        try:
            base = column_side(name)[0]
        except ValueError as exc:
            raise MeasurementError(f"{p}: header, column {k} '{cell.strip()}': {exc}") from None
        channel = CHANNELS.get(base)
        if channel is None:
            unknown.append(name)
            units[name] = (unit or "").strip()
            factors.append(1.0)
            continue
        expected = f"'{name} [{channel.unit}]' ({channel.quantity}: {_accepted(channel.quantity)})"
        if unit is None or not unit.strip():
            raise MeasurementError(f"{p}: header, column {k} '{cell.strip()}': no unit; "
                                   f"expected {expected}")
        factor = UNITS[channel.quantity].get(_normalise_unit(unit))
        if factor is None:
            raise MeasurementError(f"{p}: header, column {k} '{cell.strip()}': unit '{unit}' "
                                   f"is not a unit of {channel.quantity}; expected {expected}")
        units[name] = channel.unit
        factors.append(factor)
    return _Header(names, units, factors, unknown, [c.strip() for c in raw])


def _check_channels(p: Path, load_case: str, header: _Header) -> tuple[str, ...]:
    """The load case's input channel comes first, its required channels are present and
    per-wheel channels name their side on both wheels or on none: the file's sides."""
    try:
        return check_layout(load_case, header.names, header.display)
    except ValueError as exc:
        raise MeasurementError(f"{p}: header: {exc}") from None


def _parse_rows(p: Path, lines: Sequence[str], header_at: int, header: _Header
                ) -> tuple[list[list[float]], list[int]]:
    """The data rows after the header (unconverted values) and their line numbers."""
    names, display = header.names, header.display
    rows, row_lines = [], []
    for n in range(header_at + 1, len(lines) + 1):
        line = lines[n - 1]
        if not line.strip():
            continue
        if line.lstrip().startswith("#"):
            raise MeasurementError(f"{p}: line {n}: '#' comment lines are allowed only before "
                                   "the header row")
        cells = _cells(p, line, n)
        if len(cells) != len(names):
            raise MeasurementError(f"{p}: line {n}: {len(cells)} cells, the header has "
                                   f"{len(names)} columns")
        values = []
        for k, c in enumerate(cells):
            try:
                v = float(c)
            except ValueError:
                v = math.nan
                bad = f"'{c.strip()}' is not a number" if c.strip() else "empty cell"
            else:
                bad = f"'{c.strip()}' is not a finite number"
            if not math.isfinite(v):
                raise MeasurementError(f"{p}: line {n} (data row {len(rows) + 1}), column "
                                       f"'{display[k]}': {bad}")
            values.append(v)
        rows.append(values)
        row_lines.append(n)
    return rows, row_lines


def read_kc_test(path: str | Path,
                 jitter_tolerance: float = DEFAULT_JITTER_TOLERANCE) -> KCTest:
    """Read one K&C test file (``docs/kc_test_data.md``); values converted to mm, N, N*mm, deg.

    ``jitter_tolerance``: input reversals smaller than this fraction of the input's range do
    not count as turning points. Raises :class:`MeasurementError` naming the file, the column or
    line, and what is expected.
    """
    if not 0.0 <= jitter_tolerance < 0.5:
        raise ValueError(f"jitter_tolerance is a fraction of the input range in [0, 0.5), "
                         f"got {jitter_tolerance}")
    p = Path(path)
    lines = read_text(p, "K&C test CSV file", "save the CSV file as UTF-8").splitlines()
    notes, declared, header_at = _read_comments(p, lines)
    load_case = _resolve_load_case(p, declared)
    header = _parse_header(p, lines[header_at - 1], header_at)
    sides = _check_channels(p, load_case, header)
    names, display = header.names, header.display
    rows, row_lines = _parse_rows(p, lines, header_at, header)
    data = np.array(rows, float).reshape(len(rows), len(names)) * np.array(header.factors)
    channels = {name: data[:, k].copy() for k, name in enumerate(names)}
    branches = _check_sweep(p, display[0], channels[names[0]], row_lines, jitter_tolerance)
    _check_other_inputs(p, load_case, names, display, channels)

    warnings = []
    if header.unknown:
        listed = ", ".join(display[names.index(u)] for u in header.unknown)
        warnings.append(f"{p}: channel(s) elastokin does not know, kept unconverted: {listed}")
    return KCTest(load_case, names[0], channels, header.units, str(p), notes,
                  tuple(header.unknown), branches, warnings, sides)


# -------------------------------------------------------------------------------------- write


def _format(v: float, decimals: int) -> str:
    s = f"{v:.{decimals}f}"
    return s[1:] if re.fullmatch(r"-0\.?0*", s) else s


def _columns_to_write(p: Path, load_case: str, channels: Mapping[str, Sequence[float]],
                      units: Mapping[str, str]) -> tuple[list[str], list[np.ndarray]]:
    """The header cells and value arrays :func:`write_kc_test` writes, the input first (the
    first of its columns in ``channels``), checked as the reader checks them."""
    for name in channels:
        if _normalise_name(name) != name or not re.fullmatch(r"[a-z0-9_]+", name):
            raise MeasurementError(f"{p}: channel name '{name}': use lower-case letters, digits "
                                   "and '_'")
    inputs = input_columns(load_case, list(channels))
    order = [*inputs[:1], *(c for c in channels if c not in inputs[:1])]
    try:
        check_layout(load_case, order, order)
        bases = [column_side(name)[0] for name in order]
    except ValueError as exc:
        raise MeasurementError(f"{p}: {exc}") from None
    arrays, header = [], []
    for name, base in zip(order, bases):
        values = np.asarray(channels[name], float)
        if values.ndim != 1 or not np.all(np.isfinite(values)):
            raise MeasurementError(f"{p}: channel '{name}': needs a 1-D array of finite values")
        if arrays and values.size != arrays[0].size:
            raise MeasurementError(f"{p}: channel '{name}' has {values.size} values, "
                                   f"'{order[0]}' has {arrays[0].size}")
        if base in CHANNELS:
            unit = CHANNELS[base].unit
            if name in units and _normalise_unit(units[name]) != unit:
                raise MeasurementError(f"{p}: channel '{name}' is written in {unit} (elastokin "
                                       f"units); convert the values instead of giving unit "
                                       f"'{units[name]}'")
        else:
            unit = units.get(name, "")
            if re.search(r"[\[\],\"]", unit):
                raise MeasurementError(f"{p}: channel '{name}': unit '{unit}' may not contain "
                                       "brackets, commas or quotes")
        arrays.append(values)
        header.append(f"{name} [{unit}]" if unit else name)
    _check_sweep(p, header[0], arrays[0], list(range(1, arrays[0].size + 1)),
                 DEFAULT_JITTER_TOLERANCE)
    return header, arrays


def write_kc_test(path: str | Path, load_case: str, channels: Mapping[str, Sequence[float]], *,
                  notes: Sequence[str] = (), units: Mapping[str, str] | None = None,
                  decimals: int = 6) -> Path:
    """Write one K&C test file; deterministic bytes (UTF-8, ``\\n`` line ends).

    ``channels``: name -> values, known channels in elastokin units (mm, N, N*mm, deg, ``-``);
    one wheel's channels by their names (``toe``) or both wheels' with the side
    (``toe_left``, ``toe_right``; per-axle channels without). The load case's input channel
    is written first (of a per-wheel input given for both wheels, the first given), the
    others in the given order. ``units`` gives the unit written for unknown channels (none:
    no brackets). ``notes`` become ``#`` lines after ``# load_case:``. Values are written
    with ``decimals`` decimals. The data must pass the checks :func:`read_kc_test` makes;
    they raise :class:`MeasurementError`.
    """
    p = Path(path)
    if load_case not in LOAD_CASES:
        raise MeasurementError(f"{p}: unknown load case '{load_case}' (expected one of "
                               f"{', '.join(LOAD_CASES)})")
    header, arrays = _columns_to_write(p, load_case, channels, dict(units or {}))
    out = [f"# load_case: {load_case}"]
    for note in notes:
        for line in str(note).splitlines() or [""]:
            if re.match(r"^\s*load_case\s*:", line, re.IGNORECASE):
                raise MeasurementError(f"{p}: note '{line}' would read as the load case line")
            out.append(f"# {line}".rstrip())
    out.append(",".join(header))
    table = np.column_stack(arrays)
    out.extend(",".join(_format(v, decimals) for v in row) for row in table)
    try:
        p.write_bytes(("\n".join(out) + "\n").encode("utf-8"))
    except OSError as exc:
        raise MeasurementError(f"{p}: cannot write K&C test file ({exc.strerror})") from None
    return p
