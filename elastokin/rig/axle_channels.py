"""Per-step channels of an axle, from both wheels' solved rig steps: roll angle and roll
moment, the anti-roll bar's twist and torque, and in parallel travel the kinematic roll centre
(:mod:`elastokin.physics.axle_sweeps`, :mod:`elastokin.physics.instant_centres`, which work in
the ISO 8855 frame: the config frame is turned into it here).

Units mm, N, N*mm, deg; names and signs in :mod:`elastokin.rig.channels`.
"""

from __future__ import annotations

import warnings

import numpy as np

from elastokin.config.suspension import Suspension
from elastokin.physics.axle_sweeps import roll_angle_deg, roll_moment_Nmm, track_mm
from elastokin.physics.instant_centres import kinematic_roll_centre
from elastokin.physics.roll_motion import roll_motion
from elastokin.physics.skeleton import SkeletonElement
from elastokin.physics.states import StepState, WheelArrays
from elastokin.rig.steering import joint_elements


def iso_rotation(suspension: Suspension) -> np.ndarray:
    """The rotation from the config frame to ISO 8855 (x forward, y left, z up)."""
    s = suspension
    return np.column_stack([s.forward, s.left, s.up]).T


def design_track_mm(suspension: Suspension) -> float:
    """The axle's track at the design position [mm]: the lateral distance of the two
    wheels' contact points."""
    T = iso_rotation(suspension)
    patch = {side: T @ w.contact_patch_mm for side, w in suspension.wheels.items()}
    return abs(float(track_mm(patch["left"], patch["right"])))


def axle_columns(by_side: dict[str, list[StepState] | WheelArrays], suspension: Suspension,
                 drive, static: dict[str, StepState]) -> dict[str, np.ndarray]:
    """The axle's columns of one load case (the same in every wheel's sweep):
    ``roll_angle_deg`` (from each wheel's travel from its ``static`` state, the model's own
    static state under the design wheel loads) and ``roll_moment_Nmm`` from both wheels, the
    anti-roll bar's ``arb_twist_deg`` and ``arb_torque_Nmm``; in parallel travel (in opposite
    wheel travel on an axle joined by a flexible beam: ``Suspension.shared_beams``) the
    kinematic ``roll_centre_height_mm`` (above the contact points' mean height) and
    ``roll_centre_lateral_mm`` (ISO y, + left): each wheel's instant centre from its motion
    along the sweep, or on a dependent axle (:func:`dependent_axle`) the instant centre of
    the axle's roll motion at each step (:func:`roll_contact_velocities`). The contact points
    are the wheels' lowest points (``StepState.contact_patch_mm``)."""
    s = suspension
    T = iso_rotation(s)
    wheel = {side: WheelArrays.of(by_side[side]) for side in ("left", "right")}
    patch = {side: a.contact_patch_mm @ T.T for side, a in wheel.items()}
    centre = {side: a.wheel_centre_mm @ T.T for side, a in wheel.items()}
    travel = {side: centre[side][:, 2] - (T @ static[side].wheel_centre_mm)[2]
              for side in centre}
    track = design_track_mm(s)
    fz = {side: np.array([(T @ f)[2] for f in a.pad_force_N]) for side, a in wheel.items()}
    cols = {"roll_angle_deg": roll_angle_deg(travel["left"], travel["right"], track),
            "roll_moment_Nmm": roll_moment_Nmm(fz["left"], fz["right"], patch["left"][:, 1],
                                               patch["right"][:, 1])}
    first = wheel[s.side]
    if "arb:twist_deg" in first.scalars:
        cols["arb_twist_deg"] = first.scalars["arb:twist_deg"]
        cols["arb_torque_Nmm"] = first.scalars["arb:torque_Nmm"]
    # the kinematic roll centre from the wheels' motion in bump, or on an axle joined by a
    # flexible beam (a twist beam, whose elasticity sets the motion in roll) in roll, or on
    # a dependent axle (a solid axle) from its roll motion at each step of parallel travel
    in_roll = bool(s.shared_beams)
    if drive.load_case == ("opposite_travel" if in_roll else "parallel_travel"):
        if not in_roll and dependent_axle(s):
            steps = by_side[s.side]
            if isinstance(steps, WheelArrays):
                steps = [steps.step(i) for i in range(len(steps))]
            velocity = roll_contact_velocities(steps, s, {
                side: a.contact_patch_mm for side, a in wheel.items()})
            rc = kinematic_roll_centre(patch["left"], velocity["left"] @ T.T, patch["right"],
                                       velocity["right"] @ T.T)
            cols.update({"roll_centre_height_mm": rc.height_mm,
                         "roll_centre_lateral_mm": rc.lateral_mm})
        else:
            branch = np.asarray(drive.branch)
            cols.update(roll_centre_columns(patch, branch if drive.recorded is None
                                            else branch[drive.recorded]))
    return cols


