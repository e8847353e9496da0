"""ADAMS/Car files in, for an axle (:func:`import_adams_axle`): the suspension subsystem (its
left/right pairs; where the sides differ, the other side's hardpoints and bushing laws as
``axle.other_side`` overrides), the anti-roll bar subsystem (hardpoints, mount bushings, the
torsional rate from its ``[PARAMETER]`` block or the curve file) and the steering subsystem
(hardpoints, ``rack_ratio`` and the rack's travel limit, or the ratio curve), found from the
files given, an ADAMS/Car database or an assembly file (:func:`subsystem_files`).

Pure Python/numpy. Values in elastokin units (mm, N, N*mm, deg; a ``[PARAMETER]`` value in the
subsystem's ``[UNITS]``, except ``rack_ratio``: rad/m, S.I., as ADAMS/Car gives it); points
converted from ADAMS/Car's frame (X rearward, Y right, Z up) to the template's. A corner
template is imported as before (:func:`elastokin.formats.adams.car.import_adams`).
Conventions: ``docs/adams.md``, "Axles".
"""

from __future__ import annotations

import copy
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from functools import cache
from pathlib import Path

import numpy as np

from elastokin.config.axle import MIRROR, MIRRORED_DIRECTIONS, other_side, reflected_law
from elastokin.config.confined import Roots, confined_path
from elastokin.errors import ConfigError
from elastokin.formats.adams.assemblies import read_bushing_assemblies
from elastokin.formats.adams.axle_files import rack_ratio_check, read_curve, read_parameters
from elastokin.formats.adams.car import (
    adams_to_config,
    clean,
    import_subsystem,
    lookup_hardpoint,
    read_bushing,
)
from elastokin.formats.adams.database import database_file, input_roots, subsystem_file
from elastokin.formats.adams.mapping import AdamsMapping, read_mapping
from elastokin.formats.adams.teimorbit import read_teimorbit
from elastokin.physics.joints import BUSHING_DIRECTIONS
from elastokin.physics.laws import law_from_spec

__all__ = [
    "ROLE_SECTIONS",
    "SubsystemFiles",
    "assembly_subsystems",
    "import_adams_axle",
    "subsystem_files",
    "subsystem_role",
]

#: ADAMS/Car major role -> mapping section
ROLE_SECTIONS = {"suspension": "suspension", "antirollbar": "anti_roll_bar",
                 "steering": "steering"}


@dataclass(frozen=True)
class SubsystemFiles:
    """The subsystem file of each section (None: not given)."""

    suspension: Path
    anti_roll_bar: Path | None = None
    steering: Path | None = None

    def of(self, section: str) -> Path | None:
        return getattr(self, section)


def subsystem_role(path: str | Path) -> tuple[str | None, str | None]:
    """(MAJOR_ROLE, MINOR_ROLE) of a subsystem file's ``[SUBSYSTEM_HEADER]`` (lower case;
    None, None for a file without one, e.g. a plain hardpoint table)."""
    f = read_teimorbit(path, convert=False)
    heads = f.blocks_named("SUBSYSTEM_HEADER")
    if not heads:
        return None, None
    major, minor = heads[0].value("MAJOR_ROLE"), heads[0].value("MINOR_ROLE")
    return (str(major).strip().lower() if major is not None else None,
            str(minor).strip().lower() if minor is not None else None)


def assembly_subsystems(path: str | Path, roots: Roots | None = None
                        ) -> list[tuple[Path, int]]:
    """The subsystem files an ADAMS/Car assembly (``.asy``) names in its ``[SUBSYSTEM]``
    blocks (``USAGE``, an ``mdids://`` or ``<alias>/`` path taken in the database holding the
    assembly, or a path relative to it; inside ``roots``, default that database), with the
    line of each."""
    f = read_teimorbit(path, convert=False)
    out = []
    for b in f.blocks_named("SUBSYSTEM"):
        usage = b.value("USAGE")
        if not isinstance(usage, str) or not usage.strip():
            raise f.error(b.line, b.name, "USAGE = 'subsystem file' is missing")
        line = b.entries["USAGE"].line
        out.append((database_file(usage, path, f"{f.path}, line {line}, block [SUBSYSTEM]",
                                  roots, "the subsystem file (USAGE)", must_exist=False),
                    line))
    if not out:
        raise ConfigError(f"{f.path}: no [SUBSYSTEM] block: not an ADAMS/Car assembly file")
    return out


