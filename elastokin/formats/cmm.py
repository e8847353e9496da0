"""CMM measurement files: labelled points and lines, in IGES or CSV (units mm).

A measurement file holds points (IGES entity 116) and straight lines (IGES entity 110), each with
a label; what a label means (a mark, a joint centre, a joint axis) is said by the config's
``measurements`` section (see ``docs/measurements.md``):

- ``M1`` .. ``M4`` (or the labels the config names): the part's 4 marks;
- ``<hardpoint>`` (or the label mapped to it): a point, the joint centre on this part;
- ``<hardpoint>.Z``: a line from the centre along the joint / sleeve axis;
- ``<hardpoint>.X``: a line from the centre along the bushing's main radial direction.

IGES: the label is the entity label (directory entry field 18), followed by the subscript
number (field 19) when that is not zero; lengths are converted to mm from the global section's
unit flag; entities with a transformation matrix (entity 124) are transformed. CSV: ``#``
comment lines, then the header ``label,kind,x_mm,y_mm,z_mm,x2_mm,y2_mm,z2_mm``; ``kind`` is
``point`` or ``line`` (a line's second point in the ``*2_mm`` columns).

The writers are deterministic (same data, same bytes) so that synthetic data regenerate exactly.
"""

from __future__ import annotations

import contextlib
import csv
import io
import math
import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from elastokin.errors import MeasurementError
from elastokin.formats.text import read_text

CSV_COLUMNS = ("label", "kind", "x_mm", "y_mm", "z_mm", "x2_mm", "y2_mm", "z2_mm")

#: IGES global-section unit flag -> mm (IGES 5.3, table 3)
IGES_UNIT_MM = {1: 25.4, 2: 1.0, 4: 304.8, 5: 1609344.0, 6: 1000.0, 7: 1.0e6, 8: 0.0254,
                9: 1.0e-3, 10: 10.0, 11: 2.54e-5}
IGES_UNIT_NAME_MM = {"IN": 25.4, "INCH": 25.4, "MM": 1.0, "FT": 304.8, "MI": 1609344.0,
                     "M": 1000.0, "KM": 1.0e6, "MIL": 0.0254, "UM": 1.0e-3, "CM": 10.0,
                     "UIN": 2.54e-5}


@dataclass
class PointSet:
    """The labelled points and lines of one file, mm, in the file's frame.

    points: label -> (3,); lines: label -> (2, 3) (start, end); ``order``: point labels in
    file order."""

    source: str
    points: dict[str, np.ndarray] = field(default_factory=dict)
    lines: dict[str, np.ndarray] = field(default_factory=dict)
    order: list[str] = field(default_factory=list)

    def add_point(self, label: str, xyz, where: str) -> None:
        if not label:
            raise MeasurementError(f"{self.source}: {where}: a point without a label")
        if label in self.points:
            raise MeasurementError(f"{self.source}: {where}: label '{label}' used twice")
        self.points[label] = np.asarray(xyz, float)
        self.order.append(label)

    def add_line(self, label: str, start, end, where: str) -> None:
        if not label:
            raise MeasurementError(f"{self.source}: {where}: a line without a label")
        if label in self.lines:
            raise MeasurementError(f"{self.source}: {where}: label '{label}' used twice")
        seg = np.array([start, end], float)
        if np.linalg.norm(seg[1] - seg[0]) < 1e-6:
            raise MeasurementError(f"{self.source}: {where}: line '{label}' has zero length")
        self.lines[label] = seg


def read_points(path: str | Path) -> PointSet:
    """Read an IGES (``.igs``/``.iges``) or CSV (``.csv``) measurement file."""
    p = Path(path)
    if not p.is_file():
        raise MeasurementError(f"{p}: measurement file not found")
    suffix = p.suffix.lower()
    if suffix in (".igs", ".iges"):
        return read_iges(p)
    if suffix == ".csv":
        return read_csv(p)
    raise MeasurementError(f"{p}: unknown measurement file type '{p.suffix}' "
                           "(expected .igs, .iges or .csv)")


