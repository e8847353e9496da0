"""ADAMS/Car files out (:func:`export_adams`): an ADAMS/Car database folder holding the
subsystem file, a bushing property file per bushing and a spring property file per spring, and
the mapping file that imports them back. An axle is written as ADAMS/Car keeps one: the
suspension subsystem (its ``left/right`` pairs symmetric when the axle is mirrored, a ``left``
and a ``right`` row or block where ``axle.other_side`` makes the sides differ), an anti-roll bar
subsystem and a steering subsystem (:mod:`elastokin.formats.adams.axle`), and a suspension
assembly naming them.

Layout of ``out_dir`` (name it ``<database>.cdb``)::

    subsystems.tbl/<name>.sub   [SUBSYSTEM_HEADER], [HARDPOINT], [BUSHING_ASSEMBLY]s,
                                [NSPRING_ASSEMBLY]s (PROPERTY_FILE 'mdids://<database>/...'),
                                [PARAMETER] (anti-roll bar, steering)
    bushings.tbl/<usage>.bus    one per bushing (and side, where the sides differ)
    springs.tbl/<usage>.spr     one per spring
    dampers.tbl/<usage>.dpr     one per damper with a rate (its [DAMPER_ASSEMBLY] too)
    curves.tbl/<role>.crv       a nonlinear anti-roll bar or rack ratio (elastokin's file)
    assemblies.tbl/<name>.asy   an axle with an anti-roll bar or steering: the assembly
    mapping.yaml                elastokin <-> ADAMS names, for import-adams

Files are written in mm, newton, deg, kg, sec (``rack_ratio``: rad/m, as ADAMS/Car gives it);
hardpoints in ADAMS/Car's global frame (X rearward, Y right, Z up), curves and preloads in the
bushing frame. Writers are deterministic except the TIMESTAMPs (the current time, or
``SOURCE_DATE_EPOCH`` when set). Conventions: ``docs/adams.md``.
"""

from __future__ import annotations

import os
import re
import time
from collections.abc import Iterable, Mapping
from dataclasses import replace
from pathlib import Path

from elastokin.config.suspension import Suspension
from elastokin.errors import ConfigError
from elastokin.formats.adams.assembly_rows import bushing_rows, damper_rows, spring_rows
from elastokin.formats.adams.axle import (
    AXLE_ROLES,
    arb_parameters,
    assembly_text,
    axle_subsystems,
    curve_file_text,
    kept_once_hardpoints,
    steering_parameters,
)
from elastokin.formats.adams.mapping import PARAMETER_KEYS, AdamsMapping
from elastokin.formats.adams.property_files import (
    bushing_file_text,
    damper_file_text,
    spring_file_text,
)
from elastokin.formats.adams.subsystem import (
    MINOR_ROLES,
    SubsystemSpec,
    adams_role,
    file_name,
    hardpoint_rows,
    safe_name,
    subsystem_text,
    template_path,
)
from elastokin.formats.config_yaml import dump_config
from elastokin.version import __version__

__all__ = [
    "bushing_file_text",
    "export_adams",
    "export_timestamp",
    "mapping_text",
    "section_spec",
    "spring_file_text",
    "subsystem_spec",
]


def export_timestamp() -> str:
    """``YYYY/MM/DD,hh:mm:ss`` (UTC) of now, or of ``SOURCE_DATE_EPOCH`` when it is set."""
    epoch = os.environ.get("SOURCE_DATE_EPOCH", "").strip()
    t = float(epoch) if epoch.isdigit() else time.time()
    return time.strftime("%Y/%m/%d,%H:%M:%S", time.gmtime(t))


