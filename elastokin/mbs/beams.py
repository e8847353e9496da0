"""Flexible beam parts in Exudyn (:class:`~elastokin.config.suspension.Beam`).

A beam part is a chain of Exudyn's ``ObjectBeamGeometricallyExact`` elements (two rigid-body
nodes each, Tait-Bryan ``Rxyz`` nodes as the rigid parts have; shear-deformable, strains from
the nodes' relative motion on SE(3): exact for any rotation, converging as the square of the
element length under a varying bending moment). What was tried and measured to choose it is in
docs/beams.md. The element takes a diagonal section stiffness only (Exudyn refuses coupling
terms), so a shear centre off the node line is built from two chains:

- the **node line** (the centroid line: the named hardpoints) carries the axial and bending
  stiffness EA, EI_y, EI_z;
- a parallel chain through the **shear centre** carries the torsion and shear stiffness GJ,
  GA_y, GA_z;

and at every station the two are tied rigidly (a fixed joint to the shear-centre element's end,
offset to the node line): a rigid cross-section whose strains at the shear centre are those at
the node line plus the curvature times the offset, i.e. exactly the coupled section. A section
whose shear centre is on the node line is one chain with all six. Where two segments meet at an
angle, each has its own nodes there, tied rigidly.

Connections attach at the named nodes of the node line (rigid markers carrying the joint's
frame, or position markers). Units mm, N, N*mm, rad inside Exudyn; config frame.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from exudyn.itemInterface import (
    MarkerBodyRigid,
    MarkerNodePosition,
    MarkerNodeRigid,
    NodeRigidBodyRxyz,
    ObjectBeamGeometricallyExact,
    ObjectJointGeneric,
    SensorNode,
)
from exudyn.rigidBodyUtilities import RotationMatrix2RotXYZ, RotXYZ2G

from elastokin.config.suspension import Beam
from elastokin.errors import ModelError
from elastokin.mbs.exudyn_api import exu
from elastokin.physics.beams import NODE_TOLERANCE_MM, stations_mm

__all__ = ["BeamBody", "NOISE_FACTOR"]

#: round-off of one residual evaluation, relative to its largest term
ROUND_OFF = 2.2e-16
#: the Newton tolerance of a model with beams is this many times the beams' round-off floor
NOISE_FACTOR = 100.0


def node_frame(section: np.ndarray) -> tuple[np.ndarray, bool]:
    """(the frame of a segment's nodes, whether y and z were relabelled): the section axes,
    or (x, z, -y) when the section z axis lies closer to the config's x axis than y does
    (Tait-Bryan x-y-z angles are singular where the z column meets the x axis)."""
    R = np.asarray(section, float)
    if abs(R[0, 2]) <= abs(R[0, 1]):
        return R, False
    return np.column_stack([R[:, 0], R[:, 2], -R[:, 1]]), True


def stiffness_diagonal(beam: Beam, relabelled: bool) -> np.ndarray:
    """EA, GA_y, GA_z, GJ, EI_y, EI_z in the nodes' frame (N, N, N, N*mm^2 x 3)."""
    s = beam.section
    if relabelled:  # node y = section z, node z = -section y
        return np.array([s.EA_N, s.GA_z_N, s.GA_y_N, s.GJ_Nmm2, s.EI_z_Nmm2, s.EI_y_Nmm2])
    return np.array([s.EA_N, s.GA_y_N, s.GA_z_N, s.GJ_Nmm2, s.EI_y_Nmm2, s.EI_z_Nmm2])


@dataclass(frozen=True)
class Run:
    """Consecutive segments with the same section axes and shear-centre offset: one chain."""

    segments: tuple[int, ...]
    frame: np.ndarray  # the nodes' frame (node_frame of the section axes)
    relabelled: bool
    offset_mm: np.ndarray  # the shear centre from the node line, config frame


def runs(beam: Beam) -> list[Run]:
    """The beam's segments grouped into straight runs (:class:`Run`)."""
    out: list[Run] = []
    for i, (R, e) in enumerate(zip(beam.frames, beam.shear_centre_mm)):
        last = out[-1] if out else None
        if last is not None and np.allclose(beam.frames[last.segments[-1]], R, atol=1e-12) \
                and np.allclose(last.offset_mm, e, atol=1e-9):
            out[-1] = Run((*last.segments, i), last.frame, last.relabelled, last.offset_mm)
            continue
        frame, relabelled = node_frame(R)
        out.append(Run((i,), frame, relabelled, np.asarray(e, float)))
    return out


class BeamBody:
    """One flexible beam part built in an Exudyn system ``mbs`` (module docstring): its nodes,
    elements and ties, markers at its named nodes, the rows that hold it rigid (assembly
    checks) and the round-off floor of its residual."""

    def __init__(self, mbs, beam: Beam):
        self.mbs = mbs
        self.beam = beam
        self.nodes: list[int] = []  # every node of both chains
        self.frames: dict[int, np.ndarray] = {}  # node -> its frame (columns, config frame)
        self.positions: dict[int, np.ndarray] = {}  # node -> its design position
        self.named: dict[int, int] = {}  # index of a named node -> its node on the node line
        #: the node line's nodes in order, each place once (physics.beams.node_line's)
        self.line: list[int] = []
        self.elements: list[int] = []
        self.element_lengths: list[float] = []
        self.ties: list[int] = []
        previous = None
        for run in runs(beam):
            first, last = self._add_run(run)
            if previous is not None:
                self.ties.append(self._tie(previous, first))
            previous = last

    # ------------------------------------------------------------------ building
    def _node(self, position: np.ndarray, frame: np.ndarray) -> int:
        angles = RotationMatrix2RotXYZ(frame)
        node = self.mbs.AddNode(NodeRigidBodyRxyz(
            referenceCoordinates=[*map(float, position), *map(float, angles)],
            name=f"beam:{self.beam.part}:{len(self.nodes)}"))
        self.nodes.append(node)
        self.frames[node] = frame
        self.positions[node] = np.asarray(position, float)
        return node

    def _chain(self, stations: np.ndarray, frame: np.ndarray, stiffness) -> tuple[list, list]:
        section = exu.BeamSection()
        section.stiffnessMatrix = np.diag(stiffness)
        nodes = [self._node(p, frame) for p in stations]
        elements = []
        for a, b, pa, pb in zip(nodes[:-1], nodes[1:], stations[:-1], stations[1:]):
            length = float(np.linalg.norm(pb - pa))
            elements.append(self.mbs.AddObject(ObjectBeamGeometricallyExact(
                nodeNumbers=[a, b], length=length, sectionData=section,
                name=f"beam:{self.beam.part}:element:{len(self.elements) + len(elements)}")))
            self.element_lengths.append(length)
        self.elements += elements
        return nodes, elements

    def _add_run(self, run: Run) -> tuple[int, int]:
        """The run's chain(s) (module docstring); returns its first and last node-line
        nodes."""
        b = self.beam
        n = b.elements_per_segment
        stations = stations_mm(b.nodes_mm, run.segments, n)
        k6 = stiffness_diagonal(b, run.relabelled)
        offset = run.offset_mm
        if np.linalg.norm(offset) <= NODE_TOLERANCE_MM:
            line, _ = self._chain(stations, run.frame, k6)
        else:
            line, _ = self._chain(stations, run.frame, k6 * [1, 0, 0, 0, 1, 1])
            _, shear_elements = self._chain(stations + offset, run.frame,
                                                k6 * [0, 1, 1, 1, 0, 0])
            local = run.frame.T @ -offset  # the node line seen from the shear-centre chain
            lengths = np.linalg.norm(np.diff(stations, axis=0), axis=1)
            for k, node in enumerate(line):
                e = min(k, len(shear_elements) - 1)  # starting at station k, or the last
                x = lengths[e] / 2 * (1.0 if k == len(shear_elements) else -1.0)
                self.ties.append(self._fixed(
                    MarkerNodeRigid(nodeNumber=node),
                    MarkerBodyRigid(bodyNumber=shear_elements[e],
                                    localPosition=[x, local[1], local[2]])))
        self.line += line[1:] if self.line else line  # where two runs meet: one node
        for j, i in enumerate(run.segments):
            self.named.setdefault(i, line[j * n])
        self.named.setdefault(run.segments[-1] + 1, line[-1])
        return line[0], line[-1]

    def _tie(self, a: int, b: int) -> int:
        """Two nodes at one point (segments meeting at an angle) joined rigidly."""
        return self._fixed(
            MarkerNodeRigid(nodeNumber=a, localHT=exu.HT(self.frames[a].T, np.zeros(3))),
            MarkerNodeRigid(nodeNumber=b, localHT=exu.HT(self.frames[b].T, np.zeros(3))))

    def _fixed(self, marker0, marker1) -> int:
        markers = [self.mbs.AddMarker(marker0), self.mbs.AddMarker(marker1)]
        return self.mbs.AddObject(ObjectJointGeneric(
            markerNumbers=markers, constrainedAxes=[1] * 6,
            name=f"beam:{self.beam.part}:tie:{len(self.ties)}"))

    # ------------------------------------------------------------------ attachments
    def node_at(self, position_mm, what: str = "a connection") -> int:
        """The node-line node at a named node of the beam (within NODE_TOLERANCE_MM)."""
        p = np.asarray(position_mm, float)
        d = np.linalg.norm(self.beam.nodes_mm - p, axis=1)
        i = int(np.argmin(d))
        if d[i] > NODE_TOLERANCE_MM:
            names = ", ".join(self.beam.node_names)
            raise ModelError(f"{what} at {np.round(p, 6).tolist()} on beam part "
                             f"'{self.beam.part}' is not at one of its nodes ({names})")
        return self.named[i]

    def rigid_marker(self, position_mm, frame) -> int:
        """A marker at a named node whose axes are ``frame`` (columns, config frame) at the
        design position."""
        node = self.node_at(position_mm)
        local = self.frames[node].T @ np.asarray(frame, float)
        return self.mbs.AddMarker(MarkerNodeRigid(nodeNumber=node,
                                                  localHT=exu.HT(local, np.zeros(3))))

    def position_marker(self, position_mm) -> int:
        return self.mbs.AddMarker(MarkerNodePosition(nodeNumber=self.node_at(position_mm)))

    def record_line(self, sensors: dict[str, int]) -> list[int]:
        """Record the node line's nodes' rotation matrices and positions at every step, into
        ``sensors`` as ``part:node:<n>:R`` and ``part:node:<n>:disp`` (the keys the load
        recorder reads a node's pose by, :mod:`elastokin.mbs.loads`); returns the nodes."""
        ovt = exu.OutputVariableType
        for node in self.line:
            for key, output in (("R", ovt.RotationMatrix), ("disp", ovt.Position)):
                sensors[f"part:node:{node}:{key}"] = self.mbs.AddSensor(SensorNode(
                    nodeNumber=node, outputVariableType=output, storeInternal=True,
                    writeToFile=False))
        return list(self.line)

    # ------------------------------------------------------------------ checks
    def rigid_rows(self, n_coordinates: int) -> np.ndarray:
        """Linear equations (rows over the system's ODE2 coordinates) that hold every node at
        its design-position offset from the first node, i.e. the beam moving as one rigid
        body: d p_k = d p_0 + d w x r_k and d w_k = d w_0, with d w = G(angles) d angles."""
        first = self.nodes[0]
        i0 = self.mbs.GetNodeODE2Index(first)
        g0 = np.asarray(RotXYZ2G(RotationMatrix2RotXYZ(self.frames[first])))
        rows = []
        for node in self.nodes[1:]:
            k = self.mbs.GetNodeODE2Index(node)
            r = self.positions[node] - self.positions[first]
            block = np.zeros((6, n_coordinates))
            block[:3, k:k + 3] = np.eye(3)
            block[:3, i0:i0 + 3] = -np.eye(3)
            block[:3, i0 + 3:i0 + 6] = _cross(r) @ g0
            block[3:, k + 3:k + 6] = np.asarray(RotXYZ2G(RotationMatrix2RotXYZ(
                self.frames[node])))
            block[3:, i0 + 3:i0 + 6] -= g0
            rows.append(block)
        return np.vstack(rows) if rows else np.zeros((0, n_coordinates))

    def coordinates(self) -> np.ndarray:
        """The beam's ODE2 coordinate indices."""
        return np.concatenate([self.mbs.GetNodeODE2Index(n) + np.arange(6)
                               for n in self.nodes])

    @property
    def round_off_N(self) -> float:
        """The size of the round-off in the beam's residual (N, N*mm): the largest element
        stiffness times the coordinates' size, times the machine epsilon (observed floors are
        up to 20 times this)."""
        s = self.beam.section
        size = max(1.0, float(np.max(np.abs(self.beam.nodes_mm))))
        forces = max(s.EA_N, s.GA_y_N, s.GA_z_N) * size
        moments = max(s.EI_y_Nmm2, s.EI_z_Nmm2, s.GJ_Nmm2)
        return ROUND_OFF * (forces + moments) / min(self.element_lengths)


def _cross(r: np.ndarray) -> np.ndarray:
    """[r]x: the matrix of r x (.)."""
    return np.array([[0.0, -r[2], r[1]], [r[2], 0.0, -r[0]], [-r[1], r[0], 0.0]])
