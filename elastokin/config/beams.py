"""Resolving flexible beam parts (a part's ``beam:`` section, :mod:`elastokin.config.schema.beam`)
into :class:`~elastokin.config.suspension.Beam`: nodes at named hardpoints, section axes and
shear-centre offset per segment; on an axle the other side's copy, or for a shared beam (one
piece across the car) the other half, mirrored; every connection to a beam made at one of its
nodes. Units mm, N, N*mm^2; the config frame; every error names the key.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from elastokin.config.axle import CENTRE_PLANE_TOLERANCE_MM, MIRROR
from elastokin.config.suspension import Beam, BeamSection, Suspension
from elastokin.physics.beams import NODE_TOLERANCE_MM, section_frame, section_offset_mm

SECTION_KEYS = ("EA_N", "EI_y_Nmm2", "EI_z_Nmm2", "GJ_Nmm2", "GA_y_N", "GA_z_N")


def resolve_beams(resolver) -> tuple[Beam, ...]:
    """The config's beam parts (the ``beam`` section of ``parts``), resolved by ``resolver``
    (a :class:`~elastokin.config.resolver.Resolver`)."""
    spec = resolver.spec
    out = []
    for name, part in spec.parts.items():
        if part.beam is None:
            continue
        key = f"parts.{name}.beam"
        if name == spec.wheel.part:
            raise resolver.fail("wheel.part", f"'{name}' is a beam part: the wheel is carried "
                                "by a rigid part (fix a rigid part to the beam's node)")
        b = part.beam
        nodes = np.array([resolver.point(n, f"{key}.nodes[{i}]") for i, n in enumerate(b.nodes)])
        z_axis = resolver.axis(b.section.z_axis, f"{key}.section.z_axis")
        try:
            frames = segment_frames(nodes, [z_axis] * (len(nodes) - 1), b.nodes)
        except ValueError as exc:
            raise resolver.fail(f"{key}.nodes", str(exc)) from None
        offsets = np.array([section_offset_mm(R, b.section.shear_centre_mm) for R in frames])
        section = BeamSection(**{k: getattr(b.section, k) for k in SECTION_KEYS})
        out.append(Beam(name, tuple(b.nodes), nodes, frames, offsets, section,
                        b.elements_per_segment))
    if out:
        check_beam_uses(resolver, out)
    return tuple(out)


def segment_frames(nodes: np.ndarray, z_axes, names) -> np.ndarray:
    """Each segment's section axes (:func:`~elastokin.physics.beams.section_frame`); a
    ``ValueError`` names the segment."""
    frames = []
    for i, (a, b, z) in enumerate(zip(nodes[:-1], nodes[1:], z_axes)):
        try:
            frames.append(section_frame(a, b, z))
        except ValueError as exc:
            raise ValueError(f"segment {names[i]} -> {names[i + 1]}: {exc}") from None
    return np.array(frames)


def check_beam_uses(resolver, beams: list[Beam]) -> None:
    """What a suspension with beams cannot do (yet): CMM identification, joints from motion
    and the stiffness fit (they work on rigid parts)."""
    spec = resolver.spec
    parts = ", ".join(f"'{b.part}'" for b in beams)
    if spec.measurements is not None:
        raise resolver.fail("measurements", f"geometric identification from CMM data needs "
                            f"rigid parts; {parts} is a flexible beam: remove 'measurements'")
    if spec.motion is not None:
        raise resolver.fail("motion", f"joints from motion need rigid parts (a part's pose "
                            f"from its marks); {parts} is a flexible beam: remove 'motion'")
    if spec.kc_test is not None and spec.kc_test.stiffness_identification.enabled:
        raise resolver.fail("kc_test.stiffness_identification.enabled", "the bushing "
                            f"stiffness fit is not available with flexible beam parts ({parts}): "
                            "set it to false (the test data are still compared)")


def _mirrored_segments(beam: Beam, order) -> tuple[list, list]:
    """The mirrored section z axes and shear-centre offsets of the segments ``order``."""
    order = list(order)
    return ([MIRROR @ beam.frames[i][:, 2] for i in order],
            [MIRROR @ beam.shear_centre_mm[i] for i in order])


def mirrored_beam(beam: Beam, hardpoints, suffix: str) -> Beam:
    """The other side's copy of a corner's beam part: its nodes at the other side's
    hardpoints (``hardpoints``, by the corner's names: mirrored, or as ``axle.other_side``
    moves them), each segment's section z axis and shear centre mirrored."""
    nodes = np.array([hardpoints[n] for n in beam.node_names])
    names = tuple(n + suffix for n in beam.node_names)
    z_axes, offsets = _mirrored_segments(beam, range(len(beam.frames)))
    frames = segment_frames(nodes, z_axes, names)
    return replace(beam, part=beam.part + suffix, node_names=names, nodes_mm=nodes,
                   frames=frames, shear_centre_mm=np.array(offsets))


