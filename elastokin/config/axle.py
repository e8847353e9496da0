"""The resolved axle: a corner config with an ``axle:`` section becomes one
:class:`~elastokin.config.suspension.Suspension` carrying both corners.

The other corner is this one mirrored about the vehicle centre plane (y = 0 of the config
frame, M = diag(1, -1, 1)): every hardpoint, axis and wheel is reflected, every part, joint,
link, bushing, spring and stop that is not shared is copied under its name with the other
side's suffix (``front_arm`` -> ``front_arm_right``), parts declared in ``axle.shared`` and
connections among them and the ground are kept once. A reflected bushing frame is made
right-handed again (x' = M x, z' = M z, y' = z' x x' = -M y): a deflection along y, about x or
about z of the mirrored bushing is then the negative of the reflected one, so those three laws
are reflected (F'(u) = -F(-u)) and their preload components change sign; the mirrored bushing
then carries exactly the mirror image of the loads. ``axle.other_side`` moves hardpoints and
changes bushing rates of the other side (asymmetric axles).

Units mm, N, N*mm, deg; the config frame.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from elastokin.config.plausibility import implausible
from elastokin.config.schema.axle import AxleSpec, SteeringSpec
from elastokin.physics.laws import DirectionLaw

#: a point is on the centre plane within this distance (mm)
CENTRE_PLANE_TOLERANCE_MM = 1e-6
#: bushing directions whose deflection changes sign in the mirrored frame (y, rx, rz)
MIRRORED_DIRECTIONS = (1, 3, 5)
#: +1 / -1 per bushing direction: a deflection, force or preload in the mirrored frame
MIRROR_SIGNS = np.array([1.0, -1.0, 1.0, -1.0, 1.0, -1.0])
MIRROR_SIGNS.setflags(write=False)
MIRROR = np.diag([1.0, -1.0, 1.0])


def other_side(side: str) -> str:
    return "right" if side == "left" else "left"


def other_copy(name: str, side: str, parts, shared) -> str | None:
    """The corner part whose other-side copy ``name`` is, by the name an axle gives it
    (``rocker_right`` -> ``rocker`` on a left corner's axle: ``side`` the corner's, ``parts``
    its part names, ``shared`` those declared once); None when ``name`` is no such copy (a
    shared part has none)."""
    base = name.removesuffix("_" + other_side(side))
    if base == name or base not in parts or base in shared:
        return None
    return base


def joins_sides(item_parts, side: str, parts, shared) -> bool:
    """True for an item (connection, spring, damper, stop) between ``item_parts`` naming the
    other side's copy of a corner part (:func:`other_copy`; a heave spring between
    ``rocker`` and ``rocker_right``): an item across the car, kept once and resolved with both
    corners' hardpoints."""
    return any(other_copy(p, side, parts, shared) is not None for p in item_parts)


def reflected_law(law: DirectionLaw) -> DirectionLaw:
    """The point reflection F'(u) = -F(-u) of a law (the same law when it is odd)."""
    return DirectionLaw(tuple(-u for u in reversed(law.deflection)),
                        tuple(-f for f in reversed(law.load)))


def mirrored_laws(laws) -> tuple:
    """A bushing's six laws as its mirror has them (in the mirrored frame): the laws of
    :data:`MIRRORED_DIRECTIONS` reflected."""
    return tuple(reflected_law(law) if i in MIRRORED_DIRECTIONS else law
                 for i, law in enumerate(laws))


def steering_ratio(spec: SteeringSpec, fail) -> DirectionLaw:
    """Rack travel (mm) against steering-wheel angle (deg) from the steering section."""
    if spec.ratio_mm_per_rev is not None:
        return DirectionLaw.linear(spec.ratio_mm_per_rev / 360.0)
    c = spec.ratio_curve
    if len(c.steering_wheel_deg) != len(c.rack_travel_mm):
        raise fail("axle.steering.ratio_curve", "steering_wheel_deg and rack_travel_mm need "
                   "the same number of points")
    try:
        return DirectionLaw(tuple(c.steering_wheel_deg), tuple(c.rack_travel_mm))
    except ValueError as exc:
        raise fail("axle.steering.ratio_curve", curve_problem(
            str(exc), "steering_wheel_deg", "rack_travel_mm")) from None


def curve_problem(message: str, x: str, y: str) -> str:
    """A law's complaint (:class:`~elastokin.physics.laws.DirectionLaw`, worded for a bushing
    curve's deflection and load) in the terms of another curve, ``y`` against ``x``: it
    increases strictly through (0, 0) (the pinion's sense is found from the geometry, the bar
    twists both ways)."""
    if "at zero deflection" in message:
        return f"{y} must be 0 where {x} is 0 (the curve passes through (0, 0))"
    if "deflections must be strictly increasing" in message:
        return f"{x} must be strictly increasing"
    if "strictly increasing" in message:
        return f"{y} must increase strictly with {x}"
    return message


