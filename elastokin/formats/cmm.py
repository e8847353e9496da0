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
import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from elastokin.errors import MeasurementError

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
    try:
        text = p.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise MeasurementError(f"{p}: cannot read CSV measurement file ({exc})") from None
    rows = [(n, line) for n, line in enumerate(text.splitlines(), start=1)
            if line.strip() and not line.lstrip().startswith("#")]
    if not rows:
        raise MeasurementError(f"{p}: no header row (expected {','.join(CSV_COLUMNS)})")
    reader = csv.reader([line for _, line in rows])
    header = [h.strip() for h in next(reader)]
    missing = [c for c in CSV_COLUMNS if c not in header]
    if missing:
        raise MeasurementError(f"{p}: line {rows[0][0]}: header lacks column(s) "
                               f"{', '.join(missing)} (expected {','.join(CSV_COLUMNS)}; "
                               "coordinates in mm)")
    col = {c: header.index(c) for c in CSV_COLUMNS}
    out = PointSet(str(p))
    for (n, _), cells in zip(rows[1:], reader):
        where = f"line {n}"
        cells = [c.strip() for c in cells] + [""] * (len(header) - len(cells))
        label, kind = cells[col["label"]], cells[col["kind"]].lower()

        def num(names, cells=cells, where=where):
            try:
                return [float(cells[col[c]]) for c in names]
            except ValueError:
                bad = next(c for c in names if not _is_float(cells[col[c]]))
                raise MeasurementError(f"{p}: {where}: column {bad}: '{cells[col[bad]]}' is "
                                       "not a number (mm)") from None

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
        float(s)
    except ValueError:
        return False
    return True


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
    Path(path).write_text(buf.getvalue(), encoding="utf-8")


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


def read_iges(path: str | Path) -> PointSet:
    """Points (116) and lines (110) of an IGES file, through ``pyiges``; other entities are
    ignored. Coordinates converted to mm."""
    import pyiges

    p = Path(path)
    try:
        raw = p.read_text(encoding="latin-1").splitlines()
        if not any(len(line) > 72 and line[72] == "D" for line in raw):
            raise ValueError("no directory entries")
        with contextlib.redirect_stdout(io.StringIO()) as warnings:
            iges = pyiges.read(str(p))
    except Exception as exc:  # pyiges raises bare IndexError/ValueError on malformed files
        raise MeasurementError(f"{p}: unreadable IGES file ({type(exc).__name__}: "
                               f"{exc or 'malformed'})") from None
    if warnings.getvalue().strip():
        raise MeasurementError(f"{p}: unreadable IGES entity: "
                               f"{warnings.getvalue().strip().splitlines()[0]}")
    scale = _iges_scale_mm(p, raw)
    out = PointSet(str(p))
    for e in iges.items:
        kind = e.d.get("entity_type_number")
        if kind not in (110, 116):
            continue
        label = e.d.get("entity_label") or ""
        subscript = e.d.get("entity_subs_num") or 0
        if subscript:
            label = f"{label}{subscript}"
        where = f"entity {kind} at directory line {e.sequence_number}"
        xyz = np.atleast_2d(e.coordinate if kind == 116 else e.coordinates).astype(float)
        ptr = e.d.get("transform") or 0
        for _ in range(16):  # a chain of transformation matrices
            if not ptr:
                break
            try:
                T = iges[ptr]
                xyz = xyz @ T.to_affine()[:3, :3].T + T.to_affine()[:3, 3]
            except (KeyError, AttributeError):
                raise MeasurementError(f"{p}: {where}: transformation matrix pointer {ptr} "
                                       "does not point to an entity 124") from None
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
    Path(path).write_text("\n".join(out) + "\n", encoding="ascii")
