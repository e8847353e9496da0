"""Axle characteristics from the 12x12 wheel-centre compliance matrix (pure numpy).

**Frame and units (every function here).** ISO 8855 vehicle frame: x forward, y to the
vehicle's LEFT, z up (the rig converts from the config frame before calling). ``C`` is the
linearised compliance of both wheel centres at one state, body fixed:

- rows/columns 0-5: left wheel centre, 6-11: right wheel centre, each ``x, y, z, rx, ry, rz``;
- ``C[i, j]`` is displacement ``i`` (mm, rotations in deg) per unit load ``j`` (forces in N,
  torques in N*mm), loads applied at the wheel centres, spin locked to the knuckle. ADAMS/Car's
  1-based ``C(i, j)`` is ``C[i - 1, j - 1]``.
- In these mixed units C is not symmetric: Maxwell-Betti gives ``C[rot, force] =
  (180/pi) * C[trans, moment]`` (both are rad/N in consistent units).

**Signs of the wheel angles** (per wheel, as a K&C rig reports them and as
:mod:`elastokin.physics.wheel` defines them): toe positive **toe-in**, camber positive **top
outboard**. For small rotations ``(rx, ry, rz)`` of a wheel centre (right-handed about the ISO
axes): left wheel ``toe = -rz``, ``camber = -rx``; right wheel ``toe = +rz``, ``camber = +rx``.
(ADAMS/Car's "steer angle" is ``+rz`` on both wheels: positive turns the wheel to the left.)

Sources: ADAMS/Car help, "Output of Suspension Analyses" and the SVC pages of "Computation of
Suspension and Steering Characteristics" (Wheel Rate, Roll Center Height, Percent Roll Steer,
Roll Camber, Percent Anti-Dive Under Braking, Percent Anti-Lift Under Braking/Acceleration,
Anti-Squat Under Acceleration, Aligning Torque - Steer and Camber Compliance); Altair MotionView
"Suspension Design Factors" (same formulas with "Orientation A/B" for the two frames).
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "LOADS",
    "SIDES",
    "camber_change_deg",
    "check_compliance",
    "contact_patch_compliance",
    "named_compliances",
    "outboard_sign",
    "patch_load",
    "percent_anti_dive",
    "percent_anti_from_compliance",
    "percent_anti_lift_braking",
    "percent_anti_lift_traction",
    "percent_anti_squat",
    "roll_from_compliance",
    "toe_change_deg",
    "wheel_offset",
    "wheel_rates_from_compliance",
    "wheel_response",
]

SIDES = ("left", "right")
X, Y, Z, RX, RY, RZ = range(6)
RAD = np.pi / 180.0  # rad per deg


def wheel_offset(side: str) -> int:
    """Index of the first row/column of ``side``'s wheel centre in C (0 left, 6 right)."""
    if side not in SIDES:
        raise ValueError(f"side must be 'left' or 'right', got {side!r}")
    return 0 if side == "left" else 6


def outboard_sign(side: str) -> float:
    """+1 for the left wheel (outboard is +y in ISO 8855), -1 for the right wheel."""
    return 1.0 if wheel_offset(side) == 0 else -1.0


def check_compliance(C) -> np.ndarray:
    """C as a finite (12, 12) float array, or a one-line ValueError saying what is wrong."""
    C = np.asarray(C, dtype=float)
    if C.shape != (12, 12):
        raise ValueError("the axle compliance matrix must be 12x12 (left wheel centre 1-6, "
                         f"right 7-12: x, y, z, rx, ry, rz), got shape {C.shape}")
    if not np.all(np.isfinite(C)):
        raise ValueError("the axle compliance matrix has non-finite entries")
    return C


def toe_change_deg(rz_deg, side: str):
    """Toe change (toe-in +) of ``side``'s wheel from its small rotation about z [deg]."""
    return -outboard_sign(side) * np.asarray(rz_deg, float)


def camber_change_deg(rx_deg, side: str):
    """Camber change (top outboard +) of ``side``'s wheel from its small rotation about x."""
    return -outboard_sign(side) * np.asarray(rx_deg, float)


def _cross_matrix(r) -> np.ndarray:
    x, y, z = np.asarray(r, float).reshape(3)
    return np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])


