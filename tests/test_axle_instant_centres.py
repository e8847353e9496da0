"""Instant centres, swing arms and roll centres (elastokin.physics.instant_centres): hand
values on a swing axle and a trailing arm, the classic arm-line construction of a double
wishbone, the force-based (ADAMS/Car, from the 12x12 compliance matrix) against the kinematic
roll centre on analytic linkage models with springs, degenerate cases, property tests."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from elastokin.physics import instant_centres as ic

LOADED_RADIUS = 300.0
TRACK = 1500.0
WC_LEFT = np.array([0.0, TRACK / 2, LOADED_RADIUS])
CONTACT_LEFT = np.array([0.0, TRACK / 2, 0.0])


def mirror(p):
    """Mirror a point (or a planar (y, z) pair) in the vehicle's centre plane."""
    p = np.array(p, float)
    p[..., -2 if p.shape[-1] == 2 else 1] *= -1
    return p


# ------------------------------------------------------------------ analytic planar linkage
# The knuckle in the front view (y-z plane) has 3 degrees of freedom (y, z, rotation about x
# in rad) at the wheel centre. A two-force member (arm, spring, pivot link) from a body point
# b to a knuckle point a has the constraint row g = (e_y, e_z, (a - wc) x e) with e = (a - b)
# / |a - b|, and stiffness k g g^T.


def bar_row(a, b, wc):
    a, b, wc = (np.asarray(v, float) for v in (a, b, wc))
    e = (a - b) / np.linalg.norm(a - b)
    r = a - wc
    return np.array([e[0], e[1], r[0] * e[1] - r[1] * e[0]])


def planar_side(bars, spring, wc, k_bar, k_spring):
    """(stiffness 3x3, rigid twist (vy, vz, wx) per mm of wheel-centre travel)."""
    rows = [bar_row(a, b, wc) for a, b in bars]
    K = sum(k * np.outer(g, g) for k, g in zip(np.broadcast_to(k_bar, len(rows)), rows))
    g_s = bar_row(*spring, wc)
    K = K + k_spring * np.outer(g_s, g_s)
    twist = np.linalg.svd(np.array(rows))[2][-1]  # null space of the rigid rows
    return K, twist / twist[1]


def axle_compliance(left_bars, left_spring, right_bars, right_spring, k_bar=1.0e9,
                    k_spring=30.0, k_arb=0.0):
    """12x12 wheel-centre compliance (ISO; mm, deg per N, N*mm) of two planar knuckles
    (out-of-plane x, ry, rz on stiff diagonal springs) coupled by an anti-roll bar acting on
    the wheel centres' heights; ``k_bar``: N/mm of every bar or one per bar."""
    K = np.zeros((12, 12))
    wcs = (WC_LEFT[1:], mirror(WC_LEFT[1:]))
    for i, (bars, spring, wc) in enumerate(((left_bars, left_spring, wcs[0]),
                                            (right_bars, right_spring, wcs[1]))):
        Kp = planar_side(bars, spring, wc, k_bar, k_spring)[0]
        idx = 6 * i + np.array([1, 2, 3])  # y, z, rx
        K[np.ix_(idx, idx)] = Kp
        for j, k in ((0, 2.0e3), (4, 1.0e10), (5, 5.0e9)):  # x, ry, rz
            K[6 * i + j, 6 * i + j] = k
    g = np.zeros(12)
    g[2], g[8] = 1.0, -1.0
    K += k_arb * np.outer(g, g)
    C = np.linalg.inv(K)
    C[[3, 4, 5, 9, 10, 11], :] *= 180.0 / np.pi  # rotations in deg
    return C


def line_intersection(p1, p2, q1, q2):
    """Intersection of the 2-D lines p1-p2 and q1-q2 (independent of the module)."""
    A = np.array([p2 - p1, q1 - q2]).T
    s = np.linalg.solve(A, q1 - p1)
    return p1 + s[0] * (p2 - p1)


