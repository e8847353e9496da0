"""Axle characteristics from the 12x12 wheel-centre compliance matrix
(elastokin.physics.axle_compliance): the transfer to the contact points, the named
compliances against ADAMS/Car's and MotionView's formulas and the mirror symmetry of their
signs, wheel and roll rates from springs and an anti-roll bar, percent anti-dive / anti-lift /
anti-squat against the textbook side-view formula on trailing arms."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from elastokin.physics import axle_compliance as ac
from elastokin.physics import instant_centres as ic

DEG = 180.0 / np.pi
ROT_ROWS = [3, 4, 5, 9, 10, 11]
#: mirror in the centre plane: y flips, and so do the rotations about x and z (pseudovector)
MIRROR = np.diag([1.0, -1.0, 1.0, -1.0, 1.0, -1.0])


def to_mixed_units(C_rad):
    """Compliance in consistent units (rad) -> the module's (rotations in deg)."""
    C = np.array(C_rad, float)
    C[ROT_ROWS, :] *= DEG
    return C


def random_spd(rng, n=6, scale=None):
    A = rng.normal(size=(n, n))
    K = A @ A.T + n * np.eye(n)
    s = np.array(scale if scale is not None else [50, 50, 30, 1e7, 1e7, 1e7], float)
    return K * np.sqrt(np.outer(s, s))


def mirrored_axle(K_left, k_arb=0.0):
    """12x12 stiffness of a mirror-symmetric axle (consistent units) with an anti-roll bar
    acting on the two wheel centres' heights."""
    K = np.zeros((12, 12))
    K[:6, :6], K[6:, 6:] = K_left, MIRROR @ K_left @ MIRROR
    g = np.zeros(12)
    g[2], g[8] = 1.0, -1.0
    return K + k_arb * np.outer(g, g)


# ------------------------------------------------------------------------- contact points


def test_contact_patch_compliance_is_the_rigid_transfer_of_the_stiffness():
    rng = np.random.default_rng(1)
    K = mirrored_axle(random_spd(rng), k_arb=15.0)
    C = to_mixed_units(np.linalg.inv(K))
    r_left, r_right = np.array([3.0, -8.0, -310.0]), np.array([-2.0, 5.0, -305.0])
    # independent: the contact points' displacement/rotation is T u, loads transform by T^T
    T = np.eye(12)
    for i, r in ((0, r_left), (6, r_right)):
        T[i:i + 3, i + 3:i + 6] = -np.array([[0, -r[2], r[1]], [r[2], 0, -r[0]],
                                             [-r[1], r[0], 0]])
    expected = to_mixed_units(T @ np.linalg.inv(K) @ T.T)
    np.testing.assert_allclose(ac.contact_patch_compliance(C, r_left, r_right), expected,
                               rtol=1e-10, atol=1e-14)


def test_patch_load_moment():
    # 1000 N lateral at the contact point 300 mm below the wheel centre: Mx = +300e3 N*mm
    np.testing.assert_allclose(ac.patch_load([0, 1000.0, 0], [0, 0, -300.0]),
                               [0, 1000.0, 0, 3.0e5, 0, 0])
    # braking (-x) at the contact point pitches the wheel nose-down: My = +Rl * 1000
    np.testing.assert_allclose(ac.patch_load([-1000.0, 0, 0], [0, 0, -300.0]),
                               [-1000.0, 0, 0, 0, 3.0e5, 0])


def test_bad_compliance_matrix():
    with pytest.raises(ValueError, match="12x12"):
        ac.check_compliance(np.eye(6))
    with pytest.raises(ValueError, match="side"):
        ac.wheel_offset("front")


# -------------------------------------------------------------------- named compliances


