"""The steering axis at every rig step: caster, kingpin inclination, scrub radius and caster
trail from the wheel part's instantaneous screw axis under a small steering input with the
springs locked (ADAMS/Car's instant-axis method; the method in
:mod:`elastokin.physics.steering_axis`, definitions and signs in docs/characteristics.md).

Config frame; mm and deg.
"""

from __future__ import annotations

import warnings
from dataclasses import replace

import numpy as np

from elastokin.config.suspension import Suspension
from elastokin.physics.joints import CONSTRAINED
from elastokin.physics.states import StepState
from elastokin.physics.steering_axis import (
    SkeletonElement,
    SteeringSkeleton,
    eliminate_links,
    steering_axes_from_poses,
)
from elastokin.physics.steering_geometry import (
    caster_deg,
    caster_trail_mm,
    contact_point,
    kingpin_inclination_deg,
    scrub_radius_mm,
)
from elastokin.rig.channels import STEERING_AXIS_COLUMNS


def steering_skeleton(suspension: Suspension) -> SteeringSkeleton:
    """Constraint skeleton of ``suspension`` for the steering axis: steering released,
    springs locked."""
    s = suspension
    wheel = s.wheel.part
    racks = _rack_joints(s)
    steer_links = [lk for lk in s.links if wheel in lk.parts]
    reason = None
    if racks:
        steering = "rack travel of " + ", ".join(f"'{j.name}'" for j in racks)
        released_links: set[str] = set()
    elif len(steer_links) == 1:
        steering = f"link '{steer_links[0].name}' (tie rod) released"
        released_links = {steer_links[0].name}
    else:
        steering = "none"
        released_links = set()
        reason = ("no steering rack and " + ("no link" if not steer_links else
                  f"{len(steer_links)} links ({', '.join(lk.name for lk in steer_links)})")
                  + f" on the wheel part '{wheel}': the steering input (the one tie rod or "
                  "toe link to release) is not defined")
    if not s.springs:
        reason = reason or ("no spring: the travel cannot be locked (the steering axis is "
                            "computed with the springs locked)")
    reason = reason or flexible_reason(s, "the steering axis is")
    elements = skeleton_elements(s, True, released_links, springs_released=False)
    elements, eliminated = eliminate_links(elements, s.ground, wheel)
    return SteeringSkeleton(s.ground, wheel, tuple(elements), steering, reason,
                            tuple(eliminated))


def travel_skeleton(suspension: Suspension) -> SteeringSkeleton:
    """Constraint skeleton of ``suspension`` for the wheel's travel: the springs' lengths
    released (the input), the steering held (rack and tie rods); its screw axis gives the
    front-view instant centre (:mod:`elastokin.rig.scene_motion`)."""
    s = suspension
    reason = (None if s.springs else "no spring: the wheel's travel input is not defined") \
        or flexible_reason(s, "the instant centres are")
    elements = skeleton_elements(s, False, set(), springs_released=True)
    elements, eliminated = eliminate_links(elements, s.ground, s.wheel.part)
    return SteeringSkeleton(s.ground, s.wheel.part, tuple(elements), "spring lengths", reason,
                            tuple(eliminated))


def flexible_reason(s: Suspension, what: str) -> str | None:
    """Why a skeleton of rigid parts does not describe ``s`` (its flexible beam parts), for
    ``what`` it would give."""
    flexible = [b.part for b in s.beams if not b.rigid]
    if not flexible:
        return None
    return f"the flexible beam part(s) {', '.join(flexible)}: {what} computed for rigid " \
        "parts only"


def _rack_joints(s: Suspension) -> list:
    axle_rack = s.axle.steering.joint if s.axle is not None and s.axle.steering else None
    return [j for j in s.joints if j.kind == "rack" or j.name == axle_rack]


