"""Joints from motion, the mathematics (no solver): SCoRE against an independent sphere fit,
SARA's axes, the rack, marks ordered and a wrong one dropped at any position, the covariance
from the CMM noise against a Monte Carlo, and the message when the motion is too small."""

import re

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from elastokin.config.schema.motion import MotionSpec
from elastokin.errors import MeasurementError
from elastokin.formats.cmm_motion import MotionMeasurement
from elastokin.identification.motion.conditioning import check_located, located_condition
from elastokin.identification.motion.functional import rack_score, sara, score
from elastokin.identification.motion.identify import locate
from elastokin.identification.motion.joints import SCORE, SLIDING_SARA, JointPlan
from elastokin.identification.motion.poses import (
    noise_sigma,
    order_marks,
    propagate,
    vehicle_poses,
)
from elastokin.physics.pose import fit_pose, fit_poses

MARKS = np.array([[0.0, 0.0, 0.0], [120.0, 0.0, 0.0], [35.0, 90.0, 0.0], [55.0, 25.0, 70.0]])
SIGMA = 0.1 / 2.7955  # the case study's CMM: 95 % of points within 0.1 mm


def sphere_centre(points: np.ndarray) -> np.ndarray | None:
    """The centre of the sphere through ``points`` (algebraic fit |x|^2 = 2 c.x + k, linear):
    an independent solve, written apart from SCoRE; None when the points do not fix one
    sphere (fewer than 4 of them off a common plane)."""
    m = points.mean(axis=0)
    scale = np.abs(points - m).max() or 1.0
    x = (points - m) / scale  # centred and scaled: a well-posed linear fit
    A = np.column_stack([2.0 * x, np.ones(len(x))])
    s = np.linalg.svd(A, compute_uv=False)
    if s[3] < 1e-3 * s[0]:
        return None
    sol = np.linalg.lstsq(A, np.sum(x**2, axis=1), rcond=None)[0]
    return m + scale * sol[:3]


rotations = st.lists(st.tuples(*[st.floats(-0.6, 0.6)] * 3), min_size=5, max_size=12)


@given(rotations, st.tuples(*[st.floats(-300.0, 300.0)] * 3),
       st.tuples(*[st.floats(-150.0, 150.0)] * 3))
@settings(max_examples=40, deadline=None)
def test_score_centre_is_the_sphere_centre_of_any_point(rotvecs, centre, offset):
    """A body turning about a fixed point: every point of it stays on a sphere about that
    point. SCoRE's centre (body against ground) equals the sphere fitted to a point's path."""
    rv = np.array(rotvecs)
    if np.linalg.matrix_rank(rv, tol=0.05) < 2:  # needs turns about two axes
        return
    c = np.asarray(centre)
    R = Rotation.from_rotvec(rv).as_matrix()
    local = c + np.asarray(offset)  # body frame = vehicle frame at no rotation
    t = c - R @ c  # x = R (x_local - c) + c
    Rg, tg = np.tile(np.eye(3), (len(R), 1, 1)), np.zeros((len(R), 3))
    cg, cb, s = score(Rg, tg, R, t)
    path = np.einsum("kij,j->ki", R, local + [200.0, -50.0, 30.0]) + t  # some other point
    independent = sphere_centre(path)
    assume(independent is not None)
    np.testing.assert_allclose(cg, independent, atol=1e-5 * (1 + np.abs(c).max()))
    np.testing.assert_allclose(cg, c, atol=1e-6 * (1 + np.abs(c).max()))
    np.testing.assert_allclose(cb, c, atol=1e-6 * (1 + np.abs(c).max()))


