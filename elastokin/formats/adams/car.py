"""ADAMS/Car files in: bushing property files (``.bus``, or XML), and :func:`import_adams` (an
elastokin config from them and a hardpoint table, :mod:`elastokin.formats.adams.hardpoints`,
through a mapping file; every file named inside the databases given,
:mod:`elastokin.formats.adams.database`).

Pure Python/numpy (no Exudyn). Values are in elastokin units (mm, N, N*mm, deg), converted on
reading by :mod:`elastokin.formats.adams.teimorbit`. ADAMS/Car's global frame is X rearward,
Y right, Z up; a ``left/right`` hardpoint row stores its left point (Y < 0), the right one is its Y
mirror; an asymmetric pair is two rows, ``left`` and ``right``, each its own point. Frames and
the mapping file: :mod:`elastokin.formats.adams.mapping`; assembly blocks (left/right kept
apart): :mod:`elastokin.formats.adams.assemblies`. Bushing curves are in the bushing frame and
become piecewise-linear laws (:mod:`elastokin.physics.laws`); ADAMS interpolates them with an
Akima spline (:mod:`elastokin.formats.adams.curves`). Conventions: ``docs/adams.md``.
"""

from __future__ import annotations

import copy
import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from elastokin.config.confined import Roots
from elastokin.errors import ConfigError
from elastokin.formats.adams.assemblies import read_assemblies, read_bushing_assemblies
from elastokin.formats.adams.bushing_xml import is_xml, read_bushing_xml
from elastokin.formats.adams.curves import akima_deviation
from elastokin.formats.adams.database import database_file, input_roots, subsystem_file
from elastokin.formats.adams.hardpoints import (
    HARDPOINT_COLUMNS,
    SYMMETRIES,
    AdamsHardpoint,
    lookup_hardpoint,
    read_hardpoints,
)
from elastokin.formats.adams.mapping import (
    AdamsMapping,
    adams_to_config,
    config_to_adams,
    frame_signs,
    read_mapping,
)
from elastokin.formats.adams.teimorbit import Units, read_teimorbit
from elastokin.physics.joints import BUSHING_DIRECTIONS
from elastokin.physics.laws import DirectionLaw, law_from_spec

__all__ = [
    "BUSHING_CURVES",
    "HARDPOINT_COLUMNS",
    "SYMMETRIES",
    "AdamsHardpoint",
    "AdamsMapping",
    "BushingProperties",
    "adams_to_config",
    "apply_bushings",
    "apply_hardpoints",
    "bushing_sources",
    "clean",
    "config_to_adams",
    "database_file",
    "frame_signs",
    "import_adams",
    "import_subsystem",
    "lookup_hardpoint",
    "read_bushing",
    "read_bushing_assemblies",
    "read_hardpoints",
    "read_mapping",
    "subsystem_file",
]

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
    """A bushing property file in elastokin form.

    ``stiffness``: a bushing ``stiffness`` entry of an elastokin config, per direction
    ``{"deflection": [...], "load": [...]}`` in mm -> N (x, y, z) and deg -> N*mm (rx, ry, rz),
    or a linear rate (N/mm, N*mm/deg; an XML file's ``type="linear"``), bushing frame.
    ``damping``: the damping constants as (value, elastokin unit); elastokin is quasi-static
    and does not use them. ``akima``: per curve, the largest difference between ADAMS' Akima
    spline and elastokin's piecewise-linear law between the table points, as (load,
    deflection where it is).
    """

    path: str
    stiffness: dict[str, dict[str, list[float]] | float]
    damping: dict[str, tuple[float, str | None]]
    units: Units
    warnings: tuple[str, ...] = ()
    akima: dict[str, tuple[float, float]] = field(default_factory=dict)

    def laws(self) -> tuple[DirectionLaw, ...]:
        return tuple(law_from_spec(self.stiffness[d]) for d in BUSHING_DIRECTIONS)

    def interpolation_note(self) -> str:
        """One line: how far ADAMS' Akima interpolation is from elastokin's law."""
        worst = [(dev, d, at) for d, (dev, at) in self.akima.items() if dev > 0.0]
        if not worst:
            return "ADAMS' Akima spline and elastokin's law are the same (straight curves)"
        dev, d, at = max(worst)
        unit = ("N", "mm") if d in ("x", "y", "z") else ("N*mm", "deg")
        return (f"between table points ADAMS' Akima spline differs from elastokin's "
                f"piecewise-linear law by up to {dev:.4g} {unit[0]} ({d} at {at:.4g} {unit[1]})")


