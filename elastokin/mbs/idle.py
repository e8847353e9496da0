"""Idle spins of a model whose bushings are ideal joints, held by torsion springs.

With every bushing replaced by its ideal joint, some parts can turn without moving the wheel:
a strut rod about its own axis (a spherical top mount and a cylindrical strut), an arm between
two ball joints about the line through them. Only the ideal joints' regularising rates (1e-3 of
the bushing's) hold these idle spins, and a coil spring whose seats sit off the strut axis turns
the rod with a torque that grows with the turn: with the seats 1 mm off the axis the static
solve diverged (issue 15). Here each idle spin (the null space of the joints' constraint
Jacobian with the wheel part held) gets a torsion spring to ground about its own axis, at the
bushing's full rotational rate: it holds what the rubber holds in reality, and, being about an
idle axis, it changes neither the wheel's kinematics nor, to first order, the wheel rate.

Units: N*mm/rad inside Exudyn; the config frame.
"""

from __future__ import annotations

import numpy as np
from exudyn.itemInterface import (
    MarkerBodyRigid,
    ObjectConnectorRigidBodySpringDamper,
    ObjectJointGeneric,
)

from elastokin.mbs.exudyn_api import exu, exudyn_call
from elastokin.mbs.solve import simulation_settings
from elastokin.physics.pose import frame_from_z

#: a part's rotation counts as idle when its share of a null-space vector is above this
IDLE_THRESHOLD = 1e-6
RAD_PER_DEG = np.pi / 180.0


def idle_axes(model) -> dict[str, list[np.ndarray]]:
    """Per part, the unit axes (config frame) about which it can turn while the wheel parts
    are held and every joint (bushings as their ideal joints) is kept: the idle spins."""
    mbs, s = model.mbs, model.suspension
    wheels = list(dict.fromkeys(model.wheel_parts.values()))  # in order: reproducible
    holds = []
    for wheel in wheels:
        marker_g = mbs.AddMarker(MarkerBodyRigid(bodyNumber=model.ground,
                                                 localHT=exu.HT(np.eye(3), model.ref[wheel])))
        marker_w = model.rigid_marker(wheel, model.ref[wheel], np.eye(3))
        holds.append(mbs.AddObject(ObjectJointGeneric(
            markerNumbers=[marker_g, marker_w], constrainedAxes=[1] * 6, activeConnector=True,
            name=f"idle:hold_wheel:{wheel}")))
    try:
        exudyn_call(mbs.Assemble, f"{s.source}: finding idle spins")
        solver = exu.MainSolverStatic()
        ss = simulation_settings(model, 1)
        exudyn_call(lambda: solver.InitializeSolver(mbs, ss), f"{s.source}: idle spins")
        exudyn_call(lambda: solver.ComputeNewtonJacobian(mbs, ss), f"{s.source}: idle spins")
        jac = np.asarray(solver.GetSystemJacobian())
    finally:
        for hold in holds:
            mbs.SetObjectParameter(hold, "activeConnector", False)
        exudyn_call(mbs.Assemble, f"{s.source}: finding idle spins")
    n2 = mbs.systemData.ODE2Size()
    # a beam part counts as rigid: its deformations are held by its stiffness
    _, sv, vt = np.linalg.svd(np.vstack([jac[n2:, :n2], model.rigid_beam_rows()]))
    rank = int(np.sum(sv > 1e-9 * sv[0]))
    null = vt[rank:]
    out: dict[str, list[np.ndarray]] = {}
    for part, node in model.node.items():
        if part in wheels or not null.size:
            continue
        i0 = mbs.GetNodeODE2Index(node)
        rot = null[:, i0 + 3:i0 + 6]  # Tait-Bryan parameters: the rotation vector near 0
        _, s_rot, v_rot = np.linalg.svd(rot)
        axes = [v_rot[k] / np.linalg.norm(v_rot[k]) for k in range(s_rot.size)
                if s_rot[k] > IDLE_THRESHOLD]
        if axes:
            out[part] = axes
    return out


def hold_idle_spins(model) -> dict[str, list[int]]:
    """Add a torsion spring to ground about every idle axis of every part (see the module
    docstring), at the largest rotational rate at zero of the bushings on that part; parts
    without a bushing keep their spins as they are. Returns the spring objects by part."""
    rates: dict[str, float] = {}
    for b in model.suspension.bushings:
        k = max(law.rate_at_zero for law in b.laws[3:]) / RAD_PER_DEG  # N*mm/rad
        for part in b.parts:
            rates[part] = max(rates.get(part, 0.0), k)
    springs: dict[str, list[int]] = {}
    for part, axes in idle_axes(model).items():
        if part not in rates:
            continue
        for k, axis in enumerate(axes):
            springs.setdefault(part, []).append(_torsion_spring(model, part, axis, rates[part],
                                                                k))
    if springs:
        exudyn_call(model.mbs.Assemble, f"{model.suspension.source}: holding idle spins")
        model.geometry.in_place = False  # their axes follow from the model's Jacobian
    return springs


def _torsion_spring(model, part: str, axis: np.ndarray, rate: float, k: int) -> int:
    frame = frame_from_z(axis / np.linalg.norm(axis))
    ref = model.ref[part]
    m0 = model.mbs.AddMarker(MarkerBodyRigid(bodyNumber=model.ground,
                                             localHT=exu.HT(frame, ref)))
    m1 = model.rigid_marker(part, ref, frame)
    return model.mbs.AddObject(ObjectConnectorRigidBodySpringDamper(
        markerNumbers=[m0, m1], stiffness=np.diag([0.0] * 5 + [rate]),
        damping=np.zeros((6, 6)), name=f"idle:{part}:{k}"))