def test_sara_hinge_and_cylinder_axes():
    """A hinge: SARA's axis and a point on it; a cylindrical joint (turning and sliding):
    the same with the slide left out. Both bodies move."""
    rng = np.random.default_rng(3)
    n, p = np.array([0.0, 0.6, 0.8]), np.array([100.0, -50.0, 300.0])
    P = 9
    Ra = Rotation.from_rotvec(rng.normal(size=(P, 3)) * 0.1).as_matrix()
    ta = rng.uniform(-20, 20, (P, 3))
    Rrel = Rotation.from_rotvec(np.linspace(-0.5, 0.5, P)[:, None] * n).as_matrix()
    for slide in (0.0, 25.0):
        trel = p - Rrel @ p + np.linspace(-slide, slide, P)[:, None] * n
        Rb = Ra @ Rrel
        tb = np.einsum("kij,kj->ki", Ra, trel) + ta
        ca, cb, axis, s = sara(Ra, ta, Rb, tb, slide=bool(slide), hint=n)
        np.testing.assert_allclose(axis, n, atol=1e-9)
        assert np.linalg.norm(np.cross(ca - p, n)) < 1e-7  # on the axis
        assert s[5] < 1e-9 * s[0]  # the hinge's null direction


def test_rack_score_finds_the_end_and_the_racks_axis():
    """A rod whose end rides on a rack moved by the stated travel: the end, and the rack's
    axis times its calibration (a rack that travels 2 % more than stated)."""
    rng = np.random.default_rng(5)
    P = 10
    a = np.array([0.1, 1.0, 0.05]) / np.linalg.norm([0.1, 1.0, 0.05])
    travel = rng.uniform(-30, 30, P)
    travel[0] = 0.0
    c0, x = np.array([-73.7, -353.4, 228.3]), np.array([5.0, -20.0, 3.0])
    R = Rotation.from_rotvec(rng.normal(size=(P, 3)) * 0.2).as_matrix()
    t = c0 + 1.02 * travel[:, None] * a - R @ x
    c, c_0, v, _ = rack_score(R, t, travel)
    np.testing.assert_allclose(c, x, atol=1e-8)
    np.testing.assert_allclose(c_0, c0, atol=1e-8)
    np.testing.assert_allclose(v, 1.02 * a, atol=1e-10)


def test_batched_fit_is_the_single_fit():
    rng = np.random.default_rng(1)
    R = Rotation.random(5, random_state=rng).as_matrix()
    q = np.einsum("kij,mj->kmi", R, MARKS) + rng.uniform(-500, 500, (5, 1, 3))
    q += rng.normal(0, 0.05, q.shape)
    Rb, tb, rms = fit_poses(MARKS, q)
    for k in range(5):
        R1, t1, r1 = fit_pose(MARKS, q[k])
        np.testing.assert_allclose(Rb[k], R1, atol=1e-12)
        np.testing.assert_allclose(tb[k], t1, atol=1e-9)
        assert rms[k] == pytest.approx(r1, rel=1e-9)


# ------------------------------------------------------------ marks, poses, noise, message
def two_links(P: int, rng, turn: float = 0.35, about: np.ndarray | None = None):
    """Poses (4x4 by position, from the design position) of an arm turning about a ball
    joint C1 on the ground and of a carrier turning about a ball joint C2 on the arm; the
    rotation vectors random (``about``: all along it)."""
    C1, C2 = np.array([0.0, 0.0, 0.0]), np.array([300.0, 100.0, -50.0])
    poses = []
    for k in range(P):
        if k == 0:
            r1 = r2 = np.zeros(3)
        elif about is not None:
            r1 = r2 = about * turn * rng.uniform(-1, 1)
        else:
            r1, r2 = rng.normal(size=3) * turn, rng.normal(size=3) * turn
        R1, R2 = (Rotation.from_rotvec(r).as_matrix() for r in (r1, r2))
        T1 = np.eye(4)
        T1[:3, :3], T1[:3, 3] = R1, C1 - R1 @ C1
        c2 = T1[:3, :3] @ C2 + T1[:3, 3]
        T2 = np.eye(4)
        T2[:3, :3] = R1 @ R2
        T2[:3, 3] = c2 - T2[:3, :3] @ C2
        poses.append({"body": np.eye(4), "arm": T1, "carrier": T2})
    marks = {"body": MARKS + [-200.0, -300.0, 100.0], "arm": MARKS + [100.0, 0.0, 0.0],
             "carrier": MARKS + [300.0, 150.0, -100.0]}
    return poses, marks, C2


