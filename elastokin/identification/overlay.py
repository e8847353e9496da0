"""What the geometric identification shows in the 3D view (plain data): every part's CMM
marks as measured on the assembled, loaded suspension and where the fitted pose puts them
[11-12], and every joint's shift from its initial location (the parts measured alone) to the
identified one [19, 27]; both far smaller than the suspension, so drawn magnified by
:func:`magnification`. Vehicle (config) frame, loaded state, mm.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from elastokin.identification.geometric import Identification

#: the largest magnified shift or mark residual is drawn about this long (mm)
DRAWN_MM = 60.0


@dataclass(frozen=True)
class IdentificationOverlay:
    """Marks (``mark_labels`` "part M1"; ``measured_mm`` and ``fitted_mm`` (n, 3), NaN for a
    dropped mark) and joints (``initial_mm``, ``identified_mm`` (m, 3); ``beyond_clearance``:
    shifted farther than dL_max [1]); ``factor``: the magnification they are drawn with."""

    mark_labels: tuple[str, ...]
    measured_mm: np.ndarray
    fitted_mm: np.ndarray
    joint_names: tuple[str, ...]
    initial_mm: np.ndarray
    identified_mm: np.ndarray
    beyond_clearance: tuple[bool, ...]
    factor: float


def magnification(largest_mm: float, drawn_mm: float = DRAWN_MM) -> float:
    """A round factor (1, 2 or 5 times a power of ten, at least 1) that draws ``largest_mm``
    at most ``drawn_mm`` long."""
    if not largest_mm > 0:
        return 1.0
    k = np.floor(np.log10(drawn_mm / largest_mm))
    for m in (5.0, 2.0, 1.0):
        if m * 10.0 ** k * largest_mm <= drawn_mm:
            return max(float(m * 10.0 ** k), 1.0)
    return max(float(10.0 ** k), 1.0)  # pragma: no cover - 1 always fits


def identification_overlay(ident: Identification) -> IdentificationOverlay:
    """The overlay of an identification (module docstring): the measured marks expressed in
    the vehicle frame through the ground part's pose, which fixes the CMM frame."""
    s = ident.suspension
    g = ident.poses[s.ground].match
    labels, measured, fitted = [], [], []
    for part, pose in ident.poses.items():
        m = pose.match
        if m.local_mm is None:
            continue
        names = s.measurements.parts[part].marks if s.measurements is not None else ()
        for k in range(len(m.local_mm)):
            labels.append(f"{part} {names[k] if k < len(names) else f'mark {k + 1}'}")
        measured.append((m.measured_mm - g.t) @ g.R)
        fitted.append(pose.point(m.local_mm))
    joints = list(ident.joints.values())
    initial = np.array([j.initial_mm for j in joints]).reshape(-1, 3)
    identified = np.array([j.identified_mm for j in joints]).reshape(-1, 3)
    meas = np.concatenate(measured) if measured else np.zeros((0, 3))
    fit = np.concatenate(fitted) if fitted else np.zeros((0, 3))
    sizes = [np.linalg.norm(identified - initial, axis=1), np.linalg.norm(meas - fit, axis=1)]
    largest = max((float(np.nanmax(x)) for x in sizes if x.size), default=0.0)
    return IdentificationOverlay(tuple(labels), meas, fit, tuple(j.name for j in joints),
                                 initial, identified,
                                 tuple(bool(j.exceeds_clearance) for j in joints),
                                 magnification(largest))