def shared_beam(beam: Beam, hardpoints, suffix: str, outboard: np.ndarray, fail) -> Beam:
    """A shared beam (one piece across the car) from its config-side half: the half's first
    node on the centre plane, the others on the config side; the other half is the mirror
    image (at ``hardpoints``, by the corner's names), joined at the first node."""
    key = f"parts.{beam.part}.beam.nodes"
    first, rest = beam.nodes_mm[0], beam.nodes_mm[1:]
    if abs(float(first @ outboard)) > CENTRE_PLANE_TOLERANCE_MM:
        raise fail(key, f"'{beam.part}' is shared (axle.shared): give its half on this side, "
                   f"from its first node on the vehicle centre plane (y = 0; "
                   f"'{beam.node_names[0]}' is at y = {first[1]:.6g} mm) outward")
    inboard = [n for n, p in zip(beam.node_names[1:], rest) if float(p @ outboard)
               <= CENTRE_PLANE_TOLERANCE_MM]
    if inboard:
        raise fail(key, f"'{beam.part}' is shared (axle.shared): its nodes after the first are "
                   f"on this side of the centre plane; '{inboard[0]}' is not")
    k = len(rest)
    names = tuple(n + suffix for n in reversed(beam.node_names[1:])) + beam.node_names
    nodes = np.array([hardpoints[n] for n in reversed(beam.node_names[1:])]
                     + list(beam.nodes_mm))
    z_axes, offsets = _mirrored_segments(beam, reversed(range(k)))
    z_axes += [R[:, 2] for R in beam.frames]
    frames = segment_frames(nodes, z_axes, names)
    return replace(beam, node_names=names, nodes_mm=nodes, frames=frames,
                   shear_centre_mm=np.array(offsets + list(beam.shear_centre_mm)))


def attachments(s: Suspension) -> list[tuple[str, str, np.ndarray]]:
    """(item name, part, point) of every attachment of a connection, spring, stop or the
    anti-roll bar to a part (design position, config frame)."""
    out = []
    for items, points in ((s.joints, "position_mm"), (s.bushings, "position_mm")):
        out += [(f"connections.{c.name}", p, getattr(c, points)) for c in items
                for p in c.parts]
    out += [(f"connections.{c.name}", p, q) for c in s.links for p, q in zip(c.parts,
                                                                            c.points_mm)]
    out += [(f"springs.{c.name}", p, q) for c in s.springs for p, q in zip(c.parts,
                                                                          c.seats_mm)]
    out += [(f"stops.{c.name}", p, q) for c in s.stops for p, q in zip(c.parts, c.points_mm)]
    bar = s.axle.anti_roll_bar if s.axle is not None else None
    if bar is not None:
        out += [("axle.anti_roll_bar.point", p, bar.position_mm) for p in bar.parts]
    return out


def check_beam_attachments(s: Suspension, fail) -> None:
    """Every attachment to a beam part is at one of its nodes (the config's key named: on
    an axle the corner's item the other side's copy comes from)."""
    beams = {b.part: b for b in s.beams}
    suffix = s.axle.suffix if s.axle is not None else None
    for key, part, point in attachments(s):
        b = beams.get(part)
        if b is None or np.min(np.linalg.norm(b.nodes_mm - point, axis=1)) <= NODE_TOLERANCE_MM:
            continue
        if suffix and key.endswith(suffix):
            key = key.removesuffix(suffix)
        raise fail(key, f"its point {np.round(point, 6).tolist()} on beam part '{part}' is not "
                   f"one of the beam's nodes ({', '.join(b.node_names)}): a connection to a "
                   "beam is made at a node")
