"""Every marked body's pose at every rig position, from its marks (the paper's registration,
:mod:`elastokin.physics.pose`), and how the CMM noise on the marks propagates.

Each body's own frame is the vehicle frame at one position, its *reference* (the design
position unless its marks there fail the distance test): its 4 marks there are its template.
At every position the marks are ordered against the template and a wrong one dropped
(:func:`~elastokin.physics.pose.match_marks`, [8-10]); the ground's marks, known in the
vehicle frame, fix the CMM's frame at each position [11-12]. :class:`MotionMarks` keeps the
ordered marks, so that :func:`vehicle_poses` is a smooth function of the measured
coordinates: :func:`propagate` differentiates any result of the poses with respect to every
coordinate (the first-order covariance of that result under isotropic noise).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from elastokin.errors import MeasurementError
from elastokin.formats.cmm_motion import MotionMeasurement
from elastokin.physics.pose import fit_poses, match_marks

Poses = dict[str, tuple[np.ndarray, np.ndarray]]  # body -> R (P, 3, 3), t (P, 3)


@dataclass
class MotionMarks:
    """The ordered marks: ``raw[body]`` (P, 4, 3) in the CMM frame of each position, NaN
    where a mark was dropped (wrong) or missed; the ground's marks in the vehicle frame
    (``ground_template``); each other body's reference position (``reference``)."""

    ground: str
    ground_template: np.ndarray
    raw: dict[str, np.ndarray]
    reference: dict[str, int]
    design: int
    # the wrong marks dropped: body, position, the mark's label in its file (or its index)
    dropped: list[tuple[str, int, str]] = field(default_factory=list)

    @property
    def positions(self) -> int:
        return next(iter(self.raw.values())).shape[0]


def _sorted_distances(x: np.ndarray) -> np.ndarray:
    d = np.linalg.norm(x[:, None] - x[None], axis=2)
    return np.sort(d[np.triu_indices(len(x), 1)])


def _reference(marks: list[np.ndarray], design: int, eps_mm: float) -> int | None:
    """The first position (the design one first) whose 4 marks pass the distance test
    [8-9] against the median of every position's sorted distances: its marks hold no wrong
    point."""
    full = [k for k, m in enumerate(marks) if len(m) == 4]
    if not full:
        return None
    median = np.median([_sorted_distances(marks[k]) for k in full], axis=0)
    for k in sorted(full, key=lambda k: k != design):
        if np.max(np.abs(_sorted_distances(marks[k]) - median)) <= eps_mm:
            return k
    return None


def order_marks(data: MotionMeasurement, ground: str, design: int, eps_mm: float
                ) -> tuple[MotionMarks, list[str]]:
    """Order every body's marks at every position against its template and drop a wrong
    one [8-10]; the warnings name the file, the body and the mark. Raises naming the file
    when a body's marks match no ordering, or when no position holds 4 good marks of it."""
    warnings: list[str] = []
    raw, reference, dropped = {}, {}, []
    for body in data.marks[0]:
        per_position = [m[body] for m in data.marks]
        if body == ground:
            template, ref = data.ground_marks, None
        else:
            ref = _reference(per_position, design, eps_mm)
            if ref is None:
                raise MeasurementError(
                    f"{data.files[design]}: body '{body}': at no position do its 4 marks "
                    f"agree with its other positions' within eps = {eps_mm:g} mm: no template "
                    "for its marks (a wrong point at every position, or a body that is not "
                    "rigid)")
            template, reference[body] = per_position[ref], ref
        out = np.full((len(per_position), 4, 3), np.nan)
        for k, q in enumerate(per_position):
            try:
                match = match_marks(template, q, eps_mm, body)
            except MeasurementError as exc:
                raise MeasurementError(f"{data.files[k]}: {exc}") from None
            for i, j in enumerate(match.order):
                if j is not None:
                    out[k, i] = q[j]
            if match.dropped_mark is not None and len(q) == 4:
                bad = next(j for j in range(4) if j not in match.order)
                label = data.labels[k][body][bad] if data.labels else f"#{bad + 1}"
                dropped.append((body, k, label))
                warnings.append(f"{data.files[k]}: body '{body}': mark '{label}' is not where "
                                "the other positions put it (beyond eps): dropped, the pose "
                                "fitted to the other three")
            warnings += [f"{data.files[k]}: {w}" for w in match.warnings
                         if "pose residual" in w]
        raw[body] = out
        layout = match_marks(template, template, eps_mm, body).warnings
        warnings += [f"{data.ground_file if body == ground else data.files[ref]}: {w}"
                     for w in layout if "pose residual" not in w]
    return MotionMarks(ground, data.ground_marks, raw, reference, design, dropped), warnings


def vehicle_poses(marks: MotionMarks, bodies: list[str] | None = None) -> Poses:
    """Every body's pose (its frame -> vehicle frame) at every position (the ground: the
    identity); ``bodies``: only these."""
    weights = {b: np.isfinite(m[..., 0]).astype(float) for b, m in marks.raw.items()}
    return _poses(marks.ground, marks.ground_template, marks.raw, weights, marks.reference,
                  bodies if bodies is not None else list(marks.raw))


def _poses(ground: str, template: np.ndarray, raw: dict[str, np.ndarray],
           weights: dict[str, np.ndarray], reference: dict[str, int], bodies: list[str]
           ) -> Poses:
    """:func:`vehicle_poses` for marks with leading batch dimensions (``template`` (..., 4,
    3), ``raw[body]`` (..., P, 4, 3); ``weights[body]`` (P, 4)): poses (..., P, 3, 3) and
    (..., P, 3)."""
    Rg, tg, _ = fit_poses(template[..., None, :, :], raw[ground], weights[ground])
    shape = raw[ground].shape[:-2]
    out: Poses = {}
    for body in bodies:
        if body == ground:
            out[body] = (np.broadcast_to(np.eye(3), (*shape, 3, 3)), np.zeros((*shape, 3)))
            continue
        local = np.einsum("...kji,...kmj->...kmi", Rg, raw[body] - tg[..., None, :])
        R, t, _ = fit_poses(local[..., reference[body], None, :, :], local, weights[body])
        out[body] = (R, t)
    return out