def roll_centre_columns(patch: dict[str, np.ndarray], branch: np.ndarray
                        ) -> dict[str, np.ndarray]:
    """The kinematic roll centre at every step of a parallel (or opposite) travel sweep (ISO
    frame): the contact points' velocities are their central differences along each branch
    (one-sided at a branch's ends); a branch of one step has none (NaN)."""
    height = np.full(branch.size, np.nan)
    lateral = np.full(branch.size, np.nan)
    for name in dict.fromkeys(branch.tolist()):
        rows = np.flatnonzero(branch == name)
        if rows.size < 2:
            continue
        v = {side: np.gradient(p[rows], axis=0) for side, p in patch.items()}
        rc = kinematic_roll_centre(patch["left"][rows], v["left"], patch["right"][rows],
                                   v["right"])
        height[rows], lateral[rows] = rc.height_mm, rc.lateral_mm
    return {"roll_centre_height_mm": height, "roll_centre_lateral_mm": lateral}


def dependent_axle(suspension: Suspension) -> bool:
    """Whether the axle's wheels move together: their parts are one part (a solid axle) or
    joined through moving parts by joints, links or bushings (not through the ground, nor
    the steering rack, which the rig holds in travel, nor springs or the anti-roll bar)."""
    s = suspension
    if s.axle is None:
        return False
    held = {s.ground} | ({s.axle.steering.part} if s.axle.steering else set())
    held |= {p for j in s.joints if j.kind == "rack" for p in j.parts}  # a rack held in travel
    pairs = [c.parts for c in (*s.joints, *s.links, *s.bushings)]
    left, right = (s.wheels[side].part for side in ("left", "right"))
    reached, grown = {left}, True
    while grown:
        new = {q for a, b in pairs for p, q in ((a, b), (b, a))
               if p in reached and q not in held} - reached
        grown = bool(new)
        reached |= new
    return right in reached


def roll_contact_velocities(states: list[StepState], suspension: Suspension,
                            contact: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """Each wheel's contact-point velocity (config frame, (S, 3), per unit vertical rate: +1
    left, -1 right) in the axle's roll motion at every step, from the steps' part poses
    (:mod:`elastokin.physics.roll_motion`: every joint held, bushings as their ideal joints
    frozen at their deflection, the steering rack held); ``contact``: each wheel's contact
    point at every step (config frame, (S, 3): its lowest point, where the point of the wheel
    part moves as the tyre's contact point does in the front view); NaN without poses."""
    s = suspension
    n = len(states)
    if any(st.poses is None for st in states):
        return {side: np.full((n, 3), np.nan) for side in ("left", "right")}
    first = states[0].poses
    rotation = {p: np.array([st.poses.rotation[p] for st in states]) for p in first.rotation}
    position = {p: np.array([st.poses.displacement_mm[p] for st in states])
                + first.reference_mm[p] for p in first.rotation}
    elements = joint_elements(s, release_rack=False)
    elements += [SkeletonElement("distance", lk.parts, lk.points_mm) for lk in s.links]
    wheels = {side: (s.wheels[side].part, np.asarray(contact[side], float))
              for side in ("left", "right")}
    motion = roll_motion(s.ground, elements, rotation, position, dict(first.reference_mm),
                         wheels, s.up)
    if motion.reason is not None:
        bad = int(np.isnan(motion.contact_velocity["left"]).any(axis=1).sum())
        warnings.warn(RollCentreWarning(
            f"{s.source}: kinematic roll centre undefined at {bad} of {n} steps of parallel "
            f"travel: {motion.reason}"), stacklevel=2)
    return motion.contact_velocity


class RollCentreWarning(UserWarning):
    """The kinematic roll centre of a dependent axle is undefined at some steps (NaN)."""
