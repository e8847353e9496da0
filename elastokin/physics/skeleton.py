"""The skeleton of a suspension at the velocity level (pure numpy, all steps at once): its
joints, bushings (as their ideal joints, frozen at their deflection) and links as linear
constraints on the parts' twists, at the part poses of every rig step. Used for the steering
axis (:mod:`elastokin.physics.steering_axis`) and the roll motion of a dependent axle
(:mod:`elastokin.physics.roll_motion`).

Units: mm, rad inside; the config frame. A twist is ``(omega, v)``: angular velocity (rad per
unit input) and the velocity (mm per unit input) of the part's reference point.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["LENGTH_SCALE", "SkeletonElement", "SkeletonSteps", "constraint_rows",
           "cross_rows", "tait_bryan_dual"]

#: length (mm) scaling the rotational unknowns so that the Jacobian's columns are comparable
LENGTH_SCALE = 1000.0


@dataclass(frozen=True)
class SkeletonElement:
    """One constraint of the skeleton at the design position."""

    kind: str  # "joint" (flags in a frame) or "distance"
    parts: tuple[str, str]
    #: marker on each part, design position, mm: (3,), or (S, 3) for a design per step
    points: tuple[np.ndarray, np.ndarray]
    frame: np.ndarray | None = None  # joint frame (columns), fixed to parts[0]; or (S, 3, 3)
    flags: tuple[int, ...] = ()  # constrained tx ty tz rx ry rz in that frame
    released: bool = False  # the steering input: not a constraint, its rate must not vanish
    #: a distance kept by an eliminated two-ball-joint part: each end's point as (the part
    #: that carries it, design position), when it is not ``(parts[k], points[k])``
    anchors: tuple[tuple[str, np.ndarray], tuple[str, np.ndarray]] | None = None
    spring: bool = False  # a coil spring's length, locked: the travel is held


def tait_bryan_dual(Rrel: np.ndarray) -> np.ndarray:
    """Rows k: the vectors w_k (marker-0 frame) with d(angle_k)/dt = w_k . omega_rel for the
    Tait-Bryan x-y-z angles of ``Rrel`` (S, 3, 3) = Rx(a) Ry(b) Rz(c)."""
    a = np.arctan2(-Rrel[:, 1, 2], Rrel[:, 2, 2])
    b = np.arcsin(np.clip(Rrel[:, 0, 2], -1.0, 1.0))
    ca, sa, cb, sb = np.cos(a), np.sin(a), np.cos(b), np.sin(b)
    G = np.zeros(Rrel.shape)
    G[:, 0, 0] = 1.0
    G[:, :, 1] = np.stack([np.zeros_like(a), ca, sa], axis=-1)
    G[:, :, 2] = np.stack([sb, -sa * cb, ca * cb], axis=-1)
    return np.linalg.inv(G)


def cross_rows(a, b):
    """Row-wise cross product of (S, 3) arrays (cheaper than np.cross for small stacks)."""
    return np.stack([a[:, 1] * b[:, 2] - a[:, 2] * b[:, 1], a[:, 2] * b[:, 0] - a[:, 0] * b[:, 2],
                     a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]], axis=-1)


@dataclass(frozen=True)
class SkeletonSteps:
    """The part poses at ``n`` steps and the layout of the unknowns: 6 columns per moving part
    from ``col[part]`` on (its angular velocity times :data:`LENGTH_SCALE`, then the velocity
    of the point where its reference point now is), ``N`` in all; the ``ground`` part has
    none."""

    ground: str
    rotation: dict[str, np.ndarray]
    position: dict[str, np.ndarray]
    reference: dict[str, np.ndarray]
    n: int
    col: dict[str, int]
    N: int
    eye: np.ndarray  # (n, 3, 3) identity: the ground part's rotation

    def pose(self, part):
        if part == self.ground:
            return self.eye, None
        return self.rotation[part], self.position[part]

    def moved(self, part, p):
        """Where the design point ``p`` ((3,), or (S, 3) per step) of ``part`` is."""
        R, c = self.pose(part)
        if c is None:
            return np.broadcast_to(p, (self.n, 3))
        if np.ndim(p) == 2:
            return np.einsum("sij,sj->si", R, p - self.reference[part]) + c
        return np.einsum("sij,j->si", R, p - self.reference[part]) + c

    def translation_row(self, parts, q, a) -> np.ndarray:
        """a . (v1(q[1]) - v0(q[0])) = 0: a (S, 3) unit, v0 / v1 the velocities of parts[0] /
        parts[1] at the points q (S, 3)."""
        row = np.zeros((self.n, self.N))
        for sign, part, qk in ((-1.0, parts[0], q[0]), (1.0, parts[1], q[1])):
            if part == self.ground:
                continue
            r = qk - self.position[part]
            k = self.col[part]
            row[:, k:k + 3] += sign * cross_rows(r, a) / LENGTH_SCALE
            row[:, k + 3:k + 6] += sign * a
        return row

    def rotation_row(self, parts, w) -> np.ndarray:
        row = np.zeros((self.n, self.N))
        for sign, part in ((-1.0, parts[0]), (1.0, parts[1])):
            if part != self.ground:
                row[:, self.col[part]:self.col[part] + 3] += sign * w / LENGTH_SCALE
        return row


def constraint_rows(steps: SkeletonSteps, elements
                    ) -> tuple[list[np.ndarray], list[np.ndarray], list[bool]]:
    """The velocity constraints of the skeleton's ``elements`` at every step, (S, N) rows:
    those of the constraints, the rates of the released input, and which constraint rows lock
    a spring's length."""
    rows: list[np.ndarray] = []  # the constraints
    steer: list[np.ndarray] = []  # the released steering input's rates
    springs: list[bool] = []
    for e in elements:
        target = steer if e.released else rows
        before = len(rows)
        if e.kind == "distance":  # d|q1 - q0|/dt = 0, each end moving with its part
            ends = e.anchors or ((e.parts[0], e.points[0]), (e.parts[1], e.points[1]))
            q = (steps.moved(*ends[0]), steps.moved(*ends[1]))
            d = q[1] - q[0]
            target.append(steps.translation_row(
                e.parts, q, d / np.linalg.norm(d, axis=-1, keepdims=True)))
            springs += [e.spring] * (len(rows) - before)
            continue
        # joint: d/dt [F0^T (q1 - q0)] = F0^T (v1(q1) - v0(q1)) in the constrained directions
        # (the joint's offset, e.g. a strut's slide or a bushing's deflection, is held in the
        # frame of part 0, as Exudyn's generic joint does): both velocities at q1
        q1 = steps.moved(e.parts[1], e.points[1])
        F0 = steps.pose(e.parts[0])[0] @ e.frame  # (S, 3, 3) joint frame on part 0, columns = axes
        for i in range(3):
            if e.flags[i]:
                target.append(steps.translation_row(e.parts, (q1, q1), F0[:, :, i]))
        if any(e.flags[3:]):
            F1 = steps.pose(e.parts[1])[0] @ e.frame
            dual = tait_bryan_dual(np.swapaxes(F0, 1, 2) @ F1)
            for i in range(3):
                if e.flags[3 + i]:
                    target.append(steps.rotation_row(
                        e.parts, np.einsum("sij,sj->si", F0, dual[:, i, :])))
        springs += [False] * (len(rows) - before)
    return rows, steer, springs