def skeleton_elements(s: Suspension, rack_released: bool, released_links: set[str],
                      springs_released: bool) -> list[SkeletonElement]:
    """Every joint, bushing (its ideal joint), link and spring of ``s`` as a skeleton
    element: a rack's travel released or held (``rack_released``), the links named in
    ``released_links`` released, the springs' lengths released or locked."""
    elements = joint_elements(s, release_rack=rack_released)
    for lk in s.links:
        elements.append(SkeletonElement("distance", lk.parts, lk.points_mm,
                                        released=lk.name in released_links))
    for sp in s.springs:  # locked: the travel is held; released: the travel's input
        elements.append(SkeletonElement("distance", sp.parts, sp.seats_mm,
                                        released=springs_released, spring=not springs_released))
    return elements


def joint_elements(suspension: Suspension, release_rack: bool) -> list[SkeletonElement]:
    """Every ideal joint and every bushing (as its ideal joint, frozen at its deflection) of
    ``suspension`` as skeleton elements; a steering rack free along its axis and released
    (``release_rack``: the steering input) or held."""
    s = suspension
    axle_rack = s.axle.steering.joint if s.axle is not None and s.axle.steering else None
    elements: list[SkeletonElement] = []
    for j in s.joints:
        flags = list(j.constrained)
        shift0, shift1 = (np.zeros(3), np.zeros(3)) if j.part_shift_mm is None else \
            (np.asarray(j.part_shift_mm[0], float), np.asarray(j.part_shift_mm[1], float))
        frame = np.asarray(j.frame, float)
        points = (j.position_mm + float(j.offset_mm) * frame[:, 2] + shift0,
                  j.position_mm + shift1)
        if j.kind == "rack" or j.name == axle_rack:
            flags[2] = 0 if release_rack else 1  # the rack along its axis (the frame's z)
            if release_rack:
                elements.append(SkeletonElement("joint", j.parts, points, frame,
                                                (0, 0, 1, 0, 0, 0), released=True))
        elements.append(SkeletonElement("joint", j.parts, points, frame, tuple(flags)))
    for b in s.bushings:
        elements.append(SkeletonElement("joint", b.parts, (b.position_mm, b.position_mm),
                                        np.asarray(b.frame, float),
                                        CONSTRAINED[b.ideal_joint]))
    return elements


def steerable(suspension: Suspension) -> bool:
    """Whether the wheel can be steered at all: a steering rack, or a link (tie rod, toe
    link) on the wheel part. A suspension without either (a trailing arm, a solid axle) has no
    steering axis: its columns are empty without a warning (docs/characteristics.md)."""
    s = suspension
    rack = s.axle.steering.joint if s.axle is not None and s.axle.steering else None
    return any(j.kind == "rack" or j.name == rack for j in s.joints) or \
        any(s.wheel.part in lk.parts for lk in s.links)


def stacked_skeleton(skeletons: list[SteeringSkeleton], rows: list[int]
                     ) -> SteeringSkeleton | None:
    """One skeleton for the steps of several suspensions of one layout (a design's twins):
    each element's points and frame per step ((S, 3), (S, 3, 3)), every suspension's repeated
    for its ``rows`` steps; None when the layouts differ."""
    first = skeletons[0]
    if any(len(sk.elements) != len(first.elements) or sk.reason is not None
           or [(e.kind, e.parts, e.flags, e.released, e.anchors is None) for e in sk.elements]
           != [(e.kind, e.parts, e.flags, e.released, e.anchors is None)
               for e in first.elements] for sk in skeletons):
        return None

    def stack(values) -> np.ndarray:
        return np.concatenate([np.repeat(np.asarray(v, float)[None], r, axis=0)
                               for v, r in zip(values, rows)])

    elements = []
    for es in zip(*(sk.elements for sk in skeletons)):
        e0 = es[0]
        anchors = None if e0.anchors is None else tuple(
            (e0.anchors[k][0], stack([e.anchors[k][1] for e in es])) for k in (0, 1))
        elements.append(replace(e0, points=tuple(stack([e.points[k] for e in es])
                                                 for k in (0, 1)),
                                frame=None if e0.frame is None else stack([e.frame
                                                                           for e in es]),
                                anchors=anchors))
    return replace(first, elements=tuple(elements))


