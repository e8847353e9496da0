"""Wheel and steering-axis characteristics against hand-computed cases, in every frame and on
both sides, and the screw axis / compliance helpers against known motions and maps."""

from types import SimpleNamespace

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from elastokin.config.schema.suspension import Frame
from elastokin.config.suspension import Suspension
from elastokin.physics.steering_geometry import (
    axis_from_points,
    axis_ground_point,
    caster_deg,
    caster_trail_mm,
    compliance_matrix,
    contact_point,
    gradient,
    kingpin_inclination_deg,
    screw_axis,
    screw_axis_from_poses,
    scrub_radius_mm,
    track_change_mm,
    wheel_centre_displacement,
    wheel_ground_directions,
)
from elastokin.physics.wheel import UndeterminedSlopeWarning, camber_deg, toe_deg

# tolerances: the hand cases are exact up to rounding (1e-9); the screw axis recovered from a
# 0.01 deg finite motion loses ~1/angle digits of the position (1e-6 mm is ample)
TOL = 1e-9
TOL_SCREW = 1e-6

# ISO 8855 frame, left wheel: the frame the hand cases are written in
FWD, OUT, UP = np.array([1.0, 0, 0]), np.array([0, 1.0, 0]), np.array([0, 0, 1.0])

# Hand case. Wheel centre W, loaded radius 300 mm, zero toe and camber: contact C = (0, 750, 0).
# Steering axis through the lower ball joint L and the top mount T; T - L = (-40, -80, 400),
# i.e. direction ~ (-0.1, -0.2, 1): the top leans 0.1 rearward and 0.2 inboard per unit height.
#   caster = atan(0.1) = 5.710593 deg, KPI = atan(0.2) = 11.309932 deg
#   ground point G = L - 100 * (-0.1, -0.2, 1) = (20, 700, 0)
#   trail = (G - C) . forward = 20 mm (ahead), scrub = -(G - C) . outboard = 50 mm (inboard)
W = np.array([0.0, 750.0, 300.0])
R_LOADED = 300.0
L = np.array([10.0, 680.0, 100.0])
T = np.array([-30.0, 600.0, 500.0])
CASTER = np.degrees(np.arctan(0.1))
KPI = np.degrees(np.arctan(0.2))


def all_characteristics(point, direction, centre, spin, fwd, out, up):
    c = contact_point(centre, spin, R_LOADED, up)
    return {
        "toe": toe_deg(spin, fwd, out),
        "camber": camber_deg(spin, fwd, out, up),
        "caster": caster_deg(direction, fwd, up),
        "kpi": kingpin_inclination_deg(direction, out, up),
        "scrub": scrub_radius_mm(point, direction, c, spin, fwd, out, up),
        "trail": caster_trail_mm(point, direction, c, spin, fwd, out, up),
    }


def test_hand_case_axis_from_points():
    p, d = axis_from_points(L, T)
    assert np.allclose(d, np.array([-0.1, -0.2, 1.0]) / np.sqrt(1.05))
    c = contact_point(W, OUT, R_LOADED, UP)
    assert np.allclose(c, [0.0, 750.0, 0.0])
    assert np.allclose(axis_ground_point(p, d, c, UP), [20.0, 700.0, 0.0])
    got = all_characteristics(p, d, W, OUT, FWD, OUT, UP)
    expected = {"toe": 0.0, "camber": 0.0, "caster": CASTER, "kpi": KPI, "scrub": 50.0,
                "trail": 20.0}
    for k, v in expected.items():
        assert got[k] == pytest.approx(v, abs=TOL), k
    # the sense of the axis does not matter
    assert caster_deg(-d, FWD, UP) == pytest.approx(CASTER)
    assert kingpin_inclination_deg(-d, OUT, UP) == pytest.approx(KPI)
    assert scrub_radius_mm(T, -d, c, OUT, FWD, OUT, UP) == pytest.approx(50.0)


def test_hand_case_toe():
    # the wheel turned 36.87 deg toe-in (cos 0.8, sin 0.6) about the vertical through its
    # contact point; the steering axis stays. Outboard spin axis a = (0.6, 0.8, 0) (turned
    # forward: toe-in); heading h = (0.8, -0.6, 0); G - C = (20, -50, 0):
    #   trail = (G - C) . h = 16 + 30 = 46 mm; scrub = -(G - C) . a = -(12 - 40) = 28 mm
    a = np.array([0.6, 0.8, 0.0])
    centre = np.array([0.0, 750.0, 0.0]) + R_LOADED * UP
    h, lat = wheel_ground_directions(a, FWD, OUT, UP)
    assert np.allclose(h, [0.8, -0.6, 0.0]) and np.allclose(lat, a)
    p, d = axis_from_points(L, T)
    got = all_characteristics(p, d, centre, a, FWD, OUT, UP)
    assert got["toe"] == pytest.approx(np.degrees(np.arctan2(0.6, 0.8)))
    assert got["trail"] == pytest.approx(46.0, abs=TOL)
    assert got["scrub"] == pytest.approx(28.0, abs=TOL)
    assert got["caster"] == pytest.approx(CASTER) and got["kpi"] == pytest.approx(KPI)


