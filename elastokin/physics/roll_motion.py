"""The roll motion of an axle at every rig step, at the velocity level (pure numpy): the
contact points' velocities when the left contact point rises at unit rate and the right one
falls at unit rate, with every joint of the skeleton held (bushings frozen at their
deflection, :mod:`elastokin.physics.skeleton`). The kinematic roll centre of a dependent axle
(a solid axle: one part carries both wheels, so parallel travel only heaves it) is the
instant centre of this motion (docs/characteristics.md, "Dependent axles").

Units: mm, rad inside; the config frame. Velocities are per unit of the contact points'
vertical rate (mm/mm).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from elastokin.physics.skeleton import (
    LENGTH_SCALE,
    SkeletonElement,
    SkeletonSteps,
    constraint_rows,
    cross_rows,
)

__all__ = ["RollMotion", "roll_motion"]

#: relative singular-value threshold for the rank of the stacked rows
RANK_TOLERANCE = 1e-9
#: the pads' rates must be met to this (mm/mm): else the joints do not let the axle roll
CONSISTENCY_TOLERANCE = 1e-6
#: a null motion of the stacked rows moving a wheel part more than this is a free motion
ONE_MOTION_TOLERANCE = 1e-6


@dataclass
class RollMotion:
    """Per step (S rows), each wheel's contact-point velocity (S, 3) by side (config frame,
    per unit vertical rate of the contact points: +1 left, -1 right), NaN where undefined;
    ``reason`` says why (None when every step has one)."""

    contact_velocity: dict[str, np.ndarray]
    reason: str | None


def _pad_row(steps: SkeletonSteps, part: str, point: np.ndarray, up: np.ndarray) -> np.ndarray:
    """up . v(point) of ``part`` at every step, a (S, N) row."""
    return steps.translation_row((steps.ground, part), (point, point),
                                 np.broadcast_to(up, point.shape))


def roll_motion(ground: str, elements: list[SkeletonElement],
                rotation: dict[str, np.ndarray], position: dict[str, np.ndarray],
                reference: dict[str, np.ndarray], wheels: dict[str, tuple[str, np.ndarray]],
                up: np.ndarray) -> RollMotion:
    """The contact points' velocities in roll (module docstring) at S steps.

    elements: the skeleton's constraints (joints, bushings as ideal joints, links; no
    spring); rotation[part] (S, 3, 3), position[part] (S, 3) mm: every moving part's pose
    (its reference point ``reference[part]`` now at ``position``); wheels: by side
    (``left``, ``right``), the wheel part and its contact point (S, 3) mm; up: unit (3,).
    The motion is the least-norm solution of the joints' velocity constraints with the two
    contact points' vertical rates prescribed; where the joints do not let the contact
    points move so, or leave a wheel part's motion undetermined, the step is NaN.
    """
    parts = sorted(rotation)
    n = len(next(iter(wheels.values()))[1])
    col = {p: 6 * i for i, p in enumerate(parts)}
    steps = SkeletonSteps(ground, rotation, position, reference, n, col, 6 * len(parts),
                          np.broadcast_to(np.eye(3), (n, 3, 3)))
    rows = constraint_rows(steps, elements)[0]
    pads = [_pad_row(steps, part, point, up) for part, point in
            (wheels["left"], wheels["right"])]
    M = np.stack(rows + pads, axis=1)  # (S, m + 2, N)
    b = np.zeros(M.shape[1])
    b[-2:] = (1.0, -1.0)
    U, sv, Vt = np.linalg.svd(M, full_matrices=True)
    rank = np.sum(sv > RANK_TOLERANCE * sv[:, :1], axis=1)
    inv = np.where(np.arange(sv.shape[1]) < rank[:, None], 1.0 / np.where(sv > 0, sv, 1.0),
                   0.0)
    r = sv.shape[1]
    x = np.einsum("sji,sj->si", Vt[:, :r, :], inv * np.einsum("skj,k->sj", U[:, :, :r], b))
    ok = np.max(np.abs(M @ x[:, :, None] - b[None, :, None])[..., 0], axis=1) \
        < CONSISTENCY_TOLERANCE
    reason = None if np.all(ok) else "the joints do not let the axle roll (the contact " \
        "points cannot move in opposite directions)"
    wheel_cols = np.concatenate([np.arange(col[part], col[part] + 6)
                                 for part, _ in wheels.values()])
    # the null space: the rows of Vt from the rank on; a null motion that moves a wheel part
    null = np.arange(Vt.shape[1])[None, :] >= rank[:, None]
    free = np.any(null & (np.max(np.abs(Vt[:, :, wheel_cols]), axis=2) > ONE_MOTION_TOLERANCE),
                  axis=1)
    if np.any(free):
        ok &= ~free
        reason = reason or ("the joints leave a wheel part more than the two motions the "
                            "contact points fix (a joint missing?)")
    out = {}
    for side, (part, point) in wheels.items():
        k = col[part]
        omega, v = x[:, k:k + 3] / LENGTH_SCALE, x[:, k + 3:k + 6]
        vel = v + cross_rows(omega, point - position[part])
        vel[~ok] = np.nan
        out[side] = vel
    return RollMotion(out, reason)
