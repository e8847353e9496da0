"""The flexible beam part's elements alone (elastokin.mbs.beams) against closed-form beam
theory: a cantilever clamped at its root, loads at its tip, Timoshenko beam (shear
deformable), small loads (linear range).

Closed forms (L length, F tip force across the beam, T tip torque, e shear-centre offset):
tip deflection ``F L^3 / (3 EI) + F L / GA`` (bending + shear); twist ``T L / GJ``; a force
at the node line of a section whose shear centre is ``e`` away from it twists the beam by
``F e L / GJ`` and the node line deflects by ``F e^2 L / GJ`` more. The element converges as
the square of its length under the cantilever's linear bending moment (torsion is exact):
Richardson's extrapolation of n and 2n elements, ``(4 u_2n - u_n) / 3``, removes that error.
"""

from __future__ import annotations

import numpy as np
import pytest
from exudyn.itemInterface import (
    LoadForceVector,
    LoadTorqueVector,
    MarkerBodyRigid,
    ObjectGround,
    ObjectJointGeneric,
)
from scipy.spatial.transform import Rotation

from elastokin.config.suspension import Beam, BeamSection
from elastokin.mbs.beams import BeamBody
from elastokin.mbs.exudyn_api import exu
from elastokin.physics.beams import section_frame, section_offset_mm

E, G = 210000.0, 81000.0  # steel, N/mm^2
SECTION = BeamSection(EA_N=E * 400, EI_y_Nmm2=E * 2e5, EI_z_Nmm2=E * 5e5,
                      GJ_Nmm2=G * 3e3, GA_y_N=G * 200, GA_z_N=G * 150)
L = 1000.0


def beam(nodes, z_axis=(0.0, 0.0, 1.0), n=8, shear_centre=(0.0, 0.0)) -> Beam:
    nodes = np.asarray(nodes, float)
    frames = np.array([section_frame(a, b, z_axis) for a, b in zip(nodes[:-1], nodes[1:])])
    offsets = np.array([section_offset_mm(R, shear_centre) for R in frames])
    names = tuple(f"n{i}" for i in range(len(nodes)))
    return Beam("beam", names, nodes, frames, offsets, SECTION, n)


def tip_response(b: Beam, force=(0.0, 0.0, 0.0), torque=(0.0, 0.0, 0.0)):
    """(tip displacement mm, tip rotation vector rad), config frame, of ``b`` clamped at its
    first node under a force and torque (config frame) at its last node."""
    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    ground = mbs.AddObject(ObjectGround())
    body = BeamBody(mbs, b)
    root, tip = b.nodes_mm[0], b.nodes_mm[-1]
    clamp = mbs.AddMarker(MarkerBodyRigid(bodyNumber=ground, localPosition=root.tolist()))
    mbs.AddObject(ObjectJointGeneric(markerNumbers=[clamp, body.rigid_marker(root, np.eye(3))],
                                     constrainedAxes=[1] * 6))
    marker = body.rigid_marker(tip, np.eye(3))
    mbs.AddLoad(LoadForceVector(markerNumber=marker, loadVector=list(force)))
    mbs.AddLoad(LoadTorqueVector(markerNumber=marker, loadVector=list(torque)))
    mbs.Assemble()
    ss = exu.SimulationSettings()
    ss.staticSolver.verboseMode = 0
    ss.solution.file.write = False  # no solution/ folder in the working directory
    ss.staticSolver.newton.relativeTolerance = 1e-12
    ss.staticSolver.newton.absoluteTolerance = 100 * body.round_off_N
    ss.linearSolver.solverType = exu.LinearSolverType.EigenDense
    assert mbs.SolveStatic(ss)
    node = body.named[len(b.nodes_mm) - 1]
    u = np.asarray(mbs.GetNodeOutput(node, exu.OutputVariableType.Displacement))
    R = np.asarray(mbs.GetNodeOutput(node, exu.OutputVariableType.RotationMatrix))
    return u, Rotation.from_matrix(R.reshape(3, 3) @ body.frames[node].T).as_rotvec()


def richardson(make, n=8, **loads):
    """Tip displacement and rotation extrapolated from n and 2n elements per segment, with the
    n-element result."""
    coarse, fine = tip_response(make(n), **loads), tip_response(make(2 * n), **loads)
    return tuple((4 * f - c) / 3 for c, f in zip(coarse, fine)), coarse


def straight(direction=(1.0, 0.0, 0.0), z_axis=(0.0, 0.0, 1.0), shear_centre=(0.0, 0.0)):
    d = np.asarray(direction, float) / np.linalg.norm(direction)
    return lambda n: beam([np.zeros(3), L * d], z_axis, n, shear_centre)


