"""Per-step channels of an axle, from both wheels' solved rig steps: roll angle and roll
moment, the anti-roll bar's twist and torque, and in parallel travel the kinematic roll centre
(:mod:`elastokin.physics.axle_sweeps`, :mod:`elastokin.physics.instant_centres`, which work in
the ISO 8855 frame: the config frame is turned into it here).

Units mm, N, N*mm, deg; names and signs in :mod:`elastokin.rig.channels`.
"""

from __future__ import annotations

import numpy as np

from elastokin.config.suspension import Suspension
from elastokin.physics.axle_sweeps import roll_angle_deg, roll_moment_Nmm, track_mm
from elastokin.physics.instant_centres import kinematic_roll_centre
from elastokin.physics.states import StepState, WheelArrays


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
                 drive
                 ) -> dict[str, np.ndarray]:
    """The axle's columns of one load case (the same in every wheel's sweep):
    ``roll_angle_deg`` and ``roll_moment_Nmm`` from both wheels, the anti-roll bar's
    ``arb_twist_deg`` and ``arb_torque_Nmm``; in parallel travel the kinematic
    ``roll_centre_height_mm`` (above the contact points' mean height) and
    ``roll_centre_lateral_mm`` (ISO y, + left)."""
    s = suspension
    T = iso_rotation(s)
    wheel = {side: WheelArrays.of(by_side[side]) for side in ("left", "right")}
    patch = {side: a.contact_patch_mm @ T.T for side, a in wheel.items()}
    centre = {side: a.wheel_centre_mm @ T.T for side, a in wheel.items()}
    design_centre = {side: T @ s.wheels[side].centre_mm for side in ("left", "right")}
    travel = {side: centre[side][:, 2] - design_centre[side][2] for side in centre}
    track = design_track_mm(s)
    fz = {side: np.array([(T @ f)[2] for f in a.pad_force_N]) for side, a in wheel.items()}
    cols = {"roll_angle_deg": roll_angle_deg(travel["left"], travel["right"], track),
            "roll_moment_Nmm": roll_moment_Nmm(fz["left"], fz["right"], patch["left"][:, 1],
                                               patch["right"][:, 1])}
    first = wheel[s.side]
    if "arb:twist_deg" in first.scalars:
        cols["arb_twist_deg"] = first.scalars["arb:twist_deg"]
        cols["arb_torque_Nmm"] = first.scalars["arb:torque_Nmm"]
    if drive.load_case == "parallel_travel":
        cols.update(roll_centre_columns(patch, np.asarray(drive.branch)))
    return cols


def roll_centre_columns(patch: dict[str, np.ndarray], branch: np.ndarray
                        ) -> dict[str, np.ndarray]:
    """The kinematic roll centre at every step of a parallel-travel sweep (ISO frame): the
    contact points' velocities are their central differences along each branch (one-sided at
    a branch's ends); a branch of one step has none (NaN)."""
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
