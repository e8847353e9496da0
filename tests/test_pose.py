"""Identification geometry [1-27]: hand-checkable cases and hypothesis property tests."""

import itertools

import numpy as np
import pytest
from hypothesis import assume, example, given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from elastokin.errors import MeasurementError
from elastokin.physics.pose import (
    _passing,
    clearance_bound_mm,
    deflection_operator,
    euler_zxz_deg,
    fit_pose,
    homogeneous,
    identified_bushing_frame,
    identified_spherical_centre,
    mark_layout_warnings,
    match_marks,
    rotation_from_euler_zxz_deg,
    zero_torsion_frame,
)

EPS = 0.4
# well-spread marks with 6 distinct pairwise distances (mm, part frame)
MARKS = np.array([[0.0, 0.0, 0.0], [120.0, 0.0, 0.0], [35.0, 90.0, 0.0], [55.0, 25.0, 70.0]])


def rigid(seed):
    rng = np.random.default_rng(seed)
    return Rotation.random(random_state=rng).as_matrix(), rng.uniform(-800, 800, 3), rng


def test_clearance_bound_hand_case():
    # hole 14 mm, bolt 12 mm, inner sleeve bore 12.4 mm: 7 - 12 + 6.2 = 1.2 mm
    assert clearance_bound_mm(14.0, 12.0, 12.4) == pytest.approx(1.2)


def test_fit_pose_hand_case():
    R = Rotation.from_euler("z", 90, degrees=True).as_matrix()
    q = MARKS @ R.T + [10.0, 0.0, 0.0]
    R_fit, t, rms = fit_pose(MARKS, q)
    np.testing.assert_allclose(R_fit, R, atol=1e-12)
    np.testing.assert_allclose(t, [10, 0, 0], atol=1e-10)
    assert rms < 1e-10


def test_fit_pose_rejects_collinear_marks():
    with pytest.raises(MeasurementError, match="collinear"):
        fit_pose([[0, 0, 0], [1, 0, 0], [2, 0, 0]], [[0, 0, 0], [1, 0, 0], [2, 0, 0]])


@given(st.integers(0, 10_000), st.permutations(range(4)), st.floats(0.0, 0.05))
@settings(max_examples=60, deadline=None)
def test_pose_recovered_in_any_order_with_noise(seed, order, noise):
    R, t, rng = rigid(seed)
    measured = (MARKS @ R.T + t + rng.normal(0, noise, (4, 3)))[list(order)]
    m = match_marks(MARKS, measured, EPS, "arm")
    assert m.dropped_mark is None
    assert [m.order[i] for i in range(4)] == [list(order).index(i) for i in range(4)]
    assert np.linalg.det(m.R) == pytest.approx(1.0)
    # the pose error at the marks stays within the noise bound (3 sigma per coordinate)
    err = np.linalg.norm(MARKS @ m.R.T + m.t - (MARKS @ R.T + t), axis=1)
    assert err.max() <= 3 * np.sqrt(3) * noise + 1e-9


@given(st.integers(0, 10_000), st.integers(0, 3), st.permutations(range(4)))
@settings(max_examples=300, deadline=None)
@example(263, 0, [0, 1, 2, 3])  # the outlier completes a triangle within eps by chance
@example(8510, 2, [0, 1, 2, 3])  # ... and fits as well as the true triple: ambiguous
def test_one_gross_outlier_is_dropped(seed, bad, order):
    R, t, rng = rigid(seed)
    measured = MARKS @ R.T + t + rng.normal(0, 0.03, (4, 3))
    direction = rng.normal(size=3)
    measured[bad] += 15.0 * direction / np.linalg.norm(direction)  # a grossly wrong point
    q = measured[list(order)]
    try:
        m = match_marks(MARKS, q, EPS, "arm")
    except MeasurementError as exc:
        # rarely the wrong point completes another triangle of marks within eps and fits as
        # well as the true one: both "one point is wrong" readings hold, and the only right
        # answer is to refuse; check that this is such a case (seed 8510, bad 2 is one)
        assert "cannot tell which point is wrong" in str(exc)
        wrong = order.index(bad)
        assert any(wrong in h for marks in itertools.combinations(range(4), 3)
                   for h in _passing(MARKS, q, marks, EPS))
        return
    assert m.dropped_mark == bad
    assert m.residual_rms_mm < 0.1


@given(st.integers(0, 10_000))
@settings(max_examples=40, deadline=None)
def test_reflection_is_never_returned(seed):
    R, t, rng = rigid(seed)
    mirrored = (MARKS * [1, 1, -1]) @ R.T + t  # a mirror image of the marks
    R_fit, _, _ = fit_pose(MARKS, mirrored)
    assert np.linalg.det(R_fit) == pytest.approx(1.0)