def _pick(found: dict[str, list[tuple[Path, str | None]]], section: str, minor: str | None,
          what: str) -> Path | None:
    files = found.get(section, [])
    if len(files) > 1 and minor is not None:
        files = [f for f in files if f[1] == minor] or files
    if len(files) > 1:
        raise ConfigError(f"{what}: {len(files)} {section} subsystems "
                          f"({', '.join(str(f[0]) for f in files)}); give the minor role in "
                          "the mapping file's subsystem section")
    return files[0][0] if files else None


def subsystem_files(mapping: AdamsMapping, hardpoints: str | Path | None = None,
                    assembly: str | Path | None = None, subsystems: Sequence[str | Path] = (),
                    minor_role: str | None = None, roots: Roots | None = None
                    ) -> SubsystemFiles:
    """Which file is which subsystem: ``hardpoints`` (a subsystem file or an ADAMS/Car
    database) for the suspension, with the mapping's other subsystems found beside it by
    their names, or ``assembly`` (the subsystems it names); ``subsystems``: files whose
    ``[SUBSYSTEM_HEADER]`` says their major role (``antirollbar``, ``steering``), taken before
    those found by name. Of several subsystems of one role, the one of ``minor_role`` (front,
    rear) is taken. A file found from another must lie inside ``roots`` (default: the
    databases of the files given and the mapping's folder)."""
    found: dict[str, list[tuple[Path, str | None]]] = {}
    role = cache(subsystem_role)  # each file read once
    what = str(assembly or hardpoints)
    if roots is None:
        roots = input_roots([hardpoints, assembly, *subsystems, mapping.path])
    listed: list[tuple[Path, str]] = []
    if assembly is not None:
        for path, line in assembly_subsystems(assembly, roots):
            where = f"{assembly}, line {line}, block [SUBSYSTEM]"
            if not path.is_file():
                raise ConfigError(f"{where}: the subsystem file {path} does not exist")
            if path.suffix.lower() == ".asy" or path.resolve() == Path(assembly).resolve():
                raise ConfigError(f"{where}: USAGE names an assembly ({path}), not a subsystem "
                                  "file: an assembly of assemblies is not read")
            listed.append((path, f"{assembly}, line {line}"))
    listed += [(Path(p), str(p)) for p in subsystems]
    if hardpoints is not None:
        main = subsystem_file(hardpoints, mapping.subsystem.get("name"), roots)
        found["suspension"] = [(main, minor_role)]
        given = {role(p)[0] for p, _ in listed}
        for section, m in mapping.sections().items():
            # the mapping's other subsystems beside the suspension's, unless given
            major = next(k for k, v in ROLE_SECTIONS.items() if v == section)
            if section == "suspension" or major in given:
                continue
            path = confined_path(f"{m.subsystem.get('name')}.sub", main.parent, roots,
                                 f"{mapping.path}: key '{section}.subsystem.name'",
                                 "subsystem file")
            if path.is_file():
                listed.append((path, str(hardpoints)))
    for path, where in listed:
        major, minor = role(path)
        section = ROLE_SECTIONS.get(major or "suspension")
        if section is None:
            if assembly is None:
                raise ConfigError(f"{where}: subsystem {path} has MAJOR_ROLE '{major}'; "
                                  f"expected one of {', '.join(ROLE_SECTIONS)}")
            continue  # an assembly's wheels, body, powertrain...: not a suspension's
        found.setdefault(section, []).append((path, minor))
    if "suspension" not in found:
        raise ConfigError(f"{what}: no suspension subsystem (MAJOR_ROLE 'suspension')")
    return SubsystemFiles(*(_pick(found, s, minor_role, what)
                            for s in ("suspension", "anti_roll_bar", "steering")))