# a double wishbone, front view (y, z) of the left side: arms (outer ball joint, inner pivot)
DW_LOWER = (np.array([700.0, 130.0]), np.array([250.0, 160.0]))
DW_UPPER = (np.array([650.0, 480.0]), np.array([380.0, 440.0]))
DW_SPRING = (np.array([640.0, 200.0]), np.array([560.0, 700.0]))


def dw_left():
    return [DW_LOWER, DW_UPPER], DW_SPRING


def dw_right(lower=DW_LOWER, upper=DW_UPPER, spring=DW_SPRING):
    return ([tuple(mirror(p) for p in lower), tuple(mirror(p) for p in upper)],
            tuple(mirror(p) for p in spring))


def twist_3d(bars, spring, wc):
    """(angular velocity deg, velocity mm) of the knuckle per mm of wheel-centre travel."""
    vy, vz, wx = planar_side(bars, spring, wc, 1.0, 1.0)[1]
    return np.r_[np.degrees(wx), 0.0, 0.0], np.r_[0.0, vy, vz]


def classic_roll_centre(left, right):
    """Arm lines -> instant centres -> contact-point lines (the textbook construction)."""
    ics = []
    for (lower, upper), contact in ((left, CONTACT_LEFT[1:]), (right, mirror(CONTACT_LEFT[1:]))):
        ics.append((contact, line_intersection(*lower, *upper)))
    (cl, il), (cr, ir) = ics
    return line_intersection(cl, il, cr, ir), il, ir


# ------------------------------------------------------------------------ instant centres


def test_swing_axle_front_view_instant_centre_is_the_pivot():
    # a swing axle pivoting at (y, z) = (100, 350): the wheel centre at (750, 300) moves
    # normal to the arm; per mm of travel the rotation is 1/650 rad (arm 650 mm, horizontal
    # component) -- hand values: instant centre at the pivot, swing arm sqrt(650^2 + 50^2)
    pivot = np.array([0.0, 100.0, 350.0])
    arm = WC_LEFT - pivot
    w = np.r_[1.0 / arm[1], 0.0, 0.0]  # rad per mm: v_z = w_x * arm_y = 1
    v = np.cross(w, arm)
    c = ic.front_view_instant_centre(np.degrees(w), v, WC_LEFT, "left")
    assert float(c.horizontal_mm) == pytest.approx(100.0, abs=1e-9)
    assert float(c.z_mm) == pytest.approx(350.0, abs=1e-9)
    assert float(c.swing_arm_length_mm) == pytest.approx(np.hypot(650.0, 50.0), abs=1e-9)
    assert float(c.swing_arm_angle_deg) == pytest.approx(np.degrees(np.arctan(50 / 650)),
                                                         abs=1e-12)  # rises inboard
    # the mirrored right wheel: same numbers mirrored, same angle (rises inboard)
    cr = ic.front_view_instant_centre(np.degrees(mirror(-w)), mirror(v), mirror(WC_LEFT),
                                      "right")
    assert float(cr.horizontal_mm) == pytest.approx(-100.0, abs=1e-9)
    assert float(cr.swing_arm_angle_deg) == pytest.approx(float(c.swing_arm_angle_deg))


def test_trailing_arm_side_view_instant_centre():
    # trailing arm pivot 500 mm behind and 100 mm above the wheel centre
    wc = np.array([1000.0, 750.0, 300.0])
    pivot = wc + np.array([-500.0, 0.0, 100.0])
    w = np.r_[0.0, -1.0 / 500.0, 0.0]  # v_z = -w_y * 500 = 1 per mm
    v = np.cross(w, wc - pivot)
    c = ic.side_view_instant_centre(np.degrees(w), v, wc)
    assert float(c.horizontal_mm) == pytest.approx(500.0, abs=1e-9)
    assert float(c.z_mm) == pytest.approx(400.0, abs=1e-9)
    assert float(c.swing_arm_length_mm) == pytest.approx(np.hypot(500, 100), abs=1e-9)
    assert float(c.swing_arm_angle_deg) == pytest.approx(np.degrees(np.arctan(0.2)), abs=1e-12)