def stacked_steering_axis_columns(cases: list[tuple[list[StepState], Suspension]]
                                  ) -> list[dict[str, np.ndarray]]:
    """:func:`steering_axis_columns` of several (steps, suspension) pairs of one layout (a
    design's twins) in one computation (its fixed cost once), without warnings (the model's
    own run gives them)."""
    if not cases or not steerable(cases[0][1]):
        return [steering_axis_columns(steps, s) for steps, s in cases]
    rows = [len(steps) for steps, _ in cases]
    skeleton = stacked_skeleton([steering_skeleton(s) for _, s in cases], rows)
    if skeleton is None:
        return [steering_axis_columns(steps, s) for steps, s in cases]
    steps = [st for group, _ in cases for st in group]
    centre = np.array([st.wheel_centre_mm for st in steps])
    axes = steering_axes_from_poses(skeleton, [st.poses for st in steps], centre)
    out, start = [], 0
    for (group, s), n in zip(cases, rows):
        cut = slice(start, start + n)
        start += n
        spin = np.array([st.spin_axis for st in group])
        out.append(axis_columns(axes.direction[cut], axes.point[cut], centre[cut], spin, s))
    return out


def axis_columns(direction: np.ndarray, point: np.ndarray, centre: np.ndarray,
                 spin: np.ndarray, s: Suspension) -> dict[str, np.ndarray]:
    """The steering-axis columns from the axis (unit directions, points; (S, 3)), the wheel
    centres and spin axes (S, 3)."""
    d = direction.copy()
    d[np.abs(d @ s.up) < 1e-9] = np.nan  # a horizontal axis has no caster or ground point
    contact = contact_point(centre, spin, s.wheel.loaded_radius_mm, s.up)
    return {
        "caster_deg": caster_deg(d, s.forward, s.up),
        "kingpin_inclination_deg": kingpin_inclination_deg(d, s.outboard, s.up),
        "scrub_radius_mm": scrub_radius_mm(point, d, contact, spin, s.forward, s.outboard,
                                           s.up),
        "caster_trail_mm": caster_trail_mm(point, d, contact, spin, s.forward, s.outboard,
                                           s.up),
    }


class SteeringAxisWarning(UserWarning):
    """The steering axis is undefined at some steps (NaN columns); the message says why."""


def steering_axis_columns(states: list[StepState], suspension: Suspension
                          ) -> dict[str, np.ndarray]:
    """Caster (deg), kingpin inclination (deg), scrub radius (mm) and caster trail (mm) per
    step, the ground plane being the plane normal to ``up`` through the wheel's contact point
    (loaded radius below the centre in the wheel plane). NaN where the axis is undefined, with
    a :class:`SteeringAxisWarning`."""
    s = suspension
    centre = np.array([st.wheel_centre_mm for st in states])
    spin = np.array([st.spin_axis for st in states])
    if not steerable(s):
        nan = np.full(len(states), np.nan)
        return {name: nan.copy() for name in STEERING_AXIS_COLUMNS}
    skeleton = steering_skeleton(s)
    axes = steering_axes_from_poses(skeleton, [st.poses for st in states], centre)
    out = axis_columns(axes.direction, axes.point, centre, spin, s)
    d = axes.direction.copy()
    d[np.abs(d @ s.up) < 1e-9] = np.nan
    if skeleton.reason is not None:  # the suspension has none (the same for every run)
        warnings.warn(SteeringAxisWarning(
            f"{s.source}: no steering axis (NaN caster, kingpin inclination, scrub radius, "
            f"caster trail): {skeleton.reason}"), stacklevel=2)
    elif axes.reason is not None or np.isnan(d).any():
        bad = int(np.isnan(d).any(axis=1).sum())
        warnings.warn(SteeringAxisWarning(
            f"{s.source}: steering axis undefined at {bad} of {len(states)} steps (NaN "
            f"caster, kingpin inclination, scrub radius, caster trail): "
            f"{axes.reason or 'horizontal axis'}"), stacklevel=2)
    return out