def _other_side_hardpoints(cfg: dict, points, mapping: AdamsMapping) -> None:
    """The other side's points of the mapped hardpoints: an override in
    ``axle.other_side.hardpoints`` where they are not the mirror of the config side's."""
    side = mapping.side or cfg["side"]
    over = cfg["axle"].setdefault("other_side", {}).setdefault("hardpoints", {})
    for name, (adams, hp_side) in mapping.hardpoints.items():
        where = f"{mapping.path}: key 'hardpoints.{name}'"
        hp, this = lookup_hardpoint(points, adams, hp_side, where)
        if hp.symmetry == "single":
            over.pop(name, None)
            continue
        try:
            q = adams_to_config(hp.at(other_side(this or side)), cfg["frame"])
        except ConfigError as exc:
            raise ConfigError(f"{where}: {exc}") from None
        p = np.asarray(cfg["hardpoints"][name], float)
        if np.array_equal(MIRROR @ p, q):
            over.pop(name, None)
        else:
            over[name] = [clean(v) for v in q]


def _other_side_bushings(cfg: dict, sub: Path, mapping: AdamsMapping,
                         roots: Roots | None) -> list[Path]:
    """Where a bushing's ``right`` and ``left`` blocks name different property files: the
    other side's laws, as ``axle.other_side.connections`` overrides of the directions that
    are not the mirror of the config side's. Returns the files read."""
    side = mapping.side or cfg["side"]
    blocks = read_bushing_assemblies(sub)
    over = cfg["axle"].setdefault("other_side", {}).setdefault("connections", {})
    read = []
    for name, usage in mapping.bushing_usage.items():
        sides = blocks.get(usage, {})
        a, b = sides.get(side), sides.get(other_side(side))
        if a is not None and b is not None and a.property_file != b.property_file and \
                b.property_file:
            path = database_file(b.property_file, sub, b.where(sub, b.symmetry), roots,
                                 "PROPERTY_FILE")
            read.append(path)
            other = read_bushing(path).stiffness
            this = cfg["connections"][name]["stiffness"]
            diff = {d: copy.deepcopy(other[d]) for d in BUSHING_DIRECTIONS
                    if _mirrored(this[d], d) != law_from_spec(other[d])}
            if diff:
                over[name] = {"stiffness": diff}
                continue
        over.pop(name, None)
    return read


def _mirrored(spec, direction: str):
    law = law_from_spec(spec)
    flipped = BUSHING_DIRECTIONS.index(direction) in MIRRORED_DIRECTIONS
    return reflected_law(law) if flipped else law


def _import_section(cfg: dict, sub: Path, m: AdamsMapping, bushing_files, source: str,
                    warnings: list[str], roots: Roots, warn_unmapped: bool = False
                    ) -> tuple[dict, list[Path]]:
    """The hardpoints and bushings of one section's subsystem, on an axle both sides (the
    other side's as ``axle.other_side`` overrides). Returns (config, the files read)."""
    cfg, points, files = import_subsystem(cfg, sub, m, bushing_files, source, warnings,
                                          warn_unmapped, roots)
    if "axle" not in cfg:
        return cfg, list(files.values())
    cfg["axle"] = dict(cfg["axle"] or {})
    _other_side_hardpoints(cfg, points, m)
    return cfg, [*files.values(), *_other_side_bushings(cfg, sub, m, roots)]