def test_named_compliances_match_the_adams_and_motionview_formulas():
    rng = np.random.default_rng(7)
    C = rng.normal(size=(12, 12)) * 1e-3  # any matrix: the formulas are linear
    rl = 310.0
    n = ac.named_compliances(C, rl)
    assert len(n) == 4 * 4 * 3 * 2
    # ADAMS alt_steer_compliance.left = C(6,6) + C(6,12), steer + to the left
    assert n["aligning_torque_toe_in_phase_left_deg_per_kNm"] == pytest.approx(
        -(C[5, 5] + C[5, 11]) * 1e6)
    assert n["aligning_torque_toe_in_phase_right_deg_per_kNm"] == pytest.approx(
        (C[11, 5] + C[11, 11]) * 1e6)
    # MotionView "Left Parallel Lateral Force Steer" = C(6,2)+C(6,4)*slr+C(6,8)+C(6,10)*slr
    assert n["lateral_force_toe_in_phase_left_deg_per_kN"] == pytest.approx(
        -(C[5, 1] + C[5, 3] * rl + C[5, 7] + C[5, 9] * rl) * 1e3)
    # MotionView "Right Converging Lateral Force Camber" (left +y, right -y)
    assert n["lateral_force_camber_anti_phase_right_deg_per_kN"] == pytest.approx(
        (C[9, 1] + C[9, 3] * rl - C[9, 7] - C[9, 9] * rl) * 1e3)
    # MotionView "Left Parallel Lateral Force Deflection" (global y)
    assert n["lateral_force_wheel_centre_y_in_phase_left_mm_per_kN"] == pytest.approx(
        (C[1, 1] + C[1, 3] * rl + C[1, 7] + C[1, 9] * rl) * 1e3)
    # MotionView "Left TP Longitudinal Compliance Steer" (+x forward here)
    assert n["longitudinal_force_toe_in_phase_left_deg_per_kN"] == pytest.approx(
        -(C[5, 0] + C[5, 6] - rl * (C[5, 4] + C[5, 10])) * 1e3)
    assert n["traction_force_wheel_centre_x_single_right_mm_per_kN"] == pytest.approx(
        C[6, 6] * 1e3)


@settings(max_examples=25, deadline=None)
@given(st.integers(0, 10_000), st.floats(0.0, 50.0))
def test_named_compliances_of_a_mirrored_axle(seed, k_arb):
    """A mirror-symmetric axle: loads that are mirror images (anti-phase lateral force or
    aligning torque, in-phase longitudinal force) give equal per-wheel toe and camber on
    both wheels; the others (in-phase lateral, anti-phase longitudinal) opposite ones."""
    C = to_mixed_units(np.linalg.inv(mirrored_axle(random_spd(np.random.default_rng(seed)),
                                                   k_arb)))
    n = ac.named_compliances(C, 300.0)
    for load, unit in (("lateral_force", "kN"), ("aligning_torque", "kNm"),
                       ("longitudinal_force", "kN"), ("traction_force", "kN")):
        symmetric = "anti_phase" if load in ("lateral_force", "aligning_torque") \
            else "in_phase"
        other = "in_phase" if symmetric == "anti_phase" else "anti_phase"
        for angle in ("toe", "camber"):
            key = f"{load}_{angle}_{{}}_{{}}_deg_per_{unit}"
            left, right = n[key.format(symmetric, "left")], n[key.format(symmetric, "right")]
            assert right == pytest.approx(left, rel=1e-9, abs=1e-12)
            left, right = n[key.format(other, "left")], n[key.format(other, "right")]
            assert right == pytest.approx(-left, rel=1e-9, abs=1e-12)
            left, right = n[key.format("single", "left")], n[key.format("single", "right")]
            assert abs(right) == pytest.approx(abs(left), rel=1e-9, abs=1e-12)


# --------------------------------------------------------------------- rates and roll


def spring_axle(k, k_arb, bump_toe_rad_per_mm=0.0, bump_camber_rad_per_mm=0.0):
    """Each wheel on one motion: travel q (mm) with toe-in and camber rates, wheel rate k,
    anti-roll bar k_arb (N/mm at the wheels, on q_left - q_right). C = T K^-1 T^T."""
    T = np.zeros((12, 2))
    for i, side in enumerate(ac.SIDES):
        o = 6 * i
        T[o + 2, i] = 1.0
        T[o + 5, i] = -ac.outboard_sign(side) * bump_toe_rad_per_mm  # toe = -/+ rz
        T[o + 3, i] = -ac.outboard_sign(side) * bump_camber_rad_per_mm
    K = np.array([[k + k_arb, -k_arb], [-k_arb, k + k_arb]])
    return to_mixed_units(T @ np.linalg.inv(K) @ T.T)