def test_unmatched_marks_raise_naming_the_part():
    R, t, _ = rigid(1)
    measured = MARKS @ R.T + t
    measured[0] += [20, 0, 0]
    measured[1] += [0, 20, 0]  # two bad points: nothing can be matched
    with pytest.raises(MeasurementError, match="part 'knuckle'.*no ordering"):
        match_marks(MARKS, measured, EPS, "knuckle")


def test_symmetric_marks_are_ambiguous():
    square = np.array([[0, 0, 0], [100, 0, 0], [100, 100, 0], [0, 100, 0.0]])
    assert mark_layout_warnings(square, EPS, "plate")
    with pytest.raises(MeasurementError, match="part 'plate'.*ambiguous"):
        match_marks(square, square + 1.0, EPS, "plate")
    assert not mark_layout_warnings(MARKS, EPS)


@given(st.integers(0, 10_000))
@settings(max_examples=50, deadline=None)
def test_bushing_frame_on_part1_has_zero_torsion(seed):
    rng = np.random.default_rng(seed)
    w = rng.normal(size=3)
    v2 = rng.normal(size=3)
    assume(np.linalg.norm(np.cross(w, v2)) > 0.1 * np.linalg.norm(w) * np.linalg.norm(v2))
    B = zero_torsion_frame(w, v2)
    np.testing.assert_allclose(B.T @ B, np.eye(3), atol=1e-12)
    assert np.linalg.det(B) == pytest.approx(1.0)
    np.testing.assert_allclose(B[:, 2], w / np.linalg.norm(w), atol=1e-12)
    assert abs(B[:, 0] @ v2) < 1e-12  # u1 . v2* = 0 [17]


@given(st.floats(-179, 179), st.floats(1, 179), st.floats(-179, 179))
@settings(max_examples=60, deadline=None)
def test_euler_zxz_round_trip(psi, theta, phi):
    R = rotation_from_euler_zxz_deg([psi, theta, phi])
    np.testing.assert_allclose(euler_zxz_deg(R), [psi, theta, phi], atol=1e-8)


def test_paper_bushing_angles_round_trip():
    angles = [129.5, 90.22, 166.7]  # J1, Table 2
    np.testing.assert_allclose(euler_zxz_deg(rotation_from_euler_zxz_deg(angles)), angles)


def test_deflection_operator_single_angles():
    D = deflection_operator([1.0, 2.0, 3.0], [0.0, 0.0, 5.0])
    a = D[:3, :3]
    assert np.degrees(np.arctan2(a[1, 0], a[0, 0])) == pytest.approx(5.0)  # a21/a11 [25]
    D = deflection_operator([0, 0, 0], [4.0, 0.0, 0.0])
    a = D[:3, :3]
    assert np.degrees(np.arctan(-a[1, 2] / a[2, 2])) == pytest.approx(4.0)  # -a23/a33
    np.testing.assert_allclose(deflection_operator([1, 2, 3], [0, 0, 0])[:3, 3], [1, 2, 3])


@given(st.integers(0, 10_000))
@settings(max_examples=40, deadline=None)
def test_identified_frames_recover_a_known_shift(seed):
    rng = np.random.default_rng(seed)
    A1 = homogeneous(Rotation.random(random_state=rng).as_matrix(), rng.uniform(-500, 500, 3))
    A2 = homogeneous(Rotation.random(random_state=rng).as_matrix(), rng.uniform(-500, 500, 3))
    A3 = homogeneous(Rotation.random(random_state=rng).as_matrix(), rng.uniform(-500, 500, 3))
    B2 = homogeneous(Rotation.random(random_state=rng).as_matrix(), rng.uniform(-50, 50, 3))
    shift = rng.uniform(-1, 1, 3)
    rot = rng.uniform(-2, 2, 3)
    D = deflection_operator(shift, rot)
    # truth: part 1's inner-sleeve frame is part 2's sleeve frame moved by the deflection
    B1_true = np.linalg.inv(A1) @ A2 @ B2 @ D
    np.testing.assert_allclose(identified_bushing_frame(A1, A2, B2, D), B1_true, atol=1e-12)
    centre_global = A1 @ B1_true[:, 3]
    np.testing.assert_allclose(centre_global[:3], (A2 @ B2 @ D)[:3, 3], atol=1e-9)
    S2 = rng.uniform(-50, 50, 3)
    S3 = identified_spherical_centre(A3, A2, S2)
    np.testing.assert_allclose((A3 @ np.append(S3, 1))[:3], (A2 @ np.append(S2, 1))[:3],
                               atol=1e-9)