def write_points(path: str | Path, points: dict[str, np.ndarray],
                 lines: dict[str, np.ndarray] | None = None, comment: str = "") -> None:
    """Write an IGES or CSV file (by extension); coordinates in mm to 1e-6 mm."""
    p = Path(path)
    if p.suffix.lower() in (".igs", ".iges"):
        write_iges(p, points, lines or {}, comment)
    elif p.suffix.lower() == ".csv":
        write_csv(p, points, lines or {}, comment)
    else:
        raise MeasurementError(f"{p}: unknown measurement file type '{p.suffix}'")


# ---------------------------------------------------------------------------------------- CSV


def read_csv(path: str | Path) -> PointSet:
    p = Path(path)
    text = read_text(p, "CSV measurement file", "save the CSV file as UTF-8")
    rows = [(n, line) for n, line in enumerate(text.splitlines(), start=1)
            if line.strip() and not line.lstrip().startswith("#")]
    if not rows:
        raise MeasurementError(f"{p}: no header row (expected {','.join(CSV_COLUMNS)})")
    try:
        return _csv_points(p, rows)
    except csv.Error as exc:  # e.g. a field over the csv module's size limit
        raise MeasurementError(f"{p}: unreadable CSV measurement file ({exc}); expected "
                               f"rows of {','.join(CSV_COLUMNS)}") from None


def _csv_points(p: Path, rows: list[tuple[int, str]]) -> PointSet:
    reader = csv.reader([line for _, line in rows])
    header = [h.strip() for h in next(reader)]
    missing = [c for c in CSV_COLUMNS if c not in header]
    if missing:
        sep = " (the header is separated by ';': save the file comma-separated)" if (
            ";" in rows[0][1] and "," not in rows[0][1]) else ""
        raise MeasurementError(f"{p}: line {rows[0][0]}: header lacks column(s) "
                               f"{', '.join(missing)} (expected {','.join(CSV_COLUMNS)}; "
                               f"coordinates in mm){sep}")
    col = {c: header.index(c) for c in CSV_COLUMNS}
    out = PointSet(str(p))
    for (n, _), cells in zip(rows[1:], reader):
        where = f"line {n}"
        if len(cells) > len(header):
            raise MeasurementError(f"{p}: {where}: {len(cells)} cells, the header has "
                                   f"{len(header)} columns (a decimal comma? use '.')")
        cells = [c.strip() for c in cells] + [""] * (len(header) - len(cells))
        label, kind = cells[col["label"]], cells[col["kind"]].lower()

        def num(names, cells=cells, where=where):
            bad = next((c for c in names if not _is_float(cells[col[c]])), None)
            if bad is not None:
                raise MeasurementError(f"{p}: {where}: column {bad}: '{cells[col[bad]]}' is "
                                       "not a finite number (mm)")
            return [float(cells[col[c]]) for c in names]

        if kind == "point":
            out.add_point(label, num(("x_mm", "y_mm", "z_mm")), where)
        elif kind == "line":
            out.add_line(label, num(("x_mm", "y_mm", "z_mm")), num(("x2_mm", "y2_mm", "z2_mm")),
                         where)
        else:
            raise MeasurementError(f"{p}: {where}: kind '{cells[col['kind']]}' (expected "
                                   "'point' or 'line')")
    return out


def _is_float(s: str) -> bool:
    try:
        return math.isfinite(float(s))
    except ValueError:
        return False


def _num(x: float) -> str:
    v = f"{x:.6f}"
    return "0.000000" if v == "-0.000000" else v


def write_csv(path: str | Path, points: dict, lines: dict, comment: str = "") -> None:
    buf = io.StringIO()
    buf.write("# elastokin CMM measurement file; coordinates in mm\n")
    for line in comment.splitlines():
        buf.write(f"# {line}\n")
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(CSV_COLUMNS)
    for label, xyz in points.items():
        w.writerow([label, "point", *(_num(v) for v in xyz), "", "", ""])
    for label, seg in lines.items():
        seg = np.asarray(seg, float)
        w.writerow([label, "line", *(_num(v) for v in seg[0]), *(_num(v) for v in seg[1])])
    _write(Path(path), buf.getvalue(), "utf-8")


# --------------------------------------------------------------------------------------- IGES