def test_double_wishbone_instant_centre_is_the_arm_line_intersection():
    bars, spring = dw_left()
    w, v = twist_3d(bars, spring, WC_LEFT[1:])
    c = ic.front_view_instant_centre(w, v, WC_LEFT, "left")
    expected = line_intersection(*DW_LOWER, *DW_UPPER)
    np.testing.assert_allclose([float(c.horizontal_mm), float(c.z_mm)], expected, atol=1e-6)


def test_parallel_equal_arms_put_the_instant_centre_at_infinity():
    # parallelogram: the knuckle translates, no rotation in the front view
    lower = (np.array([700.0, 130.0]), np.array([250.0, 100.0]))
    upper = (np.array([650.0, 480.0]), np.array([200.0, 450.0]))
    w, v = twist_3d([lower, upper], DW_SPRING, WC_LEFT[1:])
    w[0] = 0.0  # exactly parallel: the solver would give ~1e-17
    c = ic.front_view_instant_centre(w, v, WC_LEFT, "left")
    assert np.isnan(c.horizontal_mm) and np.isnan(c.z_mm)
    assert c.swing_arm_length_mm == np.inf
    # the direction towards it is the arms' direction: falling 30 mm over 450 inboard
    assert float(c.swing_arm_angle_deg) == pytest.approx(-np.degrees(np.arctan(30 / 450)))


def test_no_motion_gives_nan():
    c = ic.front_view_instant_centre(np.zeros(3), np.zeros(3), WC_LEFT, "left")
    assert np.isnan(c.swing_arm_length_mm) and np.isnan(c.swing_arm_angle_deg)


def test_stacked_twists():
    bars, spring = dw_left()
    w, v = twist_3d(bars, spring, WC_LEFT[1:])
    c = ic.front_view_instant_centre(np.stack([w, 2 * w]), np.stack([v, 2 * v]),
                                     np.stack([WC_LEFT, WC_LEFT]), "left")
    assert c.horizontal_mm.shape == (2,)
    assert c.horizontal_mm[0] == pytest.approx(c.horizontal_mm[1])


@settings(max_examples=60, deadline=None)
@given(st.lists(st.floats(-1.0, 1.0), min_size=6, max_size=6),
       st.lists(st.floats(-500.0, 500.0), min_size=3, max_size=3))
def test_instant_centres_do_not_depend_on_the_reference_point(twist, shift):
    w_deg, v = np.array(twist[:3]) * 0.2, np.array(twist[3:])
    assume(abs(w_deg[0]) > 1e-3 and abs(w_deg[1]) > 1e-3)
    p, q = WC_LEFT, WC_LEFT + np.array(shift)
    v_q = ic.point_velocity(w_deg, v, p, q)  # the same motion described at q
    for view in (lambda *a: ic.front_view_instant_centre(*a, "left", at_mm=WC_LEFT),
                 lambda *a: ic.side_view_instant_centre(*a, at_mm=WC_LEFT)):
        a, b = view(w_deg, v, p), view(w_deg, v_q, q)
        scale = 1.0 + float(a.swing_arm_length_mm)
        assert float(b.horizontal_mm) == pytest.approx(float(a.horizontal_mm), abs=1e-9 * scale)
        assert float(b.z_mm) == pytest.approx(float(a.z_mm), abs=1e-9 * scale)


# --------------------------------------------------------------------------- roll centres


def contact_velocity(bars, spring, wc3):
    w, v = twist_3d(bars, spring, wc3[1:])
    return ic.point_velocity(w, v, wc3, wc3 - np.r_[0.0, 0.0, LOADED_RADIUS])


