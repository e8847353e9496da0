"""The ``[BUSHING_ASSEMBLY]``, ``[NSPRING_ASSEMBLY]`` and ``[DAMPER_ASSEMBLY]`` blocks of an
exported subsystem, with their SYMMETRY: ``left/right`` (one block, the same values on both
sides: a corner, or an axle whose other side is the mirror), ``single`` (a bushing declared once
on an axle, between shared parts or the ground), or a ``left`` and a ``right`` block when the
two sides of an axle differ (``axle.other_side``): each side's preload or spring force, and for
a bushing whose laws differ its own property file ``<usage>_<side>.bus``.

Pure Python/numpy. Preloads are in each bushing's frame (the other side's in its mirrored frame,
:mod:`elastokin.config.axle`), N and N*mm, elastokin's ``+K*u`` convention, rounded to 1e-6;
spring forces N (compression). Conventions: ``docs/adams.md``.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping

import numpy as np

from elastokin.config.axle import MIRROR_SIGNS, mirrored_laws, other_side
from elastokin.config.suspension import Bushing, Suspension
from elastokin.errors import ConfigError
from elastokin.formats.adams.car import clean
from elastokin.formats.adams.mapping import config_to_adams, frame_signs
from elastokin.formats.adams.property_files import number
from elastokin.formats.adams.subsystem import AssemblyRow, SubsystemSpec
from elastokin.physics.pose import euler_zxz_deg

__all__ = ["bushing_rows", "damper_rows", "is_mirrored_axle", "spring_rows"]

#: relative difference under which the two sides' preloads or spring forces are the same
SAME_LOAD_RTOL = 1e-6


def is_mirrored_axle(s: Suspension) -> bool:
    """An axle whose other side is exactly the mirror of the config's (no ``other_side``)."""
    if s.axle is None:
        return False
    o = (s.raw.get("axle") or {}).get("other_side") or {}
    return not o.get("hardpoints") and not o.get("connections")


def _other(s: Suspension, name: str, items) -> object | None:
    """The other side's copy of corner item ``name`` (None: declared once, or a corner)."""
    if s.axle is None:
        return None
    return next((x for x in items if x.name == name + s.axle.suffix), None)


def _sides(s: Suspension) -> tuple[str, str]:
    return s.side, other_side(s.side)


def _same(a, b) -> bool:
    a, b = np.asarray(a, float), np.asarray(b, float)
    return bool(np.all(np.abs(a - b) <= SAME_LOAD_RTOL * np.maximum(1.0, np.abs(a))))


def _bushing_row(s: Suspension, spec: SubsystemSpec, b: Bushing, usage: str, file: str,
                 preload: Mapping[str, Iterable[float]], side: str, symmetry: str
                 ) -> AssemblyRow:
    if b.name not in preload:
        raise ConfigError(f"{s.source}: no preload given for bushing '{b.name}'")
    p = [clean(round(float(v), 6)) for v in preload[b.name]]
    loc = config_to_adams(b.position_mm, s.frame)
    euler = euler_zxz_deg(np.diag(frame_signs(s.frame)) @ b.frame)
    comments = (f"$ elastokin bushing {b.name}: I part {b.parts[0]}, J part {b.parts[1]} "
                f"({side} corner)",
                "$   location " + " ".join(number(round(v, 9)) for v in loc) + " mm",
                "$   orientation body-313 " + " ".join(number(round(v, 9)) for v in euler)
                + " deg (the template's orientation is used by ADAMS/Car)")
    values = (("INACTIVE_BEHAVIOR", "normal"),
              *((f"T_PRELOAD_{a}", v) for a, v in zip("XYZ", p[:3])),
              *((f"R_PRELOAD_{a}", v) for a, v in zip("XYZ", p[3:])),
              *((f"{k}_OFFSET_{a}", 0.0) for k in "TR" for a in "XYZ"))
    return AssemblyRow(usage, spec.path("bushings.tbl", file), values, comments, symmetry)


