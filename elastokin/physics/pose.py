"""Part poses and joint frames from CMM marks: the reference paper's identification geometry.
Numbers in brackets are the equation numbers of the paper itself (Meissonnier et al., Proc.
IMechE Part D 220, 2006; in the text extracted from its PDF the label "(20)" is out of place:
by the order of the equations (20) is the z-x-z Euler angles and (21) the terms a_ij they are
computed from). Pure numpy: points in mm, angles in deg, rotations as 3x3 matrices mapping a
part's local frame to the measurement frame.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass, field

import numpy as np
from scipy.spatial.transform import Rotation

from elastokin.errors import MeasurementError

#: mark-matching tolerance for a CMM of 0.1 mm volumetric accuracy (the paper's eps)
DEFAULT_EPS_MM = 0.4


def clearance_bound_mm(hole_diameter_mm: float, bolt_diameter_mm: float,
                       inner_sleeve_diameter_mm: float) -> float:
    """dL_max = phi_out/2 - phi_bolt + phi_in/2 [1]: how far a bolted joint centre may sit from
    the housing centre measured on the part alone."""
    return hole_diameter_mm / 2.0 - bolt_diameter_mm + inner_sleeve_diameter_mm / 2.0


def fit_pose(local_pts, global_pts) -> tuple[np.ndarray, np.ndarray, float]:
    """Rigid transform (R, t) minimising sum |R p_i + t - q_i|^2 [11-12], closed form by SVD
    (Arun, Huang, Blostein 1987) with the reflection guard. Returns R, t and the residual RMS
    (mm). Needs at least 3 non-collinear points."""
    p = np.asarray(local_pts, float)
    q = np.asarray(global_pts, float)
    if p.shape != q.shape or p.ndim != 2 or p.shape[1] != 3 or p.shape[0] < 3:
        raise MeasurementError(f"a pose needs >= 3 matching points, got {p.shape} and {q.shape}")
    sv = np.linalg.svd(p - p.mean(axis=0), compute_uv=False)
    if sv[1] < 1e-6 * max(sv[0], 1e-12):
        raise MeasurementError("the marks are collinear: a pose is undefined")
    R, t, rms = fit_poses(p, q)
    return R, t, float(rms)


def fit_poses(local_pts, global_pts, weights=None) -> tuple[np.ndarray, np.ndarray,
                                                              np.ndarray]:
    """:func:`fit_pose` for stacks of point sets: ``local_pts`` and ``global_pts`` of shape
    (..., n, 3) (``local_pts`` may lack the leading dimensions: one template for every set),
    ``weights`` (..., n) with 0 for a point left out (its coordinates may then be NaN).
    Returns R (..., 3, 3), t (..., 3) and the residual RMS over the points kept (mm); no
    check of the layout (see :func:`fit_pose`)."""
    q = np.asarray(global_pts, float)
    p = np.broadcast_to(np.asarray(local_pts, float), q.shape)
    w = np.ones(q.shape[:-1]) if weights is None else np.asarray(weights, float)
    keep = w[..., None] > 0
    p, q = np.where(keep, p, 0.0), np.where(keep, q, 0.0)
    n = w.sum(axis=-1)[..., None]
    pc = np.einsum("...k,...ki->...i", w, p) / n
    qc = np.einsum("...k,...ki->...i", w, q) / n
    u, _, vt = np.linalg.svd(np.einsum("...k,...ki,...kj->...ij", w, p - pc[..., None, :],
                                       q - qc[..., None, :]))
    v = np.swapaxes(vt, -1, -2)
    d = np.sign(np.linalg.det(v @ np.swapaxes(u, -1, -2)))
    v[..., :, 2] *= d[..., None]  # reflection guard: det R = +1
    R = v @ np.swapaxes(u, -1, -2)
    t = qc - np.einsum("...ij,...j->...i", R, pc)
    residual = q - (np.einsum("...ij,...kj->...ki", R, p) + t[..., None, :])
    rms = np.sqrt(np.einsum("...k,...ki,...ki->...", w, residual, residual) / n[..., 0])
    return R, t, rms


def pose_error_gain(marks, points, step_mm: float = 1e-3) -> float:
    """How much the pose fit [11-12] amplifies measurement noise on ``marks`` at ``points``:
    the largest 3-D RMS position error of a point per unit 3-D RMS (isotropic) noise on the
    marks, from the linearised fit (finite differences). About 1/sqrt(n) at the centroid of n
    marks; large when the points lie far from a thin or small mark layout."""
    m = np.asarray(marks, float)
    x = np.atleast_2d(np.asarray(points, float))
    jac = np.empty((x.shape[0], 3, m.size))
    for k in range(m.size):
        q = m.copy().ravel()
        q[k] += step_mm
        R, t, _ = fit_pose(m, q.reshape(m.shape))
        jac[:, :, k] = (x @ R.T + t - x) / step_mm
    return float(np.max(np.sqrt(np.sum(jac**2, axis=(1, 2)) / 3.0)))


def _distances(x: np.ndarray) -> np.ndarray:
    return np.linalg.norm(x[:, None, :] - x[None, :, :], axis=2)


def mark_layout_warnings(local_marks, eps_mm: float = DEFAULT_EPS_MM,
                         part: str = "part") -> list[str]:
    """Warnings when a part's marks break [2]: the pairwise distances must differ by more than
    2 eps, or the assembled marks cannot be ordered reliably."""
    m = np.asarray(local_marks, float)
    d = _distances(m)[np.triu_indices(len(m), 1)]
    gaps = np.abs(d[:, None] - d[None, :])[np.triu_indices(d.size, 1)]
    if gaps.size and gaps.min() <= 2 * eps_mm:
        return [f"part '{part}': two mark distances differ by only {gaps.min():.3f} mm "
                f"(<= 2 eps = {2 * eps_mm:g} mm): mark order may be ambiguous"]
    return []


@dataclass
class MarkMatch:
    """The marks of one part found in the assembly.

    order[i]: index of the measured point matching local mark i (None for a dropped mark);
    dropped_mark: the local mark left out (None when all 4 matched);
    R, t: part pose, local -> measurement frame; residual_rms_mm: fit residual;
    local_mm: the 4 local marks (part frame); measured_mm: the assembled point matched to each
    (measurement frame; NaN for the dropped mark).
    """

    order: list[int | None]
    dropped_mark: int | None
    R: np.ndarray
    t: np.ndarray
    residual_rms_mm: float
    warnings: list[str] = field(default_factory=list)
    local_mm: np.ndarray | None = None
    measured_mm: np.ndarray | None = None


def _passing(local: np.ndarray, measured: np.ndarray, marks: tuple[int, ...], eps: float):
    """Assignments of ``marks`` (local indices) to distinct measured points whose distance
    matrices agree within eps [8-9]."""
    dl = _distances(local[list(marks)])
    out = []
    for perm in itertools.permutations(range(len(measured)), len(marks)):
        dq = _distances(measured[list(perm)])
        if np.max(np.abs(dl - dq)) <= eps:
            out.append(perm)
    return out


def match_marks(local_marks, measured, eps_mm: float = DEFAULT_EPS_MM,
                part: str = "part") -> MarkMatch:
    """Order the unordered assembled marks of a part and fit its pose [8-12].

    All 4 marks are tried first (the 24 permutations); when none passes, one point is wrong:
    each set of 3 local marks is tried against the measured points (the paper's text after
    (10): the wrong point is left out and the rest computed with three) and the passing
    assignment kept (its left-out mark reported); when several pass, the one whose pose fit
    is at least twice as good as any other, else an error. Two passing orderings of all four
    marks are ambiguous and raise; nothing passing raises.
    """
    local = np.asarray(local_marks, float)
    q = np.asarray(measured, float)
    if local.shape != (4, 3):
        raise MeasurementError(f"part '{part}': expected 4 local marks, got {local.shape[0]}")
    if q.ndim != 2 or q.shape[1] != 3 or not 3 <= len(q) <= 4:
        raise MeasurementError(f"part '{part}': expected 3 or 4 assembled marks, "
                               f"got {len(q)}")
    warnings = mark_layout_warnings(local, eps_mm, part)
    dropped = None
    marks: tuple[int, ...] = (0, 1, 2, 3)
    hits = _passing(local, q, marks, eps_mm) if len(q) == 4 else []
    if not hits:
        passing = [(m, h) for m in itertools.combinations(range(4), 3)
                   for h in _passing(local, q, m, eps_mm)]
        if not passing:
            raise MeasurementError(
                f"part '{part}': the assembled marks match no ordering of its marks within "
                f"eps = {eps_mm:g} mm, even with one point dropped")
        # a wrong point may by chance complete a triangle within eps (2 distances only); the
        # true triple then still fits far better: keep it when its residual is less than half
        # the next one's, otherwise the data cannot tell which point is wrong
        scored = sorted(passing, key=lambda mh: fit_pose(local[list(mh[0])],
                                                         q[list(mh[1])])[2])
        if len(scored) > 1:
            best, second = (fit_pose(local[list(m)], q[list(h)])[2] for m, h in scored[:2])
            if not best < 0.5 * second:
                raise MeasurementError(
                    f"part '{part}': with one point dropped, {len(passing)} assignments of "
                    f"the marks pass the eps = {eps_mm:g} mm test and fit equally well: "
                    "cannot tell which point is wrong")
        marks, perm = scored[0]
        hits = [perm]
        dropped = next(i for i in range(4) if i not in marks)
    if len(hits) > 1:
        raise MeasurementError(f"part '{part}': {len(hits)} orderings of the marks pass the "
                               f"eps = {eps_mm:g} mm test: the marks are ambiguous [2]")
    perm = hits[0]
    R, t, rms = fit_pose(local[list(marks)], q[list(perm)])
    order: list[int | None] = [None] * 4
    for m, k in zip(marks, perm):
        order[m] = int(k)
    if rms > eps_mm:
        warnings.append(f"part '{part}': pose residual {rms:.3f} mm exceeds eps {eps_mm:g} mm")
    matched = np.array([q[k] if k is not None else np.full(3, np.nan) for k in order])
    return MarkMatch(order, dropped, R, t, rms, warnings, local, matched)


def zero_torsion_frame(housing_axis, v2_in_part1) -> np.ndarray:
    """Bushing frame on part 1 (columns u1, v1, w) [15-18]: w is the housing axis, and u1 is
    chosen so that u1 . v2* = 0 [18] (v2* part 2's v axis seen from part 1 [14]), i.e. zero
    torsion [17] about w at static equilibrium."""
    w = np.asarray(housing_axis, float)
    w = w / np.linalg.norm(w)
    u = np.cross(np.asarray(v2_in_part1, float), w)
    n = np.linalg.norm(u)
    if n < 1e-9:
        raise MeasurementError("the bushing's y axis on part 2 is parallel to the housing axis")
    u = u / n
    return np.column_stack([u, np.cross(w, u), w])


def frame_from_z(z) -> np.ndarray:
    """A right-handed frame (columns x, y, z) whose z column is the unit vector ``z``, x
    chosen normal to it (from the global x axis, or y when z is near x)."""
    z = np.asarray(z, float)
    helper = np.array([1.0, 0.0, 0.0]) if abs(z[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    x = helper - (helper @ z) * z
    x /= np.linalg.norm(x)
    return np.column_stack([x, np.cross(z, x), z])


def euler_zxz_deg(R) -> np.ndarray:
    """(psi, theta, phi), deg, with R = Rz(psi) Rx(theta) Rz(phi): the angles [20] from the
    terms a_ij of R [21]."""
    a = np.asarray(R, float)
    theta = np.arctan2(np.hypot(a[0, 2], a[1, 2]), a[2, 2])
    psi = np.arctan2(a[0, 2], -a[1, 2])
    phi = np.arctan2(a[2, 0], a[2, 1])
    return np.degrees([psi, theta, phi])


def rotation_from_euler_zxz_deg(angles) -> np.ndarray:
    """Inverse of :func:`euler_zxz_deg` (intrinsic z-x-z)."""
    return Rotation.from_euler("ZXZ", angles, degrees=True).as_matrix()


def homogeneous(R, p) -> np.ndarray:
    T = np.eye(4)
    T[:3, :3] = R
    T[:3, 3] = p
    return T


def deflection_operator(translation_mm, rotation_deg) -> np.ndarray:
    """D = [[Rd, d], [0, 1]] [24], Rd from the three projected angles [25]:
    -a23/a33 = tan dRx, a13/a33 = tan dRy, a21/a11 = tan dRz (a Tait-Bryan x-y-z rotation for
    small angles; exact for each angle alone)."""
    rx, ry, rz = np.radians(rotation_deg)
    Rd = Rotation.from_euler("xyz", [rx, ry, rz]).as_matrix()
    return homogeneous(Rd, translation_mm)


def identified_bushing_frame(A1, A2, B_part2, D) -> np.ndarray:
    """B*_{Rp1} = A1^-1 A2 B_{Rp2} D [26]: the inner-sleeve frame on part 1 (4x4)."""
    return np.linalg.inv(A1) @ A2 @ B_part2 @ D


def identified_spherical_centre(A3, A2, S_part2) -> np.ndarray:
    """S*_{Rp3} = A3^-1 A2 S_{Rp2} [27]: a spherical centre measured on part 2, in part 3."""
    s = np.append(np.asarray(S_part2, float), 1.0)
    return (np.linalg.inv(A3) @ A2 @ s)[:3]
