"""Resolving an axle: the other corner resolved in the mirrored geometry
(:class:`MirroredResolver`) and both corners joined into one
:class:`~elastokin.config.suspension.Suspension` with the steering rack and the anti-roll bar
(:func:`expand_axle`). The mirroring rules are in :mod:`elastokin.config.axle`. Units mm, N,
N*mm, deg; the config frame; every error names the key.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from elastokin.config.axle import (
    CENTRE_PLANE_TOLERANCE_MM,
    MIRROR,
    check_axle_mass,
    check_both_sides,
    check_mirror_plane,
    check_names,
    check_other_side_plane,
    check_shared,
    check_track,
    curve_problem,
    declared_once,
    kept_once,
    mirrored_bushing,
    mirrored_hardpoints,
    other_copy,
    other_side,
    steering_ratio,
)
from elastokin.config.beams import check_beam_attachments, mirrored_beam, shared_beam
from elastokin.config.resolver import Resolver
from elastokin.config.schema.base import AxisBetween
from elastokin.config.schema.suspension import RackSpec
from elastokin.config.suspension import AntiRollBar, Axle, Steering, Suspension
from elastokin.physics.joints import CONSTRAINED
from elastokin.physics.laws import DirectionLaw, law_from_spec
from elastokin.physics.pose import frame_from_z


class MirroredResolver(Resolver):
    """The other corner of an axle: the config's corner items resolved with the mirrored
    hardpoints (and the overrides), explicit vectors reflected, corner parts and items renamed
    with the other side's suffix; connections declared once (among shared parts and the
    ground) are left to the config's corner."""

    def __init__(self, corner_resolver: Resolver, corner: Suspension):
        super().__init__(corner_resolver.spec, corner_resolver.source)
        spec = self.spec.axle
        self.other = other_side(self.spec.side)
        self.suffix = f"_{self.other}"
        self.shared = set(spec.shared)
        self.hardpoints = mirrored_hardpoints(corner, spec)

    @property
    def side(self) -> str:
        return self.other

    def name(self, name: str) -> str:
        return name + self.suffix

    def keep(self, name: str, parts: tuple[str, str]) -> bool:
        return not kept_once(name, parts, self.spec.axle, self.spec.ground) and \
            not self.across(parts)

    def part(self, name: str, key: str) -> str:
        base = super().part(name, key)
        return base if base == self.spec.ground or base in self.shared else base + self.suffix

    def axis(self, a, key: str) -> np.ndarray:
        v = super().axis(a, key)
        return v if isinstance(a, AxisBetween) else MIRROR @ v

    def bushing_frame(self, c, key: str) -> np.ndarray:
        R = super().bushing_frame(c, key)
        if c.euler_zxz_deg is None:
            return R  # axis and radial reflected already; y = z x x is right-handed
        return np.column_stack([MIRROR @ R[:, 0], -(MIRROR @ R[:, 1]), MIRROR @ R[:, 2]])

    def bushing(self, name: str, c, parts, pos, key: str):
        b = super().bushing(name, c, parts, pos, key)
        corner_name = name.removesuffix(self.suffix)
        override = self.spec.axle.other_side.connections.get(corner_name)
        laws = None if override is None else self.bushing_laws(
            override.stiffness, f"axle.other_side.connections.{corner_name}.stiffness")
        return mirrored_bushing(b, laws)


class AcrossResolver(Resolver):
    """The items joining the two sides of an axle (a heave spring between ``rocker`` and the
    other side's ``rocker_right``): kept once, resolved with both corners' hardpoints (the
    other side's by the names the axle gives them, ``heave_rocker_right``), each joining a
    part of the config's corner to the other side's copy of one."""

    def __init__(self, corner_resolver: Resolver, hardpoints: dict[str, np.ndarray]):
        super().__init__(corner_resolver.spec, corner_resolver.source)
        self.hardpoints = hardpoints

    def keep(self, name: str, parts: tuple[str, str]) -> bool:
        return self.across(parts)

    def part(self, name: str, key: str) -> str:
        a = self.spec.axle
        if other_copy(name, self.spec.side, self.spec.parts, a.shared) is not None:
            return name
        return super().part(name, key)

    def parts(self, names: tuple[str, str], key: str) -> tuple[str, str]:
        out = super().parts(names, key)
        corner = [p for p in out if p in self.spec.parts and p not in self.spec.axle.shared]
        if not corner:
            raise self.fail(f"{key}.parts", f"joins only the other side's parts ({out[0]}, "
                            f"{out[1]}): give the item on the config's side ({self.spec.side}); "
                            "the axle mirrors it")
        return out