Fail = Callable[[int, str], ConfigError]


def _check_curve(u: np.ndarray, load: np.ndarray, lines: list[int], header_line: int,
                 names: tuple[str, str], units: tuple[str, str], fail: Fail) -> None:
    """The checks a curve must pass to be an elastokin law (each error names its line)."""
    what = {"disp": "deflection", "rot": "rotation"}.get(names[0], names[0])
    if len(u) < 2:
        raise fail(header_line, f"curve has {len(u)} rows; a curve needs at least two (an "
                   "empty or unclosed table?)")
    for i in range(1, len(u)):
        if u[i] <= u[i - 1]:
            raise fail(lines[i], f"{what} {u[i]:.6g} {units[0]} does not increase on "
                       f"{u[i - 1]:.6g} {units[0]} (line {lines[i - 1]}): the curve must be "
                       "monotonic in deflection")
    for i in range(1, len(u)):
        if load[i] <= load[i - 1]:
            raise fail(lines[i], f"{names[1]} {load[i]:.6g} {units[1]} does not increase on "
                       f"{load[i - 1]:.6g} {units[1]} (line {lines[i - 1]}): elastokin needs a "
                       "strictly increasing (invertible) law")
    at_zero = _at_zero(u, load)
    if abs(at_zero) > 1e-9 * np.max(np.abs(load)):
        zero = np.flatnonzero(u == 0.0)
        if zero.size:
            line, rows = lines[zero[0]], f"line {lines[zero[0]]}"
        else:
            i = int(np.clip(np.searchsorted(u, 0.0), 1, len(u) - 1))
            line, rows = lines[i - 1], f"extrapolated from lines {lines[i - 1]} and {lines[i]}"
        raise fail(line, f"the curve gives {at_zero:.6g} {units[1]} at zero {what} ({rows}); "
                   "it must pass through (0, 0): give a load at zero deflection as the preload "
                   "(T_PRELOAD / R_PRELOAD) of the bushing assembly")


def _read_bus(path: str | Path) -> BushingProperties:
    f = read_teimorbit(path)
    warnings = list(f.warnings)
    stiffness, akima = {}, {}
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
        for row, n in zip(t.rows, t.row_lines):
            for v, c in zip(row, t.columns):
                if not isinstance(v, float) or not math.isfinite(v):
                    raise f.error(n, name, f"{c} {v!r} is not a finite number")
        u, load = np.array(t.column(columns[0])), np.array(t.column(columns[1]))
        _check_curve(u, load, t.row_lines, t.line, columns, t.units,
                     lambda line, msg, name=name: f.error(line, name, msg))
        stiffness[direction] = {"deflection": [clean(x) for x in u],
                                "load": [clean(x) for x in load]}
        akima[direction] = akima_deviation(u, load)
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
    return BushingProperties(f.path, stiffness, damping, f.units, tuple(warnings), akima)


def _read_xml(path: str | Path) -> BushingProperties:
    x = read_bushing_xml(path)
    stiffness, akima = {}, {}
    for d, names in zip(BUSHING_DIRECTIONS, (c for _, _, c in BUSHING_CURVES)):
        where = f"{x.path}, <ConnectorDirectionComponent> {d}"
        units = ("mm", "N") if d in ("x", "y", "z") else ("deg", "N*mm")
        if d in x.rates:
            rate, line = x.rates[d]
            if not rate > 0:
                raise ConfigError(f"{where}, line {line}: linear rate {rate:.6g} "
                                  f"{units[1]}/{units[0]}: must be positive")
            stiffness[d] = clean(rate)
            akima[d] = (0.0, 0.0)
            continue
        u, load, lines = (np.array(v) if i < 2 else v for i, v in enumerate(x.curves[d]))
        _check_curve(u, load, lines, x.lines[d], names, units,
                     lambda line, msg, where=where: ConfigError(f"{where}, line {line}: {msg}"))
        stiffness[d] = {"deflection": [clean(v) for v in u], "load": [clean(v) for v in load]}
        akima[d] = akima_deviation(u, load)
    return BushingProperties(x.path, stiffness, dict(x.damping), x.units, tuple(x.warnings),
                             akima)