def test_hand_case_camber():
    # camber with sin = 0.28, cos = 0.96 (top outboard: the outboard spin axis points down):
    # a = (0, 0.96, -0.28). The contact point is 300 mm down the wheel plane:
    #   C = W + 300 * (0, -0.28, -0.96) = (0, 666, 12)
    # so the ground plane is z = 12; the axis meets it 88 mm below L:
    #   G = L + 88 * (0.1, 0.2, -1) = (18.8, 697.6, 12);  G - C = (18.8, 31.6, 0)
    #   trail = 18.8 mm, scrub = -31.6 mm (the axis meets the ground outboard of the contact)
    a = np.array([0.0, 0.96, -0.28])
    c = contact_point(W, a, R_LOADED, UP)
    assert np.allclose(c, [0.0, 666.0, 12.0])
    p, d = axis_from_points(L, T)
    got = all_characteristics(p, d, W, a, FWD, OUT, UP)
    assert got["camber"] == pytest.approx(np.degrees(np.arcsin(0.28)))
    assert got["trail"] == pytest.approx(18.8, abs=TOL)
    assert got["scrub"] == pytest.approx(-31.6, abs=TOL)


# ---------------------------------------------------------------- frames and sides


def frame_vectors(x: str, y: str, side: str):
    """forward, outboard, up exactly as the config defines them (Suspension properties)."""
    s = SimpleNamespace(frame=Frame(x=x, y=y), side=side)
    return (Suspension.forward.fget(s), Suspension.outboard.fget(s), Suspension.up.fget(s))


FRAMES = [("forward", "left", "left"), ("forward", "left", "right"),
          ("rearward", "right", "left"), ("rearward", "right", "right")]


def to_frame(x: str, y: str, side: str, origin=np.zeros(3)):
    """Map ISO-left coordinates (x forward, y outboard) of the hand-case corner to the same
    corner in frame (x, y) on ``side``: mirror for the right side, axis flips for ADAMS."""
    fwd, out, up = frame_vectors(x, y, side)
    basis = np.column_stack([fwd, out, up])  # ISO-left components -> frame components

    def point(p):
        return basis @ p + origin

    def vector(v):
        return basis @ v

    return point, vector, (fwd, out, up)


@pytest.mark.parametrize("x,y,side", FRAMES)
def test_same_numbers_in_every_frame_and_side(x, y, side):
    a = np.array([0.6, 0.8, 0.0])  # the toe case, plus camber: tilt the spin axis down
    a = np.array([a[0] * 0.96, a[1] * 0.96, -0.28])
    reference = all_characteristics(L, T - L, W, a, FWD, OUT, UP)
    point, vector, (fwd, out, up) = to_frame(x, y, side, origin=np.array([1234.0, -56.0, 7.0]))
    got = all_characteristics(point(L), vector(T - L), point(W), vector(a), fwd, out, up)
    for k, v in reference.items():
        assert got[k] == pytest.approx(v, abs=TOL), k
    # displacements and track change (wheel centre moved 3 fwd, 4 out, 5 up; contact 2 out)
    disp = wheel_centre_displacement(point(W + [3.0, 4.0, 5.0]), point(W), fwd, out, up)
    assert np.allclose(disp, [3.0, 4.0, 5.0])
    c0 = contact_point(W, a, R_LOADED, UP)
    assert track_change_mm(point(c0 + [9.0, 2.0, 0.0]), point(c0), out) == pytest.approx(2.0)


@given(caster=st.floats(-10, 15), kpi=st.floats(-5, 20), toe=st.floats(-20, 20),
       camber=st.floats(-8, 8), ahead=st.floats(-80, 80), inboard=st.floats(-80, 120),
       height=st.floats(50, 600), frame=st.sampled_from(FRAMES))
