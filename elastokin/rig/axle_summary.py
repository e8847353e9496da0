"""The axle's characteristics (summary.json ``models.<label>.axle``; names, units and
definitions in :data:`elastokin.rig.channels.AXLE_CHARACTERISTIC_LIST`) from both wheels'
sweeps and the 12x12 wheel-centre compliance, with the physics of
:mod:`elastokin.physics.axle_sweeps`, :mod:`~elastokin.physics.axle_compliance`,
:mod:`~elastokin.physics.instant_centres` and :mod:`~elastokin.physics.ackermann` (ISO 8855
frame, left wheel first: the config frame and sides are turned into it here).

A figure whose load case was not run, or whose vehicle data are missing, is None.
"""

from __future__ import annotations

import numpy as np

from elastokin.config.suspension import Suspension
from elastokin.physics import ackermann, axle_compliance, axle_sweeps
from elastokin.physics.instant_centres import force_based_roll_centre
from elastokin.physics.wheel import slope
from elastokin.rig.axle_channels import design_track_mm, iso_rotation
from elastokin.rig.characteristics import determined, finer, measured
from elastokin.rig.sweeps import Sweep, find_sweep, static_row_value

#: steering ratio on centre: the local slope over this steering-wheel window (deg)
CENTRE_WINDOW_DEG = 20.0


def iso_compliance(C: np.ndarray, suspension: Suspension) -> np.ndarray:
    """The 12x12 compliance (config frame, config side first) in the ISO frame with the left
    wheel first, as :mod:`elastokin.physics.axle_compliance` takes it."""
    T = iso_rotation(suspension)
    order = [0, 1] if suspension.sides[0] == "left" else [1, 0]
    blocks = np.kron(np.eye(4), T)  # x y z, rx ry rz of each wheel
    Ci = blocks @ C @ blocks.T
    idx = np.concatenate([np.arange(6 * k, 6 * k + 6) for k in order])
    return Ci[np.ix_(idx, idx)]


def axle_characteristics(sweeps: dict[str, list[Sweep]], summaries: dict[str, dict],
                         suspension: Suspension, C: np.ndarray | None) -> dict:
    """Every axle characteristic (module docstring): ``sweeps`` and ``summaries`` (each
    wheel's summary figures) by side, ``C`` the 12x12 compliance (config frame, config side
    first) or None."""
    s = suspension
    out: dict = {c: None for c in ("roll_centre_height_mm", "roll_centre_lateral_mm")}
    travel = find_sweep(sweeps[s.side], "opposite_travel" if s.shared_beams
                        else "parallel_travel")  # in roll on a twist beam
    if travel is not None and "roll_centre_height_mm" in travel.columns:
        out["roll_centre_height_mm"] = static_row_value(travel, "roll_centre_height_mm")
        out["roll_centre_lateral_mm"] = static_row_value(travel, "roll_centre_lateral_mm")
    out.update(_roll(sweeps))
    out.update(_steering(sweeps, s))
    for side in ("left", "right"):
        rate = summaries[side].get("wheel_rate_N_per_mm")
        tyre = s.wheels[side].tyre_rate_N_per_mm
        out[f"ride_rate_{side}_N_per_mm"] = (float(axle_sweeps.ride_rate_N_per_mm(rate, tyre))
                                             if rate and rate > 0 and tyre else None)
    out.update(_from_compliance(s, C))
    # not determined (a slope from too few points, a roll centre at infinity): null
    return {k: determined(v) if isinstance(v, float) else v for k, v in out.items()}


def _roll(sweeps: dict[str, list[Sweep]]) -> dict:
    keys = ("roll_stiffness_Nmm_per_deg", "anti_roll_bar_roll_stiffness_Nmm_per_deg",
            "anti_roll_bar_share", "roll_steer_left_deg_per_deg",
            "roll_steer_right_deg_per_deg", "axle_roll_steer_deg_per_deg",
            "roll_camber_left_deg_per_deg", "roll_camber_right_deg_per_deg")
    out = dict.fromkeys(keys)
    roll = {side: find_sweep(sweeps[side], "roll_vertical_force") for side in sweeps}
    if roll["left"] is None:
        return out
    left, right = roll["left"], roll["right"]
    phi = measured(left, "roll_angle_deg")
    note = {"subject": f"model '{left.model}': ", "where": "of roll angle in the roll sweep",
            "remedy": finer(left, "roll_vertical_force")}
    out["roll_stiffness_Nmm_per_deg"] = axle_sweeps.roll_stiffness_Nmm_per_deg(
        phi, measured(left, "roll_moment_Nmm"), **note)
    if "arb_twist_deg" in left.columns:
        bar = axle_sweeps.antiroll_bar_roll_stiffness_Nmm_per_deg(
            phi, measured(left, "arb_twist_deg"), measured(left, "arb_torque_Nmm"), **note)
        out["anti_roll_bar_roll_stiffness_Nmm_per_deg"] = bar
        out["anti_roll_bar_share"] = bar / out["roll_stiffness_Nmm_per_deg"]
    out.update(axle_sweeps.roll_coefficients(
        phi, measured(left, "toe_deg"), measured(right, "toe_deg"),
        measured(left, "camber_deg"), measured(right, "camber_deg"), **note))
    return out