def corner_points(s, part: str) -> list[tuple[str, np.ndarray]]:
    """(key, point) of every attachment of ``part`` in a resolved corner (config frame)."""
    out = []
    for j in s.joints:
        out += [(f"connections.{j.name}", j.position_mm)] if part in j.parts else []
    for b in s.bushings:
        out += [(f"connections.{b.name}", b.position_mm)] if part in b.parts else []
    for lk in s.links:
        out += [(f"connections.{lk.name}", p) for q, p in zip(lk.parts, lk.points_mm)
                if q == part]
    for sp in s.springs:
        out += [(f"springs.{sp.name}", p) for q, p in zip(sp.parts, sp.seats_mm) if q == part]
    for st in s.stops:
        out += [(f"stops.{st.name}", p) for q, p in zip(st.parts, st.points_mm) if q == part]
    for dm in s.dampers:
        out += [(f"dampers.{dm.name}", p) for q, p in zip(dm.parts, dm.points_mm) if q == part]
    if s.wheel.part == part:
        out.append(("wheel.centre", s.wheel.centre_mm))
    for b in s.beams:
        out += [(f"parts.{part}.beam.nodes", p) for p in b.nodes_mm] if b.part == part else []
    return out


def check_mirror_plane(s, spec: AxleSpec, fail) -> None:
    """Every corner part lies wholly on its side of the centre plane (a part that reaches the
    plane or beyond it must be shared)."""
    y = s.outboard  # the config side's outboard direction
    for part in s.parts:
        if part in spec.shared:
            continue
        for key, p in corner_points(s, part):
            if float(p @ y) <= CENTRE_PLANE_TOLERANCE_MM:
                raise fail(key, f"the vehicle centre plane (y = 0) cuts part '{part}': its "
                           f"point at y = {p[1]:.6g} mm is not on the {s.side} side; declare "
                           f"'{part}' in axle.shared (parts spanning both sides are declared "
                           "once) or move the point")


def check_other_side_plane(s, spec: AxleSpec, fail) -> None:
    """Every ``axle.other_side`` hardpoint whose corner point lies on the corner's side of the
    centre plane lies on the other side (config frame, as the corner's points): a point typed
    with the corner's sign would put the other wheel's joint across the car."""
    out = s.outboard  # the config side's outboard direction
    other = other_side(s.side)
    for name, q in spec.other_side.hardpoints.items():
        p = np.asarray(s.hardpoints.get(name, np.zeros(3)), float)
        q = np.asarray(q, float)
        if float(p @ out) <= CENTRE_PLANE_TOLERANCE_MM or float(q @ out) < \
                -CENTRE_PLANE_TOLERANCE_MM:
            continue
        mirror = ", ".join(f"{v:g}" for v in MIRROR @ p)
        raise fail(f"axle.other_side.hardpoints.{name}", f"y = {q[1]:.6g} mm is not on the "
                   f"{other} side of the vehicle centre plane (y = 0), where the {other} "
                   f"corner's points are ('{name}' of the {s.side} corner is at y = "
                   f"{p[1]:.6g} mm, its mirror at [{mirror}]); other_side points are in the "
                   "config frame, as the hardpoints: give the y coordinate its sign")


def check_track(corner, other, fail) -> None:
    """The design track (between the two contact points, across the centre plane) is
    plausible (:mod:`elastokin.config.plausibility`): hardpoints typed in metres, or an origin
    off the vehicle centre plane (y = 0, the mirror plane), give an axle that solves but is
    not the car."""
    track = abs(float((corner.wheel.contact_patch_mm - other.wheel.contact_patch_mm)
                      @ corner.outboard))
    problem = implausible("track_mm", track)
    if problem:
        raise fail("wheel.centre", f"the axle's design track (between the contact points of "
                   f"this wheel and its mirror about y = 0) is {problem}: are the hardpoints "
                   "in mm, with the origin on the vehicle centre plane?")


