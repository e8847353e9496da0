"""Axle characteristics from rig sweeps: track, wheelbase change, roll angle, roll stiffness
and the anti-roll bar's share, roll steer and roll camber, ride rate (pure numpy).

**Frame and units.** ISO 8855 vehicle frame: x forward, y to the vehicle's LEFT, z up; mm, N,
N*mm, deg. Wheel travel: vertical motion of the wheel (contact point or wheel centre, as the
rig reports it) relative to the body, **bump +**. Wheel angles per wheel: toe-in +, camber top
outboard + (:mod:`elastokin.physics.wheel`). Sweep arrays are 1-D, one entry per rig step;
slopes are least-squares fits (:func:`elastokin.physics.wheel.slope`) over the points inside
``window`` (all points when None), loading and unloading together.

**Roll angle** (ADAMS/Car SVCROL: "the rotation of the line through the tire patches"): the
body's rotation relative to the line through the two contact points, ISO 8855 sign (right-hand
about x forward: + when the body's **left side rises**, as in a left turn), from the wheel
travels: ``phi = atan((travel_right - travel_left) / track)``.
"""

from __future__ import annotations

import numpy as np

from elastokin.physics.axle_compliance import SIDES, outboard_sign
from elastokin.physics.wheel import slope

__all__ = [
    "antiroll_bar_roll_stiffness_Nmm_per_deg",
    "half_track_mm",
    "ride_rate_N_per_mm",
    "roll_angle_deg",
    "roll_coefficients",
    "roll_moment_Nmm",
    "roll_stiffness_Nmm_per_deg",
    "track_change_mm",
    "track_mm",
    "wheelbase_change_mm",
]


def _vec(v) -> np.ndarray:
    return np.asarray(v, dtype=float)


def track_mm(contact_left_mm, contact_right_mm) -> np.ndarray:
    """Track [mm]: lateral distance between the two contact points, ``y_left - y_right``."""
    return _vec(contact_left_mm)[..., 1] - _vec(contact_right_mm)[..., 1]


def half_track_mm(contact_mm, side: str) -> np.ndarray:
    """Half-track [mm] of ``side``'s wheel: its contact point's distance outboard of the
    vehicle's centre plane (y = 0)."""
    return outboard_sign(side) * _vec(contact_mm)[..., 1]


def track_change_mm(contact_left_mm, contact_right_mm, contact_left0_mm,
                    contact_right0_mm) -> np.ndarray:
    """Track change [mm] at the contact points from the reference state ``*0``: the sum of
    both wheels' outboard displacements (+ wider)."""
    return (track_mm(contact_left_mm, contact_right_mm)
            - track_mm(contact_left0_mm, contact_right0_mm))


def wheelbase_change_mm(point_mm, point0_mm, axle: str) -> np.ndarray:
    """Wheelbase change [mm] from this axle's wheel (its wheel centre or its contact point:
    whichever point is passed) moving longitudinally from ``point0_mm``: + when the
    wheelbase grows (front wheel forward, rear wheel rearward)."""
    if axle not in ("front", "rear"):
        raise ValueError(f"axle must be 'front' or 'rear', got {axle!r}")
    dx = _vec(point_mm)[..., 0] - _vec(point0_mm)[..., 0]
    return dx if axle == "front" else -dx


def roll_angle_deg(travel_left_mm, travel_right_mm, axle_track_mm) -> np.ndarray:
    """Body roll angle [deg] relative to the line through the contact points (module
    docstring): ``atan((travel_right - travel_left) / track)``, + when the body's left side
    rises (left wheel rebounds, right wheel bumps)."""
    track = _vec(axle_track_mm)
    if np.any(~(track > 0)):
        raise ValueError("track_mm must be > 0")
    return np.degrees(np.arctan2(_vec(travel_right_mm) - _vec(travel_left_mm), track))


def roll_moment_Nmm(vertical_force_left_N, vertical_force_right_N, contact_y_left_mm,
                    contact_y_right_mm) -> np.ndarray:
    """Roll moment [N*mm]: the moment about the x axis that the body needs to hold its roll
    angle against the wheel loads (forces up on the tyres, + up), ``-(y_l F_l + y_r F_r)``;
    for contact points at ``+-track/2`` this is ``(F_right - F_left) * track / 2``, + with +
    roll."""
    return -(_vec(contact_y_left_mm) * _vec(vertical_force_left_N)
             + _vec(contact_y_right_mm) * _vec(vertical_force_right_N))