def patch_load(force_N, offset_mm) -> np.ndarray:
    """The wheel-centre load ``(F [N], r x F [N*mm])`` equivalent to ``force_N`` (3,) acting
    at the point ``offset_mm`` (3,) from the wheel centre (e.g. the contact point)."""
    F = np.asarray(force_N, float).reshape(3)
    return np.r_[F, np.cross(np.asarray(offset_mm, float).reshape(3), F)]


def contact_patch_compliance(C, offset_left_mm, offset_right_mm) -> np.ndarray:
    """C transferred to the contact points, as ADAMS/Car does for the roll centre.

    ``offset_*_mm`` (3,) is contact point minus wheel centre. Returns the 12x12 compliance of
    the two contact points (translations mm, rotations deg) under forces [N] and torques
    [N*mm] applied there: translation ``u_p = u_c + theta x r`` and load ``(F, M + r x F)``.
    """
    C = check_compliance(C)
    rows, cols = np.eye(12), np.eye(12)
    for i, r in ((0, offset_left_mm), (6, offset_right_mm)):
        Rx = _cross_matrix(r)
        rows[i:i + 3, i + 3:i + 6] = -Rx * RAD  # u_p = u - r x theta(rad)
        cols[i + 3:i + 6, i:i + 3] = Rx  # M_centre = M + r x F
    return rows @ C @ cols


def wheel_response(C, load_left, load_right, side: str) -> tuple[np.ndarray, np.ndarray]:
    """``(rotation_deg (3,), displacement_mm (3,))`` of ``side``'s wheel centre under the
    wheel-centre loads ``load_left``, ``load_right`` (6,) ``(Fx, Fy, Fz [N], Mx, My, Mz
    [N*mm])``: a small motion, usable as a twist by
    :mod:`elastokin.physics.instant_centres`."""
    C = check_compliance(C)
    u = C @ np.r_[np.asarray(load_left, float).reshape(6), np.asarray(load_right, float)
                  .reshape(6)]
    i = wheel_offset(side)
    return u[i + 3:i + 6], u[i:i + 3]


# ------------------------------------------------------------------------- named compliances

#: load cases of :func:`named_compliances`: the lateral and longitudinal forces act at the
#: contact point ``loaded_radius_mm`` below the wheel centre, the traction force at the wheel
#: centre
LOADS = ("lateral_force", "longitudinal_force", "traction_force", "aligning_torque")
_RESPONSES = (("toe", RZ, "deg"), ("camber", RX, "deg"), ("wheel_centre_x", X, "mm"),
              ("wheel_centre_y", Y, "mm"))


def _unit_load(load: str, loaded_radius_mm: float) -> tuple[np.ndarray, float, str]:
    """(wheel-centre load per unit load, factor to per kN or kN*m, unit suffix)."""
    r = np.array([0.0, 0.0, -float(loaded_radius_mm)])
    if load == "lateral_force":
        return patch_load([0.0, 1.0, 0.0], r), 1.0e3, "kN"
    if load == "longitudinal_force":
        return patch_load([1.0, 0.0, 0.0], r), 1.0e3, "kN"
    if load == "traction_force":
        return np.r_[1.0, 0.0, 0.0, 0.0, 0.0, 0.0], 1.0e3, "kN"
    if load == "aligning_torque":
        return np.r_[0.0, 0.0, 0.0, 0.0, 0.0, 1.0], 1.0e6, "kNm"
    raise ValueError(f"unknown load {load!r}; expected one of {LOADS}")