def resolve_suspension(resolver: Resolver, sha256: str, raw, config_sha256: str = "",
                       rig_sha256: str | None = None) -> Suspension:
    """The suspension ``resolver``'s config describes: its corner, or with an ``axle:``
    section both corners (:func:`expand_axle`). Arguments as :meth:`Resolver.resolve`."""
    corner = resolver.resolve(sha256, raw, config_sha256, rig_sha256)
    s = corner if resolver.spec.axle is None else expand_axle(resolver, corner)
    check_beam_attachments(s, resolver.fail)
    return s


def expand_axle(resolver: Resolver, corner: Suspension) -> Suspension:
    """Both corners of the axle of ``corner`` (the config's, resolved by ``resolver``) in one
    suspension, with the steering and the anti-roll bar (module docstring)."""
    spec = resolver.spec.axle
    check_shared(corner, spec, resolver.fail)
    check_names(corner, spec, f"_{other_side(corner.side)}", resolver.fail)
    check_mirror_plane(corner, spec, resolver.fail)
    check_both_sides(corner, spec, resolver.fail)
    check_other_side_plane(corner, spec, resolver.fail)
    check_axle_mass(spec, resolver.spec.design.wheel_load_N, resolver.fail)
    mirrored = MirroredResolver(resolver, corner)
    other = mirrored.corner()
    check_track(corner, other, resolver.fail)
    suffix = mirrored.suffix
    joints = corner.joints + other.joints
    steering = None
    if spec.steering is not None:
        steering, rack = resolve_steering(resolver, corner)
        joints = tuple(rack if j.name == rack.name else j for j in joints)
    arb = resolve_anti_roll_bar(resolver, corner, suffix)
    parts = dict(corner.parts)
    parts.update({n + suffix: p for n, p in corner.parts.items() if n not in spec.shared})
    hardpoints = dict(corner.hardpoints)
    hardpoints.update({n + suffix: v for n, v in mirrored.hardpoints.items()})
    across = AcrossResolver(resolver, hardpoints)
    a_joints, a_links, a_bushings = across.connections()
    a_springs, a_stops, a_dampers = across.springs(), across.stops(), across.dampers()
    a_items = [*(("connections", c) for c in (*a_joints, *a_links, *a_bushings)),
               *(("springs", c) for c in a_springs), *(("stops", c) for c in a_stops),
               *(("dampers", c) for c in a_dampers)]
    check_across_points(corner, a_items, spec.shared, resolver.fail)
    d = resolver.spec.design
    springs = {sp.name for sp in corner.springs + other.springs}
    balance = tuple(n for n in (d.balance_spring, f"{d.balance_spring}{suffix}")
                    if d.balance_spring and n in springs)
    axle = Axle((corner.side, mirrored.other), suffix, tuple(spec.shared), steering, arb,
                spec.vehicle, balance, tuple(it.name for _, it in a_items))
    beams = []
    for b in corner.beams:
        if b.part in spec.shared:
            beams.append(shared_beam(b, mirrored.hardpoints, suffix, corner.outboard,
                                     resolver.fail))
        else:
            beams += [b, mirrored_beam(b, mirrored.hardpoints, suffix)]
    return replace(corner, parts=parts, hardpoints=hardpoints, beams=tuple(beams),
                   joints=joints + a_joints, links=corner.links + other.links + a_links,
                   bushings=corner.bushings + other.bushings + a_bushings,
                   springs=corner.springs + other.springs + tuple(a_springs),
                   stops=corner.stops + other.stops + tuple(a_stops),
                   dampers=corner.dampers + other.dampers + tuple(a_dampers),
                   wheels={corner.side: corner.wheel, mirrored.other: other.wheel}, axle=axle)


def check_across_points(corner: Suspension, items, shared, fail) -> None:
    """Every point of an item joining the two sides (``items``: (config section, resolved
    item)) lies on the side of the part that holds it: a corner part's on the config's side
    of the centre plane, the other side's copy's on the other side (a shared part's or the
    ground's anywhere)."""
    for section, it in items:
        pts = getattr(it, "points_mm", None) or getattr(it, "seats_mm", None) or \
            (it.position_mm, it.position_mm)
        for part, p in zip(it.parts, pts):
            side = -1.0 if other_copy(part, corner.side, corner.parts, shared) else \
                1.0 if part in corner.parts and part not in shared else 0.0
            if side and float(p @ corner.outboard) * side <= CENTRE_PLANE_TOLERANCE_MM:
                where = corner.side if side > 0 else other_side(corner.side)
                raise fail(f"{section}.{it.name}", f"its point on '{part}' at y = "
                           f"{p[1]:.6g} mm is not on the {where} side of the vehicle centre "
                           "plane, where that part is")


