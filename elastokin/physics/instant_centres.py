"""Instant centres, swing arms, roll centres and side-view percent anti (pure numpy).

**Frame and units.** ISO 8855 vehicle frame: x forward, y to the vehicle's LEFT, z up; mm,
deg; the body is fixed. Points and motions may be single vectors ``(3,)`` or stacks ``(..., 3)``
(one row per rig step); results broadcast.

**Motions.** A wheel's instantaneous motion relative to the body is a twist: angular velocity
``angular_velocity_deg`` (3,) and the velocity ``velocity_mm`` (3,) of a reference point
``point_mm``, both per unit of one common parameter (wheel travel, rack travel, the magnitude
of a load for a compliance response from
:func:`elastokin.physics.axle_compliance.wheel_response`). Only their ratio matters: the
instant centres do not depend on the parameter, nor on the reference point.

**Instant centres** (ADAMS/Car "Side View Instant Center", MotionView "Front/Side View Swing
Arm"). The front-view instant centre is the point of the transverse (y-z) plane through
``at_mm`` (default the reference point) whose velocity has no y-z component: ``y = y_a -
v_z / w_x``, ``z = z_a + v_y / w_x`` (``v`` the velocity at ``at_mm``, ``w`` in rad). The
side-view instant centre, in the x-z plane through ``at_mm``: ``x = x_a + v_z / w_y``, ``z =
z_a - v_x / w_y``. Swing-arm length: distance from ``at_mm`` to the instant centre in that
view; swing-arm angle: inclination of the line from ``at_mm`` to the instant centre from the
horizontal, in (-90, 90] deg, positive when it rises **inboard** (front view) or **rearward**
(side view). With no rotation in the view (parallel, equal arms) the instant centre is at
infinity: coordinates NaN, length ``inf``, the angle still the direction towards it. Without
any motion in the view everything is NaN.

**Roll centre.** The kinematic roll centre is where the lines from each contact point to its
wheel's front-view instant centre meet (SAE J670; Milliken & Milliken, *Race Car Vehicle
Dynamics*, ch. 17). Each such line is the line through the contact point normal to the contact
point's front-view velocity, which stays defined when the instant centre is at infinity.
ADAMS/Car's roll centre ("Roll Center Height", SVCROL) is the same construction with the
contact points' displacements under opposing unit vertical forces at the contact points (C
transferred to the contact points): the **force-based** roll centre. Height is measured from
the mean height of the two contact points (the ground); lateral position is y (+ left).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from elastokin.physics.axle_compliance import (
    Z,
    contact_patch_compliance,
    outboard_sign,
    wheel_response,
)

__all__ = [
    "MAX_SWING_ARM_MM",
    "RollCentre",
    "ViewInstantCentre",
    "force_based_roll_centre",
    "front_view_instant_centre",
    "instant_centres_from_compliance",
    "kinematic_roll_centre",
    "percent_anti_geometric",
    "point_velocity",
    "side_view_instant_centre",
]

#: a swing arm longer than this (mm) is taken as infinite (no rotation in the view)
MAX_SWING_ARM_MM = 1.0e12
#: two roll-centre lines are parallel when |sin(angle between them)| is below this
PARALLEL_SIN = 1.0e-9


def _vec(v) -> np.ndarray:
    return np.asarray(v, dtype=float)


@dataclass(frozen=True)
class ViewInstantCentre:
    """An instant centre in one view (front: ``horizontal_mm`` is y; side: it is x).

    ``z_mm`` is its height in the vehicle frame; ``swing_arm_length_mm`` the distance from
    the reference point in the view (``inf`` at infinity); ``swing_arm_angle_deg`` the
    inclination of the line towards it (module docstring for the signs)."""

    horizontal_mm: np.ndarray
    z_mm: np.ndarray
    swing_arm_length_mm: np.ndarray
    swing_arm_angle_deg: np.ndarray


@dataclass(frozen=True)
class RollCentre:
    """A roll centre: ``lateral_mm`` (y, + left), ``height_mm`` above the mean height of the
    two contact points, and ``state`` saying what the numbers mean:

    - ``"finite"``: the two lines meet;
    - ``"parallel"``: the lines are parallel and distinct; the roll centre is at infinity
      (both NaN);
    - ``"coincident"``: the lines coincide (e.g. equal parallel arms with both lines along
      the ground): every point of the line qualifies; the point midway between the contact
      points is returned;
    - ``"undefined"``: a contact point does not move in the front view (both NaN).
    """

    lateral_mm: np.ndarray
    height_mm: np.ndarray
    state: np.ndarray


def point_velocity(angular_velocity_deg, velocity_mm, point_mm, at_mm) -> np.ndarray:
    """Velocity of the body-fixed point ``at_mm`` of a rigid body moving with the twist
    ``(angular_velocity_deg, velocity_mm at point_mm)``: ``v + w x (at - point)``, w in
    rad."""
    w = np.radians(_vec(angular_velocity_deg))
    return _vec(velocity_mm) + np.cross(w, _vec(at_mm) - _vec(point_mm))


def _line_angle_deg(d_horizontal, d_z) -> np.ndarray:
    """Inclination of the line along (d_horizontal, d_z) in (-90, 90] deg."""
    flip = np.where(d_horizontal < 0, -1.0, 1.0)
    return np.degrees(np.arctan2(flip * d_z, flip * d_horizontal))


def _view_centre(at_h, at_z, w, v_h, v_z, towards) -> ViewInstantCentre:
    """Instant centre of a planar velocity field: rotation ``w`` (rad), velocity ``(v_h,
    v_z)`` at ``(at_h, at_z)``; ``towards`` (+-1) the horizontal sense of a positive angle."""
    speed = np.hypot(v_h, v_z)
    with np.errstate(divide="ignore", invalid="ignore"):
        length = speed / np.abs(w)
        h, z = at_h - v_z / w, at_z + v_h / w
    at_infinity = ~(length <= MAX_SWING_ARM_MM)  # also NaN (0/0)
    # the line to the instant centre is normal to the velocity: direction (-v_z, v_h)
    angle = _line_angle_deg(-v_z * towards, v_h)
    still = (speed == 0) & (w == 0)
    angle = np.where(speed == 0, np.nan, angle)
    length = np.where(still, np.nan, np.where(at_infinity, np.inf, length))
    h = np.where(at_infinity, np.nan, h)
    z = np.where(at_infinity, np.nan, z)
    return ViewInstantCentre(h, z, length, angle)


def front_view_instant_centre(angular_velocity_deg, velocity_mm, point_mm, side: str,
                              at_mm=None) -> ViewInstantCentre:
    """Front-view (y-z) instant centre of ``side``'s wheel in the transverse plane through
    ``at_mm`` (default ``point_mm``): ``horizontal_mm`` is its y; angle positive rising
    inboard."""
    at = _vec(point_mm) if at_mm is None else _vec(at_mm)
    v = point_velocity(angular_velocity_deg, velocity_mm, point_mm, at)
    w = np.radians(_vec(angular_velocity_deg))[..., 0]
    return _view_centre(at[..., 1], at[..., 2], w, v[..., 1], v[..., 2], -outboard_sign(side))


def side_view_instant_centre(angular_velocity_deg, velocity_mm, point_mm,
                             at_mm=None) -> ViewInstantCentre:
    """Side-view (x-z) instant centre in the longitudinal plane through ``at_mm`` (default
    ``point_mm``): ``horizontal_mm`` is its x; angle positive rising rearward."""
    at = _vec(point_mm) if at_mm is None else _vec(at_mm)
    v = point_velocity(angular_velocity_deg, velocity_mm, point_mm, at)
    w = np.radians(_vec(angular_velocity_deg))[..., 1]
    # in the x-z plane seen from the left, a rotation about +y turns x towards -z: the
    # planar formulas hold with the rotation -w_y
    return _view_centre(at[..., 0], at[..., 2], -w, v[..., 0], v[..., 2], -1.0)


def _intersect(contact_left, motion_left, contact_right, motion_right) -> RollCentre:
    cl, ml, cr, mr = (_vec(a) for a in (contact_left, motion_left, contact_right, motion_right))
    a, b, c, d = ml[..., 1], ml[..., 2], mr[..., 1], mr[..., 2]  # line normals (y, z)
    yl, zl, yr, zr = cl[..., 1], cl[..., 2], cr[..., 1], cr[..., 2]
    nl, nr = np.hypot(a, b), np.hypot(c, d)
    det = a * d - b * c
    b1, b2 = a * yl + b * zl, c * yr + d * zr
    ground = 0.5 * (zl + zr)
    with np.errstate(divide="ignore", invalid="ignore"):
        y = (b1 * d - b * b2) / det
        z = (a * b2 - c * b1) / det
        parallel = np.abs(det) <= PARALLEL_SIN * nl * nr
        gap = np.abs(a * (yr - yl) + b * (zr - zl)) / nl  # right contact point from left line
        coincident = parallel & (gap <= 1.0e-9 * (1.0 + np.hypot(yr - yl, zr - zl)))
        y_mid = 0.5 * (yl + yr)
        z_mid = zl - a / b * (y_mid - yl)
    undefined = (nl == 0) | (nr == 0)
    state = np.where(undefined, "undefined", np.where(
        coincident, "coincident", np.where(parallel, "parallel", "finite")))
    y = np.where(state == "coincident", y_mid, np.where(state == "finite", y, np.nan))
    z = np.where(state == "coincident", z_mid, np.where(state == "finite", z, np.nan))
    return RollCentre(y, z - ground, state)


def kinematic_roll_centre(contact_left_mm, contact_velocity_left_mm, contact_right_mm,
                          contact_velocity_right_mm) -> RollCentre:
    """Kinematic roll centre from the contact points and their velocities relative to the
    body (any common scale, e.g. per mm of wheel travel; from :func:`point_velocity`): the
    intersection of the lines through each contact point normal to its front-view velocity
    (the lines towards the front-view instant centres)."""
    return _intersect(contact_left_mm, contact_velocity_left_mm, contact_right_mm,
                      contact_velocity_right_mm)


def force_based_roll_centre(C, wheel_centre_left_mm, wheel_centre_right_mm, contact_left_mm,
                            contact_right_mm) -> RollCentre:
    """ADAMS/Car's roll centre ("Roll Center Height", SVCROL) from the 12x12 wheel-centre
    compliance C (:mod:`~.axle_compliance` layout, ISO frame).

    C is transferred to the contact points (``CP``); opposing unit vertical forces at the
    contact points move the left one by ``(CP(2,3) - CP(2,9), CP(3,3) - CP(3,9))`` (y, z) and
    the right one by ``(CP(8,9) - CP(8,3), CP(9,9) - CP(9,3))``; the roll centre is where the
    lines through the contact points normal to these motions meet. By Maxwell-Betti
    ``CP(2,3) = CP(3,2)``: the same numbers say how far a lateral force at the contact point
    moves it vertically. With rigid joints (one motion per wheel) it is the kinematic roll
    centre; bushings and the anti-roll bar's own compliance move it. Single state only.
    """
    wl, wr, cl, cr = (_vec(a).reshape(3) for a in (wheel_centre_left_mm, wheel_centre_right_mm,
                                                    contact_left_mm, contact_right_mm))
    cp = contact_patch_compliance(C, cl - wl, cr - wr)
    motion_left = np.r_[0.0, cp[1, Z] - cp[1, 6 + Z], cp[Z, Z] - cp[Z, 6 + Z]]
    motion_right = np.r_[0.0, cp[7, 6 + Z] - cp[7, Z], cp[6 + Z, 6 + Z] - cp[6 + Z, Z]]
    return _intersect(cl, motion_left, cr, motion_right)


def instant_centres_from_compliance(C, wheel_centre_left_mm, wheel_centre_right_mm) \
        -> dict[str, ViewInstantCentre]:
    """Front- and side-view instant centres of both wheel centres from C, as ADAMS/Car
    (SVCICR) and MotionView compute them: the front view from opposing vertical forces at
    the wheel centres (``C(.,3) - C(.,9)``, left; ``C(.,9) - C(.,3)``, right), the side view
    from equal ones (``C(.,3) + C(.,9)``). Keys ``front_view_left``, ``front_view_right``,
    ``side_view_left``, ``side_view_right``; planes through the wheel centres."""
    up = np.r_[0.0, 0.0, 1.0, 0.0, 0.0, 0.0]
    out = {}
    for side, centre in (("left", wheel_centre_left_mm), ("right", wheel_centre_right_mm)):
        sign = outboard_sign(side)
        rot, disp = wheel_response(C, sign * up, -sign * up, side)
        out[f"front_view_{side}"] = front_view_instant_centre(rot, disp, centre, side)
        rot, disp = wheel_response(C, up, up, side)
        out[f"side_view_{side}"] = side_view_instant_centre(rot, disp, centre)
    return out


def percent_anti_geometric(ic_x_mm, ic_z_mm, reference_x_mm, reference_z_mm, wheelbase_mm,
                           cg_height_mm, fraction, axle: str,
                           swing_arm_angle_deg=None) -> np.ndarray:
    """Percent anti from the side-view instant centre (Milliken & Milliken ch. 17; Gillespie
    ch. 7): ``100 * fraction * tan(theta) * L / h``.

    ``theta`` is the inclination of the line from the reference point to the instant
    centre, positive when it rises towards the body's centre of gravity (rearward on the
    front axle, forward on the rear). Reference point: the contact point for outboard brakes
    (and ADAMS/Car's definition), the wheel centre for inboard brakes or a chassis-mounted
    final drive. ``fraction``: this axle's share of the braking (anti-dive front, anti-lift
    rear) or traction (anti-lift front, anti-squat rear) force. ``axle``: ``"front"`` or
    ``"rear"``. An instant centre at infinity (NaN coordinates) uses
    ``swing_arm_angle_deg`` (rising rearward +, :func:`side_view_instant_centre`)."""
    if axle not in ("front", "rear"):
        raise ValueError(f"axle must be 'front' or 'rear', got {axle!r}")
    if not (wheelbase_mm > 0 and cg_height_mm > 0):
        raise ValueError(f"wheelbase_mm and cg_height_mm must be > 0, got {wheelbase_mm}, "
                         f"{cg_height_mm}")
    with np.errstate(divide="ignore", invalid="ignore"):
        rising_rearward = (_vec(ic_z_mm) - _vec(reference_z_mm)) / (_vec(reference_x_mm)
                                                                    - _vec(ic_x_mm))
    if swing_arm_angle_deg is not None:
        rising_rearward = np.where(np.isnan(_vec(ic_x_mm)),
                                   np.tan(np.radians(_vec(swing_arm_angle_deg))),
                                   rising_rearward)
    tan_theta = rising_rearward if axle == "front" else -rising_rearward
    return 100.0 * fraction * tan_theta * wheelbase_mm / cg_height_mm