def read_bushing(path: str | Path) -> BushingProperties:
    """Read a bushing property file (TeimOrbit ``.bus`` or XML ``ConnectorBushingProperties``)
    into an elastokin bushing stiffness.

    Each of ``[FX_CURVE]`` ... ``[TZ_CURVE]`` must hold one table ``{disp force}`` (or
    ``{rot torque}``) of at least two rows, strictly increasing in deflection and in load and
    through (0, 0) (the law elastokin inverts; a load at zero deflection is a preload, given in
    the bushing assembly). Beyond the table elastokin extrapolates linearly with the end slopes.
    """
    return _read_xml(path) if is_xml(path) else _read_bus(path)


def _at_zero(u: np.ndarray, load: np.ndarray) -> float:
    """The piecewise-linear law at zero deflection, extrapolated with the end slopes."""
    if u[0] <= 0.0 <= u[-1]:
        return float(np.interp(0.0, u, load))
    i = 0 if u[0] > 0 else len(u) - 2
    return float(load[i] + (load[i + 1] - load[i]) / (u[i + 1] - u[i]) * (0.0 - u[i]))


def clean(x: float) -> float:
    """A plain float, without the sign of a negative zero."""
    x = float(x)
    return 0.0 if x == 0.0 else x


# ----------------------------------------------------------------------------------------------
# Hardpoints and bushings into a config


def apply_hardpoints(config: dict, points: Mapping[str, AdamsHardpoint],
                     mapping: AdamsMapping, source: str = "template config",
                     warn_unmapped: bool = True) -> tuple[dict, list[str]]:
    """A copy of ``config`` (an elastokin config dict) whose mapped ``hardpoints`` are the ADAMS
    points: the side chosen (hardpoint's, else mapping's, else the config's ``side``), then
    converted from the ADAMS frame to the config's ``frame``. ``source`` names the config in
    errors. Returns (config, warnings: with ``warn_unmapped``, the template hardpoints no
    section of the mapping names)."""
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
        hp, side = lookup_hardpoint(points, adams_name, side, where)
        side = side or default_side
        if hp.symmetry != "single" and side != cfg["side"]:
            warnings.append(f"{where}: takes the {side} point of '{hp.name}' for a "
                            f"{cfg['side']} corner")
        try:
            p = adams_to_config(hp.at(side), cfg["frame"])
        except ConfigError as exc:
            raise ConfigError(f"{where}: {exc}") from None
        cfg["hardpoints"][name] = [clean(v) for v in p]
    unmapped = [n for n in cfg["hardpoints"] if n not in mapping.all_hardpoints()]
    if unmapped and warn_unmapped:
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


def _assembly_files(sub: Path, mapping: AdamsMapping, side: str,
                    roots: Roots | None) -> dict[str, Path]:
    """Bushings the mapping names by ADAMS usage only: the PROPERTY_FILE of the subsystem's
    ``[BUSHING_ASSEMBLY]`` of that usage on ``side`` (or its ``single`` one), inside
    ``roots``."""
    wanted = {n: u for n, u in mapping.bushing_usage.items() if n not in mapping.bushings}
    if not wanted:
        return {}
    blocks = read_assemblies(sub, "BUSHING_ASSEMBLY")
    out = {}
    for name, usage in wanted.items():
        sides = blocks.get(usage, {})
        a = sides.get(side) or sides.get("single")
        if a is None or a.property_file is None:
            raise ConfigError(f"{mapping.path}: key 'bushings.{name}': no [BUSHING_ASSEMBLY] "
                              f"of USAGE '{usage}' ({side}) with a PROPERTY_FILE in {sub} "
                              f"(usages: {', '.join(sorted(blocks)) or 'none'})")
        out[name] = database_file(a.property_file, sub, a.where(sub, a.symmetry), roots,
                                  "PROPERTY_FILE")
    return out