def subsystem_spec(s: Suspension, mapping: AdamsMapping | None = None,
                   database: str | None = None, template: str | None = None,
                   major_role: str | None = None, minor_role: str | None = None,
                   warnings: list[str] | None = None, default_database: str | None = None
                   ) -> SubsystemSpec:
    """The subsystem's name, template, roles and database alias: the arguments
    (``export-adams``'s ``--database``, ``--template-name``, ``--major-role``,
    ``--minor-role``), else the mapping file's ``subsystem`` section, else defaults (name: the
    config's name; database: ``default_database``, else the subsystem's name; roles:
    suspension, front (an axle's ``vehicle.position``); template: ``_<name>.tpl`` in the
    database, with a warning). A bare template name (``_double_wishbone``) is taken in
    ``acar_shared``. What is given must be what ADAMS/Car and ``import-adams`` read
    (:func:`~elastokin.formats.adams.subsystem.template_path`, ``file_name``, ``adams_role``):
    an error names the option or the mapping key."""
    sub = mapping.subsystem if mapping else {}

    def given(arg: str | None, option: str, key: str) -> tuple[str | None, str]:
        if arg is not None:
            return arg, f"export-adams {option}"
        return sub.get(key), f"{mapping.path if mapping else ''}: key 'subsystem.{key}'"

    name, where = given(None, "", "name")
    name = file_name(name, where) if name else safe_name(s.name)
    db, where = given(database, "--database", "database")
    db = file_name(db, where) if db else safe_name(default_database or name)
    tpl, where = given(template, "--template-name", "template")
    if tpl:
        tpl = template_path(tpl, where)
    else:
        tpl = f"mdids://{db}/templates.tbl/_{re.sub(r'[^A-Za-z0-9_]', '_', name)}.tpl"
        if warnings is not None:
            warnings.append(f"no template given (export-adams --template-name, or "
                            f"'subsystem: template' in the mapping file): the subsystem names "
                            f"{tpl}, which ADAMS/Car needs to open it")
    major, where = given(major_role, "--major-role", "major_role")
    major = adams_role(major, ("suspension",), "the major role of a suspension subsystem",
                       where) if major else "suspension"
    minor, where = given(minor_role, "--minor-role", "minor_role")
    position = s.axle.vehicle.position if s.axle is not None and s.axle.vehicle else "front"
    minor = adams_role(minor, MINOR_ROLES, "a minor role", where) if minor else position
    return SubsystemSpec(name, tpl, major, minor, db)


def _usages(names: Iterable[str], given: Mapping[str, str], what: str,
            source: str) -> dict[str, str]:
    """Each bushing's or spring's USAGE: the mapping's (checked: it names the property file),
    else its elastokin name made a file name."""
    out: dict[str, str] = {}
    for n in names:
        usage = file_name(given[n], f"{source}: key '{what}.{n}.usage'") if n in given else \
            safe_name(n)
        if usage in out.values():
            other = next(k for k, v in out.items() if v == usage)
            raise ConfigError(f"{source}: {what} {other} and {n} both have the ADAMS usage "
                              f"'{usage}'")
        out[n] = usage
    return out


def section_spec(s: Suspension, mapping: AdamsMapping | None, role: str,
                 suspension: SubsystemSpec) -> SubsystemSpec:
    """The anti-roll bar's or steering's subsystem: the mapping section's ``subsystem``, else
    ``<suspension name>_<role>``, ADAMS/Car's template and major role for it, the
    suspension's minor role and database (what is given checked as by
    :func:`subsystem_spec`)."""
    section = getattr(mapping, role, None) if mapping else None
    sub = section.subsystem if section else {}
    major, template = AXLE_ROLES[role]

    def where(key: str) -> str:
        return f"{mapping.path if mapping else ''}: key '{role}.subsystem.{key}'"

    default = {"anti_roll_bar": "antiroll", "steering": "steering"}[role]
    name = file_name(sub["name"], where("name")) if "name" in sub else \
        f"{suspension.name}_{default}"
    if "major_role" in sub:
        major = adams_role(sub["major_role"], (major,),
                           f"the major role of the {role.replace('_', '-')} subsystem",
                           where("major_role"))
    minor = adams_role(sub["minor_role"], MINOR_ROLES, "a minor role", where("minor_role")) \
        if "minor_role" in sub else suspension.minor_role
    db = file_name(sub["database"], where("database")) if "database" in sub else \
        suspension.database
    return SubsystemSpec(name, template_path(sub.get("template") or template,
                                             where("template")), major, minor, db)


def _section(mapping: AdamsMapping | None, role: str) -> AdamsMapping | None:
    """The mapping of a subsystem's names: its section's, else the suspension section's
    (a mapping written before the anti-roll bar and steering had subsystems of their own)."""
    if mapping is None or role == "suspension":
        return mapping
    own = getattr(mapping, role)
    if own is None:
        return replace(mapping, subsystem={}, anti_roll_bar=None, steering=None)
    return replace(own, hardpoints={**mapping.hardpoints, **own.hardpoints},
                   bushing_usage={**mapping.bushing_usage, **own.bushing_usage})