def test_wheel_rates():
    C = spring_axle(30.0, 12.0)
    r = ac.wheel_rates_from_compliance(C)
    # both wheels together: the bar does not twist
    assert r["wheel_rate_in_phase_left_N_per_mm"] == pytest.approx(30.0)
    # one wheel alone: the bar in series with the other wheel's spring, in parallel with k
    assert r["wheel_rate_single_right_N_per_mm"] == pytest.approx(30.0 + 12.0 * 30.0 / 42.0)


def test_roll_rate_steer_and_camber_from_compliance():
    k, ka, t, kt = 30.0, 12.0, 1500.0, 250.0
    s, c = 2.0e-5, -1.5e-5  # toe-in and camber per mm of bump, rad
    C = spring_axle(k, ka, s, c)
    r = ac.roll_from_compliance(C, t)
    # textbook: springs k t^2 / 2, the bar ka t^2 (N*mm/rad)
    assert r["roll_stiffness_Nmm_per_deg"] == pytest.approx((k + 2 * ka) * t ** 2 / 2 / DEG)
    total = ac.roll_from_compliance(C, t, tyre_rate_N_per_mm=kt)["roll_stiffness_Nmm_per_deg"]
    assert total == pytest.approx(t ** 2 / (2 / (k + 2 * ka) + 2 / kt) / DEG)
    # + roll: left wheel rebounds, right bumps by t/2 per rad
    assert r["roll_steer_left_deg_per_deg"] == pytest.approx(-s * t / 2)
    assert r["roll_steer_right_deg_per_deg"] == pytest.approx(s * t / 2)
    assert r["roll_camber_left_deg_per_deg"] == pytest.approx(-c * t / 2)
    # toe-in in bump: in a left turn the right (outer) wheel toes in, the left toes out:
    # the axle steers left, into the turn
    assert r["axle_roll_steer_deg_per_deg"] == pytest.approx(s * t / 2)


# ------------------------------------------------------------------------ percent anti

L, H, RL = 2700.0, 550.0, 300.0


def trailing_arm_axle(pivot_x, pivot_z, wheel_x=0.0, k=30.0):
    """Both wheels on trailing arms rotating about a transverse axis through (pivot_x,
    pivot_z): the side-view instant centre. C = t t^T / k per wheel (consistent units)."""
    C = np.zeros((12, 12))
    for i, y in enumerate((750.0, -750.0)):
        wc = np.array([wheel_x, y, RL])
        w = np.array([0.0, 1.0, 0.0])
        v = np.cross(w, wc - np.array([pivot_x, y, pivot_z]))
        t = np.r_[v, w] / v[2]  # per mm of wheel-centre travel
        C[6 * i:6 * i + 6, 6 * i:6 * i + 6] = np.outer(t, t) / k
    return to_mixed_units(C)


@pytest.mark.parametrize("ic_x, ic_z", [(-600.0, 100.0), (-1500.0, 420.0), (-900.0, -50.0)])
def test_anti_dive_and_anti_lift_match_the_side_view_formula(ic_x, ic_z):
    fb = 0.7
    C = trailing_arm_axle(ic_x, ic_z)
    # outboard brakes: the line from the contact point (x 0, z 0) to the instant centre
    expected = fb * (ic_z / (0.0 - ic_x)) * L / H * 100
    out = ac.percent_anti_dive(C, L, H, RL, fb)
    assert out["left"] == pytest.approx(expected) and out["right"] == pytest.approx(expected)
    geo = ic.percent_anti_geometric(ic_x, ic_z, 0.0, 0.0, L, H, fb, "front")
    assert float(geo) == pytest.approx(expected)
    # inboard brakes: the line from the wheel centre
    expected = fb * ((ic_z - RL) / (0.0 - ic_x)) * L / H * 100
    assert ac.percent_anti_dive(C, L, H, RL, fb, "inboard")["left"] == pytest.approx(expected)
    # a rear axle: the instant centre ahead of the wheel
    rear = trailing_arm_axle(-ic_x, ic_z)
    expected = (1 - fb) * (ic_z / -ic_x) * L / H * 100
    assert ac.percent_anti_lift_braking(rear, L, H, RL, fb)["right"] == pytest.approx(expected)
    geo = ic.percent_anti_geometric(-ic_x, ic_z, 0.0, 0.0, L, H, 1 - fb, "rear")
    assert float(geo) == pytest.approx(expected)