def measured(poses, marks, rng, sigma=SIGMA, bad=None) -> MotionMeasurement:
    """The marks at every position in a CMM frame, noisy, each body's in scrambled order;
    ``bad``: (position, body, mark) moved 8 mm."""
    R, t = Rotation.random(random_state=rng).as_matrix(), rng.uniform(-900, 900, 3)
    out = []
    for k, T in enumerate(poses):
        at = {}
        for body, m in marks.items():
            q = (m @ T[body][:3, :3].T + T[body][:3, 3]) @ R.T + t
            q = q + rng.normal(0, sigma, q.shape)
            if bad == (k, body):
                q[2] += [8.0, 0.0, 0.0]
            at[body] = q[rng.permutation(4)]
        out.append(at)
    names = [f"p{k}" for k in range(len(poses))]
    ground = marks["body"] + rng.normal(0, sigma, (4, 3))
    return MotionMeasurement(names, [f"{n}.csv" for n in names], out, ground, "ground.csv")


def spec(P: int, **kw) -> MotionSpec:
    return MotionSpec.model_validate({
        "ground": {"file": "ground.csv"}, "marks": {"body": "B*", "arm": "A*", "carrier": "C*"},
        "positions": {f"p{k}": {"file": f"p{k}.csv", "wheel_travel_mm": float(k)}
                      for k in range(P)}, **kw})


PLAN = JointPlan("C2", "ball joint", SCORE, ("arm", "carrier"), "C2", np.zeros(3))


def test_poses_from_unordered_marks_and_a_wrong_one_dropped():
    rng = np.random.default_rng(11)
    poses, marks, C2 = two_links(8, rng)
    data = measured(poses, marks, rng, bad=(5, "carrier"))
    mm, warnings = order_marks(data, "body", 0, 0.4)
    assert mm.dropped == [("carrier", 5, mm.dropped[0][2])]
    assert any("p5.csv: body 'carrier'" in w for w in warnings)
    got = vehicle_poses(mm)
    for k in range(8):  # the body's frame is the vehicle frame at the design position
        np.testing.assert_allclose(got["carrier"][0][k], poses[k]["carrier"][:3, :3],
                                   atol=2e-3)
    sigma, dof = noise_sigma(mm)
    assert sigma == pytest.approx(SIGMA, rel=0.25) and dof > 50
    cov = propagate(mm, ["arm", "carrier"], lambda p: PLAN.estimate(p, 0), sigma)
    assert np.linalg.norm(PLAN.estimate(got, 0) - C2) < 3 * np.sqrt(np.trace(cov))


def test_a_wrong_mark_at_the_design_position_is_no_template():
    """The template comes from the first position whose marks agree with the others'."""
    rng = np.random.default_rng(12)
    poses, marks, C2 = two_links(8, rng)
    mm, _ = order_marks(measured(poses, marks, rng, bad=(0, "arm")), "body", 0, 0.4)
    assert mm.reference["arm"] == 1 and mm.reference["carrier"] == 0
    assert [d[:2] for d in mm.dropped] == [("arm", 0)]
    cov = propagate(mm, ["arm", "carrier"], lambda p: PLAN.estimate(p, 0), SIGMA)
    assert np.linalg.norm(PLAN.estimate(vehicle_poses(mm), 0) - C2) < 3 * np.sqrt(
        np.trace(cov))


def test_stated_uncertainty_agrees_with_the_monte_carlo_spread():
    """The covariance propagated from the noise (first order) against the spread of the
    centre over 40 draws of the noise: within 20 %; the noise the pose fits show (which the
    stated uncertainty scales with) is the CMM's, on average over the draws."""
    rng = np.random.default_rng(7)
    poses, marks, _ = two_links(10, rng)
    mm, _ = order_marks(measured(poses, marks, rng), "body", 0, 0.4)
    cov = propagate(mm, ["arm", "carrier"], lambda p: PLAN.estimate(p, 0), SIGMA)
    draws, sigmas = [], []
    for _ in range(40):
        m, _ = order_marks(measured(poses, marks, rng), "body", 0, 0.4)
        draws.append(PLAN.estimate(vehicle_poses(m), 0))
        sigmas.append(noise_sigma(m)[0])
    spread = np.sqrt(np.trace(np.cov(np.array(draws).T)))
    assert spread == pytest.approx(np.sqrt(np.trace(cov)), rel=0.2)
    assert np.mean(sigmas) == pytest.approx(SIGMA, rel=0.1)


