"""Where a :class:`~elastokin.mbs.model.SuspensionModel`'s items attach: markers on its
parts (at a position, or at a position given as a function of the suspension, registered for
twins in place: :mod:`elastokin.mbs.geometry`), and the attachments the rig and the design
balancing add from outside: supports, loads, point sensors and rig bodies.

Units mm, N, N*mm; the config frame at the design position.
"""

from __future__ import annotations

from collections.abc import Iterable

import numpy as np
from exudyn.itemInterface import (
    LoadForceVector,
    LoadTorqueVector,
    MarkerBodyPosition,
    MarkerBodyRigid,
    ObjectJointGeneric,
    SensorBody,
    SensorObject,
)
from exudyn.rigidBodyUtilities import InertiaCuboid

from elastokin.errors import ModelError
from elastokin.mbs.exudyn_api import exu, exudyn_call


class Attachments:
    """The markers and attachments of a :class:`~elastokin.mbs.model.SuspensionModel` (a
    base class: the model's data live there)."""

    def body_or_ground(self, part: str) -> int:
        if part == self.suspension.ground:
            return self.ground
        return self.body[part] if part in self.body else self.rig_bodies[part]

    def add_rig_body(self, name: str, point_mm, held: Iterable[int] | None = None) -> str:
        """A massless body that is no suspension part (no pose recorded: a rig's body, a
        wheel's contact arm, :mod:`elastokin.mbs.contact`) at ``point_mm`` (config frame);
        ``held``: held to ground in those directions (6 flags) by a support ``name`` every
        solve keeps (a lock at 0), else the caller joins it; supports and loads of parts can
        act against it (``base``). Returns ``name``."""
        if name in self.rig_bodies:
            raise ModelError(f"{self.suspension.source}: rig body '{name}' exists already")
        ref = np.asarray(self.references.get(name, point_mm), float)
        self.ref[name] = ref
        self.rig_bodies[name] = self.mbs.CreateRigidBody(
            referencePosition=ref, inertia=InertiaCuboid(density=1e-9, sideLengths=[100.0] * 3),
            nodeType=exu.NodeType.RotationRxyz, name=f"rig_body:{name}")
        self.rig_nodes[name] = self.mbs.GetObject(self.rig_bodies[name])["nodeNumber"]
        if self.options.loads:  # the rig's loads on the parts are reported where they act
            self._add_pose_sensors(name, self.rig_bodies[name])
        if held is None:
            return name
        return self.add_support(name, name, ref, held, lock=np.zeros(6))

    def set_support_axes(self, name: str, constrained: Iterable[int]) -> None:
        """Change which directions a support holds (e.g. a rig body let free to heave)."""
        self.mbs.SetObjectParameter(self.supports[name]["object"], "constrainedAxes",
                                    [int(c) for c in constrained])
        exudyn_call(self.mbs.Assemble, f"{self.suspension.source}: changing '{name}'")

    def track(self, kind: str, number, param: str, getter) -> int:
        """Register a design-dependent parameter of an item (:mod:`elastokin.mbs.geometry`);
        returns ``number``."""
        self.geometry.track(kind, number, param, getter)
        return number

    def _where(self, position):
        """(value at this model's design, getter of a suspension or None) of a position
        given as an array or as a function of the suspension (tracked for twins)."""
        if callable(position):
            return position(self.suspension), position
        return position, None

    def rigid_marker(self, part: str, position, frame) -> int:
        """A rigid marker on ``part`` at ``position`` (mm, config frame, design position)
        with axes ``frame`` (columns); on a beam part, at one of its named nodes. Either may
        be a function of the suspension: the marker then follows a twin's design
        (:mod:`elastokin.mbs.geometry`)."""
        (position, where), (frame, axes) = self._where(position), self._where(frame)
        if part in self.beams:
            return self.beams[part].rigid_marker(position, frame)
        ref = self.ref[part]
        local = np.asarray(position) - ref
        marker = self.mbs.AddMarker(MarkerBodyRigid(bodyNumber=self.body_or_ground(part),
                                                    localHT=exu.HT(np.asarray(frame), local)))
        if where is not None or axes is not None:
            def ht(s, _, p=where or (lambda s: position), f=axes or (lambda s: frame)):
                return exu.HT(np.asarray(f(s), float), np.asarray(p(s)) - ref)

            self.track("marker", marker, "localHT", ht)
        return marker

    def position_marker(self, part: str, position) -> int:
        """A position marker on ``part`` at ``position`` (as :meth:`rigid_marker`'s)."""
        position, where = self._where(position)
        if part in self.beams:
            return self.beams[part].position_marker(position)
        ref = self.ref[part]
        local = np.asarray(position) - ref
        marker = self.mbs.AddMarker(MarkerBodyPosition(bodyNumber=self.body_or_ground(part),
                                                       localPosition=local))
        if where is not None:
            self.track("marker", marker, "localPosition",
                       lambda s, _: np.asarray(where(s)) - ref)
        return marker

    def add_support(self, name: str, part: str, point_mm, constrained: Iterable[int],
                    frame=None, base: str | None = None, lock=None,
                    item: tuple[str, str] | None = None) -> str:
        """Hold ``point_mm`` (config frame, design position) of ``part`` against ground (or
        against ``base``, another part or a rig body) in the ``constrained`` directions (6
        flags: translations x y z, rotations x y z of ``frame``, columns = axes in the config
        frame; default the config frame), following an offset path given when solving;
        inactive in a solve that gives it no path, unless ``lock`` (6 offsets) makes it one of
        :attr:`locks`: active from the start, at ``lock`` unless a path is given. Its reaction
        is recorded. ``item``: (name, kind) of the reported load it belongs to
        (:mod:`elastokin.mbs.loads`; default the support's own name). Returns ``name``."""
        if name in self.supports or name in self.loads:
            raise ModelError(f"{self.suspension.source}: attachment '{name}' exists already")
        axes = np.eye(3) if frame is None else frame
        m_ground = self.rigid_marker(self.suspension.ground if base is None else base,
                                     point_mm, axes)
        m_part = self.rigid_marker(part, point_mm, axes)
        obj = self.mbs.AddObject(ObjectJointGeneric(
            markerNumbers=[m_ground, m_part], constrainedAxes=list(constrained),
            activeConnector=lock is not None, name=name))
        if lock is not None:
            self.locks[name] = np.asarray(lock, float)
        self.supports[name] = {"object": obj, "part": part, "marker": m_part}
        if item is not None:
            self.load_items[name] = item
        self.sensors[f"support:{name}"] = self.mbs.AddSensor(SensorObject(
            objectNumber=obj, outputVariableType=exu.OutputVariableType.ForceLocal,
            storeInternal=True, writeToFile=False))
        exudyn_call(self.mbs.Assemble, f"{self.suspension.source}: attaching '{name}'")
        return name

    def add_load(self, name: str, part: str, point_mm, kind: str = "force",
                 marker_of: str | None = None, item: tuple[str, str] | None = None) -> str:
        """A force (N) or torque (N*mm) on ``part`` at ``point_mm`` (config frame, design
        position; ``kind`` "force" or "torque"), following a path given when solving (zero
        without one). ``marker_of``: apply it at the marker of that support or load
        instead of a new one. ``item``: as :meth:`add_support`'s. Returns ``name``."""
        if name in self.supports or name in self.loads:
            raise ModelError(f"{self.suspension.source}: attachment '{name}' exists already")
        if marker_of is not None:
            marker = {**self.supports, **self.loads}[marker_of]["marker"]
        else:
            marker = self.rigid_marker(part, point_mm, np.eye(3))
        kind_of = LoadForceVector if kind == "force" else LoadTorqueVector
        load = self.mbs.AddLoad(kind_of(markerNumber=marker, loadVector=[0, 0, 0]))
        self.loads[name] = {"load": load, "part": part, "marker": marker, "kind": kind}
        if item is not None:
            self.load_items[name] = item
        return name

    def add_point_sensor(self, name: str, part: str, point_mm) -> str:
        """Record where ``point_mm`` (config frame, design position) of ``part`` is at every
        step (``ModelState.points[name]``, mm). Returns ``name``."""
        if f"point:{name}" in self.sensors:
            raise ModelError(f"{self.suspension.source}: point sensor '{name}' exists already")
        point, where = self._where(point_mm)
        ref = self.ref[part]
        local = np.asarray(point, float) - ref
        self.point_sensors[name] = (part, local)
        sensor = self.sensors[f"point:{name}"] = self.mbs.AddSensor(SensorBody(
            bodyNumber=self.body[part], localPosition=local.tolist(),
            outputVariableType=exu.OutputVariableType.Position, storeInternal=True,
            writeToFile=False))
        if where is not None:
            def local_of(s, _):
                return np.asarray(where(s), float) - ref

            self.track("point", name, "localPosition", local_of)
            self.track("sensor", sensor, "localPosition", lambda s, p: local_of(s, p).tolist())
        return name