def roll_stiffness_Nmm_per_deg(roll_deg, moment_Nmm, window=None, subject: str = "",
                               where: str = "of roll angle", remedy: str = "") -> float:
    """Total roll stiffness of the axle [N*mm/deg]: slope of the roll moment
    (:func:`roll_moment_Nmm`) against the roll angle (:func:`roll_angle_deg`) over
    ``window`` (deg), springs, anti-roll bar and bushings together, tyres excluded (the rig
    moves the contact points). ``subject`` starts the warning of a slope not determined
    (NaN: fewer than three distinct roll angles, :func:`elastokin.physics.wheel.slope`)."""
    return slope(roll_deg, moment_Nmm, window, what=f"{subject}roll stiffness",
                 where=where, remedy=remedy)


def antiroll_bar_roll_stiffness_Nmm_per_deg(roll_deg, bar_twist_deg, bar_torque_Nmm,
                                            window=None, subject: str = "",
                                            where: str = "of roll angle",
                                            remedy: str = "") -> float:
    """The anti-roll bar's part of the roll stiffness [N*mm/deg], from its torsion.

    By virtual work the bar's torque ``T`` (about its twist, ``bar_torque_Nmm``) holds the
    roll moment ``T * dtheta/dphi`` (``theta`` = ``bar_twist_deg``); with ``dtheta/dphi``
    the least-squares slope over ``window`` this is ``dtheta/dphi * dT/dphi``. Its share of
    the total is this divided by :func:`roll_stiffness_Nmm_per_deg` (bar and springs act in
    parallel)."""
    what = f"{subject}anti-roll bar roll stiffness"
    return (slope(roll_deg, bar_twist_deg, window, what=what, where=where, remedy=remedy)
            * slope(roll_deg, bar_torque_Nmm, window, what=what, where=where, remedy=remedy))


def roll_coefficients(roll_deg, toe_left_deg, toe_right_deg, camber_left_deg,
                      camber_right_deg, window=None, subject: str = "",
                      where: str = "of roll angle", remedy: str = "") -> dict[str, float]:
    """Roll steer and roll camber [deg/deg] from an opposite-travel sweep.

    ``roll_steer_{side}_deg_per_deg``: slope of the wheel's toe (toe-in +) against the roll
    angle; ``roll_camber_{side}_deg_per_deg``: slope of its camber (top outboard +, relative
    to the body); ``axle_roll_steer_deg_per_deg``: slope of the mean steer angle (ADAMS/Car's
    steer, + to the left: ``(-toe_left + toe_right) / 2``), positive when the axle steers
    into the turn. NaN where the roll angles are too few (:func:`roll_stiffness_Nmm_per_deg`)."""
    toe = {"left": _vec(toe_left_deg), "right": _vec(toe_right_deg)}
    camber = {"left": _vec(camber_left_deg), "right": _vec(camber_right_deg)}
    mean_steer = 0.5 * (-toe["left"] + toe["right"])
    curves = {f"roll_steer_{side}_deg_per_deg": toe[side] for side in SIDES}
    curves.update({f"roll_camber_{side}_deg_per_deg": camber[side] for side in SIDES})
    curves["axle_roll_steer_deg_per_deg"] = mean_steer
    order = ("roll_steer_left_deg_per_deg", "roll_camber_left_deg_per_deg",
             "roll_steer_right_deg_per_deg", "roll_camber_right_deg_per_deg",
             "axle_roll_steer_deg_per_deg")
    return {name: slope(roll_deg, curves[name], window, what=f"{subject}{name}",
                        where=where, remedy=remedy) for name in order}


def ride_rate_N_per_mm(wheel_rate_N_per_mm, tyre_rate_N_per_mm) -> np.ndarray:
    """Ride rate [N/mm]: the wheel rate in series with the tyre's vertical rate, ``kw kt /
    (kw + kt)`` (ADAMS/Car, MotionView "Ride Rate")."""
    kw, kt = _vec(wheel_rate_N_per_mm), _vec(tyre_rate_N_per_mm)
    if np.any(~(kw > 0)) or np.any(~(kt > 0)):
        raise ValueError("wheel and tyre rates must be > 0 N/mm")
    return kw * kt / (kw + kt)