def _global_params(text: str) -> list[str]:
    """Split an IGES global section into its parameters (Hollerith strings decoded)."""
    pdelim, rdelim = ",", ";"
    if text.startswith("1H"):
        pdelim = text[2]
        if text[3:5] == "1H" or text[4:6] == "1H":
            k = text.index("1H", 3)
            rdelim = text[k + 2]
    out, i, n = [], 0, len(text)
    while i < n:
        m = re.match(r"\s*(\d+)H", text[i:])
        if m:
            start = i + m.end()
            out.append(text[start:start + int(m.group(1))])
            i = start + int(m.group(1))
            while i < n and text[i] not in (pdelim, rdelim):
                i += 1
        else:
            j = i
            while j < n and text[j] not in (pdelim, rdelim):
                j += 1
            out.append(text[i:j].strip())
            i = j
        if i >= n or text[i] == rdelim:
            break
        i += 1
    return out


def _iges_scale_mm(path: Path, lines: list[str]) -> float:
    g = "".join(line[:72] for line in lines if len(line) > 72 and line[72] == "G")
    params = _global_params(g) if g else []
    try:
        scale = float(params[12].replace("D", "E")) if len(params) > 12 and params[12] else 1.0
        flag = int(params[13]) if len(params) > 13 and params[13] else 1
    except ValueError:
        raise MeasurementError(f"{path}: IGES global section: unreadable model scale or unit "
                               "flag (parameters 13-14)") from None
    if flag == 3:
        name = params[14].strip().upper() if len(params) > 14 else ""
        if name not in IGES_UNIT_NAME_MM:
            raise MeasurementError(f"{path}: IGES global section: unknown unit name '{name}'")
        factor = IGES_UNIT_NAME_MM[name]
    elif flag in IGES_UNIT_MM:
        factor = IGES_UNIT_MM[flag]
    else:
        raise MeasurementError(f"{path}: IGES global section: unknown unit flag {flag}")
    if not scale > 0:
        raise MeasurementError(f"{path}: IGES global section: model space scale {scale}")
    return factor / scale


def _iges_records(p: Path) -> list[str]:
    """The lines of an IGES file, checked before ``pyiges`` sees them: text, 80-column records
    (a section letter in column 73), directory entries in pairs, the terminate line at the end;
    otherwise :class:`MeasurementError` naming the file and the line."""
    bad = f"{p}: unreadable IGES file"
    try:
        data = p.read_bytes()
    except OSError as exc:
        raise MeasurementError(f"{bad} ({exc.strerror or exc})") from None
    if b"\0" in data:
        line = data.count(b"\n", 0, data.index(b"\0")) + 1
        raise MeasurementError(f"{bad}: line {line}: binary data (a NUL byte); an IGES file "
                               "is ASCII text")
    try:
        lines = data.decode("utf-8").splitlines()
    except UnicodeDecodeError as exc:
        line = data.count(b"\n", 0, exc.start) + 1
        raise MeasurementError(f"{bad}: line {line}: not ASCII text (byte {exc.start}: "
                               f"0x{data[exc.start]:02x}); an IGES file is ASCII text") from None
    if not any(len(line) > 72 and line[72] == "D" for line in lines):
        raise MeasurementError(f"{bad}: no directory entries (lines with D in column 73); "
                               "expected an ASCII IGES file")
    for n, line in enumerate(lines, start=1):
        if len(line) <= 72 or line[72] not in "SGDPT":
            raise MeasurementError(f"{bad}: line {n}: not an IGES record (expected 80 columns "
                                   "with the section letter S, G, D, P or T in column 73)")
    if sum(line[72] == "D" for line in lines) % 2:
        raise MeasurementError(f"{bad}: odd number of directory lines (an entity has two): the "
                               "file is truncated")
    if lines[-1][72] != "T":
        raise MeasurementError(f"{bad}: no terminate line (T in column 73) at the end: the "
                               "file is truncated")
    _check_iges_fields(bad, lines)
    return lines