def bushing_rows(s: Suspension, spec: SubsystemSpec, names: Iterable[str],
                 usages: Mapping[str, str], preload: Mapping[str, Iterable[float]]
                 ) -> tuple[list[AssemblyRow], dict[str, str]]:
    """The bushing blocks of the corner bushings ``names`` (module docstring) and the
    property files they name: ``bushings.tbl`` file name -> the elastokin bushing whose laws
    it holds."""
    rows, files = [], {}
    mirrored = is_mirrored_axle(s)
    this, that = _sides(s)
    for name in names:
        b = next(x for x in s.bushings if x.name == name)
        usage = usages[name]
        file = f"{usage}.bus"
        files[file] = name
        other = _other(s, name, s.bushings)
        if other is None or mirrored:
            symmetry = "single" if s.axle is not None and other is None else "left/right"
            rows.append(_bushing_row(s, spec, b, usage, file, preload, this, symmetry))
            continue
        same_laws = mirrored_laws(b.laws) == other.laws
        if same_laws and other.name in preload and b.name in preload and \
                _same(MIRROR_SIGNS * np.asarray(preload[b.name], float), preload[other.name]):
            rows.append(_bushing_row(s, spec, b, usage, file, preload, this, "left/right"))
            continue
        other_file = file if same_laws else f"{usage}_{that}.bus"
        files[other_file] = other.name
        pair = {this: _bushing_row(s, spec, b, usage, file, preload, this, this),
                that: _bushing_row(s, spec, other, usage, other_file, preload, that, that)}
        rows += [pair["left"], pair["right"]]  # as ADAMS/Car writes a pair
    return rows, files


def spring_rows(s: Suspension, spec: SubsystemSpec, names: Iterable[str],
                usages: Mapping[str, str], force: Mapping[str, float]) -> list[AssemblyRow]:
    """The spring blocks of the corner springs ``names``: USER_VALUE the design compression
    force (N), per side when the two sides of an axle differ."""
    rows = []
    this, that = _sides(s)
    for name in names:
        sp = next(x for x in s.springs if x.name == name)
        comments = (f"$ elastokin spring {sp.name}: {sp.parts[0]} -> {sp.parts[1]}, rate "
                    f"{sp.rate_N_per_mm:g} N/mm, installed length "
                    f"{sp.installed_length_mm:.3f} mm",)
        file = spec.path("springs.tbl", f"{usages[name]}.spr")
        f = clean(round(float(force.get(name, sp.design_force_N())), 6))
        other = _other(s, name, s.springs)
        g = None if other is None else clean(round(float(force.get(
            other.name, other.design_force_N())), 6))
        if other is None or is_mirrored_axle(s) or _same(f, g):
            symmetry = "single" if s.axle is not None and other is None else "left/right"
            rows.append(AssemblyRow(usages[name], file, (("VALUE_TYPE", "preload"),
                                                         ("USER_VALUE", f)), comments, symmetry))
            continue
        values = {this: f, that: g}
        rows += [AssemblyRow(usages[name], file, (("VALUE_TYPE", "preload"),
                                                  ("USER_VALUE", values[side])), comments, side)
                 for side in ("left", "right")]
    return rows


def damper_rows(s: Suspension, spec: SubsystemSpec, names: Iterable[str],
                usages: Mapping[str, str]) -> list[AssemblyRow]:
    """The damper blocks of the corner dampers ``names`` that have a rate (the property file
    holds it): ``left/right``, or ``single`` for one kept once (across the car, or among
    shared parts and the ground)."""
    rows = []
    for name in names:
        d = next(x for x in s.dampers if x.name == name)
        if d.rate_N_s_per_mm is None:
            continue
        symmetry = "single" if s.axle is not None and _other(s, name, s.dampers) is None \
            else "left/right"
        comments = (f"$ elastokin damper {d.name}: {d.parts[0]} -> {d.parts[1]}, "
                    f"{d.rate_N_s_per_mm:g} N*s/mm, installed length "
                    f"{d.installed_length_mm:.3f} mm",)
        rows.append(AssemblyRow(usages[name], spec.path("dampers.tbl", f"{usages[name]}.dpr"),
                                (), comments, symmetry))
    return rows
