"""An axle as ADAMS/Car keeps it: a suspension subsystem, an anti-roll bar subsystem (major
role ``antirollbar``) and a rack and pinion steering subsystem (major role ``steering``), each a
subsystem file of its own, joined by an assembly file (``.asy``).

Pure Python/numpy. :func:`axle_subsystems` says which of an axle config's hardpoints, bushings
and springs go into which subsystem (by the corner's names; each item's other-side copy goes
with it); :func:`arb_parameters` and :func:`steering_parameters` give their ``[PARAMETER]``
rows, :func:`curve_file_text` the curve file of a nonlinear bar or rack ratio and
:func:`assembly_text` the assembly. Units: the subsystem's (mm, newton, deg), except
``rack_ratio``, which ADAMS/Car gives in S.I. (rad of steering wheel per metre of rack travel).
Conventions: ``docs/adams.md``, "Axles".
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

from elastokin.config.axle import declared_once
from elastokin.config.suspension import Suspension
from elastokin.formats.adams.property_files import (
    UNITS_LINES,
    header_lines,
    key_line,
    number,
    provenance,
    rule,
    table_lines,
)
from elastokin.formats.adams.subsystem import ParameterRow, SubsystemSpec
from elastokin.physics.laws import DirectionLaw

__all__ = [
    "AXLE_ROLES",
    "AxleSubsystem",
    "arb_parameters",
    "assembly_text",
    "axle_subsystems",
    "centre_slope",
    "curve_file_text",
    "kept_once_hardpoints",
    "mm_per_rev",
    "rack_ratio_rad_per_m",
    "steering_parameters",
]

#: elastokin section -> (ADAMS/Car major role, default template): the suspension's template is
#: the user's (the mapping file's or --template-name); the rack and pinion steering template's
#: name is the one of Adams/Car's shipped demo vehicle assembly; the anti-roll bar's is
#: ADAMS/Car's shared-database name (not seen in a real file here: docs/adams.md)
AXLE_ROLES: dict[str, tuple[str, str | None]] = {
    "suspension": ("suspension", None),
    "anti_roll_bar": ("antirollbar", "mdids://acar_shared/templates.tbl/_antiroll.tpl"),
    "steering": ("steering", "mdids://acar_shared/templates.tbl/_rack_pinion_steering.tpl"),
}

#: keys of a connection spec that never name a hardpoint
_NOT_POINTS = ("type", "parts", "ideal_joint", "description", "stiffness", "kinematic")


@dataclass(frozen=True)
class AxleSubsystem:
    """The items of one ADAMS/Car subsystem, by the corner's names (config side)."""

    role: str
    hardpoints: tuple[str, ...]
    bushings: tuple[str, ...]
    springs: tuple[str, ...]
    dampers: tuple[str, ...] = ()


def _points(value, names: set[str]) -> set[str]:
    """The hardpoint names in a config value (any depth)."""
    if isinstance(value, str):
        return {value} & names
    if isinstance(value, Mapping):
        return set().union(*(_points(v, names) for k, v in value.items()
                             if k not in _NOT_POINTS))
    if isinstance(value, (list, tuple)):
        return set().union(*(_points(v, names) for v in value))
    return set()


