"""ADAMS/Car files out: a hardpoint table, one ``.bus`` file per bushing, the bushing preloads as
``[BUSHING_ASSEMBLY]`` blocks to paste into a subsystem file, and the mapping file that imports
them back (:func:`export_adams`).

Files are written in mm, newton, degrees (their ``[UNITS]`` block says so); hardpoints and
bushing locations/orientations in ADAMS/Car's global frame (X rearward, Y right, Z up; a
``left/right`` row stores the left point), bushing curves and preloads in the bushing frame.
Writers are deterministic: the same input gives the same bytes. Conventions: ``docs/adams.md``.
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Mapping
from pathlib import Path

import numpy as np

from elastokin.config.suspension import Suspension
from elastokin.errors import ConfigError
from elastokin.formats.adams_car import BUSHING_CURVES, clean, config_to_adams, frame_signs
from elastokin.formats.config_yaml import dump_config
from elastokin.physics.laws import DirectionLaw
from elastokin.physics.pose import euler_zxz_deg
from elastokin.version import __version__

__all__ = [
    "bushing_assembly_text",
    "bushing_file_text",
    "export_adams",
    "hardpoint_table_text",
    "mapping_text",
]

_UNITS_BLOCK = ("[UNITS]", " LENGTH  =  'mm'", " FORCE  =  'newton'", " ANGLE  =  'degrees'",
                " MASS  =  'kg'", " TIME  =  'second'")


def _num(x: float) -> str:
    """Shortest text that reads back as the same float; no negative zero."""
    return repr(clean(x))


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
    signs = np.diag(frame_signs(s.frame))
    for b in s.bushings:
        if b.name not in preload:
            raise ConfigError(f"{s.source}: no preload given for bushing '{b.name}'")
        p = [clean(round(float(v), 6)) for v in preload[b.name]]
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
    e.g. :attr:`elastokin.config.variants.DesignState.bushing_preload` (from
    :func:`elastokin.mbs.design.design_state`); needed when the config balances them
    (``design.balance_bushing_preloads``), else taken from its preload or initial deflection."""
    if not (range_mm > 0 and range_deg > 0):
        raise ConfigError(f"table range must be positive, got {range_mm} mm / {range_deg} deg")
    if bushing_preload is None:
        if s.design.balance_bushing_preloads and s.bushings:
            raise ConfigError(f"{s.source}: design.balance_bushing_preloads: the bushing "
                              "preloads must be solved first (elastokin.mbs.design.design_state)")
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