def named_compliances(C, loaded_radius_mm: float) -> dict[str, float]:
    """The named compliances of the axle, flat ``name -> value``, units in the names.

    Names are ``{load}_{response}_{phase}_{side}_{unit}``, e.g.
    ``aligning_torque_toe_in_phase_left_deg_per_kNm``:

    - load: ``lateral_force`` (+y, at the contact point ``loaded_radius_mm`` below the wheel
      centre), ``longitudinal_force`` (+x, braking is negative, at the contact point),
      ``traction_force`` (+x at the wheel centre), ``aligning_torque`` (+ about z); per kN or
      per kN*m;
    - response of each wheel: ``toe`` (toe-in +) and ``camber`` (top outboard +) in deg,
      ``wheel_centre_x`` (forward +) and ``wheel_centre_y`` (to the left +) in mm;
    - phase: ``in_phase`` (the same ISO load on both wheels: cornering, braking),
      ``anti_phase`` (+ on the left, - on the right: lateral forces both outboard, aligning
      torques both in the toe-out sense), ``single`` (this wheel loaded alone).

    ADAMS/Car's ``alt_steer_compliance.left = C(6,6) + C(6,12)`` (steer + to the left, per
    N*mm, ADAMS frame) is ``-1e-6 * aligning_torque_toe_in_phase_left_deg_per_kNm`` here; its
    right-wheel value ``C(12,6) + C(12,12)`` is ``+1e-6 *`` the right one.
    """
    C = check_compliance(C)
    out: dict[str, float] = {}
    for load in LOADS:
        w, scale, unit = _unit_load(load, loaded_radius_mm)
        phases = {"in_phase": (w, w), "anti_phase": (w, -w)}
        for side in SIDES:
            single = (w, 0 * w) if side == "left" else (0 * w, w)
            for phase, (wl, wr) in {**phases, "single": single}.items():
                u = C @ np.r_[wl, wr]
                i = wheel_offset(side)
                for response, k, runit in _RESPONSES:
                    value = u[i + k]
                    if response == "toe":
                        value = toe_change_deg(value, side)
                    elif response == "camber":
                        value = camber_change_deg(value, side)
                    out[f"{load}_{response}_{phase}_{side}_{runit}_per_{unit}"] = \
                        float(scale * value)
    return out


# ------------------------------------------------------------------------ rates and roll


def wheel_rates_from_compliance(C) -> dict[str, float]:
    """Wheel rates [N/mm] (ADAMS/Car "Wheel Rate", MotionView "Wheel Rate"): the vertical
    stiffness of each wheel centre relative to the body, tyre excluded.

    ``wheel_rate_in_phase_left_N_per_mm = 1 / (C(3,3) + C(3,9))`` (both wheels loaded, as
    ADAMS); ``wheel_rate_single_*`` is ``1 / C(3,3)`` (the other wheel free, so an anti-roll
    bar counts). Right: ``1 / (C(9,3) + C(9,9))`` and ``1 / C(9,9)``."""
    C = check_compliance(C)
    out = {}
    for side in SIDES:
        i = wheel_offset(side) + Z
        with np.errstate(divide="ignore"):
            out[f"wheel_rate_in_phase_{side}_N_per_mm"] = float(1.0 / (C[i, Z] + C[i, 6 + Z]))
            out[f"wheel_rate_single_{side}_N_per_mm"] = float(1.0 / C[i, i])
    return out


def roll_from_compliance(C, track_mm: float, tyre_rate_N_per_mm: float | None = None) \
        -> dict[str, float]:
    """Roll stiffness, roll steer and roll camber from C (ADAMS/Car SVCROL, MotionView
    "Roll Rate" and "Roll Steer, Caster, and Camber").

    Opposing unit vertical forces (+1 N on the left, -1 N on the right) give the height
    difference ``Dz = C(3,3) - C(3,9) - C(9,3) + C(9,9)`` (+ ``2 / tyre_rate`` with tyres in
    series). The **roll angle** is the body's rotation relative to the line through the
    contact points, ISO sign (+ = body's left side up): ``phi = -atan(Dz / track)``.

    Returns ``roll_stiffness_Nmm_per_deg = track^2 / Dz * pi/180`` (ADAMS "Suspension Roll
    Rate", or "Total Roll Rate" with the tyre), and per wheel ``roll_steer_{side}`` (toe-in
    change per roll angle) and ``roll_camber_{side}`` (camber change relative to the body, top
    outboard +, per roll angle) in deg/deg, and ``axle_roll_steer_deg_per_deg``: the mean steer
    angle (+ to the left, ADAMS's "steer") per roll angle; positive steers the axle into a
    turn (a left turn rolls the body positive).
    """
    C = check_compliance(C)
    if not track_mm > 0:
        raise ValueError(f"track_mm must be > 0, got {track_mm}")
    dz = C[Z, Z] - C[Z, 6 + Z] - C[6 + Z, Z] + C[6 + Z, 6 + Z]
    if tyre_rate_N_per_mm is not None:
        if not tyre_rate_N_per_mm > 0:
            raise ValueError(f"tyre_rate_N_per_mm must be > 0, got {tyre_rate_N_per_mm}")
        dz += 2.0 / tyre_rate_N_per_mm
    phi_deg = -np.degrees(np.arctan(dz / track_mm))
    anti_phase = C[:, Z] - C[:, 6 + Z]  # response to +1 N on the left, -1 N on the right
    pair = {s: anti_phase[wheel_offset(s):wheel_offset(s) + 6] for s in SIDES}
    with np.errstate(divide="ignore", invalid="ignore"):
        out = {"roll_stiffness_Nmm_per_deg": float(track_mm ** 2 / dz * RAD)}
        for s in SIDES:
            out[f"roll_steer_{s}_deg_per_deg"] = float(toe_change_deg(pair[s][RZ], s) / phi_deg)
            out[f"roll_camber_{s}_deg_per_deg"] = float(camber_change_deg(pair[s][RX], s)
                                                        / phi_deg)
        out["axle_roll_steer_deg_per_deg"] = float(0.5 * (pair["left"][RZ] + pair["right"][RZ])
                                                   / phi_deg)
    return out


