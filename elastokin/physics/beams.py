"""Geometry of a flexible beam part (pure numpy): its section axes along each segment.

A beam's node line is its centroid line (where the axial and bending stiffness act); each
segment (node i to node i + 1) has section axes x (along the segment, from node i to node
i + 1), z (the config's section z axis projected normal to x) and y = z x x. The shear centre
is given in (y, z) of those axes. Units mm; config frame.
"""

from __future__ import annotations

import numpy as np

#: a point within this distance (mm) of a beam's node is that node
NODE_TOLERANCE_MM = 1e-6
#: a section z axis closer than this to the segment's direction (sine of the angle) is refused
MIN_SECTION_SINE = np.sin(np.radians(1.0))


def section_frame(start_mm, end_mm, z_axis) -> np.ndarray:
    """Section axes of the segment ``start_mm`` -> ``end_mm`` as columns (x along the
    segment, z the unit projection of ``z_axis`` normal to it, y = z x x). Raises
    ``ValueError`` when the segment has no length or ``z_axis`` runs along it."""
    d = np.asarray(end_mm, float) - np.asarray(start_mm, float)
    length = float(np.linalg.norm(d))
    if length < 1e-6:
        raise ValueError("two consecutive nodes coincide: a segment needs a length")
    x = d / length
    z = np.asarray(z_axis, float)
    z = z - (z @ x) * x
    if np.linalg.norm(z) < MIN_SECTION_SINE * np.linalg.norm(z_axis):
        raise ValueError("the section z axis runs along the segment (at least 1 deg apart)")
    z /= np.linalg.norm(z)
    return np.column_stack([x, np.cross(z, x), z])


def section_offset_mm(frame, offset_yz_mm) -> np.ndarray:
    """A point given in a section's (y, z) axes as a vector of the config frame."""
    R = np.asarray(frame, float)
    return R[:, 1] * float(offset_yz_mm[0]) + R[:, 2] * float(offset_yz_mm[1])
