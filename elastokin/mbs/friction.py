"""Dry friction in spherical joints (the synthetic real suspension only) as Jenkins elements:
a rotational stick spring between the two parts (stiffness = breakaway torque / presliding
rotation) whose anchor slips so that the torque never exceeds the breakaway torque (return
mapping after every solved step). Rate-independent hysteresis. Torques N*mm, rotations rad."""

from __future__ import annotations

import numpy as np
from exudyn.itemInterface import ObjectConnectorRigidBodySpringDamper

from elastokin.errors import ModelError
from elastokin.mbs.exudyn_api import exu

#: re-solves of a step at most, and the accepted torque excess (relative)
FRICTION_ITERATIONS = 200
FRICTION_TOLERANCE = 1e-3


def add_element(model, name: str, torque_Nmm: float, presliding_rad: float) -> dict:
    """The friction element of the spherical joint ``name`` of ``model``."""
    s = model.suspension
    joint = next((j for j in s.joints if j.name == name), None)
    if joint is None or joint.kind != "spherical":
        raise ModelError(f"{s.source}: ball-joint friction on '{name}': expected the name of "
                         "a spherical joint")
    if not torque_Nmm > 0:
        raise ModelError(f"{s.source}: ball-joint friction on '{name}': breakaway torque "
                         f"must be positive, got {torque_Nmm}")
    k = torque_Nmm / presliding_rad  # N*mm/rad
    m0 = model.rigid_marker(joint.parts[0], joint.position_mm, np.eye(3))
    m1 = model.rigid_marker(joint.parts[1], joint.position_mm, np.eye(3))
    obj = model.mbs.AddObject(ObjectConnectorRigidBodySpringDamper(
        markerNumbers=[m0, m1], stiffness=np.diag([0.0, 0.0, 0.0, k, k, k]),
        damping=np.zeros((6, 6)), offset=[0.0] * 6, name=f"friction:{name}"))
    return {"object": obj, "k": k, "torque": float(torque_Nmm), "anchor": np.zeros(3)}


def slip(model) -> float:
    """Return mapping of every friction element at the current state: where the stick torque
    exceeds the breakaway torque the anchor moves so that it equals it. Returns the largest
    excess torque relative to the breakaway torque (0 when all stick)."""
    ovt = exu.OutputVariableType
    worst = 0.0
    for e in model.friction.values():
        theta = np.asarray(model.mbs.GetObjectOutput(e["object"], ovt.Rotation), float)
        trial = e["k"] * (theta - e["anchor"])
        size = float(np.linalg.norm(trial))
        if size > e["torque"]:
            worst = max(worst, size / e["torque"] - 1.0)
            e["anchor"] = theta - (e["torque"] / e["k"]) * trial / size
            model.mbs.SetObjectParameter(e["object"], "offset",
                                         [0.0, 0.0, 0.0, *e["anchor"].tolist()])
    return worst


def set_active(model, on: bool) -> None:
    """Friction on (stick springs at their stiffness) or released (no stick torque)."""
    for e in model.friction.values():
        k = e["k"] if on else 0.0
        model.mbs.SetObjectParameter(e["object"], "stiffness", np.diag([0.0, 0.0, 0.0, k, k, k]))


def at_rest(model) -> None:
    """Anchor every friction element at its current rotation (no stick torque)."""
    ovt = exu.OutputVariableType
    for e in model.friction.values():
        e["anchor"] = np.asarray(model.mbs.GetObjectOutput(e["object"], ovt.Rotation), float)
        model.mbs.SetObjectParameter(e["object"], "offset",
                                     [0.0, 0.0, 0.0, *e["anchor"].tolist()])


def reset(model) -> None:
    """Every anchor back at the design position."""
    for e in model.friction.values():
        e["anchor"] = np.zeros(3)
        model.mbs.SetObjectParameter(e["object"], "offset", [0.0] * 6)