# ----------------------------------------------------------------------- anti-dive family


def percent_anti_from_compliance(C, longitudinal_force_N: float, vertical_force_left_N: float,
                                 vertical_force_right_N: float, loaded_radius_mm: float,
                                 reference: str = "contact_patch") -> dict[str, float]:
    """Percent anti (dive, lift, squat) per wheel, the core of ADAMS/Car's SVCANB/SVCANA.

    Per unit total braking or traction force: ``longitudinal_force_N`` on each wheel (ISO, +
    forward: braking negative) and the weight-transfer vertical forces (+ up). With
    ``reference="contact_patch"`` (ADAMS/Car; outboard brakes, drive torque reacted by the
    wheel carrier or a live axle) the longitudinal force acts at the contact point
    ``loaded_radius_mm`` below the wheel centre, ``Zf = F [C(3,1) - Rl C(3,5)] + F [C(3,7) -
    Rl C(3,11)]``; with ``"wheel_centre"`` (inboard brakes, chassis-mounted final drive:
    MotionView's "fixed differential") at the wheel centre. ``Zw = V_l C(3,3) + V_r C(3,9)``;
    ``percent = -100 Zf / Zw`` (left; right with rows 9). Positive: the geometry resists the
    pitch the weight transfer causes.
    """
    C = check_compliance(C)
    if reference not in ("contact_patch", "wheel_centre"):
        raise ValueError(f"reference must be 'contact_patch' or 'wheel_centre', got "
                         f"{reference!r}")
    rl = float(loaded_radius_mm) if reference == "contact_patch" else 0.0
    out = {}
    for side in SIDES:
        i = wheel_offset(side) + Z
        zf = sum(longitudinal_force_N * (C[i, j + X] - rl * C[i, j + RY]) for j in (0, 6))
        zw = vertical_force_left_N * C[i, Z] + vertical_force_right_N * C[i, 6 + Z]
        with np.errstate(divide="ignore", invalid="ignore"):
            out[side] = float(-100.0 * zf / zw)
    return out


def _check_vehicle(wheelbase_mm, cg_height_mm, fraction, what):
    if not (wheelbase_mm > 0 and cg_height_mm > 0):
        raise ValueError(f"wheelbase_mm and cg_height_mm must be > 0, got {wheelbase_mm}, "
                         f"{cg_height_mm}")
    if not 0.0 <= fraction <= 1.0:
        raise ValueError(f"{what} must be within [0, 1], got {fraction}")


def _live_axle(force, loaded_radius_mm, live_axle_ratio, track_mm):
    """Vertical wheel forces (left, right) reacting the driveshaft torque of a live axle."""
    if live_axle_ratio is None:
        return 0.0, 0.0
    if not (live_axle_ratio > 0 and track_mm is not None and track_mm > 0):
        raise ValueError("a live axle needs live_axle_ratio > 0 and track_mm > 0")
    t_drive = loaded_radius_mm * abs(2.0 * force) / live_axle_ratio
    return -t_drive / track_mm, t_drive / track_mm


