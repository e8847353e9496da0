"""ADAMS/Car files in: bushing property files (``.bus``), hardpoint tables, the mapping file,
frames, and :func:`import_adams` (an elastokin config from them).

Pure Python/numpy (no Exudyn). Values are in elastokin units (mm, N, N*mm, deg), converted on
reading by :mod:`elastokin.formats.teimorbit`. ADAMS/Car's global frame is X rearward, Y right,
Z up; a ``left/right`` hardpoint pair stores its left point (Y < 0), the right one is its Y
mirror. :func:`adams_to_config` / :func:`config_to_adams` convert explicitly to and from the
config's ``frame`` (``{x: rearward|forward, y: right|left}``, z up, same origin). Bushing curves
are in the bushing frame, piecewise linear (:mod:`elastokin.physics.laws`). Conventions:
``docs/adams.md``.
"""

from __future__ import annotations

import copy
import math
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from elastokin.config.loading import read_yaml
from elastokin.errors import ConfigError
from elastokin.formats.teimorbit import Units, read_teimorbit
from elastokin.physics.joints import BUSHING_DIRECTIONS
from elastokin.physics.laws import DirectionLaw

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
    "clean",
    "config_to_adams",
    "frame_signs",
    "import_adams",
    "read_bushing",
    "read_bushing_assemblies",
    "read_hardpoints",
    "read_mapping",
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
        stiffness[direction] = {"deflection": [clean(x) for x in u],
                                "load": [clean(x) for x in load]}
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


def clean(x: float) -> float:
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


def frame_signs(frame) -> np.ndarray:
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
    return frame_signs(frame) * np.asarray(point, float)


def config_to_adams(point, frame) -> np.ndarray:
    """A point (mm) or direction from the config frame ``frame`` to ADAMS/Car's global frame."""
    return frame_signs(frame) * np.asarray(point, float)


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
    data, _ = read_yaml(path, "ADAMS mapping file")  # strict YAML: no key twice
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
        cfg["hardpoints"][name] = [clean(v) for v in p]
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
    it to :func:`elastokin.config.loading.suspension_from_dict`. ``source`` names the template in
    errors. Returns (config, warnings)."""
    mapping = read_mapping(mapping_file)
    cfg, warnings = apply_hardpoints(template, read_hardpoints(hardpoints_file), mapping,
                                     source)
    files = {**mapping.bushings, **{k: Path(v) for k, v in (bushing_files or {}).items()}}
    props = {name: read_bushing(file) for name, file in files.items()}
    for p in props.values():
        warnings += p.warnings
    return apply_bushings(cfg, props, source), warnings


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