@settings(max_examples=60, deadline=None)
def test_random_geometry_frame_invariant(caster, kpi, toe, camber, ahead, inboard, height,
                                         frame):
    # the axis built from its angles meets the ground (through the zero-camber contact point
    # of a zero-toe wheel) 'ahead' and 'inboard' of it: with zero toe and camber, trail and
    # scrub are exactly those
    d = np.array([-np.tan(np.radians(caster)), -np.tan(np.radians(kpi)), 1.0])
    g = np.array([ahead, 750.0 - inboard, 0.0])
    p = g + height * d
    assert caster_deg(d, FWD, UP) == pytest.approx(caster, abs=1e-9)
    assert kingpin_inclination_deg(d, OUT, UP) == pytest.approx(kpi, abs=1e-9)
    ref0 = all_characteristics(p, d, W, OUT, FWD, OUT, UP)
    assert ref0["trail"] == pytest.approx(ahead, abs=1e-9)
    assert ref0["scrub"] == pytest.approx(inboard, abs=1e-9)
    # with toe and camber, the same numbers in every frame and side
    from elastokin.physics.wheel import spin_axis_from_angles

    a = spin_axis_from_angles(toe, camber, FWD, OUT, UP)
    ref = all_characteristics(p, d, W, a, FWD, OUT, UP)
    point, vector, (fwd, out, up) = to_frame(*frame, origin=np.array([-500.0, 80.0, 30.0]))
    got = all_characteristics(point(p), vector(d), point(W), vector(a), fwd, out, up)
    for k, v in ref.items():
        assert got[k] == pytest.approx(v, abs=1e-8), k


def test_vectorised_over_steps():
    p, d = axis_from_points(L, T)
    spins = np.array([[0.0, 1.0, 0.0], [0.6, 0.8, 0.0], [0.0, 0.96, -0.28]])
    centres = np.array([W, [0.0, 750.0, 300.0], W])
    c = contact_point(centres, spins, R_LOADED, UP)
    stacked = scrub_radius_mm(np.tile(p, (3, 1)), np.tile(d, (3, 1)), c, spins, FWD, OUT, UP)
    single = [scrub_radius_mm(p, d, c[i], spins[i], FWD, OUT, UP) for i in range(3)]
    assert np.allclose(stacked, single)
    assert np.allclose(stacked, [50.0, 28.0, -31.6])


def test_horizontal_axis_is_an_error():
    with pytest.raises(ValueError, match="horizontal"):
        caster_deg([1.0, 0.0, 0.0], FWD, UP)
    with pytest.raises(ValueError, match="zero length"):
        axis_from_points(L, L)


# -------------------------------------------------------------------------- screw axis


unit_vectors = st.tuples(*[st.floats(-1, 1)] * 3).map(np.array).filter(
    lambda v: np.linalg.norm(v) > 0.1).map(lambda v: v / np.linalg.norm(v))
points = st.tuples(*[st.floats(-1000, 1000)] * 3).map(np.array)


def motion(n, p, angle_deg, d):
    """Rotation by angle about the line (p, n), then translation d along n: x -> R x + t."""
    R = Rotation.from_rotvec(np.radians(angle_deg) * n).as_matrix()
    return R, p - R @ p + d * n


@given(n=unit_vectors, p=points, angle=st.floats(-179.0, 179.0), d=st.floats(-100, 100))
@settings(max_examples=200, deadline=None)
def test_screw_axis_recovers_random_motions(n, p, angle, d):
    assume(abs(angle) > 0.01)
    R, t = motion(n, p, angle, d)
    s = screw_axis(R, t, orient=n)
    assert np.allclose(s.direction, n, atol=1e-9)
    assert s.angle_deg == pytest.approx(angle, abs=1e-9)
    assert s.translation_mm == pytest.approx(d, abs=1e-7)
    # the point is on the true axis and the closest to the origin
    off = (s.point - p) - ((s.point - p) @ n) * n
    assert np.linalg.norm(off) < TOL_SCREW
    assert abs(s.point @ n) < TOL_SCREW
    # the opposite orientation flips direction, angle and translation, not the line
    s2 = screw_axis(R, t, orient=-n)
    assert np.allclose(s2.direction, -n) and s2.angle_deg == pytest.approx(-angle, abs=1e-9)
    assert s2.translation_mm == pytest.approx(-d, abs=1e-7)
    # the point nearest a given point
    q = np.array([100.0, -200.0, 300.0])
    s3 = screw_axis(R, t, near=q)
    assert abs((s3.point - q) @ s3.direction) < TOL_SCREW


@given(n=unit_vectors, p=points, angle=st.floats(0.01, 170.0), d=st.floats(-50, 50),
       pose_axis=unit_vectors, pose_angle=st.floats(-180, 180), t1=points)
