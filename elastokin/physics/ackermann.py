"""Steering characteristics of a steered axle: steer angles, steering ratio, turn radius,
Ackermann angle, percent Ackermann, Ackermann error, outside turn diameter (pure numpy).

**Frame and units.** ISO 8855 top view (x forward, y to the LEFT), mm, deg. A road wheel's
**steer angle** (ADAMS/Car's "steer angle") is + when the wheel turns to the **left**
(right-hand rotation about up), on both wheels, unlike toe (toe-in +, per wheel):
``steer_left = -toe_left``, ``steer_right = +toe_right``. Angles may be arrays (one entry per
rig step); results broadcast.

**Relative angles.** Pass steer angles measured from the straight-ahead position, static toe
removed (:func:`steer_angles_from_toe` with the static toe): this module's Ackermann is the
*relative* one. With static toe left in (absolute), the wheels are not parallel at zero input,
so percent Ackermann runs off to +-infinity as the input goes to zero and a toe-in setting
reads as anti-Ackermann at every steer angle; the relative figure describes the linkage.

**Turn geometry** (rear wheels not steered, no slip; wheelbase ``L``, track ``t`` of the
steered axle at the contact points). The inner wheel is on the side the vehicle turns to (the
sign of the mean steer angle); ``di``, ``do`` are the inner and outer angles in the turn's
sense. In top view each wheel's spindle line crosses the rear axle's line ``L cot d`` from
the wheel: at ``t/2 + L cot di`` (inner) and ``-t/2 + L cot do`` (outer) from the vehicle's
centre line, towards the inside of the turn.

- turn radius ``R = L (cot di + cot do) / 2``: the midpoint of the two crossings (the turn
  radius of MotionView's "Curb to Curb Diameter and Ackerman", method 4);
- Ackermann angle ``atan(L / R)`` (SAE J670 "Ackerman steer angle": wheelbase over turn
  radius), signed with the turn (+ left);
- percent Ackermann ``100 L (cot do - cot di) / t``: 0 % when the wheels are parallel, 100 %
  when both spindle lines meet on the rear axle's line (MotionView's wording; ADAMS/Car's own
  formula was not found), negative for anti-Ackermann. It is the fraction of the track by
  which the linkage draws the two crossings together: exact at 0 % and 100 %. MotionView's
  method 1 (``100 (L cot do - R) / (t/2)`` with ``R = L / tan`` of the mean angle) differs
  by about ``(di - do) / (di + do)`` relative (cot of the mean against the mean of cot);
- Ackermann error ``do - atan(L / (R + t/2))`` (MotionView "Ackerman Deviation"): the outer
  wheel's angle minus the angle that would put its spindle line through the turn centre at
  ``R``; + when the outer wheel steers more (less than 100 % Ackermann);
- outside turn diameter ``2 sqrt((R + t/2)^2 + L^2)``: the circle the outer front contact
  point runs on (MotionView "Curb to Curb Diameter"): curb-to-curb measured at the contact
  point (no tyre half-width), not wall-to-wall (no body overhang);
- the ideal (100 %) Ackermann steer angle of one wheel given the other's
  (:func:`ackermann_partner_steer_deg`): both spindle lines through one point of the rear
  axle's line, ``cot d_right - cot d_left = t / L`` in signed angles (+ left), whichever way
  the vehicle turns.
"""

from __future__ import annotations

import numpy as np

from elastokin.physics.axle_compliance import outboard_sign

__all__ = [
    "ackermann_angle_deg",
    "ackermann_partner_steer_deg",
    "ackermann_error_deg",
    "outside_turn_diameter_mm",
    "percent_ackermann",
    "steer_angles_from_toe",
    "steering_ratio_local",
    "steering_ratio_overall",
    "turn_radius_mm",
]

#: percent Ackermann is NaN when either wheel steers less than this (deg): 0/0 near
#: straight ahead
MIN_STEER_DEG = 0.5


def _vec(v) -> np.ndarray:
    return np.asarray(v, dtype=float)


def steer_angles_from_toe(toe_left_deg, toe_right_deg, static_toe_left_deg=0.0,
                          static_toe_right_deg=0.0) -> tuple[np.ndarray, np.ndarray]:
    """Relative steer angles ``(left, right)`` [deg], + to the left, from the wheels' toe
    angles (toe-in +) and their static toe (straight ahead)."""
    return (-(_vec(toe_left_deg) - _vec(static_toe_left_deg)),
            _vec(toe_right_deg) - _vec(static_toe_right_deg))


def _check_lengths(wheelbase_mm, track_mm) -> None:
    if not (np.all(_vec(wheelbase_mm) > 0) and np.all(_vec(track_mm) > 0)):
        raise ValueError(f"wheelbase_mm and track_mm must be > 0, got {wheelbase_mm}, "
                         f"{track_mm}")


def _turn(steer_left_deg, steer_right_deg, wheelbase_mm, track_mm):
    """(sense, inner, outer [rad, in the turn's sense], cot inner, cot outer, L, t)."""
    _check_lengths(wheelbase_mm, track_mm)
    left, right = np.radians(_vec(steer_left_deg)), np.radians(_vec(steer_right_deg))
    sense = np.where(left + right < 0, -1.0, 1.0)  # turning right: mirror
    inner = sense * np.where(sense > 0, left, right)
    outer = sense * np.where(sense > 0, right, left)
    with np.errstate(divide="ignore"):
        cot_i, cot_o = 1.0 / np.tan(inner), 1.0 / np.tan(outer)
    return sense, inner, outer, cot_i, cot_o, _vec(wheelbase_mm), _vec(track_mm)