def test_anti_dive_hand_value():
    # IC 600 mm behind and 100 mm above the contact point: tan = 1/6;
    # 0.7 * (1/6) * 2700 / 550 * 100 = 57.2727 %
    C = trailing_arm_axle(-600.0, 100.0)
    assert ac.percent_anti_dive(C, L, H, RL, 0.7)["left"] == pytest.approx(57.272727, abs=1e-5)


def test_anti_squat_and_traction_anti_lift():
    fd = 0.4
    rear = trailing_arm_axle(800.0, 450.0)  # IC ahead of a rear wheel, above its centre
    # chassis-mounted final drive: the line from the wheel centre
    expected = (1 - fd) * ((450.0 - RL) / 800.0) * L / H * 100
    out = ac.percent_anti_squat(rear, L, H, RL, fd, drive="inboard")
    assert out["left"] == pytest.approx(expected)
    geo = ic.percent_anti_geometric(800.0, 450.0, 0.0, RL, L, H, 1 - fd, "rear")
    assert float(geo) == pytest.approx(expected)
    # ADAMS's contact-point form
    expected = (1 - fd) * (450.0 / 800.0) * L / H * 100
    assert ac.percent_anti_squat(rear, L, H, RL, fd)["left"] == pytest.approx(expected)
    front = trailing_arm_axle(-700.0, 200.0)
    expected = fd * (200.0 / 700.0) * L / H * 100
    assert ac.percent_anti_lift_traction(front, L, H, RL, fd)["right"] == pytest.approx(expected)


def test_live_axle_torque_reaction():
    # diagonal vertical compliance and a known C(3,1): Zf, Zw by hand
    C = np.zeros((12, 12))
    C[2, 2] = C[8, 8] = 1 / 30.0
    C[2, 0] = C[8, 6] = 0.01
    fd, ratio, t = 0.0, 3.5, 1500.0
    f = 0.5  # rear traction per wheel per unit total
    torque = RL * 1.0 / ratio
    out = ac.percent_anti_squat(C, L, H, RL, fd, live_axle_ratio=ratio, track_mm=t)
    for side, vt in (("left", -torque / t), ("right", torque / t)):
        zf, zw = f * 0.01, (H / (2 * L) + vt) / 30.0
        assert out[side] == pytest.approx(-100 * zf / zw)
    with pytest.raises(ValueError, match="live axle"):
        ac.percent_anti_squat(C, L, H, RL, fd, live_axle_ratio=ratio)


def test_anti_geometric_at_infinity_uses_the_swing_arm_angle():
    # parallel trailing links inclined 5 deg, rising rearward: the IC is at infinity
    out = ic.percent_anti_geometric(np.nan, np.nan, 0.0, 0.0, L, H, 0.7, "front",
                                    swing_arm_angle_deg=5.0)
    assert float(out) == pytest.approx(0.7 * np.tan(np.radians(5.0)) * L / H * 100)


def test_side_view_instant_centre_from_compliance():
    C = trailing_arm_axle(-600.0, 100.0)
    out = ic.instant_centres_from_compliance(C, [0, 750.0, RL], [0, -750.0, RL])
    sv = out["side_view_right"]
    assert float(sv.horizontal_mm) == pytest.approx(-600.0)
    assert float(sv.z_mm) == pytest.approx(100.0)
    # pure trailing arms do not rotate in the front view: instant centre at infinity,
    # the wheel centre moves straight up so the direction towards it is horizontal
    fv = out["front_view_left"]
    assert fv.swing_arm_length_mm == np.inf and float(fv.swing_arm_angle_deg) == 0.0