def import_adams_axle(template: dict, files: SubsystemFiles, mapping_file: str | Path,
                      bushing_files: Mapping[str, str | Path] | None = None,
                      source: str = "template config", roots: Roots | None = None
                      ) -> tuple[dict, list[str], list[Path]]:
    """An elastokin config dict from an axle's ADAMS/Car subsystems (module docstring):
    ``template`` (a corner, or an axle config) with the hardpoints and bushings of every
    section of the mapping file, and on an axle its other side, anti-roll bar and steering.
    Every file a file names must lie inside ``roots`` (default: the databases of ``files`` and
    the mapping file's folder). Returns (config, warnings, the property and curve files
    read). Not yet validated."""
    if roots is None:
        roots = input_roots([files.suspension, files.anti_roll_bar, files.steering,
                             mapping_file])
    mapping = read_mapping(mapping_file, roots)
    warnings: list[str] = []
    # every bushing file given is taken in the suspension's step; a section's again in its own
    cfg, read = _import_section(template, files.suspension, mapping, bushing_files, source,
                                warnings, roots, warn_unmapped=True)
    sections = mapping.sections()
    if "axle" not in cfg and len(sections) > 1:
        keys = ", ".join(k for k in sections if k != "suspension")
        raise ConfigError(f"{mapping.path}: keys {keys}: {source} is a corner (no 'axle' "
                          "section)")
    for section in ("anti_roll_bar", "steering"):
        m = sections.get(section)
        if m is None:
            if (cfg.get("axle") or {}).get(section):
                warnings.append(f"{mapping.path}: no '{section}' section: the {section} of "
                                f"{source} is kept as it was (its hardpoints from the "
                                "suspension subsystem where the mapping names them)")
            continue
        sub = files.of(section)
        if sub is None:
            raise ConfigError(f"{mapping.path}: key '{section}': no {section} subsystem given "
                              f"(import-adams --subsystem FILE.sub, an --assembly naming it, "
                              f"or a database holding '{m.subsystem.get('name', '?')}.sub')")
        if not (cfg.get("axle") or {}).get(section):
            raise ConfigError(f"{mapping.path}: key '{section}': {source} has no "
                              f"axle.{section} to take it")
        given = {k: v for k, v in (bushing_files or {}).items()
                 if k in m.bushings or k in m.bushing_usage}
        cfg, more = _import_section(cfg, sub, m, given, source, warnings, roots)
        read += more
        read += _section_values(cfg, section, sub, m)
    _tidy(cfg)
    return cfg, warnings, read


def _section_values(cfg: dict, section: str, sub: Path, m: AdamsMapping) -> list[Path]:
    """The anti-roll bar's rate or curve, the steering's ratio or curve and travel limit."""
    spec = cfg["axle"][section] = dict(cfg["axle"][section])
    params = read_parameters(sub)
    curve = m.curve_file()  # inside the folders given
    if section == "anti_roll_bar":
        if curve is not None:
            u, f = read_curve(curve, ("rot", "torque"))
            spec.pop("rate_Nmm_per_deg", None)
            spec["curve"] = {"deflection": u, "load": f}
            return [curve]
        spec.pop("curve", None)
        spec["rate_Nmm_per_deg"] = params.positive(m.parameters["stiffness"],
                                                   "rotational_stiffness",
                                                   "the anti-roll bar's torsional rate")
        return []
    spec["limit_mm"] = params.positive(m.parameters["travel_limit"], "length",
                                       "the rack's travel limit each way")
    if curve is not None:
        u, x = read_curve(curve, ("rot", "disp"))
        spec.pop("ratio_mm_per_rev", None)
        spec["ratio_curve"] = {"steering_wheel_deg": u, "rack_travel_mm": x}
        return [curve]
    spec.pop("ratio_curve", None)
    spec["ratio_mm_per_rev"] = rack_ratio_check(params, m.parameters["rack_ratio"])
    return []


def _tidy(cfg: dict) -> None:
    """Empty ``axle.other_side`` entries left out."""
    axle = cfg.get("axle")
    if not isinstance(axle, dict) or "other_side" not in axle:
        return
    o = axle["other_side"]
    for k in ("hardpoints", "connections"):
        if k in o and not o[k]:
            del o[k]
    if not o:
        del axle["other_side"]
