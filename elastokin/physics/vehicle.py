"""The whole car's figures from its two axles' (pure numpy; docs/characteristics.md "Whole
car"): roll stiffness distribution, the roll axis, the roll gradient, the understeer-gradient
contributions of lateral-force compliance steer and of roll steer, the body's heave and pitch
from both axles' wheel travel.

Conventions: ISO 8855 (x forward, y left, z up); mm, N, N*mm, deg; an axle's steer angle +
to the left (the mean of its wheels' steer angles); body roll + when the body's left side
rises (as in a left turn, lateral acceleration + to the left); an understeer gradient in deg
of road-wheel steer per g of lateral acceleration, + understeer (SAE J670, ISO 8855). "g" is
the standard acceleration of gravity; a weight in N is a lateral force per g.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


def _check_positive(**values) -> None:
    for name, v in values.items():
        if not np.all(np.asarray(v, float) > 0):
            raise ValueError(f"{name} must be > 0, got {v}")


def cg_behind_front_axle_mm(wheelbase_mm, weight_front_N, weight_rear_N):
    """The CG's distance behind the front axle: ``L W_r / (W_f + W_r)`` (moments about the
    front axle's contact line)."""
    _check_positive(wheelbase_mm=wheelbase_mm, weight_front_N=weight_front_N,
                    weight_rear_N=weight_rear_N)
    return wheelbase_mm * weight_rear_N / (weight_front_N + weight_rear_N)


def roll_stiffness_distribution(front_Nmm_per_deg, rear_Nmm_per_deg):
    """The front axle's share of the car's roll stiffness, ``K_f / (K_f + K_r)`` (0 ... 1;
    the rear's is one less it). NaN when the total is not positive."""
    kf, kr = np.asarray(front_Nmm_per_deg, float), np.asarray(rear_Nmm_per_deg, float)
    total = kf + kr
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(total > 0, kf / total, np.nan)


@dataclass(frozen=True)
class RollAxis:
    """The roll axis (side view): the line through the front and the rear roll centre.

    ``height_under_cg_mm``: its height at the CG's longitudinal position (linear
    interpolation between the axles); ``inclination_deg``: ``atan((h_r - h_f) / L)``, + when
    the axis rises towards the rear (the usual: the front roll centre lower);
    ``moment_arm_mm``: the CG's height above it (the roll moment's arm,
    ``h - h_ra``)."""

    height_under_cg_mm: float
    inclination_deg: float
    moment_arm_mm: float


def roll_axis(front_height_mm, rear_height_mm, wheelbase_mm, cg_behind_front_mm,
              cg_height_mm) -> RollAxis:
    """The roll axis through the roll centres ``front_height_mm`` (at the front axle) and
    ``rear_height_mm`` (at the rear axle, ``wheelbase_mm`` behind), both above the ground,
    at the CG ``cg_behind_front_mm`` behind the front axle and ``cg_height_mm`` high."""
    _check_positive(wheelbase_mm=wheelbase_mm)
    hf, hr = float(front_height_mm), float(rear_height_mm)
    under = hf + (hr - hf) * cg_behind_front_mm / wheelbase_mm
    return RollAxis(under, float(np.degrees(np.arctan2(hr - hf, wheelbase_mm))),
                    float(cg_height_mm) - under)


def roll_gradient_deg_per_g(weight_N, moment_arm_mm, roll_stiffness_Nmm_per_deg):
    """Body roll per g of lateral acceleration (Gillespie, *Fundamentals of Vehicle
    Dynamics*, ch. 7): ``W h' / (K_phi - W h')`` rad per g with ``K_phi`` per rad, ``h'`` the
    CG's height above the roll axis; the denominator's ``W h'`` is the CG's own moment as the
    body rolls. Deg per g; NaN when the springs do not hold the body (``K_phi <= W h'``)."""
    k_rad = np.degrees(np.asarray(roll_stiffness_Nmm_per_deg, float))  # N*mm per rad
    m = np.asarray(weight_N, float) * np.asarray(moment_arm_mm, float)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(k_rad > m, np.degrees(m / (k_rad - m)), np.nan)


def axle_steer_deg(toe_left_deg, toe_right_deg):
    """An axle's steer angle (+ to the left: the mean of its wheels' steer angles) from its
    wheels' toe (toe-in +): ``(toe_r - toe_l) / 2`` (a toe-in of the left wheel turns it to
    the right). Also for rates: toe per unit load gives steer per unit load."""
    return 0.5 * (np.asarray(toe_right_deg, float) - np.asarray(toe_left_deg, float))


def compliance_steer_terms_deg_per_g(steer_front_deg_per_N, steer_rear_deg_per_N,
                                     weight_front_N, weight_rear_N):
    """The understeer gradient's lateral-force compliance steer terms (Gillespie ch. 6,
    Table 6.1; Bundorf's cornering compliances), front and rear, deg per g: ``-s_f W_f`` and
    ``+s_r W_r``, with ``s`` each axle's steer angle (+ left) per lateral force at its
    contact patches in phase (+ left; N, both wheels together) and ``W`` its weight (the
    lateral force it carries per g). Their sum is the term, ``s_r W_r - s_f W_f``.

    In a left turn the tyres push each axle to the left by ``W a_y``: a front axle that then
    steers left adds to the driver's steer (oversteer), a rear one that steers left, as the
    front does, takes slip from the rear (understeer)."""
    return (-np.asarray(steer_front_deg_per_N, float) * np.asarray(weight_front_N, float),
            np.asarray(steer_rear_deg_per_N, float) * np.asarray(weight_rear_N, float))


def roll_steer_terms_deg_per_g(roll_steer_front_deg_per_deg, roll_steer_rear_deg_per_deg,
                               roll_gradient_deg_per_g):
    """The understeer gradient's roll steer terms (Gillespie ch. 6, Table 6.1), front and
    rear, deg per g: ``-e_f dphi/da_y`` and ``+e_r dphi/da_y``, ``e`` each axle's steer angle
    (+ left) per degree of roll (+ left side up, as in a left turn) and ``dphi/da_y`` the
    roll gradient: the signs of :func:`compliance_steer_terms_deg_per_g`."""
    grad = np.asarray(roll_gradient_deg_per_g, float)
    return (-np.asarray(roll_steer_front_deg_per_deg, float) * grad,
            np.asarray(roll_steer_rear_deg_per_deg, float) * grad)


def body_heave_pitch(travel_front_mm, travel_rear_mm, wheelbase_mm, cg_behind_front_mm
                     ) -> tuple[np.ndarray, np.ndarray]:
    """The body's heave at the CG (mm, + up) and pitch (deg, + nose down: ISO, about y to
    the left) relative to the ground, from each axle's mean wheel travel (mm, + bump: the
    body comes down towards the wheel) with the tyres rigid."""
    _check_positive(wheelbase_mm=wheelbase_mm)
    zf = -np.asarray(travel_front_mm, float)  # the body's height change at each axle
    zr = -np.asarray(travel_rear_mm, float)
    heave = zf + (zr - zf) * cg_behind_front_mm / wheelbase_mm
    return heave, np.degrees(np.arctan2(zr - zf, wheelbase_mm))