def test_swing_axle_roll_centre_hand_value():
    # pivots at (+-100, 350), contact points at (+-750, 0): the lines meet on the centre
    # plane at 350 * 750 / 650 = 403.846 mm
    left = [(np.array([100.0, 350.0]), np.array([100.0, 850.0])),
            (np.array([100.0, 350.0]), np.array([600.0, 350.0]))]
    spring = (np.array([640.0, 200.0]), np.array([560.0, 700.0]))
    rl, rr = left, [tuple(mirror(p) for p in bar) for bar in left]
    sr = tuple(mirror(p) for p in spring)
    kin = ic.kinematic_roll_centre(CONTACT_LEFT, contact_velocity(rl, spring, WC_LEFT),
                                   mirror(CONTACT_LEFT), contact_velocity(rr, sr,
                                                                          mirror(WC_LEFT)))
    assert str(kin.state) == "finite"
    assert float(kin.lateral_mm) == pytest.approx(0.0, abs=1e-9)
    assert float(kin.height_mm) == pytest.approx(350.0 * 750.0 / 650.0, abs=1e-9)
    C = axle_compliance(rl, spring, rr, sr, k_arb=20.0)
    force = ic.force_based_roll_centre(C, WC_LEFT, mirror(WC_LEFT), CONTACT_LEFT,
                                       mirror(CONTACT_LEFT))
    assert float(force.height_mm) == pytest.approx(350.0 * 750.0 / 650.0, abs=1e-3)
    assert float(force.lateral_mm) == pytest.approx(0.0, abs=1e-3)


@pytest.mark.parametrize("k_arb", [0.0, 25.0])
@pytest.mark.parametrize("asymmetric", [False, True])
def test_force_based_equals_kinematic_roll_centre_with_rigid_joints(k_arb, asymmetric):
    """The double wishbone with rigid arms (1e9 N/mm against a 30 N/mm spring): one motion
    per wheel, so the contact point moves along the same line under any load: ADAMS's
    force-based roll centre must equal the arm-line construction (to ~1e-4 mm: the arms'
    finite stiffness)."""
    bars, spring = dw_left()
    upper_r = (mirror(DW_UPPER[0]), mirror(DW_UPPER[1] + np.array([0.0, 60.0])))
    rbars, rspring = dw_right(upper=tuple(mirror(p) for p in upper_r)) if asymmetric \
        else dw_right()
    C = axle_compliance(bars, spring, rbars, rspring, k_arb=k_arb)
    force = ic.force_based_roll_centre(C, WC_LEFT, mirror(WC_LEFT), CONTACT_LEFT,
                                       mirror(CONTACT_LEFT))
    rc, _, _ = classic_roll_centre(bars, rbars)
    kin = ic.kinematic_roll_centre(CONTACT_LEFT, contact_velocity(bars, spring, WC_LEFT),
                                   mirror(CONTACT_LEFT),
                                   contact_velocity(rbars, rspring, mirror(WC_LEFT)))
    assert str(force.state) == str(kin.state) == "finite"
    np.testing.assert_allclose([float(kin.lateral_mm), float(kin.height_mm)], rc, atol=1e-6)
    np.testing.assert_allclose([float(force.lateral_mm), float(force.height_mm)], rc,
                               atol=1e-3)
    if not asymmetric:
        assert float(kin.lateral_mm) == pytest.approx(0.0, abs=1e-9)


def test_bushing_compliance_separates_force_based_from_kinematic():
    # a compliant lower arm (1000 N/mm: its bushings) gives way under the force it carries
    # when the wheel is loaded vertically: the force-based roll centre moves, the kinematic
    # one (rigid arms) cannot see it
    bars, spring = dw_left()
    rbars, rspring = dw_right()
    C = axle_compliance(bars, spring, rbars, rspring, k_bar=(1.0e3, 1.0e9))
    force = ic.force_based_roll_centre(C, WC_LEFT, mirror(WC_LEFT), CONTACT_LEFT,
                                       mirror(CONTACT_LEFT))
    rc, _, _ = classic_roll_centre(bars, rbars)
    assert float(force.lateral_mm) == pytest.approx(0.0, abs=1e-9)
    assert abs(float(force.height_mm) - rc[1]) > 1.0