def _steering(sweeps: dict[str, list[Sweep]], s: Suspension) -> dict:
    keys = ("steering_ratio_overall", "steering_ratio_centre", "percent_ackermann_lock",
            "ackermann_error_lock_deg", "outside_turn_diameter_mm", "max_steer_inner_deg",
            "max_steer_outer_deg")
    out = dict.fromkeys(keys)
    left = find_sweep(sweeps["left"], "steering")
    right = find_sweep(sweeps["right"], "steering")
    if left is None:
        return out
    swa = left.columns["steering_wheel_angle_deg"]
    sl, sr = left.columns["steer_angle_deg"], right.columns["steer_angle_deg"]
    out["steering_ratio_overall"] = ackermann.steering_ratio_overall(swa, sl, sr)
    # d(steering-wheel angle)/d(mean steer), fitted where the steering wheel is on centre
    out["steering_ratio_centre"] = slope(
        0.5 * (sl + sr), swa, keep=np.abs(swa) <= CENTRE_WINDOW_DEG,
        what=f"model '{left.model}': steering ratio on centre (steering_ratio_centre)",
        where=f"with the steering-wheel angle within +-{CENTRE_WINDOW_DEG:g} deg",
        remedy=finer(left, "steering"))
    k = int(np.argmax(0.5 * (sl + sr)))  # the left lock: both wheels steered left
    out["max_steer_inner_deg"], out["max_steer_outer_deg"] = float(sl[k]), float(sr[k])
    v = s.axle.vehicle
    if v is None:
        return out
    args = (sl[k], sr[k], v.wheelbase_mm, design_track_mm(s))
    out["percent_ackermann_lock"] = float(ackermann.percent_ackermann(*args))
    out["ackermann_error_lock_deg"] = float(ackermann.ackermann_error_deg(*args))
    out["outside_turn_diameter_mm"] = float(ackermann.outside_turn_diameter_mm(*args))
    return out


def _from_compliance(s: Suspension, C: np.ndarray | None) -> dict:
    out = dict.fromkeys(("roll_centre_height_force_based_mm", "percent_anti_dive",
                         "percent_anti_lift_braking", "percent_anti_lift_traction",
                         "percent_anti_squat"))
    if C is None:
        return out
    Ci = iso_compliance(C, s)
    T = iso_rotation(s)
    wc = {side: T @ s.wheels[side].centre_mm for side in ("left", "right")}
    cp = {side: T @ s.wheels[side].contact_patch_mm for side in ("left", "right")}
    rc = force_based_roll_centre(Ci, wc["left"], wc["right"], cp["left"], cp["right"])
    out["roll_centre_height_force_based_mm"] = float(rc.height_mm)
    out["named_compliances"] = axle_compliance.named_compliances(Ci, s.wheel.loaded_radius_mm)
    out["compliance_matrix_12x12"] = {
        "rows": "left wheel centre x y z [mm], rx ry rz [deg], then the right wheel's",
        "columns": "force x y z [N], torque x y z [N*mm] at the left, then the right wheel "
                   "centre", "frame": "ISO 8855 (x forward, y left, z up)",
        "values": Ci.tolist()}
    v = s.axle.vehicle
    if v is None:
        return out
    r = s.wheel.loaded_radius_mm
    # a live axle (ADAMS/Car's dependent suspension): the pinion torque reacted by the housing
    live = {} if v.live_axle_ratio is None else {"live_axle_ratio": v.live_axle_ratio,
                                                 "track_mm": design_track_mm(s)}
    if v.position == "front":
        out["percent_anti_dive"] = _mean(axle_compliance.percent_anti_dive(
            Ci, v.wheelbase_mm, v.cg_height_mm, r, v.brake_fraction, v.brakes))
        out["percent_anti_lift_traction"] = _mean(axle_compliance.percent_anti_lift_traction(
            Ci, v.wheelbase_mm, v.cg_height_mm, r, v.drive_fraction, v.drive, **live))
    else:
        out["percent_anti_lift_braking"] = _mean(axle_compliance.percent_anti_lift_braking(
            Ci, v.wheelbase_mm, v.cg_height_mm, r, 1.0 - v.brake_fraction, v.brakes))
        out["percent_anti_squat"] = _mean(axle_compliance.percent_anti_squat(
            Ci, v.wheelbase_mm, v.cg_height_mm, r, 1.0 - v.drive_fraction, v.drive, **live))
    return out


def _mean(per_side: dict[str, float]) -> float | None:
    """The axle's figure of a per-wheel result (both wheels' mean; one for a symmetric
    axle)."""
    values = [float(v) for k, v in per_side.items() if isinstance(v, (int, float))]
    return float(np.mean(values)) if values else None
