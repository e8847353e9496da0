"""ADAMS/Car files out (:func:`export_adams`): an ADAMS/Car database folder holding the
subsystem file, a bushing property file per bushing and a spring property file per spring, and
the mapping file that imports them back.

Layout of ``out_dir`` (name it ``<database>.cdb``)::

    subsystems.tbl/<name>.sub   [SUBSYSTEM_HEADER], [HARDPOINT], [BUSHING_ASSEMBLY]s,
                                [NSPRING_ASSEMBLY]s (PROPERTY_FILE 'mdids://<database>/...')
    bushings.tbl/<usage>.bus    one per bushing
    springs.tbl/<usage>.spr     one per spring
    mapping.yaml                elastokin <-> ADAMS names, for import-adams

Files are written in mm, newton, deg, kg, sec; hardpoints in ADAMS/Car's global frame (X
rearward, Y right, Z up), curves and preloads in the bushing frame. Writers are deterministic
except the subsystem's TIMESTAMP (the current time, or ``SOURCE_DATE_EPOCH`` when set).
Conventions: ``docs/adams.md``.
"""

from __future__ import annotations

import os
import time
from collections.abc import Iterable, Mapping
from pathlib import Path

import numpy as np

from elastokin.config.suspension import Suspension
from elastokin.errors import ConfigError
from elastokin.formats.adams_car import clean
from elastokin.formats.adams_mapping import AdamsMapping, config_to_adams, frame_signs
from elastokin.formats.adams_property_files import (
    bushing_file_text,
    number,
    spring_file_text,
)
from elastokin.formats.adams_subsystem import (
    AssemblyRow,
    SubsystemSpec,
    hardpoint_rows,
    safe_name,
    subsystem_text,
)
from elastokin.formats.config_yaml import dump_config
from elastokin.physics.pose import euler_zxz_deg
from elastokin.version import __version__

__all__ = [
    "bushing_file_text",
    "export_adams",
    "export_timestamp",
    "mapping_text",
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
                   warnings: list[str] | None = None) -> SubsystemSpec:
    """The subsystem's name, template, roles and database alias: the arguments, else the
    mapping file's ``subsystem`` section, else defaults (name: the config's name; database: the
    subsystem's name; roles: suspension, front; template: ``_<name>.tpl`` in the database, with
    a warning). A bare template name (``_double_wishbone``) is taken in ``acar_shared``."""
    sub = mapping.subsystem if mapping else {}
    name = safe_name(sub.get("name") or s.name)
    db = safe_name(database or sub.get("database") or name)
    tpl = template or sub.get("template")
    if not tpl:
        tpl = f"mdids://{db}/templates.tbl/_{name}.tpl"
        if warnings is not None:
            warnings.append(f"no template given (export-adams --template-name, or "
                            f"'subsystem: template' in the mapping file): the subsystem names "
                            f"{tpl}, which ADAMS/Car needs to open it")
    elif "/" not in tpl and "\\" not in tpl:
        tpl = f"mdids://acar_shared/templates.tbl/{tpl.removesuffix('.tpl')}.tpl"
    return SubsystemSpec(name, tpl, major_role or sub.get("major_role") or "suspension",
                         minor_role or sub.get("minor_role") or "front", db)


def _usages(names: Iterable[str], given: Mapping[str, str], what: str,
            source: str) -> dict[str, str]:
    out: dict[str, str] = {}
    for n in names:
        usage = safe_name(given.get(n, n))
        if usage in out.values():
            other = next(k for k, v in out.items() if v == usage)
            raise ConfigError(f"{source}: {what} {other} and {n} both have the ADAMS usage "
                              f"'{usage}'")
        out[n] = usage
    return out


def _bushing_rows(s: Suspension, spec: SubsystemSpec, usages: Mapping[str, str],
                  preload: Mapping[str, Iterable[float]]) -> list[AssemblyRow]:
    signs = np.diag(frame_signs(s.frame))
    rows = []
    for b in s.bushings:
        if b.name not in preload:
            raise ConfigError(f"{s.source}: no preload given for bushing '{b.name}'")
        p = [clean(round(float(v), 6)) for v in preload[b.name]]
        loc = config_to_adams(b.position_mm, s.frame)
        euler = euler_zxz_deg(signs @ b.frame)
        comments = (f"$ elastokin bushing {b.name}: I part {b.parts[0]}, J part {b.parts[1]} "
                    f"({s.side} corner)",
                    "$   location " + " ".join(number(round(v, 9)) for v in loc) + " mm",
                    "$   orientation body-313 " + " ".join(number(round(v, 9)) for v in euler)
                    + " deg (the template's orientation is used by ADAMS/Car)")
        values = (("INACTIVE_BEHAVIOR", "normal"),
                  *((f"T_PRELOAD_{a}", v) for a, v in zip("XYZ", p[:3])),
                  *((f"R_PRELOAD_{a}", v) for a, v in zip("XYZ", p[3:])),
                  *((f"{k}_OFFSET_{a}", 0.0) for k in "TR" for a in "XYZ"))
        rows.append(AssemblyRow(usages[b.name], spec.path("bushings.tbl",
                                                          f"{usages[b.name]}.bus"),
                                values, comments))
    return rows