def bushing_sources(subsystem: str | Path, mapping: AdamsMapping, side: str,
                    bushing_files: Mapping[str, str | Path] | None = None,
                    roots: Roots | None = None) -> dict[str, Path]:
    """The property file of each bushing to import: ``bushing_files``, else the mapping's
    ``file``, else the PROPERTY_FILE of the subsystem's ``[BUSHING_ASSEMBLY]`` of the mapping's
    ``usage`` on ``side``, found in the database holding the subsystem file (and inside
    ``roots``, default that database)."""
    sub = subsystem_file(subsystem, roots=roots)
    named = {}
    for name in mapping.bushings:
        named[name] = mapping.bushing_file(name)
        if not named[name].is_file():
            raise ConfigError(f"{mapping.path}: key '{mapping.key}bushings.{name}.file': the "
                              f"property file {named[name]} does not exist")
    return {**_assembly_files(sub, mapping, side, roots), **named,
            **{k: Path(v) for k, v in (bushing_files or {}).items()}}


def import_adams(template: dict, hardpoints_file: str | Path, mapping_file: str | Path,
                 bushing_files: Mapping[str, str | Path] | None = None,
                 source: str = "template config") -> tuple[dict, list[str]]:
    """An elastokin config dict: ``template`` with its hardpoints taken from an ADAMS hardpoint
    table (a subsystem file, or an ADAMS/Car database holding one) through a mapping file, and
    the stiffness of the named bushings from property files: ``bushing_files``, else the
    mapping's ``file``, else the PROPERTY_FILE of the subsystem's ``[BUSHING_ASSEMBLY]`` of the
    mapping's ``usage``. Every path a file names must lie inside the database of
    ``hardpoints_file`` or the mapping file's folder (docs/adams.md). Not yet validated: pass
    it to :func:`elastokin.config.loading.suspension_from_dict`. ``source`` names the template
    in errors. Returns (config, warnings)."""
    roots = input_roots([hardpoints_file, mapping_file])
    mapping = read_mapping(mapping_file, roots)
    sub = subsystem_file(hardpoints_file, mapping.subsystem.get("name"), roots)
    warnings: list[str] = []
    cfg, _, _ = import_subsystem(template, sub, mapping, bushing_files, source, warnings,
                                 roots=roots)
    return cfg, warnings


def import_subsystem(config: dict, subsystem: str | Path, mapping: AdamsMapping,
                     bushing_files: Mapping[str, str | Path] | None, source: str,
                     warnings: list[str], warn_unmapped: bool = True,
                     roots: Roots | None = None
                     ) -> tuple[dict, dict[str, AdamsHardpoint], dict[str, Path]]:
    """A copy of ``config`` with the hardpoints ``mapping`` names taken from the subsystem file
    (:func:`apply_hardpoints`) and the stiffness of its bushings from their property files
    (:func:`bushing_sources`, on the mapping's side, else the config's). What was read
    tolerantly, and with ``warn_unmapped`` the hardpoints no section maps, is appended to
    ``warnings``; the files named must lie inside ``roots`` (default: the subsystem's
    database). Returns (config, the subsystem's hardpoint table, each bushing's file)."""
    points = read_hardpoints(subsystem, warnings)
    cfg, more = apply_hardpoints(config, points, mapping, source, warn_unmapped)
    warnings += more
    files = bushing_sources(subsystem, mapping, mapping.side or cfg["side"], bushing_files,
                            roots)
    props = {name: read_bushing(file) for name, file in files.items()}
    for p in props.values():
        warnings += p.warnings
    return apply_bushings(cfg, props, source), points, files