def check_shared(s, spec: AxleSpec, fail) -> None:
    """Shared parts exist (a shared wheel part carries both wheels: a solid axle); the
    overrides name corner items only."""
    for i, name in enumerate(spec.shared):
        if name not in s.parts:
            raise fail(f"axle.shared[{i}]", f"no part '{name}' (parts: {', '.join(s.parts)})")
    for i, name in enumerate(spec.shared):
        if name in spec.shared[:i]:
            raise fail(f"axle.shared[{i}]", f"'{name}' is listed twice (a shared part is "
                       "declared once)")
    once = _declared_once(s, spec)
    for name in spec.other_side.hardpoints:
        key = f"axle.other_side.hardpoints.{name}"
        if name not in s.hardpoints:
            raise fail(key, f"no hardpoint '{name}' on this corner")
        users = [c for c, pts in once if name in pts]
        if users:
            raise fail(key, f"hardpoint '{name}' belongs to connection '{users[0]}', declared "
                       "once for both sides (between shared parts or the ground): a shared "
                       "part cannot be declared again on the other side")
    bushings = {b.name for b in s.bushings}
    for name in spec.other_side.connections:
        if name not in bushings:
            raise fail(f"axle.other_side.connections.{name}", f"no bushing '{name}' on this "
                       f"corner (bushings: {', '.join(sorted(bushings)) or 'none'})")
        if name in {c for c, _ in once}:
            raise fail(f"axle.other_side.connections.{name}", f"bushing '{name}' joins shared "
                       "parts or the ground: it is declared once for both sides")


def check_names(s, spec: AxleSpec, suffix: str, fail) -> None:
    """No corner name is the name the axle gives to another item's copy on the other side
    (``front_arm`` and ``front_arm_right``; a hardpoint ``X_right`` beside ``X``): a part named
    as a shared part's other-side copy declares a shared part on both sides; any other such
    name would be taken twice, the user's item silently replaced by the mirror. Parts,
    connections, springs and dampers share one namespace (:meth:`Resolver.check_names`);
    hardpoints and stops have their own."""
    shared = set(spec.shared)
    side = suffix.removeprefix("_")
    for name in sorted(spec.shared):
        copy = name + suffix
        if copy in s.parts:
            raise fail(f"parts.{copy}", f"'{copy}' is the other side's '{name}', a shared "
                       f"part (axle.shared): a shared part is declared once for both sides; "
                       f"remove '{copy}' and attach the connections to '{name}'")
    mirrored = {}  # a generated name -> what it copies
    for name in s.parts:
        if name not in shared and name != s.ground:
            mirrored[name + suffix] = f"part '{name}'"
    for section in ("connections", "springs", "dampers"):
        for name, item in (s.raw.get(section) or {}).items():
            if mirrored_item(name, tuple(item["parts"]), spec, s):
                mirrored[name + suffix] = f"{section[:-1]} '{name}'"
    sections = {"parts": mirrored, "connections": mirrored, "springs": mirrored,
                "dampers": mirrored,
                "stops": {n + suffix: f"stop '{n}'" for n in (s.raw.get("stops") or {})},
                "hardpoints": {n + suffix: f"hardpoint '{n}'" for n in s.hardpoints}}
    for section, generated in sections.items():
        for name in sorted(s.raw.get(section) or {}):
            if name in generated:
                raise fail(f"{section}.{name}", f"'{name}' is the name of the mirrored "
                           f"copy of {generated[name]} on the {side} side (the axle names "
                           "the other corner's items so): it would be taken twice; rename it")


def _declared_once(s, spec: AxleSpec) -> list[tuple[str, set[str]]]:
    """(connection, its hardpoint names) of the connections among shared parts and the
    ground, from the config's mapping."""
    out = []
    for name, c in s.raw["connections"].items():
        if kept_once(name, c["parts"], spec, s.ground):
            pts = c["at"] if isinstance(c.get("at"), (list, tuple)) else [c.get("at")]
            names = {p for p in pts if isinstance(p, str)}
            for k in ("axis", "radial", "torsion_axis"):
                v = c.get(k)
                if isinstance(v, dict):
                    names |= {v.get("from"), v.get("to")} - {None}
            out.append((name, names))
    return out


def mirrored_hardpoints(s, spec: AxleSpec) -> dict[str, np.ndarray]:
    """The other side's hardpoints by the corner's names: reflected, then overridden."""
    out = {k: MIRROR @ np.asarray(v, float) for k, v in s.hardpoints.items()}
    out.update({k: np.asarray(v, float) for k, v in spec.other_side.hardpoints.items()})
    return out


def mirrored_bushing(b, override_laws: tuple | None) -> object:
    """The other side's copy of a resolved bushing ``b`` (already resolved in the reflected
    geometry): laws of the flipped directions reflected and their initial deflection negated
    (module docstring), then the override's laws where given (None elsewhere; in the mirrored
    bushing's own frame, BUSHING_DIRECTIONS order)."""
    laws = list(mirrored_laws(b.laws))
    u0 = MIRROR_SIGNS * np.asarray(b.initial_deflection, float)
    for i, law in enumerate(override_laws or ()):
        if law is not None:
            laws[i] = law
    return replace(b, laws=tuple(laws), initial_deflection=u0)