def noise_sigma(marks: MotionMarks) -> tuple[float, int]:
    """The CMM noise (sigma per coordinate, mm) estimated from the residuals of every pose
    fit but the references' (exact by construction), and its degrees of freedom. A fit of n
    marks leaves 3n - 6 of them; template and measured marks are both noisy, so each
    residual holds twice the variance."""
    g = marks.ground
    weights = {b: np.isfinite(m[..., 0]).astype(float) for b, m in marks.raw.items()}
    Rg, tg, rms = fit_poses(marks.ground_template, marks.raw[g], weights[g])
    n = weights[g].sum(axis=1)
    sum_sq, dof = float(np.sum(rms**2 * n)), float(np.sum(3 * n - 6))
    for body, m in marks.raw.items():
        if body == g:
            continue
        local = np.einsum("kji,kmj->kmi", Rg, m - tg[:, None, :])
        _, _, rms = fit_poses(local[marks.reference[body]], local, weights[body])
        n = weights[body].sum(axis=1)
        keep = np.arange(len(n)) != marks.reference[body]
        sum_sq += float(np.sum((rms**2 * n)[keep]))
        dof += float(np.sum((3 * n - 6)[keep]))
    if dof <= 0:
        return 0.0, 0
    return float(np.sqrt(sum_sq / (2.0 * dof))), int(dof)


def propagate(marks: MotionMarks, bodies: list[str], result: Callable[[Poses], np.ndarray],
              sigma_mm: float, step_mm: float = 1e-4) -> np.ndarray:
    """The covariance of ``result(poses)`` (a vector) under isotropic noise ``sigma_mm`` on
    every measured coordinate it depends on (the ground's marks in both frames and the
    ``bodies``' marks at every position): sigma^2 J J^T with J by forward differences,
    exact to first order. The orderings and dropped marks stay as found. A coordinate at a
    position that is no body's reference changes only the poses there: those are fitted
    again, all at once; the others (references, the ground's template) change every pose."""
    g = marks.ground
    involved = [g, *[b for b in bodies if b != g]]
    weights = {b: np.isfinite(marks.raw[b][..., 0]).astype(float) for b in involved}
    refs = {marks.reference[b] for b in involved if b != g}
    base_poses = _poses(g, marks.ground_template, marks.raw, weights, marks.reference,
                        involved)
    base = result(base_poses)
    local, full = [], []  # (array name, flat index)
    arrays = {"": marks.ground_template, **{b: marks.raw[b] for b in involved}}
    for name, a in arrays.items():
        for i in np.flatnonzero(np.isfinite(a.reshape(-1))):
            k = i // 12
            at_reference = k in refs if name == g else k == marks.reference.get(name)
            (full if not name or at_reference else local).append((name, int(i)))
    columns = [_full_column(marks, involved, weights, result, base, name, i, step_mm)
               for name, i in full]
    columns += _local_columns(marks, involved, weights, base_poses, result, base, local,
                              step_mm)
    J = np.array(columns).T
    return sigma_mm**2 * J @ J.T


def _perturbed(a: np.ndarray, i: int, step_mm: float) -> np.ndarray:
    out = a.copy()
    out.reshape(-1)[i] += step_mm
    return out


def _full_column(marks: MotionMarks, involved: list[str], weights, result, base, name: str,
                 i: int, step_mm: float) -> np.ndarray:
    """A coordinate that changes every pose: all of them fitted again."""
    template = marks.ground_template if name else _perturbed(marks.ground_template, i,
                                                              step_mm)
    raw = {b: _perturbed(marks.raw[b], i, step_mm) if b == name else marks.raw[b]
           for b in involved}
    poses = _poses(marks.ground, template, raw, weights, marks.reference, involved)
    return (result(poses) - base) / step_mm


def _local_columns(marks: MotionMarks, involved: list[str], weights, base_poses: Poses, result,
                   base, items: list[tuple[str, int]], step_mm: float) -> list[np.ndarray]:
    """Coordinates that change the poses at their own position only: every body's pose
    there fitted again, for all of them at once."""
    if not items:
        return []
    g = marks.ground
    k = np.array([i // 12 for _, i in items])
    at = {b: marks.raw[b][k] for b in involved}  # (n, 4, 3) each: at each item's position
    for row, (name, i) in enumerate(items):
        at[name][row].reshape(-1)[i % 12] += step_mm
    Rg, tg, _ = fit_poses(marks.ground_template, at[g], weights[g][k])
    Rg0, tg0, _ = fit_poses(marks.ground_template, marks.raw[g], weights[g])
    new = {}
    for b in involved[1:]:
        ref = marks.reference[b]
        template = (marks.raw[b][ref] - tg0[ref]) @ Rg0[ref]
        local = np.einsum("nji,nmj->nmi", Rg, at[b] - tg[:, None, :])
        new[b] = fit_poses(template, local, weights[b][k])[:2]
    columns = []
    for row, kk in enumerate(k):
        poses = dict(base_poses)
        for b, (R, t) in new.items():
            Rb, tb = base_poses[b][0].copy(), base_poses[b][1].copy()
            Rb[kk], tb[kk] = R[row], t[row]
            poses[b] = (Rb, tb)
        columns.append((result(poses) - base) / step_mm)
    return columns