def test_stacked_roll_centres():
    bars, spring = dw_left()
    rbars, rspring = dw_right()
    vl = contact_velocity(bars, spring, WC_LEFT)
    vr = contact_velocity(rbars, rspring, mirror(WC_LEFT))
    up = np.r_[0.0, 0.0, 1.0]
    rc = ic.kinematic_roll_centre(np.stack([CONTACT_LEFT] * 2), np.stack([vl, up]),
                                  np.stack([mirror(CONTACT_LEFT)] * 2), np.stack([vr, up]))
    assert list(rc.state) == ["finite", "coincident"]
    assert rc.height_mm[0] == pytest.approx(classic_roll_centre(bars, rbars)[0][1])
    assert rc.height_mm[1] == 0.0


def test_parallel_and_coincident_roll_centre_lines():
    # contact points move straight up: both lines along the ground (equal parallel arms)
    up = np.r_[0.0, 0.0, 1.0]
    rc = ic.kinematic_roll_centre(CONTACT_LEFT, up, mirror(CONTACT_LEFT), up)
    assert str(rc.state) == "coincident"
    assert float(rc.height_mm) == 0.0 and float(rc.lateral_mm) == 0.0
    # two distinct parallel lines (an asymmetric axle): roll centre at infinity
    v = np.r_[0.0, -0.1, 1.0]
    rc = ic.kinematic_roll_centre(CONTACT_LEFT, v, mirror(CONTACT_LEFT) + np.r_[0, 0, 50.0], v)
    assert str(rc.state) == "parallel"
    assert np.isnan(rc.height_mm) and np.isnan(rc.lateral_mm)
    rc = ic.kinematic_roll_centre(CONTACT_LEFT, np.zeros(3), mirror(CONTACT_LEFT), up)
    assert str(rc.state) == "undefined" and np.isnan(rc.height_mm)


arm_point = st.tuples(st.floats(-40.0, 40.0), st.floats(-40.0, 40.0))


@settings(max_examples=40, deadline=None)
@given(arm_point, arm_point, arm_point, arm_point)
def test_mirrored_axle_has_its_roll_centre_on_the_centre_plane(d1, d2, d3, d4):
    lower = (DW_LOWER[0] + np.array(d1), DW_LOWER[1] + np.array(d2))
    upper = (DW_UPPER[0] + np.array(d3), DW_UPPER[1] + np.array(d4))
    bars = [lower, upper]
    rbars, rspring = dw_right(lower, upper)
    kin = ic.kinematic_roll_centre(CONTACT_LEFT, contact_velocity(bars, DW_SPRING, WC_LEFT),
                                   mirror(CONTACT_LEFT),
                                   contact_velocity(rbars, rspring, mirror(WC_LEFT)))
    assume(str(kin.state) == "finite" and abs(float(kin.height_mm)) < 1e5)
    assert float(kin.lateral_mm) == pytest.approx(0.0, abs=1e-7 * (1 + abs(kin.height_mm)))
    C = axle_compliance(bars, DW_SPRING, rbars, rspring, k_arb=10.0)
    force = ic.force_based_roll_centre(C, WC_LEFT, mirror(WC_LEFT), CONTACT_LEFT,
                                       mirror(CONTACT_LEFT))
    assert float(force.lateral_mm) == pytest.approx(0.0, abs=1e-6 * (1 + abs(force.height_mm)))


def test_instant_centres_from_compliance():
    bars, spring = dw_left()
    rbars, rspring = dw_right()
    C = axle_compliance(bars, spring, rbars, rspring, k_arb=15.0)
    out = ic.instant_centres_from_compliance(C, WC_LEFT, mirror(WC_LEFT))
    expected = line_intersection(*DW_LOWER, *DW_UPPER)
    left, right = out["front_view_left"], out["front_view_right"]
    np.testing.assert_allclose([float(left.horizontal_mm), float(left.z_mm)], expected,
                               atol=1e-3)
    np.testing.assert_allclose([float(right.horizontal_mm), float(right.z_mm)],
                               mirror(expected), atol=1e-3)
    # planar knuckles: no pitch rotation, the side-view centre is at infinity
    assert out["side_view_left"].swing_arm_length_mm == np.inf
