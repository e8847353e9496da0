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


def stations_mm(nodes_mm, segments, elements_per_segment: int) -> np.ndarray:
    """The element ends along consecutive ``segments`` (indices) of a node line: the first
    segment's start, then ``elements_per_segment`` equal steps along each segment ((k, 3),
    mm): where the beam's nodes are (:mod:`elastokin.mbs.beams`)."""
    pts = np.asarray(nodes_mm, float)
    segments = list(segments)
    n = int(elements_per_segment)
    out = [pts[segments[0]]]
    for i in segments:
        out += [pts[i] + (pts[i + 1] - pts[i]) * k / n for k in range(1, n + 1)]
    return np.array(out)


def node_line(nodes_mm, elements_per_segment: int) -> tuple[np.ndarray, np.ndarray]:
    """Every node of a beam's node line through its named ``nodes_mm`` (n, 3), each place
    once (m = (n - 1) x elements_per_segment + 1): their positions (m, 3) mm at the design
    position, and the segment each belongs to (m,) (the one it starts; the last node: the
    last segment), whose section axes and shear centre it has."""
    segments = len(nodes_mm) - 1
    positions = stations_mm(nodes_mm, range(segments), elements_per_segment)
    which = np.minimum(np.arange(len(positions)) // int(elements_per_segment), segments - 1)
    return positions, which


def mean_rotation(rotations: np.ndarray) -> np.ndarray:
    """The rotation nearest to the mean of rotation matrices (..., k, 3, 3) in the Frobenius
    norm (chordal L2 mean: the polar factor of their sum), (..., 3, 3)."""
    u, _, vt = np.linalg.svd(np.sum(rotations, axis=-3))
    d = np.sign(np.linalg.det(u @ vt))
    u = u.copy()
    u[..., :, 2] *= d[..., None]
    return u @ vt


def twist_deg(rotations: np.ndarray) -> np.ndarray:
    """How far each of a beam's node rotations (..., k, 3, 3) is turned from their mean
    (:func:`mean_rotation`): the angle (deg, (..., k)) of the relative rotation: the beam's
    twist and bending, its rigid motion taken out."""
    rel = np.swapaxes(mean_rotation(rotations), -1, -2)[..., None, :, :] @ rotations
    c = np.clip((np.trace(rel, axis1=-2, axis2=-1) - 1.0) / 2.0, -1.0, 1.0)
    return np.degrees(np.arccos(c))


def magnified_rotations(rotations: np.ndarray, factor: float) -> np.ndarray:
    """A beam's node rotations (..., k, 3, 3) with their turn from the mean rotation
    (:func:`twist_deg`) multiplied by ``factor``: R_mean exp(factor log(R_mean^T R)), the
    deformation drawn magnified, the rigid motion as it is."""
    from scipy.spatial.transform import Rotation

    R = np.asarray(rotations, float)
    mean = mean_rotation(R)[..., None, :, :]
    rel = np.swapaxes(mean, -1, -2) @ R
    shape = rel.shape[:-2]
    vec = Rotation.from_matrix(rel.reshape(-1, 3, 3)).as_rotvec() * float(factor)
    return mean @ Rotation.from_rotvec(vec).as_matrix().reshape(*shape, 3, 3)
