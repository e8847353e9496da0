"""The multibody model of a :class:`~elastokin.config.suspension.Suspension` in Exudyn.

Model units: mm, N, N*mm, rad inside Exudyn (bushing laws convert to deg); the model frame is
the config frame. Every moving part is a rigid body (Tait-Bryan ``Rxyz`` node, reference
rotation identity, so a body's local frame is the config frame at the design position):

- ideal joints: ``ObjectJointGeneric`` with the joint's constrained axes in its own frame
  (``ObjectJointSpherical`` for a plain ball joint);
- links: ``ObjectConnectorDistance``;
- bushings: ``ObjectConnectorRigidBodySpringDamper`` whose 6 loads come from a symbolic user
  function (C++ speed) evaluating the laws at deflection + initial deflection; a bushing
  modelled by its ideal joint (``Bushing.kinematic``) becomes that joint, plus a regularising
  rotational spring of 1e-3 times its rates on the joint's free rotations (it only fixes idle
  spins, e.g. of a link arm about its own axis, and does not change the kinematics);
- coil springs, dampers (no force at rest): ``ObjectConnectorSpringDamper`` between points;
- ball-joint friction (:mod:`elastokin.mbs.friction`), for the synthetic real suspension.

The model knows nothing of a rig. Whatever drives it is attached from outside as **supports**
(a point of a part held against ground in chosen directions, following an offset path) and
**loads** (a force or torque at a point of a part, following a path); the rig
(:mod:`elastokin.rig`) attaches its pad and wheel loads this way, the design balancing and the
assembly check their own support. :mod:`elastokin.mbs.solve` solves static steps along the
attachments' paths.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
from exudyn.itemInterface import (
    ObjectConnectorDistance,
    ObjectGround,
    ObjectJointGeneric,
    ObjectJointSpherical,
    SensorBody,
    SensorObject,
)
from exudyn.rigidBodyUtilities import InertiaCuboid

from elastokin.config.suspension import Suspension
from elastokin.config.variants import BallJointFriction, DesignState
from elastokin.errors import ModelError
from elastokin.mbs import friction
from elastokin.mbs.attachments import Attachments
from elastokin.mbs.axle_elements import add_anti_roll_bar, add_line_elements, add_steering_lock
from elastokin.mbs.beams import NOISE_FACTOR, BeamBody
from elastokin.mbs.bushings import DEG, add_bushing
from elastokin.mbs.exudyn_api import EXUDYN_VERSION, exu, exudyn_call
from elastokin.mbs.geometry import Geometry, item_preloads, of
from elastokin.mbs.loads import LoadRecorder
from elastokin.mbs.options import NO_LOADS, ModelOptions
from elastokin.physics.states import PartPoses

__all__ = ["DEG", "EXUDYN_VERSION", "NO_LOADS", "ModelOptions", "SuspensionModel"]

#: Newton residual below which a step has converged (N, N*mm, mm): the residual noise floor
ABSOLUTE_TOLERANCE = 1e-6


def joint_points(j) -> tuple[np.ndarray, np.ndarray]:
    """Where each part's marker of joint ``j`` sits (mm, config frame): at its position, each
    moved by its part's as-built shift (assembly clearance; the static solve closes the gap)
    and part 0's by the joint's offset along its z (a rack held at travel_mm: the constraint
    then puts part 1 there)."""
    shift0, shift1 = (np.zeros(3), np.zeros(3)) if j.part_shift_mm is None else \
        (np.asarray(j.part_shift_mm[0], float), np.asarray(j.part_shift_mm[1], float))
    if list(j.constrained) == [1, 1, 1, 0, 0, 0] and not j.offset_mm:
        return j.position_mm + shift0, j.position_mm + shift1
    frame = np.asarray(j.frame, float)
    return j.position_mm + float(j.offset_mm) * frame[:, 2] + shift0, j.position_mm + shift1


class SuspensionModel(Attachments):
    """An assembled Exudyn model of one suspension.

    ``preloads``: spring forces and bushing loads at the design position (default: the
    springs' own preloads and the bushings' initial deflections); ``friction``: ball-joint
    friction; ``balancing``: every bushing held by its ideal joint with its loads read back
    (:func:`elastokin.mbs.design.design_state` only), ``balancing_offsets`` the rotations
    (rad, bushing frame) at which its stiff rotational springs carry no torque;
    ``references``: the parts' reference positions (default: each part's centre of mass or
    the mean of its points), so that two models of nearby geometries share their
    coordinates' meaning. Build it
    once, attach supports and loads, then solve as often as needed
    (:mod:`elastokin.mbs.solve`): every solve restarts from the design position.
    """

    def __init__(self, suspension: Suspension, options: ModelOptions = ModelOptions(),
                 preloads: DesignState | None = None, friction_spec: BallJointFriction | None
                 = None, balancing: bool = False,
                 balancing_offsets: Mapping[str, np.ndarray] | None = None,
                 references: Mapping[str, np.ndarray] | None = None):
        self.suspension = suspension
        #: the parts' (and rig bodies') reference positions, when given: those of another
        #: model of the same parts (a design sensitivity's twin, :mod:`elastokin.mbs.twins`;
        #: that model's own mapping, so that rig bodies it gets later are shared too)
        self.references = references if references is not None else {}
        self.options = options
        self.balancing = balancing
        self.friction_spec = friction_spec
        self.substeps = friction_spec.substeps if friction_spec is not None else 1
        # bushing loads at the design position (N, N*mm) -> initial deflections of the
        # (scaled) laws, so that a stiffer bushing carries the same preload
        self.preloads = item_preloads(suspension, options.stiffness_scale, preloads,
                                      balancing_offsets)
        #: the model's own, while a design twin's are set in place (mbs/twins.py)
        self.design_preloads = self.preloads
        self.bushing_preload = self.preloads.bushing_preload
        self.initial_deflection = self.preloads.initial_deflection
        self.spring_force = self.preloads.spring_force
        #: the design-dependent parameters, for twins in place (:mod:`elastokin.mbs.geometry`)
        self.geometry = Geometry()
        self.keep_alive: list = []  # symbolic input paths of the current solve
        self.bushing_functions: list = []  # symbolic bushing laws (must outlive the model)
        self.supports: dict[str, dict] = {}
        #: supports active in every solve, at this offset unless a path is given
        self.locks: dict[str, np.ndarray] = {}
        #: bodies of the rig (add_rig_body) and their nodes
        self.rig_bodies: dict[str, int] = {}
        self.rig_nodes: dict[str, int] = {}
        self.loads: dict[str, dict] = {}
        self.sensors: dict[str, int] = {}
        self.point_sensors: dict[str, tuple[str, np.ndarray]] = {}  # part, local position
        #: the reported load (item, kind) of attachments and of objects added outside the
        #: config, by their name (:mod:`elastokin.mbs.loads`; default: their own name)
        self.load_items: dict[str, tuple[str, str]] = {}
        self._build()
        #: records every element's load (ModelOptions.record_loads), sensors added per solve
        self.load_recorder = LoadRecorder(self) if options.loads else None

    # ------------------------------------------------------------------ building
    @property
    def balancing_offsets(self) -> dict[str, np.ndarray]:
        """A balancing model's stiff rotational springs' offsets (rad), by bushing."""
        return self.preloads.balancing_offsets

    @property
    def wheel_part(self) -> str:
        return self.suspension.wheel.part

    @property
    def wheel_parts(self) -> dict[str, str]:
        """The part carrying each wheel, by side (both on an axle)."""
        return {side: w.part for side, w in self.suspension.wheels.items()}

    def _build(self) -> None:
        s = self.suspension
        self.SC = exu.SystemContainer()
        mbs = self.mbs = self.SC.AddSystem()
        self.ground = mbs.AddObject(ObjectGround())
        self.body: dict[str, int] = {}
        self.ref: dict[str, np.ndarray] = {s.ground: np.zeros(3)}
        self._add_bodies()
        self.node = {n: mbs.GetObject(b)["nodeNumber"] for n, b in self.body.items()}
        #: the flexible parts (beam elements), by part name
        self.beams = {b.part: BeamBody(mbs, b) for b in s.beams if not b.rigid}
        self.joints = {j.name: self._add_joint(j) for j in s.joints}
        self.links: dict[str, int] = {}
        for link in s.links:
            points = of("links", link.name, lambda lk: lk.points_mm)
            m0 = self.position_marker(link.parts[0], lambda s, pts=points: pts(s)[0])
            m1 = self.position_marker(link.parts[1], lambda s, pts=points: pts(s)[1])

            def length(s, _=None, pts=points) -> float:
                return float(np.linalg.norm(pts(s)[1] - pts(s)[0]))

            self.links[link.name] = self.track("object", mbs.AddObject(ObjectConnectorDistance(
                markerNumbers=[m0, m1], distance=length(s), name=f"link:{link.name}")),
                "distance", length)
        self.bushings = {b.name: add_bushing(self, b) for b in s.bushings}
        spec = self.friction_spec
        self.friction = {} if spec is None else {
            name: friction.add_element(self, name, torque, spec.presliding_deg * DEG)
            for name, torque in spec.torque_Nmm.items()}
        self.springs, self.dampers, self.stops = add_line_elements(self)
        bar = s.axle.anti_roll_bar if s.axle is not None else None
        self.anti_roll_bar = add_anti_roll_bar(self, bar) if bar is not None else None
        self._add_sensors()
        exudyn_call(mbs.Assemble, f"{s.source}: assembling the model")
        if s.axle is not None and s.axle.steering is not None:
            add_steering_lock(self, s.axle.steering)

    def _add_bodies(self) -> None:
        s, mbs = self.suspension, self.mbs
        points = self._part_points()
        flexible = {b.part for b in s.beams if not b.rigid}
        for name, part in s.parts.items():
            if not points.get(name):
                raise ModelError(f"{s.source}: part '{name}' is not connected to anything")
            if name in flexible:
                continue
            if part.centre_of_mass is not None:
                ref = np.asarray(s.hardpoints[part.centre_of_mass] if isinstance(
                    part.centre_of_mass, str) else part.centre_of_mass, float)
            else:
                ref = np.mean(points[name], axis=0)
            ref = np.asarray(self.references.get(name, ref), float)
            self.ref[name] = ref
            mass_t = (part.mass_kg or 1.0) * 1e-3  # tonne in the mm-N-s system
            self.body[name] = mbs.CreateRigidBody(
                referencePosition=ref,
                inertia=InertiaCuboid(density=mass_t / 1e6, sideLengths=[100.0] * 3),
                nodeType=exu.NodeType.RotationRxyz,
                name=f"part:{name}",
            )

    def _part_points(self) -> dict[str, list[np.ndarray]]:
        s = self.suspension
        pts: dict[str, list[np.ndarray]] = {n: [] for n in s.parts}
        items = [(j.parts, (j.position_mm, j.position_mm)) for j in s.joints]
        items += [(lk.parts, lk.points_mm) for lk in s.links]
        items += [(b.parts, (b.position_mm, b.position_mm)) for b in s.bushings]
        items += [(sp.parts, sp.seats_mm) for sp in s.springs]
        items += [(st.parts, st.points_mm) for st in s.stops]
        items += [(dm.parts, dm.points_mm) for dm in s.dampers]
        for parts, (p0, p1) in items:
            for part, p in zip(parts, (p0, p1)):
                if part in pts:
                    pts[part].append(p)
        for w in s.wheels.values():
            if w.part in pts:
                pts[w.part].append(w.centre_mm)
        bar = s.axle.anti_roll_bar if s.axle is not None else None
        for part in bar.parts if bar is not None else ():
            pts[part].append(bar.position_mm)
        return pts

    def _add_joint(self, j) -> int:
        joint = of("joints", j.name, lambda x: x)
        if list(j.constrained) == [1, 1, 1, 0, 0, 0] and not j.offset_mm:
            # 3 algebraic equations instead of the generic joint's 6
            return self.mbs.AddObject(ObjectJointSpherical(
                markerNumbers=[self.position_marker(j.parts[k], lambda s, k=k:
                                                    joint_points(joint(s))[k])
                               for k in (0, 1)], name=f"joint:{j.name}"))
        m0, m1 = (self.rigid_marker(j.parts[k], lambda s, k=k: joint_points(joint(s))[k],
                                    lambda s: joint(s).frame) for k in (0, 1))
        return self.mbs.AddObject(ObjectJointGeneric(
            markerNumbers=[m0, m1], constrainedAxes=list(j.constrained),
            name=f"joint:{j.name}"))

    def _add_sensors(self) -> None:
        """Record the model's own outputs in C++ at each load step (no Python call per step):
        spring forces and lengths, damper lengths, bushing deflections and loads, and the poses
        of the wheel part (always) and of every other part (``ModelOptions.part_poses``)."""
        mbs = self.mbs
        ovt = exu.OutputVariableType

        def obj(number, output):
            return mbs.AddSensor(SensorObject(objectNumber=number, outputVariableType=output,
                                              storeInternal=True, writeToFile=False))

        for name, o in self.springs.items():
            self.sensors[f"spring:{name}"] = obj(o, ovt.ForceLocal)
            self.sensors[f"spring_length:{name}"] = obj(o, ovt.Distance)
        for name, o in self.dampers.items():
            self.sensors[f"damper_length:{name}"] = obj(o, ovt.Distance)
        for name, e in self.bushings.items():
            for key, output in (("d", ovt.DisplacementLocal), ("r", ovt.Rotation),
                                ("f", ovt.ForceLocal), ("t", ovt.TorqueLocal)):
                self.sensors[f"bushing:{name}:{key}"] = obj(e["object"], output)
        for name, o in self.stops.items():
            self.sensors[f"stop:{name}"] = obj(o, ovt.ForceLocal)
        if self.anti_roll_bar is not None:
            self.sensors["arb:r"] = obj(self.anti_roll_bar, ovt.Rotation)
            self.sensors["arb:t"] = obj(self.anti_roll_bar, ovt.TorqueLocal)
        recorded = self.body if self.options.part_poses else {
            part: self.body[part] for part in self.wheel_parts.values()}
        for name, number in recorded.items():
            self._add_pose_sensors(name, number)
        self.pose_refs = {name: self.ref[name] for name in recorded}  # shared, read-only
        #: the beam parts' node lines, their nodes' poses recorded with every part's
        lines = {p: b.record_line(self.sensors) for p, b in self.beams.items()} \
            if self.options.part_poses and self.options.beam_nodes else {}
        self.node_lines = {p: line for p, line in lines.items() if line}

    def _add_pose_sensors(self, name: str, number: int) -> None:
        """Record a body's rotation matrix and displacement at every step
        (``part:<name>:R``, ``part:<name>:disp``)."""
        ovt = exu.OutputVariableType
        for key, output in (("R", ovt.RotationMatrix), ("disp", ovt.Displacement)):
            self.sensors[f"part:{name}:{key}"] = self.mbs.AddSensor(SensorBody(
                bodyNumber=number, localPosition=[0.0, 0.0, 0.0], outputVariableType=output,
                storeInternal=True, writeToFile=False))

    def start_from(self, coordinates) -> None:
        """Make every later solve start from these coordinates (every body's displacement and
        rotation parameters, as :meth:`coordinates` returns them) instead of the design
        position: a start close to the solution for a model whose design state is far from
        equilibrium (:func:`elastokin.mbs.design.settle_by_continuation`)."""
        q = np.asarray(coordinates, float)
        for node in [*self.node.values(), *(n for b in self.beams.values() for n in b.nodes)]:
            i0 = self.mbs.GetNodeODE2Index(node)
            self.mbs.SetNodeParameter(node, "initialCoordinates", q[i0:i0 + 6].tolist())
        exudyn_call(self.mbs.Assemble, f"{self.suspension.source}: setting the start")

    def set_bushing_laws(self, laws: Mapping[str, Sequence]) -> None:
        """Give parametric bushings (``ModelOptions.parametric_bushings``) new laws: per
        bushing six laws, each its config law scaled and stiffened
        (:class:`~elastokin.physics.laws.ProgressiveLaw`); the preload each bushing carries at
        the design position is kept (its initial deflection follows). No rebuild."""
        for name, six in laws.items():
            params = self.bushings.get(name, {}).get("parametric")
            if params is None:
                raise ModelError(f"{self.suspension.source}: bushing '{name}' is not "
                                 "parametric (ModelOptions.parametric_bushings)")
            scale = self.options.stiffness_scale
            self.apply_bushing_law_values(
                {name: params.values([law.scaled(scale) for law in six])})

    def bushing_law_values(self) -> dict[str, np.ndarray]:
        """The current (3, 6) scale / cubic / initial-deflection values of every parametric
        bushing (see :meth:`set_bushing_laws`)."""
        return {name: e["parametric"].current for name, e in self.bushings.items()
                if "parametric" in e}

    def apply_bushing_law_values(self, values: Mapping[str, np.ndarray]) -> None:
        """Set parametric bushings to values from :meth:`bushing_law_values` (or from a
        parametric bushing's ``values``): a cheap switch between law sets."""
        for name, v in values.items():
            self.bushings[name]["parametric"].apply(v)
            self.initial_deflection[name] = np.asarray(v[2], float).copy()

    @property
    def absolute_tolerance(self) -> float:
        """The Newton solver's absolute tolerance (N, N*mm, mm): :data:`ABSOLUTE_TOLERANCE`, or
        above the round-off floor of a model with beams (their stiff elements' residual)."""
        floors = [NOISE_FACTOR * b.round_off_N for b in self.beams.values()]
        return max([ABSOLUTE_TOLERANCE, *floors])

    def rigid_beam_rows(self) -> np.ndarray:
        """Linear equations over the ODE2 coordinates holding every beam part rigid (the
        assembly checks count a beam as a rigid part, as a bushing counts as its ideal
        joint)."""
        n2 = self.mbs.systemData.ODE2Size()
        rows = [b.rigid_rows(n2) for b in self.beams.values()]
        return np.vstack(rows) if rows else np.zeros((0, n2))

    def coordinates(self) -> np.ndarray:
        """The bodies' coordinates in the current (last solved) state."""
        return np.array(self.mbs.systemData.GetODE2Coordinates())

    # ------------------------------------------------------------------ reading the state
    def part_poses(self) -> PartPoses:
        """Poses of every moving part in the current (last solved) state."""
        ovt = exu.OutputVariableType
        poses = PartPoses()
        for name, b in self.body.items():
            poses.rotation[name] = np.asarray(
                self.mbs.GetObjectOutputBody(b, ovt.RotationMatrix, [0, 0, 0])).reshape(3, 3)
            poses.displacement_mm[name] = np.asarray(
                self.mbs.GetObjectOutputBody(b, ovt.Displacement, [0, 0, 0]))
            poses.reference_mm[name] = self.ref[name].copy()
        return poses

    def balancing_bushing_loads(self) -> dict[str, np.ndarray]:
        """Balancing model: the load each bushing carries in the current state (Fx Fy Fz N,
        Tx Ty Tz N*mm, bushing frame, +K*u convention): the reaction force of its translational
        constraint and the torque of its stiff rotational springs."""
        if not self.balancing:
            raise ModelError("balancing_bushing_loads: not a balancing model")
        ovt = exu.OutputVariableType
        out = {}
        for name, e in self.bushings.items():
            spring = np.r_[self.mbs.GetObjectOutput(e["object"], ovt.ForceLocal),
                           self.mbs.GetObjectOutput(e["object"], ovt.TorqueLocal)]
            # the constraint's reaction on parts[0] is opposite to a spring's +K*u
            spring[:3] -= np.asarray(self.mbs.GetObjectOutput(e["ideal"], ovt.ForceLocal))
            out[name] = spring
        return out

    def solver_settings(self) -> dict:
        """Solver settings recorded with every result (traceability)."""
        sv = self.suspension.solver
        return {
            "solver": "exudyn SolveStatic (Newton, load steps along the rig path)",
            "newton_relative_tolerance": sv.newton_tolerance,
            "newton_absolute_tolerance": self.absolute_tolerance,
            "max_newton_iterations": sv.max_newton_iterations,
            "modified_newton": sv.modified_newton,
            "adaptive_step": sv.adaptive_step,
            "linear_solver": "EigenDense",
            "node_type": "RotationRxyz",
            "user_functions": self.options.user_functions,
            "kinematic": self.suspension.kinematic,
            "stiffness_scale": self.options.stiffness_scale,
            **({"beam_elements": {p: b.beam.elements_per_segment * (len(b.beam.nodes_mm) - 1)
                                  for p, b in self.beams.items()}} if self.beams else {}),
        }
