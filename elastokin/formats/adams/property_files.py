"""ADAMS/Car property files out: a bushing property file (``.bus``) per bushing, a spring property
file (``.spr``) per spring and a damper property file (``.dpr``) per damper with a rate, as
TeimOrbit text in mm, newton, deg, kg, sec, and the writing conventions every exported file
shares (titles at column 1, keys padded, numbers as the shortest text that reads back as the
same float).

Pure Python/numpy. Curves are in the bushing frame (elastokin's ``+K*u`` convention); a linear
rate is written as a straight table over +-``range``, a curve as given (extended with its end
slopes to that range when narrower). ADAMS interpolates the table with an Akima spline: at the
table points it equals elastokin's piecewise-linear law; between them it differs by
:func:`elastokin.formats.adams.curves.akima_deviation` (zero for a straight table).
Conventions: ``docs/adams.md``.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

from elastokin.config.suspension import Suspension
from elastokin.formats.adams.car import BUSHING_CURVES, clean
from elastokin.formats.adams.curves import akima_deviation
from elastokin.physics.laws import DirectionLaw
from elastokin.version import __version__

__all__ = [
    "UNITS_LINES",
    "bushing_file_text",
    "curve_points",
    "damper_file_text",
    "header_lines",
    "key_line",
    "number",
    "provenance",
    "rule",
    "spring_file_text",
    "table_lines",
]

#: the ``[UNITS]`` block of every exported file, as ADAMS/Car writes it
UNITS_LINES = ("[UNITS]", " LENGTH  =  'mm'", " FORCE   =  'newton'", " ANGLE   =  'deg'",
               " MASS    =  'kg'", " TIME    =  'sec'")


def number(x: float) -> str:
    """Shortest text that reads back as the same float; no negative zero."""
    return repr(clean(x))


def rule(name: str) -> str:
    """The ``$-----...NAME`` separator ADAMS/Car writes above a block (80 columns)."""
    return "$" + name.rjust(79, "-")


def key_line(key: str, value, width: int) -> str:
    """`` KEY  =  value`` with the key padded to ``width`` (strings quoted)."""
    text = f"'{value}'" if isinstance(value, str) else number(value)
    return f" {key.ljust(width)}  =  {text}"


def provenance(s: Suspension) -> str:
    return f"$ elastokin {__version__}: '{s.name}' (config sha256 {s.sha256[:12]})"


def header_lines(file_type: str, version: float, comments: list[str]) -> list[str]:
    """``[MDI_HEADER]`` with its ``(COMMENTS)`` sub-block, titles at column 1."""
    lines = [rule("MDI_HEADER"), "[MDI_HEADER]", key_line("FILE_TYPE", file_type, 12),
             key_line("FILE_VERSION", version, 12), key_line("FILE_FORMAT", "ASCII", 12)]
    if comments:
        lines += ["(COMMENTS)", "{comment_string}",
                  *("'" + c.replace("'", "`") + "'" for c in comments)]
    return lines


def curve_points(law: DirectionLaw, half_range: float) -> tuple[list[float], list[float]]:
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


def table_lines(columns: tuple[str, str], u: Sequence[float], f: Sequence[float]
                ) -> list[str]:
    """The lines of a curve table ``{u f}`` (header ``columns``), a row per point, numbers as
    :func:`number`, right-aligned to columns 22 and 46."""
    lines = ["{" + columns[0].rjust(21) + columns[1].rjust(24) + "}"]
    return lines + [" " + number(a).rjust(21) + number(c).rjust(24) for a, c in zip(u, f)]


def bushing_file_text(s: Suspension, bushing: str, range_mm: float = 10.0,
                      range_deg: float = 10.0) -> str:
    """A ``.bus`` bushing property file (mm, newton, deg) with the six curves of a bushing:
    a linear rate as a straight table over +-``range_mm`` / +-``range_deg``, a curve as given
    (extended with its end slopes to that range when narrower). Damping: zero."""
    b = next(x for x in s.bushings if x.name == bushing)
    curves, notes = [], []
    for (direction, name, columns), law in zip(BUSHING_CURVES, b.laws):
        u, f = curve_points(law, range_mm if direction in ("x", "y", "z") else range_deg)
        curves += [rule(name), f"[{name}]", *table_lines(columns, u, f)]
        dev, at = akima_deviation(u, f)
        if dev > 1e-9 * max(abs(v) for v in f):
            unit = ("N", "mm") if direction in ("x", "y", "z") else ("N*mm", "deg")
            notes.append(f"$ {name}: between its points ADAMS' Akima spline differs from "
                         f"elastokin's law by up to {dev:.4g} {unit[0]} (at {at:.4g} {unit[1]})")
    lines = [provenance(s),
             f"$ bushing {b.name}: {b.parts[0]} (I) -> {b.parts[1]} (J); curves in the bushing "
             "frame (z axial, x main radial),",
             "$ mm -> N and deg -> N*mm; beyond a table elastokin extrapolates linearly with the "
             "end slopes.", *notes,
             *header_lines("bus", 4.0, [f"elastokin bushing {b.name} of {s.name}"]),
             rule("UNITS"), *UNITS_LINES,
             rule("SHAPE"), "[SHAPE]",
             "$ graphics only: nominal sleeve (elastokin has no bushing geometry)",
             "{radius      width}", " 25.0        50.0", " 25.0        50.0",
             rule("DAMPING"), "[DAMPING]",
             "$ elastokin is quasi-static: no damping"]
    lines += [key_line(f"{k}_DAMPING", 0.0, 10) for k in ("FX", "FY", "FZ", "TX", "TY", "TZ")]
    return "\n".join(lines + curves) + "\n"


def spring_file_text(s: Suspension, spring: str, force_N: float | None = None,
                     half_range: float = 100.0) -> str:
    """A ``.spr`` spring property file (mm, newton): ``FREE_LENGTH`` (installed length +
    design force / rate; the design force ``force_N``, else the config's) and the linear rate as
    a straight ``{disp force}`` table (disp: compression from free length) from -``half_range``
    to ``half_range`` past the design compression."""
    sp = next(x for x in s.springs if x.name == spring)
    force = sp.design_force_N() if force_N is None else float(force_N)
    compression = force / sp.rate_N_per_mm
    free = sp.installed_length_mm + compression
    step = half_range / 2
    lo = math.floor(min(-half_range, compression - half_range) / step)
    hi = math.ceil(max(half_range, compression + half_range) / step)
    u = [clean(k * step) for k in range(lo, hi + 1)]
    lines = [provenance(s),
             f"$ spring {sp.name}: {sp.parts[0]} -> {sp.parts[1]}; rate {sp.rate_N_per_mm:g} "
             f"N/mm; design force {force:.6g} N at installed length "
             f"{sp.installed_length_mm:.6g} mm;",
             "$ disp: compression from free length (mm), force: compression (N).",
             *header_lines("spr", 4.0, [f"elastokin spring {sp.name} of {s.name}"]),
             rule("UNITS"), *UNITS_LINES, rule("SPRING_DATA"), "[SPRING_DATA]",
             key_line("FREE_LENGTH", clean(round(free, 9)), 11),
             rule("CURVE"), "[CURVE]",
             *table_lines(("disp", "force"), u, [sp.rate_N_per_mm * x for x in u])]
    return "\n".join(lines) + "\n"


def damper_file_text(s: Suspension, damper: str, half_range: float = 1000.0) -> str:
    """A ``.dpr`` damper property file (mm, newton, sec): the linear damping rate as a
    straight ``{vel force}`` table (velocity mm/s, + extension; force N, + resisting
    extension) over +-``half_range`` mm/s."""
    d = next(x for x in s.dampers if x.name == damper)
    v = [clean(k * half_range / 2) for k in range(-2, 3)]
    lines = [provenance(s),
             f"$ damper {d.name}: {d.parts[0]} -> {d.parts[1]}; linear, "
             f"{d.rate_N_s_per_mm:g} N*s/mm (elastokin's rig is quasi-static: not used there).",
             "$ vel: extension velocity (mm/s), force: the damper's force (N), + in extension.",
             *header_lines("dpr", 4.0, [f"elastokin damper {d.name} of {s.name}"]),
             rule("UNITS"), *UNITS_LINES, rule("CURVE"), "[CURVE]",
             *table_lines(("vel", "force"), v, [clean(d.rate_N_s_per_mm * x) for x in v])]
    return "\n".join(lines) + "\n"