@pytest.mark.parametrize("turn", [0.0, 1e-5])
def test_positions_without_motion_give_the_clear_message(turn):
    rng = np.random.default_rng(2)
    poses, marks, _ = two_links(6, rng, turn=turn)
    mm, _ = order_marks(measured(poses, marks, rng), "body", 0, 0.4)
    with pytest.raises(MeasurementError) as err:
        locate(PLAN, mm, vehicle_poses(mm), SIGMA, spec(6), [f"p{k}.csv" for k in range(6)])
    msg = str(err.value)
    assert msg.startswith("p0.csv: joint 'C2' (ball joint, arm - carrier, SCoRE): the motion "
                          "is too small to locate it")
    assert "condition number" in msg and "Over the 6 positions, carrier turns" in msg
    assert re.search(r"relative to arm by at most 0\.0\d deg", msg)
    assert "Add positions that turn carrier relative to arm" in msg


def test_turns_about_one_axis_name_the_missing_direction_and_the_fix():
    """Every turn about the vertical: the centre is not located along it; the message names
    the direction, the turn that would locate it and the rig input that gives it."""
    rng = np.random.default_rng(4)
    poses, marks, _ = two_links(8, rng, turn=0.3, about=np.array([0.0, 0.0, 1.0]))
    mm, _ = order_marks(measured(poses, marks, rng), "body", 0, 0.4)
    P = vehicle_poses(mm)
    assert located_condition(PLAN, P, 0) > 1e3
    with pytest.raises(MeasurementError, match=r"not located along \(0\.00, 0\.00, 1\.00\)"
                       r".*wheel travel \(wheel_travel_mm"):
        locate(PLAN, mm, P, SIGMA, spec(8), [f"p{k}.csv" for k in range(8)])


def test_a_well_turned_joint_passes_the_check_and_partly_located_keeps_the_config():
    rng = np.random.default_rng(6)
    poses, marks, C2 = two_links(10, rng)
    mm, _ = order_marks(measured(poses, marks, rng), "body", 0, 0.4)
    P = vehicle_poses(mm)
    check_located(PLAN, P, 0, spec(10), [], condition=located_condition(PLAN, P, 0))
    joint = locate(PLAN, mm, P, SIGMA, spec(10), [])
    assert joint.worst_std_mm < 0.5 and not joint.from_config
    config = C2 + [5.0, 0.0, 0.0]
    plan = JointPlan("C2", "ball joint", SCORE, ("arm", "carrier"), "C2", config)
    strict = spec(10, max_uncertainty_mm=0.1, partly_located=["C2"])
    partly = locate(plan, mm, P, SIGMA, strict, [])
    for d, std in partly.from_config:  # the config's along what the motion does not fix
        assert std > 0.1
        assert (partly.point_mm - config) @ d == pytest.approx(0.0, abs=1e-9)
    assert partly.from_config and partly.worst_std_mm <= 0.1 + 1e-12


def test_cylindrical_joint_located_with_its_axis_and_uncertainty():
    rng = np.random.default_rng(8)
    poses, marks, C2 = two_links(10, rng)
    n = np.array([0.0, 0.0, 1.0])  # the carrier turns and slides about/along z at C2
    for k, T in enumerate(poses[1:], start=1):
        rel = np.eye(4)
        rel[:3, :3] = Rotation.from_rotvec(0.5 * np.sin(k) * n).as_matrix()
        rel[:3, 3] = C2 - rel[:3, :3] @ C2 + 10.0 * np.cos(k) * n
        T["carrier"] = T["arm"] @ rel
    mm, _ = order_marks(measured(poses, marks, rng), "body", 0, 0.4)
    plan = JointPlan("C2", "cylindrical", SLIDING_SARA, ("arm", "carrier"), "C2",
                     C2 + 40.0 * n, n)
    joint = locate(plan, mm, vehicle_poses(mm), SIGMA, spec(10), [])
    assert np.degrees(np.arccos(abs(joint.axis @ n))) < 0.3
    assert np.linalg.norm(np.cross(joint.point_mm - C2, n)) < 0.3
    assert joint.point_mm[2] == pytest.approx(C2[2] + 40.0, abs=0.5)  # nearest the config's
    assert joint.axis_uncertainty_deg < 0.3