def percent_anti_dive(C, wheelbase_mm, cg_height_mm, loaded_radius_mm, front_brake_fraction,
                      brakes: str = "outboard") -> dict[str, float]:
    """Front percent anti-dive under braking (ADAMS/Car "Percent Anti-Dive Under Braking"):
    braking force ``-fb/2`` per wheel, weight transfer ``+h/(2L)`` per wheel, per unit total
    braking force. ``brakes``: ``"outboard"`` (contact point, ADAMS) or ``"inboard"``
    (wheel centre)."""
    _check_vehicle(wheelbase_mm, cg_height_mm, front_brake_fraction, "front_brake_fraction")
    v = cg_height_mm / (2.0 * wheelbase_mm)
    return percent_anti_from_compliance(C, -front_brake_fraction / 2.0, v, v, loaded_radius_mm,
                                        _torque_reference(brakes, "brakes"))


def percent_anti_lift_braking(C, wheelbase_mm, cg_height_mm, loaded_radius_mm,
                              front_brake_fraction, brakes: str = "outboard") -> dict[str, float]:
    """Rear percent anti-lift under braking (ADAMS/Car "Percent Anti-Lift Under Braking"):
    braking force ``-(1 - fb)/2`` per wheel, weight transfer ``-h/(2L)`` per wheel."""
    _check_vehicle(wheelbase_mm, cg_height_mm, front_brake_fraction, "front_brake_fraction")
    v = -cg_height_mm / (2.0 * wheelbase_mm)
    return percent_anti_from_compliance(C, -(1.0 - front_brake_fraction) / 2.0, v, v,
                                        loaded_radius_mm, _torque_reference(brakes, "brakes"))


def _torque_reference(where: str, name: str) -> str:
    """Where the brake or drive force acts: the contact patch when the torque is reacted by
    the wheel carrier (``outboard``), the wheel centre when by the body (``inboard``)."""
    if where not in ("outboard", "inboard"):
        raise ValueError(f"{name} must be 'outboard' or 'inboard', got {where!r}")
    return "contact_patch" if where == "outboard" else "wheel_centre"


def percent_anti_lift_traction(C, wheelbase_mm, cg_height_mm, loaded_radius_mm,
                               front_drive_fraction, drive: str = "outboard",
                               live_axle_ratio: float | None = None,
                               track_mm: float | None = None) -> dict[str, float]:
    """Front percent anti-lift under acceleration (ADAMS/Car "Percent Anti-lift Under
    Acceleration"): traction ``+fd/2`` per wheel, weight transfer ``-h/(2L)``; a live
    (dependent) axle adds ``-/+ T/track`` (left/right) with ``T = Rl |F_l + F_r| /
    live_axle_ratio``. ``drive``: where the drive torque is reacted, ``"outboard"`` (by the
    wheel carrier: the force at the contact point, ADAMS) or ``"inboard"`` (by the body: at
    the wheel centre)."""
    _check_vehicle(wheelbase_mm, cg_height_mm, front_drive_fraction, "front_drive_fraction")
    f = front_drive_fraction / 2.0
    vl, vr = _live_axle(f, loaded_radius_mm, live_axle_ratio, track_mm)
    v = -cg_height_mm / (2.0 * wheelbase_mm)
    return percent_anti_from_compliance(C, f, v + vl, v + vr, loaded_radius_mm,
                                        _torque_reference(drive, "drive"))


def percent_anti_squat(C, wheelbase_mm, cg_height_mm, loaded_radius_mm, front_drive_fraction,
                       drive: str = "outboard", live_axle_ratio: float | None = None,
                       track_mm: float | None = None) -> dict[str, float]:
    """Rear percent anti-squat under acceleration (ADAMS/Car "Anti-Squat Under
    Acceleration"): traction ``+(1 - fd)/2`` per wheel, weight transfer ``+h/(2L)``, live
    axle and ``drive`` as :func:`percent_anti_lift_traction`."""
    _check_vehicle(wheelbase_mm, cg_height_mm, front_drive_fraction, "front_drive_fraction")
    f = (1.0 - front_drive_fraction) / 2.0
    vl, vr = _live_axle(f, loaded_radius_mm, live_axle_ratio, track_mm)
    v = cg_height_mm / (2.0 * wheelbase_mm)
    return percent_anti_from_compliance(C, f, v + vl, v + vr, loaded_radius_mm,
                                        _torque_reference(drive, "drive"))
