"""The loads every element of a model transmits at every recorded step, read back from Exudyn
in C++ (sensors) and turned into forces and moments in numpy (:class:`LoadRecorder`).

Every connector of the model (joints, links, bushings and their ideal joints, springs, stops,
the anti-roll bar, ball-joint friction, idle-spin springs), every support and every load is an
*element*; elements are grouped into the reported *items* (:class:`~elastokin.physics.states
.LoadItem`): a bushing modelled by its ideal joint is that joint plus its regularising spring,
a ball joint with friction is the joint plus its friction element, a wheel's contact patch is
the rig's pad plus the loads at the patch and the wheel centre (attachments name their item,
:meth:`~elastokin.mbs.model.SuspensionModel.add_support`; an object added outside the config
names it in ``SuspensionModel.load_items``; an attachment's load is on the part it holds). A
flexible (beam) part's own ties are internal to it; a connection at one of its nodes is read
at the node's recorded pose.

What Exudyn applies (its C++ source, checked here by every part's free-body equilibrium to the
Newton residual, ``tests/test_loads.py``):

- ``ObjectJointSpherical``: output ``Force`` is the force on marker 1's body, global; the
  opposite on marker 0's, each at its marker.
- ``ObjectJointGeneric``: ``ForceLocal`` is the Lagrange multiplier of the translations in the
  joint frame J0 (marker 0's), the force on marker 1's body; ``TorqueLocal`` is the *raw*
  multiplier of each rotation constraint ``a0 . b1`` (an axis of J0 dotted with one of J1), not
  a torque: the torque on marker 1's body is ``-sum lambda_k (a0_k x b1_k)``. With all three
  translations held the forces act at each marker; otherwise (a cylindrical joint, a pad)
  both act at marker 1.
- ``ObjectConnectorDistance``: ``Force`` is the multiplier, + pushing the markers apart.
- ``ObjectConnectorSpringDamper``: ``ForceLocal`` is the tension.
- ``ObjectConnectorRigidBodySpringDamper``: ``ForceLocal``, ``TorqueLocal`` in J0 are the
  force and torque on marker 0's body at marker 0; the opposite on marker 1's body at marker
  1 (the moments are not transferred between the two points: the deflection makes them
  differ by (p1 - p0) x F, Exudyn's small-deflection formulation). With
  ``useIntrinsicFormulation`` (the anti-roll bar) both act at the mid-point, in the mid-frame.

Units mm, N, N*mm; config frame.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np
from exudyn.itemInterface import SensorLoad, SensorNode, SensorObject

from elastokin.errors import ModelError
from elastokin.mbs.exudyn_api import exu
from elastokin.physics.loads import (
    FORCE,
    FORCE_LOCAL,
    MOMENT,
    MOMENT_B,
    MOMENT_LOCAL,
    POINT,
    POINT_B,
    QUANTITIES,
)
from elastokin.physics.states import LoadItem, LoadTable

#: the kind of a reported item by the prefix of its Exudyn object's name (mbs.model)
KIND_BY_PREFIX = {"joint": "joint", "link": "link", "bushing": "bushing", "ideal": "bushing",
                  "spring": "spring", "stop": "stop", "friction": "joint", "idle": "idle_spin"}
#: items whose force acts along the line between their two points (no moment)
TWO_POINT = ("link", "spring", "stop")
#: the raw outputs recorded per Exudyn object type
OUTPUTS = {"JointSpherical": ("Force",), "JointGeneric": ("ForceLocal", "TorqueLocal"),
           "ConnectorDistance": ("Force",), "ConnectorSpringDamper": ("ForceLocal",),
           "ConnectorRigidBodySpringDamper": ("ForceLocal", "TorqueLocal")}


@dataclass
class _Marker:
    """Where a marker is: on the body or node whose pose is recorded as ``part:<key>:R``,
    ``part:<key>:disp`` (None: the ground) at ``local`` (relative to its reference point
    ``ref``, design position) with axes ``rotation`` (columns, in its frame); ``part``: the
    suspension's part it belongs to (a beam part's for its nodes; the ground's, also for a
    rig body)."""

    key: str | None
    local: np.ndarray
    rotation: np.ndarray
    ref: np.ndarray
    part: str | None


@dataclass
class _Element:
    """One Exudyn object or load and how it enters its item: ``flip`` when the item's first
    part is the object's marker-1 body (supports: the load on the suspension's part)."""

    item: int
    kind: str  # Exudyn object type, or "Load"/"LoadTorque"
    number: int
    markers: tuple[_Marker, ...]
    flip: bool = False
    params: dict = field(default_factory=dict)


class LoadRecorder:
    """The elements of a model grouped into items, with the sensors that record them
    (created by :meth:`update` before each solve, as attachments may have been added) and
    :meth:`tables`, the loads of recorded steps."""

    def __init__(self, model):
        self.model = model
        self.items: list[LoadItem] = []
        self.force_only: list[bool] = []  # per item: every element a force at its point
        self.elements: list[_Element] = []
        self.known: set[tuple[str, int]] = set()
        #: the sensor key recording each (object, output) (the model's own sensors reused)
        self.keys: dict[tuple[int, str], str] = {}

    # ------------------------------------------------------------------ elements
    def update(self) -> None:
        """Register every object and load not seen yet, with its sensors."""
        mbs = self.model.mbs
        for key, sensor in self.model.sensors.items():
            if key not in self.keys.values():
                s = mbs.GetSensor(sensor)
                if s["sensorType"] == "Object":
                    self.keys.setdefault((int(s["objectNumber"]), str(
                        s["outputVariableType"]).rpartition(".")[2]), key)
        for number in range(mbs.systemData.NumberOfObjects()):
            if ("object", number) not in self.known:
                self.known.add(("object", number))
                self._add_object(number)
        for number in range(mbs.systemData.NumberOfLoads()):
            if ("load", number) not in self.known:
                self.known.add(("load", number))
                self._add_load(number)

    def _add_object(self, number: int) -> None:
        mbs = self.model.mbs
        obj = mbs.GetObject(number)
        kind = obj["objectType"]
        if kind not in OUTPUTS:
            return
        if obj["name"].startswith("beam:"):
            return  # within a flexible part (its ties): internal, not a load on it
        markers = tuple(self._marker(m) for m in obj["markerNumbers"])
        if not any(self._moving(m) for m in markers):
            return  # between the ground and the rig's own bodies (the heave beam's holder)
        parts = tuple(m.part for m in markers)
        name, what = self._item_name(obj["name"])
        # an attachment's load is on the part it holds (a support: its marker 1)
        attached = obj["name"] in self.model.supports or obj["name"] in self.model.load_items
        flip = attached and not self._moving(markers[0]) and self._moving(markers[1])
        item = self._item(name, what, parts[::-1] if flip else parts)
        params = {"constrained": obj.get("constrainedAxes"),
                  "intrinsic": bool(obj.get("useIntrinsicFormulation", False)),
                  "rotation": (np.asarray(obj.get("rotationMarker0", np.eye(3)), float),
                               np.asarray(obj.get("rotationMarker1", np.eye(3)), float))}
        self.elements.append(_Element(item, kind, number, markers, flip, params))
        constrained = params["constrained"]
        self.force_only[item] &= kind == "JointSpherical" or (
            kind == "JointGeneric" and not any(constrained[3:]))
        for output in _outputs(kind, constrained):
            if (number, output) not in self.keys:
                key = self.keys[number, output] = f"load:{number}:{output}"
                self.model.sensors[key] = mbs.AddSensor(SensorObject(
                    objectNumber=number, storeInternal=True, writeToFile=False,
                    outputVariableType=getattr(exu.OutputVariableType, output)))

    def _add_load(self, number: int) -> None:
        model, mbs = self.model, self.model.mbs
        # (a contact load is an object: mbs.contact)
        entry = next(((n, e) for n, e in model.loads.items()
                      if "load" in e and int(e["load"]) == number), None)
        if entry is None:
            return
        name, e = entry
        marker = self._marker(mbs.GetLoad(number)["markerNumber"])
        if not self._moving(marker):
            return  # on the ground or a rig body (the heave beam's load)
        item = self._item(*self._item_name(name, "load"),
                          (marker.part, model.suspension.ground))
        kind = "Load" if e["kind"] == "force" else "LoadTorque"
        self.elements.append(_Element(item, kind, number, (marker,)))
        self.force_only[item] = False
        model.sensors[f"load:L{number}"] = mbs.AddSensor(SensorLoad(
            loadNumber=number, storeInternal=True, writeToFile=False))

    def _marker(self, number: int) -> _Marker:
        model = self.model
        m = model.mbs.GetMarker(number)
        if m.get("localHT") is not None:  # a rigid marker (it may list localPosition too)
            ht = np.asarray(m["localHT"], float)
            rotation, local = ht[:3, :3], ht[:3, 3]
        else:
            rotation, local = np.eye(3), np.asarray(m.get("localPosition", np.zeros(3)), float)
        if "nodeNumber" in m:  # at a node of a flexible (beam) part
            node = int(m["nodeNumber"])
            part = next((p for p, b in model.beams.items() if node in map(int, b.nodes)), None)
            if part is None:
                raise ModelError(f"{model.suspension.source}: loads cannot be recorded at node "
                                 f"{node}: it belongs to no part")
            key = f"node:{node}"
            if f"part:{key}:R" not in model.sensors:  # its pose: position as displacement
                ovt = exu.OutputVariableType
                for what, output in (("R", ovt.RotationMatrix), ("disp", ovt.Position)):
                    model.sensors[f"part:{key}:{what}"] = model.mbs.AddSensor(SensorNode(
                        nodeNumber=node, outputVariableType=output, storeInternal=True,
                        writeToFile=False))
            return _Marker(key, local, rotation, np.zeros(3), part)
        body = int(m["bodyNumber"])
        if body == int(model.ground):
            return _Marker(None, local, rotation, np.zeros(3), model.suspension.ground)
        key = next((n for n, b in {**model.body, **model.rig_bodies}.items() if int(b) == body),
                   None)
        if key is None:
            raise ModelError(f"{model.suspension.source}: loads cannot be recorded on body "
                             f"{body}: it is no part of the model")
        # a rig body (the heave beam, a wheel's contact arm: mbs.contact) is on the rig's side,
        # the ground's: the contact arm's joint then reports the pad's load on the wheel part
        return _Marker(key, local, rotation, model.ref[key],
                       key if key in model.body else model.suspension.ground)

    def _moving(self, marker: _Marker) -> bool:
        """Whether the marker is on a moving part of the suspension."""
        return marker.part is not None and marker.part != self.model.suspension.ground

    def _item_name(self, name: str, default: str = "support") -> tuple[str, str]:
        """(reported item, its kind) of an Exudyn object or load of this name: an attachment
        or an object the model registered (``model.load_items``), then by the name's
        prefix; a support or load nothing registered: its own name, kind ``default``."""
        model = self.model
        if name in model.load_items:
            item, kind = model.load_items[name]
            return self._free(item), kind
        if name in model.supports or name in model.loads:
            return self._free(name), default
        prefix, _, rest = name.partition(":")
        if name == "anti_roll_bar":
            return self._free("anti_roll_bar"), "anti_roll_bar"
        if prefix == "idle":
            part, _, k = rest.partition(":")
            return self._free(f"idle_spin_{part}_{k}"), "idle_spin"
        if prefix in KIND_BY_PREFIX and rest:
            kind = KIND_BY_PREFIX[prefix]
            steering = model.suspension.axle.steering if model.suspension.axle else None
            if kind == "joint" and steering is not None and rest == steering.joint:
                kind = "rack"
            return rest, kind
        return name, "other"

    def _free(self, name: str) -> str:
        """``name`` for an element elastokin adds, unless the config uses it (then
        ``name_element``)."""
        s = self.model.suspension
        taken = {c.name for c in (*s.joints, *s.links, *s.bushings, *s.springs, *s.stops)}
        return f"{name}_element" if name in taken else name

    def _item(self, name: str, kind: str, parts) -> int:
        for k, item in enumerate(self.items):
            if item.name == name:
                return k
        self.items.append(LoadItem(name, kind, (parts[0] or "", parts[1] or ""),
                                   kind in TWO_POINT))
        self.force_only.append(True)
        return len(self.items) - 1

    def reported_items(self) -> tuple[LoadItem, ...]:
        """The items, each saying whether it may transmit a moment."""
        return tuple(replace(item, moments=not (item.two_point or only))
                     for item, only in zip(self.items, self.force_only))

    # ------------------------------------------------------------------ values
    def tables(self, stored: dict[str, np.ndarray], steps: np.ndarray) -> LoadTable:
        """The loads at the rows ``steps`` of the sensors' ``stored`` data (key -> Exudyn's
        stored (rows, 1 + values), time first): a table of (n, items, quantities, 3) values
        (:data:`~elastokin.physics.loads.QUANTITIES`)."""
        data = _Rows(stored, steps)
        n = len(steps)
        out = np.zeros((n, len(self.items), len(QUANTITIES), 3))
        frames: dict[int, np.ndarray] = {}  # the item's frame: its first element's
        active = self._active()
        for e in self.elements:
            if not active.get(e.number, True):
                continue
            geometry = [self._geometry(m, data, n) for m in e.markers]
            f, m_a, p_a, p_b, m_b, frame = self._element_loads(e, data, geometry)
            row = out[:, e.item]
            if e.item not in frames:  # the item's points: its first element's
                row[:, POINT], row[:, POINT_B] = p_a, p_b
                row[:, FORCE], row[:, MOMENT], row[:, MOMENT_B] = f, m_a, m_b
                frames[e.item] = frame
                continue
            row[:, FORCE] += f
            row[:, MOMENT] += m_a + _cross(p_a - row[:, POINT], f)
            row[:, MOMENT_B] += m_b - _cross(p_b - row[:, POINT_B], f)
        for k, frame in frames.items():
            out[:, k, FORCE_LOCAL] = np.einsum("nji,nj->ni", frame, out[:, k, FORCE])
            out[:, k, MOMENT_LOCAL] = np.einsum("nji,nj->ni", frame, out[:, k, MOMENT])
        return LoadTable(self.reported_items(), out, self.model.suspension.ground)

    def _active(self) -> dict[int, bool]:
        mbs = self.model.mbs
        return {e.number: bool(mbs.GetObjectParameter(e.number, "activeConnector"))
                for e in self.elements if e.kind in OUTPUTS}

    def _geometry(self, marker: _Marker, data, n: int) -> tuple[np.ndarray, np.ndarray]:
        """(positions (n, 3), frames (n, 3, 3)) of a marker at every step."""
        if marker.key is None:
            return (np.broadcast_to(marker.local, (n, 3)),
                    np.broadcast_to(marker.rotation, (n, 3, 3)))
        R = data[f"part:{marker.key}:R"].reshape(n, 3, 3)
        disp = data[f"part:{marker.key}:disp"]
        return (R @ marker.local + marker.ref + disp, R @ marker.rotation)

    def _element_loads(self, e: _Element, data, geometry):
        """Force on the item's first part (n, 3), its moment about the element's point on
        it, that point, the point on the second part, the moment on the second part about
        it, and the element's frame (n, 3, 3) for the local components."""
        (p0, A0), (p1, A1) = (geometry + geometry)[:2]
        raw = [data[self.keys[e.number, o]] for o in _outputs(e.kind, e.params.get("constrained"))]
        zero = np.zeros_like(p0)
        if e.kind in ("Load", "LoadTorque"):
            v = data[f"load:L{e.number}"]
            if e.kind == "Load":
                return v, zero, p0, p0, zero, A0
            return zero, v, p0, p0, -v, A0
        if e.kind == "JointSpherical":
            f1, m1, at0 = raw[0], zero, p0
        elif e.kind == "JointGeneric":
            r0, r1 = e.params["rotation"]
            A0, A1 = A0 @ r0, A1 @ r1
            f1 = np.einsum("nij,nj->ni", A0, raw[0])
            m1 = _generic_torque(e.params["constrained"], raw[1] if len(raw) > 1 else None, A0,
                                 A1)
            at0 = p0 if all(e.params["constrained"][:3]) else p1
        elif e.kind in ("ConnectorDistance", "ConnectorSpringDamper"):
            d = p1 - p0
            u = d / np.linalg.norm(d, axis=1, keepdims=True)
            scalar = raw[0].reshape(len(u), -1)[:, :1]
            f1 = scalar * u if e.kind == "ConnectorDistance" else -scalar * u
            m1, at0, A0 = zero, p0, _line_frames(u)
        else:  # ConnectorRigidBodySpringDamper: on marker 0's body, at marker 0
            frame = _mid_frames(A0, A1) if e.params["intrinsic"] else A0
            f0 = np.einsum("nij,nj->ni", frame, raw[0])
            m0 = np.einsum("nij,nj->ni", frame, raw[1])
            if e.params["intrinsic"]:
                p0 = p1 = 0.5 * (p0 + p1)
            f1, m1, at0 = -f0, -m0, p0
        if e.flip:  # the item's first part is marker 1's body
            return f1, m1, p1, at0, -m1, A0
        return -f1, -m1, at0, p1, m1, A0