def turn_radius_mm(steer_left_deg, steer_right_deg, wheelbase_mm, track_mm) -> np.ndarray:
    """Turn radius [mm] from the rear axle's centre to the turn centre (module docstring);
    ``inf`` straight ahead."""
    _, _, _, cot_i, cot_o, L, _ = _turn(steer_left_deg, steer_right_deg, wheelbase_mm,
                                        track_mm)
    return _radius(cot_i, cot_o, L)


def _radius(cot_inner, cot_outer, wheelbase_mm) -> np.ndarray:
    with np.errstate(invalid="ignore"):
        return wheelbase_mm * (cot_inner + cot_outer) / 2.0


def ackermann_angle_deg(steer_left_deg, steer_right_deg, wheelbase_mm, track_mm) -> np.ndarray:
    """Ackermann angle [deg] ``atan(L / R)``, + turning left; 0 straight ahead."""
    sense, _, _, cot_i, cot_o, L, _ = _turn(steer_left_deg, steer_right_deg, wheelbase_mm,
                                            track_mm)
    return sense * np.degrees(np.arctan(L / _radius(cot_i, cot_o, L)))


def percent_ackermann(steer_left_deg, steer_right_deg, wheelbase_mm, track_mm,
                      min_steer_deg: float = MIN_STEER_DEG) -> np.ndarray:
    """Percent Ackermann ``100 L (cot do - cot di) / t`` (module docstring); NaN where
    either wheel steers less than ``min_steer_deg``."""
    _, inner, outer, cot_i, cot_o, L, t = _turn(steer_left_deg, steer_right_deg,
                                                wheelbase_mm, track_mm)
    small = np.minimum(np.abs(inner), np.abs(outer)) < np.radians(min_steer_deg)
    with np.errstate(invalid="ignore"):
        return np.where(small, np.nan, 100.0 * L * (cot_o - cot_i) / t)


def ackermann_error_deg(steer_left_deg, steer_right_deg, wheelbase_mm, track_mm) -> np.ndarray:
    """Ackermann error [deg] ``do - atan(L / (R + t/2))`` in the turn's sense (module
    docstring): + when the outer wheel steers more than its Ackermann angle for the turn
    radius ``R``."""
    _, _, outer, cot_i, cot_o, L, t = _turn(steer_left_deg, steer_right_deg, wheelbase_mm,
                                            track_mm)
    return np.degrees(outer - np.arctan(L / (_radius(cot_i, cot_o, L) + t / 2.0)))


def ackermann_partner_steer_deg(steer_deg, side: str, wheelbase_mm,
                                track_mm) -> np.ndarray:
    """The steer angle [deg, + left] of the OTHER wheel that makes 100 % Ackermann with
    ``side``'s wheel at ``steer_deg``: ``cot d_right - cot d_left = t / L`` (module
    docstring), i.e. ``tan d_right = sin d_left / (cos d_left + (t/L) sin d_left)`` from the
    left wheel and ``tan d_left = sin d_right / (cos d_right - (t/L) sin d_right)`` from the
    right; 0 at 0. The inner wheel's ideal from the outer's and the outer's from the inner's
    are the same relation."""
    sign = outboard_sign(side)
    _check_lengths(wheelbase_mm, track_mm)
    d = np.radians(_vec(steer_deg))
    k = sign * _vec(track_mm) / _vec(wheelbase_mm)
    return np.degrees(np.arctan2(np.sin(d), np.cos(d) + k * np.sin(d)))


def outside_turn_diameter_mm(steer_left_deg, steer_right_deg, wheelbase_mm,
                             track_mm) -> np.ndarray:
    """Outside turn diameter [mm], curb-to-curb at the outer front contact point:
    ``2 sqrt((R + t/2)^2 + L^2)``; ``inf`` straight ahead."""
    L, t = _vec(wheelbase_mm), _vec(track_mm)
    R = turn_radius_mm(steer_left_deg, steer_right_deg, wheelbase_mm, track_mm)
    return 2.0 * np.hypot(R + t / 2.0, L)


def _mean_steer(steer_left_deg, steer_right_deg) -> np.ndarray:
    return 0.5 * (_vec(steer_left_deg) + _vec(steer_right_deg))


def steering_ratio_local(steering_wheel_deg, steer_left_deg, steer_right_deg) -> np.ndarray:
    """Local steering ratio [deg/deg] at every step: ``d(steering-wheel angle) / d(mean
    road-wheel steer angle)`` (SAE J670's steering ratio as a gradient), second-order
    central differences (one-sided at the ends); the mean steer angle must change
    monotonically along the sweep."""
    swa, mean = _vec(steering_wheel_deg).ravel(), _mean_steer(steer_left_deg,
                                                              steer_right_deg).ravel()
    if swa.size != mean.size or swa.size < 3:
        raise ValueError("need at least 3 steps with one steering-wheel angle per step")
    step = np.diff(mean)
    if not (np.all(step > 0) or np.all(step < 0)):
        raise ValueError("the mean road-wheel steer angle must change monotonically along "
                         "the sweep (sort the steps by steering-wheel angle)")
    return np.gradient(swa, mean)


def steering_ratio_overall(steering_wheel_deg, steer_left_deg, steer_right_deg) -> float:
    """Overall steering ratio [deg/deg]: the steering-wheel angle range of the sweep over
    the mean road-wheel steer angle's change across it (lock to lock for a full sweep)."""
    swa, mean = _vec(steering_wheel_deg).ravel(), _mean_steer(steer_left_deg,
                                                              steer_right_deg).ravel()
    lo, hi = int(np.argmin(swa)), int(np.argmax(swa))
    if mean[hi] == mean[lo]:
        raise ValueError("the road wheels do not steer over the sweep")
    return float((swa[hi] - swa[lo]) / (mean[hi] - mean[lo]))