def _spring_rows(s: Suspension, spec: SubsystemSpec, usages: Mapping[str, str],
                 force: Mapping[str, float]) -> list[AssemblyRow]:
    rows = []
    for sp in s.springs:
        f = force.get(sp.name, sp.design_force_N())
        comments = (f"$ elastokin spring {sp.name}: {sp.parts[0]} -> {sp.parts[1]}, rate "
                    f"{sp.rate_N_per_mm:g} N/mm, installed length "
                    f"{sp.installed_length_mm:.3f} mm",)
        rows.append(AssemblyRow(usages[sp.name], spec.path("springs.tbl",
                                                           f"{usages[sp.name]}.spr"),
                                (("VALUE_TYPE", "preload"),
                                 ("USER_VALUE", clean(round(float(f), 6)))), comments))
    return rows


def mapping_text(s: Suspension, spec: SubsystemSpec, written: Mapping[str, tuple[str, str]],
                 bushings: Mapping[str, str], springs: Mapping[str, str]) -> str:
    """The mapping file that imports the exported database back into ``s``'s config."""
    data = {"elastokin_adams_mapping": 1, "side": s.side,
            "subsystem": {"name": spec.name, "template": spec.template,
                          "major_role": spec.major_role, "minor_role": spec.minor_role,
                          "database": spec.database},
            "hardpoints": {n: (a if side in ("single", s.side) else {"adams": a, "side": side})
                           for n, (a, side) in written.items()},
            "bushings": {n: {"file": f"bushings.tbl/{u}.bus", "usage": u}
                         for n, u in bushings.items()},
            "springs": {n: {"usage": u} for n, u in springs.items()}}
    head = [f"elastokin {__version__}: mapping of the ADAMS/Car database exported from "
            f"'{s.name}'", "(docs/adams.md): elastokin name: ADAMS name; bushings: property "
            "file (relative to this file) and usage"]
    return dump_config(data, "\n".join(head), flow=False)


def export_adams(s: Suspension, out_dir: str | Path,
                 bushing_preload: Mapping[str, Iterable[float]] | None = None,
                 range_mm: float = 10.0, range_deg: float = 10.0, *,
                 spring_force: Mapping[str, float] | None = None,
                 mapping: AdamsMapping | None = None, spec: SubsystemSpec | None = None,
                 timestamp: str | None = None, warnings: list[str] | None = None
                 ) -> list[Path]:
    """Write ``out_dir`` as an ADAMS/Car database (module docstring); returns the paths written.

    ``bushing_preload``: loads at the design position per bushing (N, N*mm, bushing frame),
    e.g. :attr:`elastokin.config.variants.DesignState.bushing_preload` (from
    :func:`elastokin.mbs.design.design_state`); needed when the config balances them
    (``design.balance_bushing_preloads``), else taken from its preload or initial deflection.
    ``spring_force``: compression force per spring at its installed length (default: the
    config's). ``mapping``: elastokin -> ADAMS names and the template; ``spec`` (default:
    :func:`subsystem_spec` with ``out_dir``'s name, less ``.cdb``, as the database alias)."""
    if not (range_mm > 0 and range_deg > 0):
        raise ConfigError(f"table range must be positive, got {range_mm} mm / {range_deg} deg")
    if bushing_preload is None:
        if s.design.balance_bushing_preloads and s.bushings:
            raise ConfigError(f"{s.source}: design.balance_bushing_preloads: the bushing "
                              "preloads must be solved first (elastokin.mbs.design.design_state)")
        bushing_preload = {b.name: [law(u) for law, u in zip(b.laws, b.initial_deflection)]
                           for b in s.bushings}
    spec = spec or subsystem_spec(s, mapping, Path(out_dir).name.removesuffix(".cdb"),
                                  warnings=warnings)
    rows, written = hardpoint_rows(s, mapping)
    source = mapping.path if mapping else s.source
    bushings = _usages([b.name for b in s.bushings], mapping.bushing_usage if mapping else {},
                       "bushings", source)
    springs = _usages([sp.name for sp in s.springs], mapping.spring_usage if mapping else {},
                      "springs", source)
    out = Path(out_dir)
    files = {f"subsystems.tbl/{spec.name}.sub": subsystem_text(
        s, spec, rows, _bushing_rows(s, spec, bushings, bushing_preload),
        _spring_rows(s, spec, springs, spring_force or {}), timestamp or export_timestamp())}
    for b in s.bushings:
        files[f"bushings.tbl/{bushings[b.name]}.bus"] = bushing_file_text(s, b.name, range_mm,
                                                                          range_deg)
    for sp in s.springs:
        files[f"springs.tbl/{springs[sp.name]}.spr"] = spring_file_text(
            s, sp.name, (spring_force or {}).get(sp.name))
    files["mapping.yaml"] = mapping_text(s, spec, written, bushings, springs)
    written_paths = []
    for rel, text in files.items():
        path = out / rel
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text, encoding="utf-8", newline="\n")
        written_paths.append(path)
    return written_paths
