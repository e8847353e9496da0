"""The steering axis at every rig step: the instantaneous screw axis of the wheel part relative
to the ground part under a small steering input, springs locked (pure numpy, all steps at
once). The method, its cases and its cost are in docs/characteristics.md ("The steering axis");
the skeleton of a suspension (what is released, what is locked) is built by
:func:`elastokin.rig.steering.steering_skeleton`.

Units: mm, rad inside; the config frame. A twist is ``(omega, v)``: angular velocity (rad per
unit input) and the velocity (mm per unit input) of the part's reference point.
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

__all__ = ["SkeletonElement", "SteeringAxes", "SteeringSkeleton", "eliminate_links",
           "steering_axes", "steering_axes_from_poses"]

#: relative singular-value threshold for the rank of the constraint Jacobian
RANK_TOLERANCE = 1e-9
#: the wheel part's twists must span one direction: second singular value below this (relative)
ONE_DOF_TOLERANCE = 1e-6


@dataclass(frozen=True)
class SteeringSkeleton:
    """The constraints used for the steering axis (see the module doc), or ``reason`` why the
    suspension has none that can be computed."""

    ground: str
    wheel_part: str
    elements: tuple[SkeletonElement, ...]
    steering: str  # what was released, for the record
    reason: str | None = None
    eliminated: tuple[str, ...] = ()  # two-ball-joint parts replaced by distances


_BALL = (1, 1, 1, 0, 0, 0)


def eliminate_links(elements: list[SkeletonElement], ground: str, wheel: str):
    """Every part held only by two ball joints (an arm between a bushing and a ball joint,
    neither the ground nor the wheel part) replaced by the distance it keeps (exact)."""
    """Replace every part held by exactly two ball joints (a spherical joint, or a bushing
    whose ideal joint is spherical) and nothing else, e.g. a lower arm between a bushing and
    a ball joint, by the distance it keeps between the parts at its ends. Exact at the
    velocity level (the part's only other motion is its idle spin about its own axis) and
    halves the unknowns of a McPherson."""
    touching: dict[str, list[tuple[int, int]]] = {}
    for i, e in enumerate(elements):
        for side, part in enumerate(e.parts):
            touching.setdefault(part, []).append((i, side))
    out, used, eliminated = list(elements), set(), []
    for part, uses in touching.items():
        if part in (ground, wheel) or len(uses) != 2:
            continue
        (i, si), (j, sj) = uses
        ei, ej = elements[i], elements[j]
        ends = (ei.parts[1 - si], ej.parts[1 - sj])
        if i == j or used & {i, j} or part in ends or ends[0] == ends[1] or not all(
                e.kind == "joint" and tuple(e.flags) == _BALL and not e.released
                for e in (ei, ej)):
            continue
        used |= {i, j}
        eliminated.append(part)
        # a ball joint makes the velocities of its two parts equal at its second part's
        # marker (see translation_row), so the part keeps the distance between those points
        out.append(SkeletonElement("distance", ends, (ei.points[1 - si], ej.points[1 - sj]),
                            anchors=((ei.parts[1], ei.points[1]), (ej.parts[1], ej.points[1]))))
    return [e for k, e in enumerate(out) if k not in used], eliminated


@dataclass
class SteeringAxes:
    """The steering axis per step: unit ``direction`` (pointing up), ``point`` on it (the point
    closest to the wheel centre), and the ``pitch_mm_per_rad`` of the steering screw (the
    wheel part's translation along the axis per radian of steer); NaN rows where undefined,
    ``reason`` says why (None when every step has an axis)."""

    direction: np.ndarray  # (S, 3)
    point: np.ndarray  # (S, 3) mm
    pitch_mm_per_rad: np.ndarray  # (S,)
    reason: str | None


def _nan_axes(n: int, reason: str) -> SteeringAxes:
    return SteeringAxes(np.full((n, 3), np.nan), np.full((n, 3), np.nan), np.full(n, np.nan),
                        reason)


def _null_spaces(A: np.ndarray):
    """Orthonormal null-space bases of the stacked matrices ``A`` (S, m, N): yields
    ``(step indices, basis (s, N, nullity))`` per group of steps with the same nullity.

    Fast path: Householder QR of ``A^T`` (full row rank: the null space is the trailing
    ``N - m`` columns of Q). Steps whose rows are dependent (a redundant constraint, e.g. a
    heave spring locked with the corner springs that lock its ends already) take it again
    without the rows that depend on the others at the first such step, where the dropped rows
    still vanish on the basis found; the rest falls back to the SVD."""
    S, m, N = A.shape
    todo = np.arange(S)
    for rows in (np.arange(m), None):
        if todo.size == 0:
            return
        if rows is None:  # drop the rows dependent at the first step left, and try again
            rows = _independent_rows(A[todo[0]])
            if rows.size == m:
                break
        found, todo = _qr_null_spaces(A, todo, rows)
        if found is not None:
            yield found
    if todo.size:
        B = A[todo]
        if m < N:  # square it up: zero rows change no null space
            B = np.concatenate([B, np.zeros((todo.size, N - m, N))], axis=1)
        _, sv, Vt = np.linalg.svd(B)
        rank = np.sum(sv > RANK_TOLERANCE * sv[:, :1], axis=1)
        for r in np.unique(rank):
            sel = rank == r
            yield todo[sel], np.swapaxes(Vt[sel][:, r:, :], 1, 2)


def _qr_null_spaces(A: np.ndarray, todo: np.ndarray, rows: np.ndarray):
    """The QR fast path of :func:`_null_spaces` on the steps ``todo`` with the constraint
    ``rows`` of ``A``: ((steps, basis) or None, the steps it did not solve). A step is solved
    when those rows have full rank and every other row vanishes on the basis."""
    m, N = rows.size, A.shape[2]
    if m >= N:
        return None, todo
    Q, R = np.linalg.qr(np.swapaxes(A[todo][:, rows, :], 1, 2), mode="complete")
    diag = np.abs(np.diagonal(R[:, :m, :m], axis1=1, axis2=2))
    full = diag.min(axis=1) > 1e-6 * diag.max(axis=1)
    basis = Q[:, :, m:]
    others = np.setdiff1d(np.arange(A.shape[1]), rows)
    if others.size:
        rest = A[todo][:, others, :]
        scale = np.max(np.abs(rest), axis=(1, 2), keepdims=True) + 1e-300
        full &= np.max(np.abs(rest @ basis / scale), axis=(1, 2)) < RANK_TOLERANCE ** 0.5
    found = (todo[full], basis[full]) if np.any(full) else None
    return found, todo[~full]


def _independent_rows(M: np.ndarray) -> np.ndarray:
    """Indices of the rows of ``M`` (m, N), each kept when it is independent of those kept
    before it (Gram-Schmidt, relative tolerance ``RANK_TOLERANCE ** 0.5``)."""
    basis: list[np.ndarray] = []
    keep = []
    for i, row in enumerate(M):
        r = row.copy()
        for b in basis:
            r -= (r @ b) * b
        norm = np.linalg.norm(r)
        if norm > RANK_TOLERANCE ** 0.5 * max(np.linalg.norm(row), 1e-300):
            basis.append(r / norm)
            keep.append(i)
    return np.asarray(keep, int)


def _idle_locks(A: np.ndarray, springs: np.ndarray, k: int) -> list[tuple[np.ndarray,
                                                                          np.ndarray]]:
    """Per group of steps, rows that lock the idle motions: those the joints allow with the
    wheel part (columns ``k:k+6``) held and the springs unlocked (a strut rod turning about
    its own axis). With spring seats off the strut axis such a turn changes the spring's
    length, so a locked spring no longer locks the travel alone; the rubber of the top mount,
    which the ideal joints leave out, holds it in reality."""
    S, _, N = A.shape
    hold = np.zeros((S, 6, N))
    hold[:, :, k:k + 6] = np.eye(6)
    free = np.concatenate([A[:, ~springs, :], hold], axis=1)
    return [(idx, np.swapaxes(basis, 1, 2)) for idx, basis in _null_spaces(free)]


def _wheel_twists(A: np.ndarray, E: np.ndarray, k: int, n: int) -> tuple[np.ndarray, str | None]:
    """The wheel part's twist per step (its columns ``k:k+6``, i.e. ``(omega *
    LENGTH_SCALE, v)``, of unit norm) from the constraint rows ``A`` (S, m, N) and the
    steering rates ``E`` (S, r, N): NaN rows, and the first reason, where the wheel part does
    not keep exactly one motion that moves the steering input."""
    twist = np.full((n, 6), np.nan)
    bad: str | None = None
    for idx, null in _null_spaces(A):
        if null.shape[2] == 0:
            bad = bad or "the wheel part cannot move with the steering released"
            continue
        # the wheel part's share of each motion: (s, 6, nullity); one direction expected
        u, w, vt = np.linalg.svd(null[:, k:k + 6, :])
        ok = w[:, 0] > ONE_DOF_TOLERANCE
        if null.shape[2] > 1:
            ok &= w[:, 1] < ONE_DOF_TOLERANCE * w[:, 0]
        if not np.all(ok):
            bad = bad or ("the wheel part keeps " + ("no" if not np.any(w[~ok, 0] >
                          ONE_DOF_TOLERANCE) else "more than one") + " degree of freedom with "
                          "the steering released and the springs locked (the springs do not "
                          "lock the travel?)")
        # that motion must move the steering input (else it is not steering: e.g. a spring
        # that locks the rack instead of the travel)
        x = np.einsum("snk,sk->sn", null, vt[:, 0, :] / np.where(ok, w[:, 0], 1.0)[:, None])
        moves = np.max(np.abs(np.einsum("srn,sn->sr", E[idx], x)), axis=1) > ONE_DOF_TOLERANCE
        if np.any(ok & ~moves):
            bad = bad or ("the motion left with the springs locked does not move the steering "
                          "input (the springs lock the steering, not the travel?)")
        ok &= moves
        twist[idx[ok]] = u[ok, :, 0]
    return twist, bad


def _screw_axes(twist: np.ndarray, bad: str | None, position: dict[str, np.ndarray],
                wheel_part: str, wheel_centre: np.ndarray) -> SteeringAxes:
    """The screw axis of the wheel part's ``twist`` (S, 6) per step: direction pointing up,
    the point closest to ``wheel_centre``, the pitch; ``bad`` (or a pure translation) is the
    reason."""
    omega, v = twist[:, :3] / LENGTH_SCALE, twist[:, 3:]
    w2 = np.sum(omega * omega, axis=-1)
    translation = w2 < (ONE_DOF_TOLERANCE / LENGTH_SCALE) ** 2
    if np.any(translation):
        bad = bad or "the steering motion is a pure translation (no axis)"
        w2 = np.where(translation, np.nan, w2)
    c = position[wheel_part]
    direction = omega / np.sqrt(w2)[:, None]
    flip = np.where(direction[:, 2:3] < 0, -1.0, 1.0)  # config z is up
    direction = direction * flip
    point = c + cross_rows(omega, v) / w2[:, None]
    point = point + np.sum((wheel_centre - point) * direction, axis=-1)[:, None] * direction
    pitch = np.sum(omega * v, axis=-1) / w2
    return SteeringAxes(direction, point, pitch, bad)


def steering_axes(skeleton: SteeringSkeleton, rotation: dict[str, np.ndarray],
                  position: dict[str, np.ndarray], reference: dict[str, np.ndarray],
                  wheel_centre: np.ndarray) -> SteeringAxes:
    """Steering axis at S steps from the part poses.

    rotation[part]: (S, 3, 3) rotation from the design position; position[part]: (S, 3) mm,
    where the part's reference point ``reference[part]`` (3,) now is. Every moving part of the
    skeleton must be given; the ground part is not. wheel_centre: (S, 3) mm (the returned
    point is the axis point closest to it).
    """
    n = len(wheel_centre)
    if skeleton.reason is not None:
        return _nan_axes(n, skeleton.reason)
    parts = sorted(p for p in rotation if p not in skeleton.eliminated)
    col = {p: 6 * i for i, p in enumerate(parts)}
    steps = SkeletonSteps(skeleton.ground, rotation, position, reference, n, col,
                          6 * len(parts), np.broadcast_to(np.eye(3), (n, 3, 3)))
    rows, steer, springs = constraint_rows(steps, skeleton.elements)
    A = np.stack(rows, axis=1)  # (S, m, N)
    E = np.stack(steer, axis=1)  # (S, r, N)
    k = col[skeleton.wheel_part]
    twist, bad = _wheel_twists(A, E, k, n)
    if bad is not None and "more than one" in bad and any(springs):
        # the travel not locked by the springs alone: lock the idle motions too, and retry
        twist, bad = np.full((n, 6), np.nan), None
        for idx, locks in _idle_locks(A, np.array(springs), k):
            t_idx, b_idx = _wheel_twists(np.concatenate([A[idx], locks], axis=1), E[idx], k,
                                         idx.size)
            twist[idx], bad = t_idx, bad or b_idx
    return _screw_axes(twist, bad, position, skeleton.wheel_part, wheel_centre)


def steering_axes_from_poses(skeleton: SteeringSkeleton, poses: list,
                             wheel_centre: np.ndarray) -> SteeringAxes:
    """:func:`steering_axes` from one :class:`elastokin.physics.states.PartPoses` per step (``None``
    entries, e.g. states without poses, give NaN rows)."""
    n = len(poses)
    have = [i for i, p in enumerate(poses) if p is not None]
    if not have:
        return _nan_axes(n, "no part poses recorded for these steps")
    first = poses[have[0]]
    names = list(first.rotation)
    rotation = {m: np.array([poses[i].rotation[m] for i in have]) for m in names}
    position = {m: np.array([poses[i].displacement_mm[m] for i in have])
                + first.reference_mm[m] for m in names}
    axes = steering_axes(skeleton, rotation, position, dict(first.reference_mm),
                         np.asarray(wheel_centre, float)[have])
    if len(have) == n:
        return axes
    out = _nan_axes(n, axes.reason or "no part poses recorded for some steps")
    out.direction[have], out.point[have], out.pitch_mm_per_rad[have] = \
        axes.direction, axes.point, axes.pitch_mm_per_rad
    return out