#: the integer fields pyiges reads: (first column, end column, name), per directory line
_IGES_DE_FIELDS = (
    ((0, 8, "entity type"), (8, 16, "parameter pointer"), (16, 24, "structure"),
     (24, 32, "line font"), (32, 40, "level"), (40, 48, "view"),
     (48, 56, "transformation matrix"), (56, 65, "label display"), (65, 72, "status number")),
    ((8, 16, "line weight"), (16, 24, "colour"), (24, 32, "parameter line count"),
     (32, 40, "form number"), (64, 72, "subscript number")))


def _is_iges_int(text: str) -> bool:
    """An integer field as pyiges reads it (blank: default)."""
    try:
        int(text.strip() or "0")
    except ValueError:
        return False
    return True


def _check_iges_fields(bad: str, lines: list[str]) -> None:
    """The directory entries' integer fields and the parameter lines' pointers, with the line
    of the first bad one (``pyiges`` fails on them without saying where)."""
    first_lines = set()
    d_count = 0
    for n, line in enumerate(lines, start=1):
        if line[72] == "D":
            for a, b, name in _IGES_DE_FIELDS[d_count % 2]:
                cell = line[a:b].replace(" ", "0") if name == "status number" else line[a:b]
                if not _is_iges_int(cell):
                    raise MeasurementError(f"{bad}: line {n}, columns {a + 1}-{b}: "
                                           f"'{line[a:b].strip()}' is not an integer ({name})")
            if not line[73:].strip().isdigit():
                raise MeasurementError(f"{bad}: line {n}, columns 74-80: sequence number "
                                       f"'{line[73:].strip()}' is not an integer")
            if d_count % 2 == 0:
                first_lines.add(int(line[73:]))
            d_count += 1
        elif line[72] == "P" and not (line[64:72].strip().isdigit()
                                      and int(line[64:72]) in first_lines):
            raise MeasurementError(f"{bad}: line {n}, columns 65-72: '{line[64:72].strip()}' "
                                   "is not the sequence number of a directory entry")


def _iges_xyz(p: Path, e, kind: int, where: str) -> np.ndarray:
    """The coordinates of a point (116, shape (1, 3)) or a line (110, (2, 3)) entity."""
    try:
        xyz = np.atleast_2d(e.coordinate if kind == 116 else e.coordinates).astype(float)
    except (AttributeError, TypeError, ValueError):  # pyiges never parsed its parameters
        raise MeasurementError(f"{p}: unreadable IGES file: {where}: no parameter data (the "
                               "file is truncated or the directory entry's parameter pointer "
                               "is wrong)") from None
    if not np.all(np.isfinite(xyz)):
        raise MeasurementError(f"{p}: {where}: coordinates {xyz.ravel().tolist()} are not "
                               "finite numbers")
    return xyz


def read_iges(path: str | Path) -> PointSet:
    """Points (116) and lines (110) of an IGES file, through ``pyiges``; other entities are
    ignored. Coordinates converted to mm. Every problem (a truncated, binary or malformed
    file, an entity ``pyiges`` cannot read) raises :class:`MeasurementError` naming the file."""
    import pyiges

    p = Path(path)
    raw = _iges_records(p)
    try:
        with contextlib.redirect_stdout(io.StringIO()) as warnings:
            iges = pyiges.read(str(p))
        entities = list(iges.items)
    except Exception as exc:  # pyiges raises bare IndexError/ValueError on malformed files
        raise MeasurementError(f"{p}: unreadable IGES file ({type(exc).__name__}: "
                               f"{exc or 'malformed'})") from None
    if warnings.getvalue().strip():
        raise MeasurementError(f"{p}: unreadable IGES entity: "
                               f"{warnings.getvalue().strip().splitlines()[0]}")
    scale = _iges_scale_mm(p, raw)
    out = PointSet(str(p))
    for e in entities:
        kind = e.d.get("entity_type_number")
        if kind not in (110, 116):
            continue
        label = e.d.get("entity_label") or ""
        subscript = e.d.get("entity_subs_num") or 0
        if subscript:
            label = f"{label}{subscript}"
        where = f"entity {kind} at directory line {e.sequence_number}"
        xyz = _iges_xyz(p, e, kind, where)
        ptr = e.d.get("transform") or 0
        for _ in range(16):  # a chain of transformation matrices
            if not ptr:
                break
            try:
                T = iges[ptr]
                xyz = xyz @ T.to_affine()[:3, :3].T + T.to_affine()[:3, 3]
            except (KeyError, IndexError, AttributeError, TypeError, ValueError):
                raise MeasurementError(f"{p}: {where}: transformation matrix pointer {ptr} "
                                       "does not point to a readable entity 124") from None
            ptr = T.d.get("transform") or 0
        xyz = xyz * scale
        if kind == 116:
            out.add_point(label, xyz[0], where)
        else:
            out.add_line(label, xyz[0], xyz[1], where)
    return out