def resolve_steering(resolver: Resolver, corner: Suspension):
    """(the steering, the rack joint as a sliding joint): the connection named by
    ``axle.steering.rack`` must be of type ``rack``, between shared parts or the ground."""
    spec = resolver.spec
    st = spec.axle.steering
    key = "axle.steering.rack"
    c = spec.connections.get(st.rack)
    racks = [n for n, v in spec.connections.items() if isinstance(v, RackSpec)]
    if not isinstance(c, RackSpec):
        raise resolver.fail(key, f"'{st.rack}' is not a connection of type rack (type-rack "
                            f"connections: {', '.join(racks) or 'none'})")
    part = c.parts[1]
    if not declared_once(c.parts, spec.axle.shared, spec.ground) or part == spec.ground:
        raise resolver.fail(key, f"the rack part '{part}' spans both sides: declare it in "
                            "axle.shared (and the part the rack slides in, unless the ground)")
    joint = next(j for j in corner.joints if j.name == st.rack)
    if abs(joint.offset_mm) > st.limit_mm:
        raise resolver.fail(f"connections.{st.rack}.travel_mm", f"{joint.offset_mm:g} mm is "
                            f"beyond the rack's travel limit axle.steering.limit_mm "
                            f"{st.limit_mm:g}")
    ratio = steering_ratio(st, resolver.fail)
    steering = Steering(st.rack, part, joint.position_mm, joint.frame[:, 2], joint.offset_mm,
                        st.limit_mm, ratio)
    return steering, replace(joint, kind="translational",
                             constrained=CONSTRAINED["translational"], offset_mm=0.0)


def resolve_anti_roll_bar(resolver: Resolver, corner: Suspension, suffix: str
                          ) -> AntiRollBar | None:
    """The anti-roll bar's torsion spring between this corner's bar half and its mirror."""
    a = resolver.spec.axle.anti_roll_bar
    if a is None:
        return None
    key = "axle.anti_roll_bar"
    part = resolver.part(a.part, key + ".part")
    if part == resolver.spec.ground or part in resolver.spec.axle.shared or \
            part == corner.wheel.part:
        raise resolver.fail(key + ".part", f"'{part}' must be this corner's half of the bar "
                            "(a moving part, not shared, not the wheel's)")
    check_drop_link(corner, part, resolver.spec.axle.shared, resolver.fail)
    pos = resolver.point(a.point, key + ".point")
    if abs(pos[1]) > 1e-3:
        raise resolver.fail(key + ".point", f"the bar's torsion spring joins the halves on "
                            f"the vehicle centre plane (y = 0); the point is at y = "
                            f"{pos[1]:.6g} mm")
    axis = resolver.axis(a.axis, key + ".axis")
    if a.rate_Nmm_per_deg is not None:
        law = DirectionLaw.linear(a.rate_Nmm_per_deg)
    else:
        try:
            law = law_from_spec(a.curve)
        except ValueError as exc:
            raise resolver.fail(key + ".curve", curve_problem(
                str(exc), "deflection (deg of twist)", "load (N*mm)")) from None
    return AntiRollBar((part, part + suffix), pos, frame_from_z(axis), law)


def wheel_side_parts(corner: Suspension, shared, without: str) -> set[str]:
    """The corner's parts joined to its wheel part through moving, unshared parts (not
    through ``without``, the ground or a shared part): the parts that move with the wheel."""
    fixed = set(shared) | {corner.ground, without}
    pairs = [c.parts for c in corner.joints + corner.links + corner.bushings]
    pairs += [sp.parts for sp in corner.springs]
    reached, grown = {corner.wheel.part}, True
    while grown:
        new = {q for a, b in pairs for p, q in ((a, b), (b, a))
               if p in reached and q not in fixed}
        grown = bool(new - reached)
        reached |= new
    return reached


def check_drop_link(corner: Suspension, part: str, shared, fail) -> None:
    """The anti-roll bar's half ``part`` reaches the wheel: a drop link (or a joint or
    bushing) joins it to a part that moves with the wheel (:func:`wheel_side_parts`)."""
    wheel_side = wheel_side_parts(corner, shared, part)
    links = [(c.name, set(c.parts) - {part}) for c in corner.joints + corner.links
             + corner.bushings if part in c.parts]
    if any(others & wheel_side for _, others in links):
        return
    found = ", ".join(f"'{n}' to {'/'.join(sorted(o)) or part}" for n, o in links) or "none"
    raise fail("axle.anti_roll_bar.part", f"the bar half '{part}' has no drop link to a part "
               f"that moves with the wheel ({', '.join(sorted(wheel_side))}); its "
               f"connections: {found}; add a link from '{part}' to one of them")