@settings(max_examples=100, deadline=None)
def test_screw_axis_from_poses(n, p, angle, d, pose_axis, pose_angle, t1):
    R1 = Rotation.from_rotvec(np.radians(pose_angle) * pose_axis).as_matrix()
    R, t = motion(n, p, angle, d)
    R2, t2 = R @ R1, R @ t1 + t
    s = screw_axis_from_poses(R1, t1, R2, t2, orient=n)
    assert np.allclose(s.direction, n, atol=1e-9)
    assert s.angle_deg == pytest.approx(angle, abs=1e-8)
    assert s.translation_mm == pytest.approx(d, abs=1e-6)
    off = (s.point - p) - ((s.point - p) @ n) * n
    assert np.linalg.norm(off) < TOL_SCREW


def test_steering_axis_from_two_knuckle_poses():
    # the hand-case knuckle steered by 0.01 deg about the hand-case axis (plus 1 um along it):
    # the instant axis gives the hand-case caster, KPI, scrub and trail
    _, d = axis_from_points(L, T)
    R, t = motion(d, L, 0.01, 1e-3)
    R1, t1 = np.eye(3), np.array([5.0, 700.0, 250.0])  # knuckle pose at design (any)
    s = screw_axis_from_poses(R1, t1, R @ R1, R @ t1 + t, orient=UP, near=W)
    c = contact_point(W, OUT, R_LOADED, UP)
    assert s.angle_deg == pytest.approx(0.01)
    assert caster_deg(s.direction, FWD, UP) == pytest.approx(CASTER, abs=1e-9)
    assert kingpin_inclination_deg(s.direction, OUT, UP) == pytest.approx(KPI, abs=1e-9)
    ground = (s.point, s.direction, c, OUT, FWD, OUT, UP)
    assert scrub_radius_mm(*ground) == pytest.approx(50.0, abs=1e-6)
    assert caster_trail_mm(*ground) == pytest.approx(20.0, abs=1e-6)


def test_screw_axis_errors():
    with pytest.raises(ValueError, match="pure translation"):
        screw_axis(np.eye(3), [1.0, 2.0, 3.0])
    with pytest.raises(ValueError, match="proper rotation"):
        screw_axis(np.diag([1.0, 1.0, -1.0]), np.zeros(3))
    with pytest.raises(ValueError, match="3x3"):
        screw_axis(np.eye(2), np.zeros(3))


# --------------------------------------------------------------------------- gradients


def test_gradient_window_and_scale():
    travel = np.r_[np.linspace(0, -90, 91), np.linspace(-90, 90, 181)]
    toe = -0.003 * travel + 2e-7 * travel**3
    inside = np.abs(travel) <= 50
    expected = 1000 * np.polyfit(travel[inside], toe[inside], 1)[0]
    assert gradient(travel, toe, (-50, 50), scale=1000) == pytest.approx(expected)
    assert gradient([0.0, 1.0, 2.0], [1.0, 3.0, 5.0]) == pytest.approx(2.0)
    with pytest.warns(UndeterminedSlopeWarning, match="0 distinct points within 100 <= x <= 200"):
        assert np.isnan(gradient(travel, toe, (100, 200)))


def test_compliance_matrix_recovers_linear_map():
    rng = np.random.default_rng(4)
    A = rng.normal(size=(6, 6)) * np.r_[1e-2, 1e-2, 1e-2, 1e-5, 1e-5, 1e-5]
    b = rng.normal(size=6)
    steps = [100.0, 100.0, 100.0, 1e5, 1e5, 1e5]
    C = compliance_matrix(lambda x: A @ x + b, steps)
    assert C.shape == (6, 6)
    assert np.allclose(C, A, rtol=1e-10, atol=1e-15)
    # central differences are exact for a quadratic too: gradient at load0 = A + Q load0
    Q = rng.normal(size=(6, 6)) * 1e-6
    Q = Q + Q.T
    x0 = np.r_[500.0, -200.0, 4500.0, 1e4, 0.0, -3e4]

    def quad(x):
        return A @ x + 0.5 * np.array([x @ (Q * (i + 1)) @ x for i in range(6)])

    exact = A + np.array([(Q * (i + 1)) @ x0 for i in range(6)])
    assert np.allclose(compliance_matrix(quad, steps, load0=x0), exact, rtol=1e-7, atol=1e-12)
    # a scalar step applies to every input
    assert np.allclose(compliance_matrix(lambda x: A @ x, 1.0), A, rtol=1e-10, atol=1e-15)


def test_compliance_matrix_errors():
    with pytest.raises(ValueError, match="> 0"):
        compliance_matrix(lambda x: x, [1.0, 1.0, 0.0, 1.0, 1.0, 1.0])
    with pytest.raises(ValueError, match="3 entries for 6 inputs"):
        compliance_matrix(lambda x: x, [1.0, 1.0, 1.0], load0=np.zeros(6))
    with pytest.raises(ValueError, match="non-finite"):
        compliance_matrix(lambda x: x * np.nan, 1.0)