def axle_subsystems(s: Suspension) -> dict[str, AxleSubsystem]:
    """Which subsystem each corner item goes into: the anti-roll bar's the connections of the
    bar's part (bushings to the body, drop links) and the hardpoints only they and
    ``axle.anti_roll_bar`` name; the steering's the connections between the rack part and
    shared parts or the ground and the hardpoints only they name; everything else (tie rods
    included, as in ADAMS/Car's suspension templates) the suspension's. A corner is one
    suspension subsystem."""
    raw = s.raw
    names = set(raw["hardpoints"])
    corner_bushings = tuple(b.name for b in s.bushings if b.name in raw["connections"])
    corner_springs = tuple(sp.name for sp in s.springs if sp.name in raw.get("springs", {}))
    dampers = tuple(d.name for d in s.dampers if d.name in raw.get("dampers", {}))
    if s.axle is None:
        return {"suspension": AxleSubsystem("suspension", tuple(s.hardpoints), corner_bushings,
                                            corner_springs, dampers)}
    conns = {"anti_roll_bar": set(), "steering": set()}
    arb = (raw["axle"] or {}).get("anti_roll_bar")
    keep = set(s.axle.shared) | {s.ground}
    for cname, c in raw["connections"].items():
        parts = set(c["parts"])
        if arb is not None and arb["part"] in parts:
            conns["anti_roll_bar"].add(cname)
        elif s.axle.steering is not None and s.axle.steering.part in parts and parts <= keep:
            conns["steering"].add(cname)
    used = {role: set().union(*(_points(raw["connections"][c], names) for c in cs))
            for role, cs in conns.items()}
    if arb is not None:
        used["anti_roll_bar"] |= _points({"point": arb["point"], "axis": arb["axis"]}, names)
    rest = {k: v for k, v in raw.items() if k not in ("hardpoints", "connections", "axle")}
    elsewhere = _points(rest, names) | set().union(*(
        _points(c, names) for n, c in raw["connections"].items()
        if n not in conns["anti_roll_bar"] | conns["steering"]))
    own = {role: pts - elsewhere - set().union(*(v for r, v in used.items() if r != role))
           for role, pts in used.items()}
    out = {"suspension": AxleSubsystem(
        "suspension", tuple(n for n in raw["hardpoints"] if not any(n in v for v in own.values())),
        tuple(b for b in corner_bushings if not any(b in cs for cs in conns.values())),
        corner_springs, dampers)}
    for role in ("anti_roll_bar", "steering"):
        if conns[role] or own[role]:
            out[role] = AxleSubsystem(role, tuple(n for n in raw["hardpoints"] if n in own[role]),
                                      tuple(b for b in corner_bushings if b in conns[role]), ())
    if arb is not None and "anti_roll_bar" not in out:
        out["anti_roll_bar"] = AxleSubsystem("anti_roll_bar", (), (), ())
    if s.axle.steering is not None and "steering" not in out:
        out["steering"] = AxleSubsystem("steering", (), (), ())
    return out


def kept_once_hardpoints(s: Suspension) -> frozenset[str]:
    """On an axle, the config's hardpoints that only connections, springs, dampers and stops
    kept once name (among shared parts and the ground, not in ``axle.both_sides``: a Panhard
    rod's ends, a Watt's linkage's): ADAMS/Car's ``single`` hardpoints. Empty for a corner."""
    raw = s.raw
    if s.axle is None:
        return frozenset()
    names = set(raw["hardpoints"])
    both = set((raw["axle"] or {}).get("both_sides") or ())
    once, mirrored = set(), set()
    for section in ("connections", "springs", "dampers", "stops"):
        for item, spec in (raw.get(section) or {}).items():
            kept = item not in both and declared_once(tuple(spec["parts"]), s.axle.shared,
                                                      s.ground)
            (once if kept else mirrored).update(_points(spec, names))
    rest = {k: v for k, v in raw.items()
            if k not in ("hardpoints", "connections", "springs", "dampers", "stops", "axle")}
    return frozenset(once - mirrored - _points(rest, names))


def centre_slope(law: DirectionLaw) -> float:
    """The slope of a law at zero deflection: of the segment holding zero, the mean of the two
    meeting there when zero is a table point (a linear law: its rate)."""
    u, k = law.deflection, law.slopes
    if 0.0 in u[1:-1]:
        i = u.index(0.0)
        return 0.5 * (k[i - 1] + k[i])
    i = min(max(sum(1 for x in u if x < 0.0) - 1, 0), len(k) - 1)
    return float(k[i])


def rack_ratio_rad_per_m(mm_per_rev: float) -> float:
    """ADAMS/Car's ``rack_ratio`` (steering-wheel angle per rack travel, rad/m, S.I.) of a rack
    ratio in mm of rack travel per steering-wheel revolution."""
    return 2.0 * math.pi * 1000.0 / mm_per_rev


def mm_per_rev(rack_ratio: float) -> float:
    """mm of rack travel per steering-wheel revolution of ADAMS/Car's ``rack_ratio`` (rad/m),
    rounded to 12 significant digits (the binary noise of 2*pi, as every converted value)."""
    return float(f"{2.0 * math.pi * 1000.0 / rack_ratio:.12g}")


