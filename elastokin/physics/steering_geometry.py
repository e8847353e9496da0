"""Wheel and steering-axis characteristics (pure numpy; ISO 8855 / SAE J670 names).

Like :mod:`elastokin.physics.wheel`, every function takes vectors in one frame (the config frame)
together with the unit vectors ``forward``, ``outboard`` (away from the vehicle centreline on
this wheel's side) and ``up`` of that frame, so the same code serves ISO 8855 (x forward,
y left) and ADAMS/Car (x rearward, y right) frames and both sides of the car. Points in mm,
angles in deg. Vector arguments may be single vectors ``(3,)`` or stacks ``(..., 3)`` (one row
per rig step); results broadcast accordingly.

The steering axis is a line given by any point on it and its direction (either sense): from two
points (:func:`axis_from_points`, e.g. the strut top mount and the lower ball joint) or, in
general, as the instantaneous screw axis of the knuckle under a small steer input
(:func:`screw_axis_from_poses`, the "instant axis" method). The ground plane is the plane
through the wheel's contact point normal to ``up``; the wheel/ground line runs through the
contact point along the wheel's heading.

Sign conventions (per wheel, as a K&C rig reports them; angles in the vehicle's planes, ground
offsets along the wheel/ground line and normal to it, as ADAMS/Car's suspension
characteristics):

==============================  ====  =============================================================
characteristic                  unit  positive when
==============================  ====  =============================================================
toe (:mod:`~.geometry`)         deg   toe-in: the front of the wheel turned towards the centreline
camber (:mod:`~.geometry`)      deg   the top of the wheel leans outboard
caster angle                    deg   the steering axis top leans rearward (side view, vehicle
                                      forward-up plane)
kingpin inclination             deg   the steering axis top leans inboard (front view, vehicle
                                      outboard-up plane)
scrub radius                    mm    the steering axis meets the ground inboard of the contact
                                      point (distance normal to the wheel/ground line)
caster trail (mech. trail)      mm    the steering axis meets the ground ahead of the contact
                                      point (distance along the wheel/ground line)
wheel-centre displacement       mm    longitudinal forward, lateral outboard, vertical up (bump)
track change (per wheel)        mm    the contact point moves outboard
screw axis angle / translation  deg,  right-handed rotation about / translation along the
                                mm    axis direction
==============================  ====  =============================================================

Gradients (:func:`gradient`) are least-squares slopes over a window (bump steer deg/m, compliance
steer deg/kN: pass ``scale=1000``); :func:`compliance_matrix` is the linearised wheel-centre
compliance by central differences.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from elastokin.physics.wheel import slope

__all__ = [
    "ScrewAxis",
    "axis_from_points",
    "axis_ground_point",
    "caster_deg",
    "caster_trail_mm",
    "compliance_matrix",
    "contact_point",
    "gradient",
    "kingpin_inclination_deg",
    "screw_axis",
    "screw_axis_from_poses",
    "scrub_radius_mm",
    "track_change_mm",
    "wheel_centre_displacement",
    "wheel_ground_directions",
]

#: rotations smaller than this (rad) are treated as pure translations by :func:`screw_axis`
MIN_SCREW_ANGLE_RAD = 1e-12


def _vec(v) -> np.ndarray:
    return np.asarray(v, dtype=float)


def _dot(a, b) -> np.ndarray:
    return np.sum(_vec(a) * _vec(b), axis=-1)


def _unit(v, what: str) -> np.ndarray:
    v = _vec(v)
    n = np.linalg.norm(v, axis=-1, keepdims=True)
    if np.any(n < 1e-12):
        raise ValueError(f"{what} has zero length")
    return v / n


# ------------------------------------------------------------------------------- screw axis


@dataclass(frozen=True)
class ScrewAxis:
    """A finite helical (screw) motion: rotate by ``angle_deg`` about the line through ``point``
    along ``direction`` (right-handed), and translate ``translation_mm`` along ``direction``.

    ``direction`` is a unit vector; ``point`` (mm) is the point of the axis closest to the
    reference point given to :func:`screw_axis` (the origin by default).
    """

    direction: np.ndarray
    point: np.ndarray
    angle_deg: float
    translation_mm: float


def _check_rotation(R) -> np.ndarray:
    R = _vec(R)
    if R.shape != (3, 3) or not np.all(np.isfinite(R)):
        raise ValueError(f"a rotation must be a finite 3x3 matrix, got shape {R.shape}")
    if np.max(np.abs(R.T @ R - np.eye(3))) > 1e-6 or np.linalg.det(R) < 0:
        raise ValueError("the matrix is not a proper rotation (R^T R = I, det R = +1 to 1e-6)")
    return R


def screw_axis(R, t, orient=None, near=None) -> ScrewAxis:
    """Screw axis of the rigid motion ``x -> R x + t`` (Chasles' theorem).

    Parameters
    ----------
    R : (3, 3) rotation matrix; t : (3,) translation [mm].
    orient : (3,), optional. Flip the axis (and the signs of angle and translation) so that
        ``direction . orient > 0``; e.g. ``up`` for a steering axis.
    near : (3,) [mm], optional. Return the point of the axis closest to it (default origin).

    Raises ``ValueError`` for a pure translation (no rotation: the axis has no position).
    """
    R = _check_rotation(R)
    t = _vec(t).reshape(3)
    # rotation vector, robust for small angles and near 180 deg (scipy uses quaternions)
    from scipy.spatial.transform import Rotation

    rotvec = Rotation.from_matrix(R).as_rotvec()
    angle = float(np.linalg.norm(rotvec))
    if angle < MIN_SCREW_ANGLE_RAD:
        raise ValueError(f"the motion is a pure translation (rotation {np.degrees(angle):.3g} "
                         "deg): its screw axis has no position")
    n = rotvec / angle
    if orient is not None and n @ _vec(orient) < 0:
        n, angle = -n, -angle
    d = float(n @ t)
    # the axis point p normal to n solves (I - R) p = t - d n; (I - R) is singular along n,
    # so add the row n . p = 0 and solve by least squares
    A = np.vstack([np.eye(3) - R, n[None, :]])
    b = np.r_[t - d * n, 0.0]
    p = np.linalg.lstsq(A, b, rcond=None)[0]
    if near is not None:
        p = p + ((_vec(near) - p) @ n) * n
    return ScrewAxis(n, p, float(np.degrees(angle)), d)


def screw_axis_from_poses(R1, t1, R2, t2, orient=None, near=None) -> ScrewAxis:
    """Screw axis of a body's motion from pose 1 to pose 2.

    A pose ``(R, t)`` maps body coordinates to the frame: ``x = R x_body + t`` (as
    :func:`elastokin.physics.pose.fit_pose` returns). The relative motion is ``R = R2 R1^T``,
    ``t = t2 - R t1``. For the steering axis, take the knuckle's poses before and after a small
    steer input with ``orient=up``; ``orient`` and ``near`` as in :func:`screw_axis`.
    """
    R1, R2 = _check_rotation(R1), _check_rotation(R2)
    R = R2 @ R1.T
    return screw_axis(R, _vec(t2).reshape(3) - R @ _vec(t1).reshape(3), orient, near)


def axis_from_points(p1, p2) -> tuple[np.ndarray, np.ndarray]:
    """An axis through two points [mm]: ``(p1, unit direction from p1 to p2)``.

    For a steering axis pass e.g. the lower ball joint and the strut top mount.
    """
    p1 = _vec(p1)
    return p1, _unit(_vec(p2) - p1, "the axis between the two points")


# --------------------------------------------------------------------- steering-axis angles


def _upward(axis_direction, up) -> np.ndarray:
    d = _unit(axis_direction, "the steering axis direction")
    du = _dot(d, up)[..., None]
    if np.any(np.abs(du) < 1e-9):
        raise ValueError("the steering axis is horizontal: caster, kingpin inclination and "
                         "its ground point are undefined")
    return np.where(du < 0, -d, d)


def caster_deg(axis_direction, forward, up) -> np.ndarray:
    """Caster angle [deg]: steering-axis inclination from ``up`` in side view (the vehicle's
    forward-up plane), positive when the top of the axis leans rearward. Either sense of
    ``axis_direction`` gives the same value."""
    d = _upward(axis_direction, up)
    return np.degrees(np.arctan2(-_dot(d, forward), _dot(d, up)))


def kingpin_inclination_deg(axis_direction, outboard, up) -> np.ndarray:
    """Kingpin (steering-axis) inclination [deg] from ``up`` in front view (the vehicle's
    outboard-up plane), positive when the top of the axis leans inboard."""
    d = _upward(axis_direction, up)
    return np.degrees(np.arctan2(-_dot(d, outboard), _dot(d, up)))


def axis_ground_point(axis_point, axis_direction, ground_point, up) -> np.ndarray:
    """Where the axis meets the ground plane (through ``ground_point``, normal to ``up``) [mm]."""
    p = _vec(axis_point)
    d = _upward(axis_direction, up)
    s = _dot(_vec(ground_point) - p, up) / _dot(d, up)
    return p + s[..., None] * d


# ------------------------------------------------------------------------ wheel on the ground


def contact_point(centre, spin_axis, loaded_radius_mm, up) -> np.ndarray:
    """Contact point [mm]: ``loaded_radius_mm`` from the wheel centre, straight down within the
    wheel plane (normal to ``spin_axis``), as :class:`elastokin.config.Wheel` defines it."""
    a = _unit(spin_axis, "the spin axis")
    down = -_vec(up)
    radial = down - _dot(down, a)[..., None] * a
    radial = _unit(radial, "the wheel plane's downward direction (spin axis vertical)")
    return _vec(centre) + np.asarray(loaded_radius_mm, float)[..., None] * radial


def wheel_ground_directions(spin_axis, forward, outboard, up) -> tuple[np.ndarray, np.ndarray]:
    """Unit ``(heading, lateral)`` of the wheel on the ground plane.

    ``lateral`` is the spin axis projected on the ground, pointing outboard; ``heading`` is the
    wheel/ground line (normal to ``lateral`` and ``up``), pointing forward. With zero toe they
    are ``forward`` and ``outboard``; toe rotates both about ``up``.
    """
    a = _vec(spin_axis)
    lateral = a - _dot(a, up)[..., None] * _vec(up)
    lateral = _unit(lateral, "the spin axis' ground projection (spin axis vertical)")
    lateral = np.where(_dot(lateral, outboard)[..., None] < 0, -lateral, lateral)
    # the sign of forward x outboard . up says which side of the car (and frame handedness)
    hand = np.sign(np.cross(_vec(forward), _vec(outboard)) @ _vec(up))
    heading = hand * np.cross(lateral, _vec(up))
    return heading, lateral


def _ground_offset(axis_point, axis_direction, contact, spin_axis, forward, outboard, up):
    g = axis_ground_point(axis_point, axis_direction, contact, up)
    heading, lateral = wheel_ground_directions(spin_axis, forward, outboard, up)
    r = g - _vec(contact)
    return _dot(r, heading), _dot(r, lateral)


def scrub_radius_mm(axis_point, axis_direction, contact, spin_axis, forward, outboard,
                    up) -> np.ndarray:
    """Scrub radius (kingpin offset at ground) [mm]: distance from the contact point to the
    steering axis' ground point along the wheel's ``lateral`` ground direction (normal to the
    wheel/ground line), positive when the axis meets the ground **inboard** of the contact
    point."""
    return -_ground_offset(axis_point, axis_direction, contact, spin_axis, forward, outboard,
                           up)[1]


def caster_trail_mm(axis_point, axis_direction, contact, spin_axis, forward, outboard,
                    up) -> np.ndarray:
    """Caster (mechanical) trail [mm]: distance from the contact point to the steering axis'
    ground point along the wheel/ground line, positive when the axis meets the ground **ahead**
    of the contact point."""
    return _ground_offset(axis_point, axis_direction, contact, spin_axis, forward, outboard,
                          up)[0]


# ------------------------------------------------------------------------------ displacements


def wheel_centre_displacement(centre, centre0, forward, outboard, up) -> np.ndarray:
    """Wheel-centre displacement from ``centre0`` [mm], ``(..., 3)``: columns longitudinal
    (forward +), lateral (outboard +), vertical (up +, i.e. wheel travel, bump +)."""
    d = _vec(centre) - _vec(centre0)
    return np.stack([_dot(d, forward), _dot(d, outboard), _dot(d, up)], axis=-1)


def track_change_mm(contact, contact0, outboard) -> np.ndarray:
    """Track change per wheel [mm]: lateral displacement of the contact point from
    ``contact0``, positive outboard (the axle's track change is the sum of both wheels')."""
    return _dot(_vec(contact) - _vec(contact0), outboard)


# ----------------------------------------------------------------------------------- gradients


def gradient(x, y, window=None, scale: float = 1.0) -> float:
    """Least-squares slope ``scale * dy/dx`` over the points with ``window[0] <= x <=
    window[1]`` (all points if ``window`` is None); NaN, with an
    :class:`~elastokin.physics.wheel.UndeterminedSlopeWarning`, with fewer than three distinct
    x values there (:func:`elastokin.physics.wheel.slope`).

    Loading and unloading branches inside the window are fitted together (the slope of their
    mean). ``scale`` converts units: bump steer deg/m from toe [deg] against travel [mm] and
    compliance steer deg/kN from toe against force [N] both take ``scale=1000``.
    """
    return scale * slope(x, y, window, what="gradient")


def compliance_matrix(f: Callable[[np.ndarray], np.ndarray], steps, load0=None) -> np.ndarray:
    """Compliance matrix ``C[i, j] = d f_i / d load_j`` by central differences.

    ``f`` maps a load vector to a displacement vector; for the wheel centre the load is
    ``(Fx, Fy, Fz [N], Mx, My, Mz [N*mm])`` and the displacement ``(x, y, z [mm], rx, ry,
    rz [deg])``, both in the frame ``f`` uses, so ``C`` is 6x6 with blocks mm/N, mm/(N*mm),
    deg/N and deg/(N*mm) (times 1000 for per kN or per N*m). ``steps`` is the load increment
    per input (scalar or one per input, > 0), ``load0`` the linearisation point (default
    zero). Exact (to rounding) when ``f`` is linear or quadratic; error O(step^2) otherwise.
    """
    h = _vec(steps)
    x0 = np.zeros(6 if h.ndim == 0 else h.size) if load0 is None else _vec(load0).ravel()
    h = np.broadcast_to(h, x0.shape) if h.ndim == 0 else h.ravel()
    if h.shape != x0.shape:
        raise ValueError(f"steps has {h.size} entries for {x0.size} inputs")
    if not np.all(np.isfinite(h) & (h > 0)):
        raise ValueError(f"every step must be finite and > 0, got {h.tolist()}")
    columns = []
    for j in range(x0.size):
        e = np.zeros_like(x0)
        e[j] = h[j]
        plus, minus = (np.asarray(f(x0 + s * e), float).ravel() for s in (1.0, -1.0))
        if plus.shape != minus.shape or not (np.all(np.isfinite(plus))
                                             and np.all(np.isfinite(minus))):
            raise ValueError(f"f returned non-finite or inconsistent output for input {j}")
        columns.append((plus - minus) / (2.0 * h[j]))
    return np.column_stack(columns)
