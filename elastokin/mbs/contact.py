"""The tyre's contact point in the model: supports and loads at the wheel's lowest point.

The contact point is ONE point, :func:`elastokin.physics.steering_geometry.contact_point`: the
wheel's lowest point along the ground normal (``up``), ``loaded_radius_mm`` from the wheel
centre in the wheel plane. It is not fixed to the wheel part: the tyre rolls on the rig's pad,
so as the knuckle pitches the point slides round the tyre (a point fixed to the knuckle at the
design contact point is 1.95 mm behind the tyre's bottom at -50 mm travel on a plain double
wishbone). Exudyn's markers are fixed to their body; two elements put the rig's support and
loads at the moving point exactly, at every Newton iteration of every step (no lag, no
re-solve):

- **the contact arm** (:func:`contact_arm`): a massless body per wheel turning about the spin
  axis at the wheel centre (a revolute joint to the wheel part) whose tip, ``loaded_radius_mm``
  out, is kept at the wheel's lowest point by one rotation constraint against the ground: the
  arm's tangent stays horizontal, i.e. the arm stays in the vertical plane through the spin
  axis. A support at the tip holds the lowest point's height. Its vertical reaction has no
  moment about the spin axis (the tip lies in the vertical plane through it), so the
  rotation constraint carries nothing and the wheel part receives exactly the vertical force
  at its lowest point through the revolute joint.
- **the contact load** (:func:`add_contact_load`): a force at the lowest point of the braked
  wheel (a braking force's moment about the spin axis belongs to the wheel part, which the
  free-turning arm could not pass on) is a connector from ground to the wheel centre whose
  user function gives the force and its moment ``(P - c) x F``, ``P - c`` the loaded radius
  along the wheel plane's downward direction at the wheel part's current rotation.

Units mm, N, N*mm; rotations rad inside Exudyn; the config frame (``up`` is its z axis).
"""

from __future__ import annotations

import math

import numpy as np
from exudyn.itemInterface import ObjectConnectorRigidBodySpringDamper, ObjectJointGeneric

from elastokin.mbs.exudyn_api import exu, exudyn_call
from elastokin.mbs.user_functions import attach_user_function, make_path_function
from elastokin.physics.pose import frame_from_z

#: the arm turns about the spin axis (its frame's z) and nothing else
REVOLUTE_Z = (1, 1, 1, 1, 1, 0)
#: one rotation held: the ground frame's y (up) normal to the arm frame's z (its tangent)
TANGENT_HORIZONTAL = (0, 0, 0, 1, 0, 0)


def arm_name(side: str) -> str:
    """The contact arm of the wheel on ``side`` (a body of the model, not a suspension part)."""
    return f"wheel:contact_arm:{side}"


def contact_arm(model, side: str, item: tuple[str, str] | None = None) -> str:
    """The contact arm of the wheel on ``side`` (module docstring), added on first use; its tip
    is the wheel's contact point at the design position (``Wheel.contact_patch_mm``).
    Returns its name, the part to attach supports at the contact point to. ``item``: the
    reported load (:mod:`elastokin.mbs.loads`) its joint to the wheel part belongs to (what a
    support on the arm applies to the wheel passes through it). Its markers are functions of
    the suspension (:func:`wheel_centre`, :func:`spin_frame`, :func:`down_frames`): a
    design's twin moves them in place (:mod:`elastokin.mbs.geometry`)."""
    name = arm_name(side)
    if item is not None:
        model.load_items[f"{name}:spin"] = item
    if name in model.rig_bodies:
        return name
    w = model.suspension.wheels[side]
    model.add_rig_body(name, w.centre_mm)
    centre, spin = wheel_centre(side), spin_frame(side)
    m_wheel = model.rigid_marker(w.part, centre, spin)
    m_arm = model.rigid_marker(name, centre, spin)
    mbs = model.mbs
    mbs.AddObject(ObjectJointGeneric(markerNumbers=[m_wheel, m_arm],
                                     constrainedAxes=list(REVOLUTE_Z), name=f"{name}:spin"))
    m_ground = model.rigid_marker(model.suspension.ground, centre,
                                  lambda s: down_frames(s, side)[0])
    m_tangent = model.rigid_marker(name, centre, lambda s: down_frames(s, side)[1])
    mbs.AddObject(ObjectJointGeneric(markerNumbers=[m_ground, m_tangent],
                                     constrainedAxes=list(TANGENT_HORIZONTAL),
                                     name=f"{name}:down"))
    exudyn_call(mbs.Assemble, f"{model.suspension.source}: the contact arm of the {side} "
                              "wheel")
    return name


def wheel_centre(side: str):
    """The design wheel centre (mm) of the wheel on ``side`` of a suspension."""
    return lambda s: s.wheels[side].centre_mm


def spin_frame(side: str):
    """A frame (columns) whose z is the design spin axis of the wheel on ``side``."""
    return lambda s: frame_from_z(s.wheels[side].spin_axis)