@pytest.mark.parametrize("direction, z_axis", [
    ((1.0, 0.0, 0.0), (0.0, 0.0, 1.0)),
    ((0.0, 1.0, 0.0), (0.0, 0.0, 1.0)),  # a cross beam of an axle
    ((0.3, 0.5, 0.8), (0.0, 0.0, 1.0)),
    ((0.0, 0.0, 1.0), (1.0, 0.0, 0.0)),  # section z along x: nodes' axes relabelled
])
def test_tip_force_and_torque(direction, z_axis):
    make = straight(direction, z_axis)
    R = section_frame(np.zeros(3), np.asarray(direction, float), z_axis)
    F, T = 10.0, 1000.0
    (u, _), (u8, _) = richardson(make, force=F * R[:, 2])
    bending = F * L**3 / (3 * SECTION.EI_y_Nmm2) + F * L / SECTION.GA_z_N
    assert R[:, 2] @ u == pytest.approx(bending, rel=1e-6)
    # the element's error: 0.39 % with 8 elements, a quarter of it with 16 (h^2)
    assert R[:, 2] @ u8 / bending - 1 == pytest.approx(-0.0039, abs=2e-4)
    (u, _), _ = richardson(make, force=F * R[:, 1])
    assert R[:, 1] @ u == pytest.approx(F * L**3 / (3 * SECTION.EI_z_Nmm2)
                                        + F * L / SECTION.GA_y_N, rel=1e-6)
    _, rot = tip_response(make(8), torque=T * R[:, 0])
    assert R[:, 0] @ rot == pytest.approx(T * L / SECTION.GJ_Nmm2, rel=1e-9)
    (u, _), _ = richardson(make, force=F * R[:, 0])
    assert R[:, 0] @ u == pytest.approx(F * L / SECTION.EA_N, rel=1e-6)


def test_shear_centre_offset():
    """A force at the node line twists a section whose shear centre is off that line; the
    same force through the shear centre (a force at the node line and its moment about the
    shear centre) does not."""
    e = 20.0
    make = straight(shear_centre=(e, 0.0))  # the shear centre along the section's y
    F = 10.0
    (u, rot), _ = richardson(make, force=(0.0, 0.0, F))
    # beam along x, z up: y points to +y; a +z force at the node line, e along +y from the
    # shear centre's point of view is a torque -F e about x
    assert rot[0] == pytest.approx(-F * e * L / SECTION.GJ_Nmm2, rel=1e-5)
    assert u[2] == pytest.approx(F * L**3 / (3 * SECTION.EI_y_Nmm2) + F * L / SECTION.GA_z_N
                                 + F * e**2 * L / SECTION.GJ_Nmm2, rel=1e-5)
    _, rot = tip_response(make(8), force=(0.0, 0.0, F), torque=(F * e, 0.0, 0.0))
    assert abs(rot[0]) < 1e-6 * F * e * L / SECTION.GJ_Nmm2
    # without the offset, no twist at all
    _, rot = tip_response(straight()(8), force=(0.0, 0.0, F))
    assert abs(rot[0]) < 1e-15


def test_kinked_beam():
    """An L-shaped cantilever: segment a along x, then b along y (its nodes at the corner tied
    rigidly), a vertical tip force. Closed form: both segments bend in the vertical plane (EI_y
    on each: y = z x x), segment a also twists by F b (its end rotation turns segment b):
    ``w = F (a^3 + b^3) / (3 EI) + F (a + b) / GA_z + F b^2 a / GJ``."""
    a, b_ = 600.0, 400.0

    def make(n):
        return beam([[0.0, 0.0, 0.0], [a, 0.0, 0.0], [a, b_, 0.0]], n=n)

    F = 1.0  # 1e-3 rad of twist: the geometric nonlinearity below 1e-5
    (u, _), _ = richardson(make, force=(0.0, 0.0, F))
    s = SECTION
    expected = (F * (a**3 + b_**3) / (3 * s.EI_y_Nmm2) + F * (a + b_) / s.GA_z_N
                + F * b_**2 * a / s.GJ_Nmm2)
    assert u[2] == pytest.approx(expected, rel=1e-5)


def test_beam_node_sensors_of_a_run_that_reached_no_step():
    """A solve that fails before its first step leaves no rows: a beam's node arrays are
    empty (steps 0, nodes, ...), not a reshape error hiding the solver's message."""
    from types import SimpleNamespace

    from elastokin.mbs.solve import combined_sensors

    frames = {n: np.eye(3) for n in ("a", "b")}
    model = SimpleNamespace(bushings={}, node_lines={"beam": ["a", "b"]},
                            beams={"beam": SimpleNamespace(frames=frames)})
    data = {f"part:node:{n}:{k}": np.zeros((0, 9 if k == "R" else 3))
            for n in frames for k in ("R", "disp")}
    out = combined_sensors(data, model)
    assert out["beam:beam:node_R"].shape == (0, 2, 3, 3)
    assert out["beam:beam:node_x"].shape == (0, 2, 3)