def _parameters(s: Suspension, role: str, mapping: AdamsMapping | None):
    """A subsystem's [PARAMETER] rows and its section's keys in the mapping file written: the
    parameter names (the mapping's, else the defaults) and, for a nonlinear bar or rack
    ratio, ``curve``: the curve file."""
    if role == "suspension":
        return [], {}
    section = getattr(mapping, role, None) if mapping else None
    keys = dict(section.parameters if section else PARAMETER_KEYS[role])
    raw = s.raw["axle"][role]
    curve = None if raw.get("curve") is None and raw.get("ratio_curve") is None else \
        f"curves.tbl/{role}.crv"
    make = arb_parameters if role == "anti_roll_bar" else steering_parameters
    rows = make(s, keys, curve)
    if curve is not None:
        keys["curve"] = curve
    return rows, keys


def mapping_text(s: Suspension, specs: Mapping[str, SubsystemSpec],
                 written: Mapping[str, Mapping[str, tuple[str, str]]],
                 bushings: Mapping[str, Mapping[str, str]], springs: Mapping[str, str],
                 extra: Mapping[str, dict] | None = None,
                 dampers: Mapping[str, str] | None = None) -> str:
    """The mapping file that imports the exported database back into ``s``'s config: per
    subsystem (``specs``, by section) its names (``written``: elastokin hardpoint -> (ADAMS
    name, side); ``bushings``: elastokin bushing -> usage), the springs' and dampers' usages
    and each section's ``extra`` keys (parameter names, curve file)."""
    def section(role: str) -> dict:
        spec = specs[role]
        out = {"subsystem": {"name": spec.name, "template": spec.template,
                             "major_role": spec.major_role, "minor_role": spec.minor_role,
                             "database": spec.database}}
        if written[role]:
            out["hardpoints"] = {n: (f"hps_{a}" if side == "single" else a if side == s.side
                                     else {"adams": a, "side": side})
                                 for n, (a, side) in written[role].items()}
        if bushings[role] or role == "suspension":
            out["bushings"] = {n: {"file": f"bushings.tbl/{u}.bus", "usage": u}
                               for n, u in bushings[role].items()}
        return out

    data = {"elastokin_adams_mapping": 1, "side": s.side, **section("suspension"),
            "springs": {n: {"usage": u} for n, u in springs.items()},
            **({"dampers": {n: {"usage": u} for n, u in dampers.items()}} if dampers else {})}
    for role in ("anti_roll_bar", "steering"):
        if role in specs:
            data[role] = {**section(role), **(extra or {}).get(role, {})}
    head = [f"elastokin {__version__}: mapping of the ADAMS/Car database exported from "
            f"'{s.name}'", "(docs/adams.md): elastokin name: ADAMS name; bushings: property "
            "file (relative to this file) and usage"]
    return dump_config(data, "\n".join(head), flow=False)


def beam_warning(s: Suspension) -> str:
    """What the export leaves out of a suspension with flexible beam parts."""
    names = ", ".join(f"'{b.part}'" for b in s.beams)
    return (f"the flexible beam part(s) {names} are not exported: ADAMS/Car takes a twist "
            "beam's cross beam as a flexible body (an MNF from a finite-element model: "
            "_twist_beam_advanced, configuration 'Flexible body') or as its template's own "
            "beam parts, neither of which a subsystem file carries; its nodes are exported as "
            "hardpoints and its section is written in the subsystem file's header comments, "
            "and import-adams takes the beam from the template config")


def _preloads(s: Suspension, bushing_preload):
    if bushing_preload is not None:
        return bushing_preload
    if s.design.balance_bushing_preloads and s.bushings:
        raise ConfigError(f"{s.source}: design.balance_bushing_preloads: the bushing "
                          "preloads must be solved first (elastokin.mbs.design.design_state)")
    return {b.name: [law(u) for law, u in zip(b.laws, b.initial_deflection)]
            for b in s.bushings}


