"""Functional joint methods: where a joint is, from the relative motion of the two bodies it
joins (biomechanics' answer to locating a joint without taking it apart). Pure numpy/scipy.

Every function takes each body's pose at the P measured positions, ``R`` (P, 3, 3) and ``t``
(P, 3), mapping the body's local frame to the vehicle frame (mm), and returns local
coordinates; :func:`world_point` and :func:`world_axis` carry them to one position.

- :func:`score`: a ball joint's centre, SCoRE (Ehrig et al. 2006, J. Biomech. 39:2798): the
  point fixed in both bodies, ``R_a,k c_a + t_a,k = R_b,k c_b + t_b,k`` for every k, as one
  linear least-squares problem ``[R_a,k  -R_b,k] [c_a; c_b] = t_b,k - t_a,k``;
- :func:`sara`: a hinge axis, SARA (Ehrig et al. 2007, J. Biomech. 40:2150): the same matrix
  has a null direction along a hinge's axis; the axis is its smallest right singular vector
  and a point on it the solution without that direction; ``slide=True`` for a cylindrical
  joint (the bodies also slide along the axis: the residual along the axis is left out);
- :func:`rack_score`: a ball joint on the steering rack, which slides relative to the
  ground by the rig's stated travel s_k (a tie rod's inner end): ``R_k c + t_k = c_0 + s_k
  v``, linear, the rack's axis v fitted with the rack.

Their error behaviour (Woltring et al. 1985, J. Biomech. 18:379): the centre is uncertain
along the direction about which the bodies do not turn relative to each other; the smallest
singular value measures it (:func:`weak_direction`).
"""

from __future__ import annotations

import numpy as np
from scipy.spatial.transform import Rotation


def _system(Ra, ta, Rb, tb) -> tuple[np.ndarray, np.ndarray]:
    """SCoRE's stacked matrix (3P, 6) and right-hand side (3P,)."""
    A = np.concatenate([np.asarray(Ra, float), -np.asarray(Rb, float)], axis=2)
    return A.reshape(-1, 6), (np.asarray(tb, float) - np.asarray(ta, float)).reshape(-1)


def score(Ra, ta, Rb, tb) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """SCoRE: the ball-joint centre in body a's (c_a) and body b's (c_b) frame, and the
    singular values of the stacked matrix (largest first; the smallest tells how well the
    motion locates the centre)."""
    A, y = _system(Ra, ta, Rb, tb)
    u, s, vt = np.linalg.svd(A, full_matrices=False)
    x = vt.T @ ((u.T @ y) / s)
    return x[:3], x[3:], s


def sara(Ra, ta, Rb, tb, slide: bool = False, hint=None
         ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """SARA: a hinge (``slide``: a cylindrical joint) between bodies a and b. Returns a point
    on the axis in a's frame and in b's (the minimum-norm one), the axis in a's frame (unit;
    oriented along ``hint``, a vector in a's frame, when given) and the singular values of
    the stacked matrix."""
    Ra, Rb = np.asarray(Ra, float), np.asarray(Rb, float)
    A, y = _system(Ra, ta, Rb, tb)
    _, s, vt = np.linalg.svd(A, full_matrices=False)
    axis = vt[5, :3] / np.linalg.norm(vt[5, :3])
    if hint is not None and axis @ np.asarray(hint, float) < 0:
        axis = -axis
    if slide:  # leave out each position's residual along the axis (the slide)
        m = Ra @ axis  # (P, 3): the axis in the vehicle frame at every position
        proj = np.eye(3) - m[:, :, None] * m[:, None, :]
        A = (proj @ A.reshape(-1, 3, 6)).reshape(-1, 6)
        y = (proj @ y.reshape(-1, 3, 1)).reshape(-1)
    u, sp, vtp = np.linalg.svd(A, full_matrices=False)
    x = vtp[:5].T @ ((u[:, :5].T @ y) / sp[:5])  # without the axis's null direction
    return x[:3], x[3:], axis, s


def rack_score(R, t, travel_mm) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """A ball joint between a body (poses R, t) and the steering rack, which slides relative
    to the ground by the rig's stated travel s_k along an axis: the body's point c (its
    frame) is at ``c_0 + s_k v`` (vehicle frame) at every position, ``R_k c + t_k = c_0 +
    s_k v``: linear in c, c_0 and v, the rack's axis times the ratio of its true to its stated
    travel (|v| = 1 for a calibrated rack). Without travel, SCoRE against the ground. Returns
    c, c_0, v and the singular values."""
    R, t = np.asarray(R, float), np.asarray(t, float)
    s_k = np.asarray(travel_mm, float)
    eye = np.tile(np.eye(3), (len(t), 1, 1))
    blocks = [R, -eye] + ([-s_k[:, None, None] * eye] if np.any(s_k) else [])
    A = np.concatenate(blocks, axis=2).reshape(3 * len(t), -1)
    u, sv, vt = np.linalg.svd(A, full_matrices=False)
    x = vt.T @ ((u.T @ -t.reshape(-1)) / sv)
    v = x[6:] if np.any(s_k) else np.zeros(3)
    return x[:3], x[3:6], v, sv


def world_point(R, t, local, position: int) -> np.ndarray:
    """A body's point (its frame) in the vehicle frame at ``position``."""
    return np.asarray(R, float)[position] @ np.asarray(local, float) + np.asarray(t)[position]


def world_axis(R, local_axis, position: int) -> np.ndarray:
    """A body's direction (its frame) in the vehicle frame at ``position`` (unit)."""
    v = np.asarray(R, float)[position] @ np.asarray(local_axis, float)
    return v / np.linalg.norm(v)


def relative_rotations(Ra, Rb, reference: int) -> np.ndarray:
    """The rotation of body b relative to body a at every position, from ``reference``, as
    rotation vectors (rad) in the vehicle frame at the reference position (P, 3)."""
    Ra, Rb = np.asarray(Ra, float), np.asarray(Rb, float)
    rel = np.swapaxes(Ra, 1, 2) @ Rb  # b in a's frame
    delta = rel @ rel[reference].T  # from the reference position, a's frame
    return Rotation.from_matrix(delta).as_rotvec() @ Ra[reference].T


def weak_direction(Ra, ta, Rb, tb, reference: int) -> tuple[np.ndarray, float]:
    """The direction (vehicle frame, at ``reference``) along which the motion locates a ball
    joint worst, and the condition number of SCoRE's matrix (largest over smallest singular
    value)."""
    A, _ = _system(Ra, ta, Rb, tb)
    _, s, vt = np.linalg.svd(A, full_matrices=False)
    d = np.asarray(Ra, float)[reference] @ vt[5, :3] + np.asarray(Rb, float)[reference] @ \
        vt[5, 3:]
    norm = np.linalg.norm(d)
    d = d / norm if norm > 1e-12 else np.asarray(Ra, float)[reference] @ vt[5, :3] / \
        np.linalg.norm(vt[5, :3])
    return d, float(s[0] / s[5]) if s[5] > 0 else float("inf")
