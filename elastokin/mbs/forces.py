"""Forces that each connector and attachment of a solved model applies to one part (config
frame, N): an independent check of a static solve (they must sum to zero)."""

from __future__ import annotations

import numpy as np

from elastokin.mbs.contact import arm_name
from elastokin.mbs.exudyn_api import exu
from elastokin.mbs.model import SuspensionModel


def _marker_rotation(model: SuspensionModel, obj: int, k: int) -> np.ndarray:
    mbs = model.mbs
    m = mbs.GetObject(obj)["markerNumbers"][k]
    marker = mbs.GetMarker(m)
    local = np.asarray(marker["localHT"])[:3, :3] if marker.get("localHT") is not None \
        else np.eye(3)
    if "nodeNumber" in marker:  # at a node of a beam part
        R = np.asarray(mbs.GetNodeOutput(marker["nodeNumber"],
                                         exu.OutputVariableType.RotationMatrix))
        return R.reshape(3, 3) @ local
    body = marker["bodyNumber"]
    if body == model.ground:
        return local
    R = np.asarray(mbs.GetObjectOutputBody(body, exu.OutputVariableType.RotationMatrix,
                                           [0, 0, 0]))
    return R.reshape(3, 3) @ local


def _marker_position(model: SuspensionModel, obj: int, k: int) -> np.ndarray:
    m = model.mbs.GetObject(obj)["markerNumbers"][k]
    return np.asarray(model.mbs.GetMarkerOutput(m, exu.OutputVariableType.Position))


def forces_on_part(model: SuspensionModel, part: str) -> dict[str, np.ndarray]:
    """Force (N, config frame) that each connector applies to ``part`` in the current (last
    solved) state, by connector name; supports and loads attached to the part are summed per
    owner (the part of their name before ':', e.g. ``rig``). Joint torques are not included."""
    mbs, s = model.mbs, model.suspension
    ovt = exu.OutputVariableType
    out: dict[str, np.ndarray] = {}

    def sign(parts: tuple[str, str]) -> float:
        return (-1.0 if parts[0] == part else 1.0) if part in parts else 0.0

    for j in s.joints:
        obj = model.joints[j.name]
        if sign(j.parts):
            if mbs.GetObject(obj)["objectType"] == "JointSpherical":
                f1 = np.asarray(mbs.GetObjectOutput(obj, ovt.Force))  # on body 1, global
            else:
                f1 = _marker_rotation(model, obj, 0) @ np.asarray(
                    mbs.GetObjectOutput(obj, ovt.ForceLocal))
            out[j.name] = sign(j.parts) * f1
    for lk in s.links:
        if sign(lk.parts):
            obj = model.links[lk.name]
            d = _marker_position(model, obj, 1) - _marker_position(model, obj, 0)
            # the distance constraint's multiplier is positive in compression
            compression = float(np.asarray(mbs.GetObjectOutput(obj, ovt.Force)).ravel()[0])
            out[lk.name] = sign(lk.parts) * compression * d / np.linalg.norm(d)
    for b in s.bushings:
        if sign(b.parts):
            e = model.bushings[b.name]
            f0 = _marker_rotation(model, e["object"], 0) @ np.asarray(
                mbs.GetObjectOutput(e["object"], ovt.ForceLocal))  # +K*u: on body 0
            total = -f0
            if e.get("ideal") is not None:
                total = total + _marker_rotation(model, e["ideal"], 0) @ np.asarray(
                    mbs.GetObjectOutput(e["ideal"], ovt.ForceLocal))
            out[b.name] = sign(b.parts) * total
    for sp in s.springs:
        if sign(sp.parts):
            obj = model.springs[sp.name]
            d = _marker_position(model, obj, 1) - _marker_position(model, obj, 0)
            tension = float(mbs.GetObjectOutput(obj, ovt.ForceLocal))
            out[sp.name] = -sign(sp.parts) * tension * d / np.linalg.norm(d)
    _attachment_forces(model, part, out)
    return out


def _attachment_forces(model: SuspensionModel, part: str, out: dict) -> None:
    """Supports and loads on ``part``; a support on a wheel's contact arm acts on its wheel
    part (the massless arm passes the force on through its joint,
    :mod:`elastokin.mbs.contact`)."""
    mbs = model.mbs
    ovt = exu.OutputVariableType
    carrier = {arm_name(side): w.part for side, w in model.suspension.wheels.items()}

    def add(name: str, force) -> None:
        owner = name.partition(":")[0]
        force = np.asarray(force, float)
        out[owner] = out[owner] + force if owner in out else force

    for name, e in model.supports.items():
        if carrier.get(e["part"], e["part"]) == part \
                and mbs.GetObjectParameter(e["object"], "activeConnector"):
            add(name, mbs.GetObjectOutput(e["object"], ovt.ForceLocal))
    for name, e in model.loads.items():
        if e["part"] != part:
            continue
        if e["kind"] == "force":
            add(name, mbs.GetLoadValues(e["load"]))
        elif e["kind"] == "contact" and mbs.GetObjectParameter(e["object"],
                                                               "activeConnector"):
            # the connector's loads are those on its first body, the ground
            add(name, -np.asarray(mbs.GetObjectOutput(e["object"], ovt.ForceLocal)))