def _outputs(kind: str, constrained) -> tuple[str, ...]:
    """The outputs recorded of an object: a generic joint holding no rotation has no torque
    (pads, the steering gear: one sensor less each)."""
    if kind == "JointGeneric" and not any(constrained[3:]):
        return OUTPUTS[kind][:1]
    return OUTPUTS.get(kind, ())


class _Rows(dict):
    """Sensor values at the picked rows, the time column dropped, taken when first asked."""

    def __init__(self, stored: dict[str, np.ndarray], steps: np.ndarray):
        super().__init__()
        self.stored, self.steps = stored, steps

    def __missing__(self, key: str) -> np.ndarray:
        value = self[key] = self.stored[key][self.steps, 1:]
        return value


def _generic_torque(constrained, lam: np.ndarray | None, A0: np.ndarray, A1: np.ndarray
                    ) -> np.ndarray:
    """Torque (n, 3) of a generic joint on marker 1's body from its rotation multipliers
    (module docstring): each constraint ``a0 . b1`` contributes ``-lambda (a0 x b1)``."""
    locked = [k for k in range(3) if constrained[3 + k]]
    if not locked:
        return np.zeros((len(A0), 3))
    free = [k for k in range(3) if not constrained[3 + k]]
    if len(locked) == 3:
        pairs = {0: (2, 1), 1: (2, 0), 2: (0, 1)}
    elif len(locked) == 2:
        pairs = {k: (free[0], k) for k in locked}
    else:
        pairs = {locked[0]: (free[0], free[1])}
    out = np.zeros((len(lam), 3))
    for k, (i, j) in pairs.items():
        out -= lam[:, k:k + 1] * _cross(A0[:, :, i], A1[:, :, j])
    return out


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Row-wise cross products of (n, 3) arrays (np.cross's overhead, without it)."""
    out = np.empty(np.broadcast_shapes(a.shape, b.shape))
    out[..., 0] = a[..., 1] * b[..., 2] - a[..., 2] * b[..., 1]
    out[..., 1] = a[..., 2] * b[..., 0] - a[..., 0] * b[..., 2]
    out[..., 2] = a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]
    return out


def _mid_frames(A0: np.ndarray, A1: np.ndarray) -> np.ndarray:
    """The mid-rotation between two frames (n, 3, 3): A0 exp(log(A0^T A1) / 2)."""
    from scipy.spatial.transform import Rotation

    half = Rotation.from_matrix(np.swapaxes(A0, 1, 2) @ A1).as_rotvec() / 2.0
    return A0 @ Rotation.from_rotvec(half).as_matrix()


def _line_frames(u: np.ndarray) -> np.ndarray:
    """Frames (n, 3, 3) with z along the unit vectors ``u`` (n, 3)."""
    helper = np.where(np.abs(u[:, :1]) < 0.9, [[1.0, 0.0, 0.0]], [[0.0, 1.0, 0.0]])
    x = _cross(helper, u)
    x /= np.linalg.norm(x, axis=1, keepdims=True)
    return np.stack([x, _cross(u, x), u], axis=2)


__all__ = ["LoadRecorder"]