def down_frames(suspension, side: str) -> tuple[np.ndarray, np.ndarray]:
    """(the ground's frame, the arm's) of the contact arm's rotation constraint at the design
    position: the ground frame's y is ``up``, the arm frame's z the wheel's tangent (normal to
    its spin axis and to ``up``)."""
    up = suspension.up
    tangent = np.cross(suspension.wheels[side].spin_axis, up)
    tangent /= np.linalg.norm(tangent)
    return np.column_stack([tangent, up, np.cross(tangent, up)]), frame_from_z(tangent)


def add_contact_load(model, name: str, side: str, item: tuple[str, str] | None = None) -> str:
    """A force (N, config frame) at the contact point of the wheel on ``side`` following a
    path given when solving (module docstring; inactive without one); ``item``: the reported
    load it belongs to (:mod:`elastokin.mbs.loads`). Returns ``name``. The loaded radius is
    compiled into the load's user function: a design's twin with another is built as a model
    of its own (:class:`~elastokin.mbs.geometry.Geometry`'s ``fixed``)."""
    w = model.suspension.wheels[side]
    centre = wheel_centre(side)
    m_ground = model.rigid_marker(model.suspension.ground, centre, np.eye(3))
    # the wheel part's marker has its z along the spin axis: the connector's rotation
    # parameters then give the current spin axis with two angles (contact_load_function)
    m_wheel = model.rigid_marker(w.part, centre, spin_frame(side))
    obj = model.mbs.AddObject(ObjectConnectorRigidBodySpringDamper(
        markerNumbers=[m_ground, m_wheel], stiffness=np.zeros((6, 6)),
        damping=np.zeros((6, 6)), activeConnector=False, name=name))
    model.loads[name] = {"object": obj, "part": w.part, "marker": m_wheel, "kind": "contact",
                         "side": side}
    model.geometry.fixed.append(lambda s, _: s.wheels[side].loaded_radius_mm)
    if item is not None:
        model.load_items[name] = item
    exudyn_call(model.mbs.Assemble, f"{model.suspension.source}: attaching '{name}'")
    return name


def set_contact_path(model, name: str, ts: np.ndarray, values: np.ndarray) -> None:
    """Make the contact load ``name`` follow the piecewise-linear path ``values`` (n+1, 3)
    over load time ``ts`` (an all-zero path switches it off)."""
    e = model.loads[name]
    mbs = model.mbs
    active = bool(np.any(values))
    mbs.SetObjectParameter(e["object"], "activeConnector", active)
    if not active:  # no user function of an earlier solve left behind
        mbs.SetObjectParameter(e["object"], "springForceTorqueUserFunction", 0)
        return
    symbolic = model.options.user_functions == "symbolic"
    set_contact_function(model, name, make_path_function(ts, values, "load", symbolic),
                         symbolic)


def set_contact_function(model, name: str, path, symbolic: bool = False) -> None:
    """Make the contact load ``name`` apply the force ``path(mbs, t, None)`` (N, config frame;
    a path function of :mod:`elastokin.mbs.user_functions`, or any Python function of that
    signature: the design sensitivities' twins feed the force of the step at hand,
    :class:`~elastokin.mbs.twins.StepInputs`), and switch it on."""
    e = model.loads[name]
    w = model.suspension.wheels[e["side"]]
    model.mbs.SetObjectParameter(e["object"], "activeConnector", True)
    function = contact_load_function(path, w.loaded_radius_mm, symbolic)
    attach_user_function(model, e["object"], "springForceTorqueUserFunction", function,
                         symbolic, model.keep_alive)


def contact_load_function(path, loaded_radius_mm: float, symbolic: bool):
    """The contact load's ``springForceTorqueUserFunction``: the force ``path(t)`` (N, config
    frame) at the contact point, as the force and its moment about the wheel centre, from the
    current spin axis ``a``: the third column of the connector's rotation (Tait-Bryan x-y-z
    angles of the wheel part's marker, its z the spin axis, against the ground),
    ``a = (sin t1, -sin t0 cos t1, cos t0 cos t1)``; the contact point lies ``r = R (a_z a -
    up) / sqrt(1 - a_z^2)`` from the centre (``up`` the config frame's z). Exudyn's sign: the
    loads on the connector's first body, the ground."""
    sin, cos, sqrt = (exu.symbolic.sin, exu.symbolic.cos, exu.symbolic.sqrt) if symbolic \
        else (math.sin, math.cos, math.sqrt)
    radius = float(loaded_radius_mm)

    def forces(mbs, t, itemNumber, displacement, rotation, velocity, angularVelocity,
               stiffness, damping, rotJ0, rotJ1, offset):
        f = path(mbs, t, None)
        s0, c0, s1, c1 = sin(rotation[0]), cos(rotation[0]), sin(rotation[1]), cos(rotation[1])
        az = c0 * c1
        n = sqrt(1.0 - az * az)
        scale = radius * az / n
        r = [scale * s1, -scale * s0 * c1, -radius * n]
        m = [r[1] * f[2] - r[2] * f[1], r[2] * f[0] - r[0] * f[2], r[0] * f[1] - r[1] * f[0]]
        return [-f[0], -f[1], -f[2], -m[0], -m[1], -m[2]]

    return forces