def declared_once(parts: tuple[str, str], shared, ground: str) -> bool:
    """True for a connection among shared parts and the ground (kept once on an axle)."""
    return set(parts) <= set(shared) | {ground}


def kept_once(name: str, parts: tuple[str, str], spec: AxleSpec, ground: str) -> bool:
    """True for a connection, spring or stop kept once on an axle: among shared parts and
    the ground, and not listed in ``axle.both_sides``."""
    return name not in spec.both_sides and declared_once(parts, spec.shared, ground)


def mirrored_item(name: str, parts: tuple[str, str], spec: AxleSpec, s) -> bool:
    """True for an item of the config ``s`` (validated or resolved; ``spec`` its axle) that the
    other side has a mirrored copy of: neither kept once (:func:`kept_once`) nor joining the
    two sides."""
    return not kept_once(name, parts, spec, s.ground) and \
        not joins_sides(parts, s.side, s.parts, spec.shared)


def item_points(s, name: str) -> list[np.ndarray]:
    """The points (config frame) of the resolved corner's connection, spring, damper or stop
    ``name``."""
    for j in (*s.joints, *s.bushings):
        if j.name == name:
            return [j.position_mm]
    for item, attr in ((s.links, "points_mm"), (s.springs, "seats_mm"),
                       (s.stops, "points_mm"), (s.dampers, "points_mm")):
        for it in item:
            if it.name == name:
                return list(getattr(it, attr))
    return []


def check_both_sides(s, spec: AxleSpec, fail) -> None:
    """Every name of ``axle.both_sides`` is a connection, spring or stop among shared parts
    and the ground (a corner's are on both sides already), not the steering rack, with every
    point on the config's side of the centre plane (its mirror is the other side's)."""
    sections = {sec: s.raw.get(sec) or {}
                for sec in ("connections", "springs", "dampers", "stops")}
    rack = spec.steering.rack if spec.steering is not None else None
    for i, name in enumerate(spec.both_sides):
        key = f"axle.both_sides[{i}]"
        found = [sec for sec, items in sections.items() if name in items]
        if not found:
            raise fail(key, f"no connection, spring, damper or stop '{name}'")
        if name in spec.both_sides[:i]:
            raise fail(key, f"'{name}' is listed twice")
        parts = tuple(sections[found[0]][name]["parts"])
        if not declared_once(parts, spec.shared, s.ground):
            corner = sorted(set(parts) - set(spec.shared) - {s.ground})
            raise fail(key, f"'{name}' joins the corner part '{corner[0]}': it is on both "
                       "sides already (axle.both_sides is for items among shared parts and "
                       "the ground)")
        if name == rack:
            raise fail(key, f"'{name}' is the steering rack (axle.steering.rack), kept once")
        for p in item_points(s, name):
            if float(p @ s.outboard) <= CENTRE_PLANE_TOLERANCE_MM:
                raise fail(f"{found[0]}.{name}", f"listed in axle.both_sides, but its point at "
                           f"y = {p[1]:.6g} mm is not on the {s.side} side of the vehicle "
                           "centre plane: its mirror would be on this side")


#: the wheel load at rest of ``axle.vehicle.axle_mass_kg`` may differ from the design wheel
#: load by this factor either way (the static-load analysis may be at another payload);
#: beyond it, it is a slip (a total mass, a load in N, a mass of the other axle)
AXLE_MASS_TOLERANCE = 2.0


def check_axle_mass(spec: AxleSpec, design_wheel_load_N: float, fail) -> None:
    """The mass ``axle.vehicle.axle_mass_kg`` gives this axle agrees with the design wheel
    load (within :data:`AXLE_MASS_TOLERANCE`)."""
    v = spec.vehicle
    if v is None or v.axle_mass_kg is None:
        return
    mass = getattr(v.axle_mass_kg, v.position)
    at_rest = mass * 9.80665 / 2.0
    ratio = at_rest / design_wheel_load_N
    if not 1.0 / AXLE_MASS_TOLERANCE <= ratio <= AXLE_MASS_TOLERANCE:
        expected = 2.0 * design_wheel_load_N / 9.80665
        raise fail(f"axle.vehicle.axle_mass_kg.{v.position}",
                   f"{mass:g} kg puts {at_rest:.0f} N on each wheel at rest, {ratio:.2f} times "
                   f"design.wheel_load_N ({design_wheel_load_N:g} N): expected the mass this "
                   f"({v.position}) axle carries, about {expected:.0f} kg for that design load")
