"""Axle characteristics from rig sweeps (elastokin.physics.axle_sweeps): track, half-track,
wheelbase change by hand; an opposite-travel (roll) sweep of an analytic axle (springs, an
anti-roll bar, bump steer and camber) against the hand formulas and against the same
characteristics from its compliance matrix."""

from __future__ import annotations

import numpy as np
import pytest

from elastokin.physics import axle_compliance as ac
from elastokin.physics import axle_sweeps as sw

DEG = 180.0 / np.pi
T = 1500.0  # track
K_SPRING, K_ARB_WHEEL = 30.0, 12.0  # N/mm at the wheel
ARM = 250.0  # bar lever: the bar twists (z_left - z_right) / ARM rad
K_BAR = K_ARB_WHEEL * ARM ** 2 / DEG  # N*mm/deg: the same bar as a torsion spring
BUMP_TOE, BUMP_CAMBER = 0.004, -0.0025  # deg per mm of bump (toe-in +, top outboard +)


def test_track_half_track_and_wheelbase_change():
    left, right = np.array([10.0, 752.0, 0.0]), np.array([12.0, -749.0, 0.0])
    assert sw.track_mm(left, right) == pytest.approx(1501.0)
    assert sw.half_track_mm(right, "right") == pytest.approx(749.0)
    left0, right0 = np.array([10.0, 750.0, 0.0]), np.array([12.0, -750.0, 0.0])
    assert sw.track_change_mm(left, right, left0, right0) == pytest.approx(1.0)  # 2 - 1
    assert sw.wheelbase_change_mm([13.0, 0, 0], [10.0, 0, 0], "front") == pytest.approx(3.0)
    assert sw.wheelbase_change_mm([13.0, 0, 0], [10.0, 0, 0], "rear") == pytest.approx(-3.0)
    stacked = sw.track_mm(np.stack([left, left0]), np.stack([right, right0]))
    np.testing.assert_allclose(stacked, [1501.0, 1500.0])


def test_roll_angle_sign_and_value():
    # left wheel rebounds 10 mm, right bumps 10 mm: the body's left side rises
    assert sw.roll_angle_deg(-10.0, 10.0, T) == pytest.approx(np.degrees(np.arctan(20 / T)))
    with pytest.raises(ValueError, match="track"):
        sw.roll_angle_deg(0.0, 0.0, 0.0)


def roll_sweep(amplitude_mm=20.0, n=41, static_N=4000.0):
    """An opposite-travel sweep of the analytic axle, as the rig would record it."""
    d = np.linspace(-amplitude_mm, amplitude_mm, n)
    zl, zr = -d, d  # + roll
    fl = static_N + K_SPRING * zl + K_ARB_WHEEL * (zl - zr)
    fr = static_N + K_SPRING * zr + K_ARB_WHEEL * (zr - zl)
    twist = np.degrees((zl - zr) / ARM)
    return dict(zl=zl, zr=zr, fl=fl, fr=fr, twist=twist, torque=K_BAR * twist,
                toe_l=BUMP_TOE * zl, toe_r=BUMP_TOE * zr, cam_l=BUMP_CAMBER * zl,
                cam_r=BUMP_CAMBER * zr)


def test_roll_stiffness_and_antiroll_bar_share():
    s = roll_sweep()
    roll = sw.roll_angle_deg(s["zl"], s["zr"], T)
    moment = sw.roll_moment_Nmm(s["fl"], s["fr"], T / 2, -T / 2)
    total = sw.roll_stiffness_Nmm_per_deg(roll, moment)
    # textbook: (k t^2 / 2 + k_arb t^2) per rad; 2.4e-4 from atan over +-20 mm
    expected_total = (K_SPRING * T ** 2 / 2 + K_ARB_WHEEL * T ** 2) / DEG
    assert total == pytest.approx(expected_total, rel=5e-4)
    bar = sw.antiroll_bar_roll_stiffness_Nmm_per_deg(roll, s["twist"], s["torque"])
    assert bar == pytest.approx(K_ARB_WHEEL * T ** 2 / DEG, rel=5e-4)
    # share: 2 k_arb / (k + 2 k_arb) = 4/9 (the bar's slope is a product of two fitted
    # slopes, each 1.2e-4 off through atan)
    assert bar / total == pytest.approx(2 * K_ARB_WHEEL / (K_SPRING + 2 * K_ARB_WHEEL),
                                        rel=5e-4)
    # the same axle's compliance matrix gives the same roll stiffness
    C = _compliance()
    from_C = ac.roll_from_compliance(C, T)["roll_stiffness_Nmm_per_deg"]
    assert total == pytest.approx(from_C, rel=5e-4)
    # and a small window the linear value
    assert sw.roll_stiffness_Nmm_per_deg(roll, moment, (-0.1, 0.1)) == pytest.approx(
        from_C, rel=1e-6)


def _compliance():
    """The analytic axle's 12x12 compliance (module units): one motion per wheel."""
    Tm = np.zeros((12, 2))
    for i, side in enumerate(ac.SIDES):
        o = 6 * i
        Tm[o + 2, i] = 1.0
        Tm[o + 5, i] = -ac.outboard_sign(side) * np.radians(BUMP_TOE)
        Tm[o + 3, i] = -ac.outboard_sign(side) * np.radians(BUMP_CAMBER)
    K = np.array([[K_SPRING + K_ARB_WHEEL, -K_ARB_WHEEL], [-K_ARB_WHEEL,
                                                           K_SPRING + K_ARB_WHEEL]])
    C = Tm @ np.linalg.inv(K) @ Tm.T
    C[[3, 4, 5, 9, 10, 11], :] *= DEG
    return C


def test_roll_steer_and_camber_from_the_sweep_and_from_C():
    s = roll_sweep(amplitude_mm=2.0)
    roll = sw.roll_angle_deg(s["zl"], s["zr"], T)
    r = sw.roll_coefficients(roll, s["toe_l"], s["toe_r"], s["cam_l"], s["cam_r"])
    per_rad = T / 2 / DEG  # mm of wheel travel per deg of roll
    assert r["roll_steer_left_deg_per_deg"] == pytest.approx(-BUMP_TOE * per_rad, rel=1e-5)
    assert r["roll_steer_right_deg_per_deg"] == pytest.approx(BUMP_TOE * per_rad, rel=1e-5)
    assert r["roll_camber_right_deg_per_deg"] == pytest.approx(BUMP_CAMBER * per_rad,
                                                               rel=1e-5)
    assert r["axle_roll_steer_deg_per_deg"] == pytest.approx(BUMP_TOE * per_rad, rel=1e-5)
    from_C = ac.roll_from_compliance(_compliance(), T)
    for key, value in r.items():
        assert from_C[key] == pytest.approx(value, rel=1e-5), key


def test_ride_rate():
    assert sw.ride_rate_N_per_mm(30.0, 250.0) == pytest.approx(30 * 250 / 280)
    with pytest.raises(ValueError):
        sw.ride_rate_N_per_mm(30.0, 0.0)