def export_adams(s: Suspension, out_dir: str | Path,
                 bushing_preload: Mapping[str, Iterable[float]] | None = None,
                 range_mm: float = 10.0, range_deg: float = 10.0, *,
                 spring_force: Mapping[str, float] | None = None,
                 mapping: AdamsMapping | None = None, spec: SubsystemSpec | None = None,
                 timestamp: str | None = None, warnings: list[str] | None = None
                 ) -> list[Path]:
    """Write ``out_dir`` as an ADAMS/Car database (module docstring); returns the paths written.

    ``bushing_preload``: loads at the design position per bushing (N, N*mm, bushing frame; on
    an axle every bushing of both sides), e.g.
    :attr:`elastokin.config.variants.DesignState.bushing_preload` (from
    :func:`elastokin.mbs.design.design_state`); needed when the config balances them
    (``design.balance_bushing_preloads``), else taken from its preload or initial deflection.
    ``spring_force``: compression force per spring at its installed length (default: the
    config's). ``mapping``: elastokin -> ADAMS names and the templates; ``spec``: the
    suspension subsystem's (default: :func:`subsystem_spec` with ``out_dir``'s name, less
    ``.cdb``, as the database alias)."""
    if not (range_mm > 0 and range_deg > 0):
        raise ConfigError(f"table range must be positive, got {range_mm} mm / {range_deg} deg")
    preload = _preloads(s, bushing_preload)
    force = spring_force or {}
    spec = spec or subsystem_spec(s, mapping, warnings=warnings,
                                  default_database=Path(out_dir).name.removesuffix(".cdb"))
    if s.beams and warnings is not None:
        warnings.append(beam_warning(s))
    parts = axle_subsystems(s)
    specs = {role: spec if role == "suspension" else section_spec(s, mapping, role, spec)
             for role in parts}
    names = [p.name for p in specs.values()]
    if len(set(names)) < len(names):
        raise ConfigError(f"{mapping.path if mapping else s.source}: two subsystems are both "
                          f"named '{[n for n in names if names.count(n) > 1][0]}'")
    source = mapping.path if mapping else s.source
    given = {k: v for role in parts for k, v in
             (_section(mapping, role).bushing_usage if mapping else {}).items()}
    usages = _usages([b for p in parts.values() for b in p.bushings], given, "bushings", source)
    springs = _usages(parts["suspension"].springs, mapping.spring_usage if mapping else {},
                      "springs", source)
    dampers = _usages(parts["suspension"].dampers, mapping.damper_usage if mapping else {},
                      "dampers", source)
    unrated = [d.name for d in s.dampers if d.name in dampers and d.rate_N_s_per_mm is None]
    if unrated and warnings is not None:
        warnings.append(f"damper(s) {', '.join(unrated)} without rate_N_s_per_mm: their points "
                        "are exported, no [DAMPER_ASSEMBLY] (its property file needs the rate)")
    stamp = timestamp or export_timestamp()
    files, bus_files, written, extra = {}, {}, {}, {}
    for role, part in parts.items():
        sp = specs[role]
        rows, written[role] = hardpoint_rows(s, _section(mapping, role), part.hardpoints,
                                             kept_once_hardpoints(s))
        brows, more = bushing_rows(s, sp, part.bushings, usages, preload)
        bus_files.update(more)
        params, extra[role] = _parameters(s, role, mapping)
        files[f"subsystems.tbl/{sp.name}.sub"] = subsystem_text(
            s, sp, rows, brows, spring_rows(s, sp, part.springs, springs, force), stamp, params,
            damper_rows(s, sp, part.dampers, dampers))
    for file, name in bus_files.items():
        files[f"bushings.tbl/{file}"] = bushing_file_text(s, name, range_mm, range_deg)
    for name in parts["suspension"].springs:
        files[f"springs.tbl/{springs[name]}.spr"] = spring_file_text(s, name, force.get(name))
    for name in parts["suspension"].dampers:
        if name not in unrated:
            files[f"dampers.tbl/{dampers[name]}.dpr"] = damper_file_text(s, name)
    for role, keys in extra.items():
        if "curve" in keys:
            files[keys["curve"]] = curve_file_text(s, role)
    if len(parts) > 1:
        files[f"assemblies.tbl/{spec.name}.asy"] = assembly_text(s, specs, stamp)
    files["mapping.yaml"] = mapping_text(
        s, specs, written, {r: {b: usages[b] for b in p.bushings} for r, p in parts.items()},
        springs, extra, dampers)
    out = Path(out_dir)
    paths = []
    for rel, text in files.items():
        path = out / rel
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text, encoding="utf-8", newline="\n")
        paths.append(path)
    return paths