def arb_parameters(s: Suspension, names: dict[str, str], curve_file: str | None
                   ) -> list[ParameterRow]:
    """The anti-roll bar's torsional rate (N*mm/deg of twist between the halves; on a curve,
    its rate at zero twist, the curve being in ``curve_file``)."""
    law = s.axle.anti_roll_bar.law
    rate = s.raw["axle"]["anti_roll_bar"].get("rate_Nmm_per_deg")
    what = ("torsional rate of the anti-roll bar between its halves, N*mm/deg (elastokin "
            "axle.anti_roll_bar.rate_Nmm_per_deg)")
    if curve_file is not None:
        what = (f"torsional rate at zero twist of the anti-roll bar, N*mm/deg; its curve: "
                f"{curve_file}")
    return [ParameterRow(names["stiffness"], "single", "real",
                         float(rate) if rate is not None else centre_slope(law), what)]


def steering_parameters(s: Suspension, names: dict[str, str], curve_file: str | None
                        ) -> list[ParameterRow]:
    """``rack_ratio`` (rad/m, S.I.; on a curve, its on-centre value, the curve being in
    ``curve_file``) and the rack's travel limit each way (mm)."""
    st = s.axle.steering
    c = s.raw["axle"]["steering"].get("ratio_mm_per_rev")  # mm per revolution
    c = float(c) if c is not None else 360.0 * centre_slope(st.ratio)
    what = (f"swa to rack displacement ratio in S.I. (rad/meter): {number(c)} mm of rack per "
            "steering-wheel revolution")
    if curve_file is not None:
        what += f" on centre; the ratio curve: {curve_file}"
    return [ParameterRow(names["rack_ratio"], "single", "real", rack_ratio_rad_per_m(c), what),
            ParameterRow(names["travel_limit"], "single", "real", st.limit_mm,
                         "rack travel limit each way from the centre, mm")]


def curve_file_text(s: Suspension, role: str) -> str:
    """An elastokin curve file (TeimOrbit, mm, newton, deg): the anti-roll bar's torque (N*mm)
    against twist (deg), ``{rot torque}``, or the rack travel (mm) against steering-wheel angle
    (deg), ``{rot disp}``. ADAMS/Car does not read it (its templates take the scalar
    parameters); ``import-adams`` does."""
    if role == "anti_roll_bar":
        law, columns = s.axle.anti_roll_bar.law, ("rot", "torque")
        what = "anti-roll bar torque (N*mm) against twist between the halves (deg)"
    else:
        law, columns = s.axle.steering.ratio, ("rot", "disp")
        what = "rack travel (mm) against steering-wheel angle (deg, + to the left)"
    lines = [provenance(s), f"$ {what}; elastokin's piecewise-linear law through these points",
             *header_lines("crv", 1.0, [f"elastokin {role} curve of {s.name}"]),
             rule("UNITS"), *UNITS_LINES, rule("CURVE"), "[CURVE]",
             *table_lines(columns, law.deflection, law.load)]
    return "\n".join(lines) + "\n"


def assembly_text(s: Suspension, specs: dict[str, SubsystemSpec], timestamp: str) -> str:
    """A suspension assembly file (``.asy``) naming the axle's subsystems and ADAMS/Car's
    suspension test rig, in the form of Adams/Car's assembly files."""
    lines = [provenance(s),
             *header_lines("asy", 2.0, ["Adams/Car suspension assembly"]),
             rule("ASSEMBLY_HEADER"), "[ASSEMBLY_HEADER]",
             key_line("ASSEMBLY_CLASS", "suspension", 14),
             key_line("TIMESTAMP", timestamp, 14),
             rule("PLUGINS"), "[PLUGINS]", key_line("PLUGIN_LIST", "acar", 11),
             rule("UNITS"), *UNITS_LINES]
    for spec in specs.values():
        template = spec.template.rsplit("/", 1)[-1].removesuffix(".tpl")
        lines += [rule("SUBSYSTEM"), "[SUBSYSTEM]", "$ Subsystem information:",
                  f"$       Major Role : {spec.major_role}",
                  f"$       Minor Role : {spec.minor_role}",
                  f"$       Template   : {template}", "",
                  key_line("USAGE", spec.path("subsystems.tbl", f"{spec.name}.sub"), 5)]
    lines += [rule("TESTRIG"), "[TESTRIG]", key_line("USAGE", "__MDI_SUSPENSION_TESTRIG", 5)]
    return "\n".join(lines) + "\n"