def _iges_lines(text: str, letter: str, width: int = 72) -> list[str]:
    return [f"{text[i:i + width]:<{width}}{letter}" for i in range(0, max(len(text), 1), width)]


def _hollerith(s: str) -> str:
    return f"{len(s)}H{s}"


def _wrap_params(params: list[str], width: int) -> list[str]:
    """Join parameters with ',' (';' after the last) into lines of at most ``width``."""
    out, cur = [], ""
    for k, prm in enumerate(params):
        tok = prm + (";" if k == len(params) - 1 else ",")
        if cur and len(cur) + len(tok) > width:
            out.append(cur)
            cur = ""
        cur += tok
    out.append(cur)
    return out


def write_iges(path: str | Path, points: dict, lines: dict, comment: str = "") -> None:
    """A minimal IGES 5.3 file of labelled points (116) and lines (110), mm, deterministic
    (the file date is fixed so that the same data give the same bytes)."""
    for label in [*points, *lines]:
        if len(label) > 8:
            raise MeasurementError(f"{path}: IGES label '{label}' is longer than 8 characters; "
                                   "map it to a shorter label in the config (measurements."
                                   "parts.<part>.labels)")
    start = [line for text in (comment or "elastokin CMM measurement file (mm)").splitlines()
             for line in _iges_lines(text, "S")]
    name = Path(path).name
    glob = ["1H,", "1H;", _hollerith("elastokin"), _hollerith(name), _hollerith("elastokin"),
            _hollerith("elastokin iges writer 1"), "32", "38", "6", "308", "15",
            _hollerith("elastokin"), "1.0", "2", "2HMM", "1", "1.0",
            _hollerith("20000101.000000"), "1.0E-6", "0.0", _hollerith("elastokin"),
            _hollerith("elastokin"), "11", "0", _hollerith("20000101.000000")]
    gsec = [f"{line:<72}G" for line in _wrap_params(glob, 72)]
    entities = [(116, label, [f"{_num(v)}" for v in xyz] + ["0"])
                for label, xyz in points.items()]
    entities += [(110, label, [_num(v) for v in np.asarray(seg, float).ravel()])
                 for label, seg in lines.items()]
    dsec, psec = [], []
    for k, (etype, label, params) in enumerate(entities):
        de_seq = 2 * k + 1
        plines = _wrap_params([str(etype), *params], 64)
        p_start = len(psec) + 1
        for pl in plines:
            psec.append(f"{pl:<64}{de_seq:>8}P")
        dsec.append(f"{etype:>8}{p_start:>8}{0:>8}{1:>8}{0:>8}{0:>8}{0:>8}{0:>8}{'00000000':>8}D")
        dsec.append(f"{etype:>8}{0:>8}{0:>8}{len(plines):>8}{0:>8}{'':>8}{'':>8}{label:>8}"
                    f"{0:>8}D")
    out = []
    for sec in (start, gsec, dsec, psec):
        out += [f"{line}{i:>7}" for i, line in enumerate(sec, start=1)]
    out.append(f"S{len(start):07d}G{len(gsec):07d}D{len(dsec):07d}P{len(psec):07d}"
               f"{'':<40}T{1:>7}")
    _write(Path(path), "\n".join(out) + "\n", "ascii")


def _write(p: Path, text: str, encoding: str) -> None:
    try:
        p.write_text(text, encoding=encoding)
    except (OSError, UnicodeEncodeError) as exc:
        raise MeasurementError(f"{p}: cannot write measurement file ({exc})") from None
