"""The Exudyn layer: build the multibody model of a :class:`~elastokin.config.Suspension`, solve
static equilibria and quasi-static sweeps. The only module that imports ``exudyn``.

Model units: mm, N, N*mm, rad inside Exudyn (bushing laws convert to deg); the model frame is the
config frame. Every moving part is a rigid body (Tait-Bryan ``Rxyz`` node, reference rotation
identity, so a body's local frame is the config frame at the design position). Parts:

- ideal joints: ``ObjectJointGeneric`` with the joint's constrained axes in its own frame;
- links: ``ObjectConnectorDistance``;
- bushings: ``ObjectConnectorRigidBodySpringDamper`` whose 6 loads come from a symbolic user
  function (C++ speed) evaluating the piecewise-linear laws at deflection + initial deflection;
  in the kinematic model a bushing becomes its ideal joint, plus a regularising rotational spring
  of 1e-3 times its rates on the joint's free rotations (it only fixes idle spins, e.g. of a link
  arm about its own axis, and does not change the kinematics);
- coil springs: ``ObjectConnectorSpringDamper`` between the seats;
- the wheel: the contact patch point on the wheel part. The K&C rig pad prescribes its vertical
  position (displacement control, x and y free) or applies forces there (force control).
"""

from __future__ import annotations

import contextlib
import io
import os
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np

from elastokin.config.suspension import Bushing, Suspension
from elastokin.errors import ModelError, SolverError

os.environ.setdefault("EXUDYN_NO_GUI", "1")
import exudyn as exu  # noqa: E402
from exudyn.advancedUtilities import CreateSymbolicUserFunction  # noqa: E402
from exudyn.itemInterface import (  # noqa: E402
    LoadForceVector,
    LoadTorqueVector,
    MarkerBodyPosition,
    MarkerBodyRigid,
    ObjectConnectorDistance,
    ObjectConnectorRigidBodySpringDamper,
    ObjectConnectorSpringDamper,
    ObjectGround,
    ObjectJointGeneric,
    ObjectJointSpherical,
    SensorBody,
    SensorObject,
)
from exudyn.rigidBodyUtilities import InertiaCuboid  # noqa: E402

exu.config.printToConsole = False
EXUDYN_VERSION = exu.__version__

_DEG = np.pi / 180.0
#: stiffness of the regularising springs on an ideal joint's free rotations, relative to the
#: bushing's rotational rates (kinematic model only)
REGULARISATION = 1e-3
#: Newton residual below which a step has converged (N, N*mm, mm): the residual noise floor
ABSOLUTE_TOLERANCE = 1e-6
#: ball-joint friction: re-solves of a step at most, and the accepted torque excess (relative)
FRICTION_ITERATIONS = 200
FRICTION_TOLERANCE = 1e-3
#: stiffness holding a bushing's ideal-joint rotations while balancing the design preloads
_BALANCING_ROTATION = 1e9  # N*mm/rad


@dataclass(frozen=True)
class ModelOptions:
    """How a suspension is turned into an Exudyn model.

    kinematic: bushings replaced by their ideal joints.
    stiffness_scale: every bushing law's load multiplied by this factor.
    user_functions: how bushing laws and rig paths are evaluated: ``"symbolic"`` (Exudyn
        symbolic functions at C++ speed; linear bushings use Exudyn's own stiffness matrix) or
        ``"python"`` (Python callbacks: the straightforward, slow reference).
    part_poses: record every part's pose at every step (``StepState.poses``, needed for the
        steering-axis columns); off, steps carry no poses and sweeps no steering-axis columns
        (the stiffness fit, which does not use them).
    """

    kinematic: bool = False
    stiffness_scale: float = 1.0
    user_functions: str = "symbolic"
    part_poses: bool = True  # record every part's pose per step (the steering-axis columns)

    def __post_init__(self):
        if self.user_functions not in ("symbolic", "python"):
            raise ModelError(f"ModelOptions.user_functions must be 'symbolic' or 'python', "
                             f"got '{self.user_functions}'")
        if not self.stiffness_scale > 0:
            raise ModelError(f"ModelOptions.stiffness_scale must be positive, got "
                             f"{self.stiffness_scale}")


@dataclass
class StepState:
    """Outputs of one solved step, config frame, mm / N / N*mm / deg."""

    wheel_centre_mm: np.ndarray
    spin_axis: np.ndarray
    wheel_rotation: np.ndarray
    contact_patch_mm: np.ndarray
    pad_force_N: np.ndarray
    spring_force_N: dict[str, float]
    bushing_deflection: dict[str, np.ndarray]  # x y z mm, rx ry rz deg (incl. initial)
    bushing_load: dict[str, np.ndarray]  # Fx Fy Fz N, Tx Ty Tz N*mm (bushing frame)
    #: every moving part's pose at this step (steering axis, see elastokin.steering_axis)
    poses: PartPoses | None = None


@dataclass
class PartPoses:
    """Rigid-body poses of every moving part at one step: rotation (3, 3) and the displacement
    (mm) of its reference point ``reference_mm`` (config frame, design position)."""

    rotation: dict[str, np.ndarray] = field(default_factory=dict)
    displacement_mm: dict[str, np.ndarray] = field(default_factory=dict)
    reference_mm: dict[str, np.ndarray] = field(default_factory=dict)

    def moved(self, part: str, points_mm) -> np.ndarray:
        """Where points of ``part`` given at the design position (mm, (..., 3)) are now; the
        ground part and unknown parts do not move."""
        x = np.asarray(points_mm, float)
        if part not in self.rotation:
            return x.copy()
        ref = self.reference_mm[part]
        return (x - ref) @ self.rotation[part].T + ref + self.displacement_mm[part]

    def transform(self, part: str) -> np.ndarray:
        """4x4 homogeneous transform from the design position to the current one."""
        T = np.eye(4)
        if part in self.rotation:
            T[:3, :3] = self.rotation[part]
            T[:3, 3] = self.moved(part, np.zeros(3))
        return T


def _exudyn_call(fn: Callable, what: str):
    """Call Exudyn, turning its errors into one-line :class:`SolverError` / :class:`ModelError`."""
    buf = io.StringIO()
    try:
        with contextlib.redirect_stdout(buf):
            return fn()
    except Exception as exc:  # Exudyn raises RuntimeError/ValueError with long traces
        lines = [ln.strip() for ln in str(exc).splitlines()]
        useful = [ln for ln in lines if ln and not ln.startswith(("At:", "/", "File", "<"))
                  and "check your Python code" not in ln]
        detail = "; ".join(useful[:2]) or type(exc).__name__
        raise SolverError(f"{what}: {detail}") from None


class SuspensionModel:
    """An assembled Exudyn model of one suspension.

    Build it once, then call :meth:`solve_static` or :meth:`sweep` as often as needed: each call
    restarts from the design position.
    """

    def __init__(self, suspension: Suspension, options: ModelOptions = ModelOptions(),
                 bushing_preload: dict[str, np.ndarray] | None = None,
                 spring_force_N: dict[str, float] | None = None, _balancing: bool = False,
                 joint_friction_Nmm: dict[str, float] | None = None,
                 presliding_deg: float = 0.05, substeps: int = 1):
        self.suspension = suspension
        self.substeps = int(substeps)  # default solver steps per returned step, see run()
        # dry friction in spherical joints (synthetic real suspension only): breakaway torque
        # (N*mm) per joint and the stick rotation before it slips (deg); see _add_friction
        self._friction_spec = dict(joint_friction_Nmm or {})
        self._presliding_rad = presliding_deg * _DEG
        self.options = options
        self._balancing = _balancing
        # bushing loads at the design position (N, N*mm) -> initial deflections of the
        # (scaled) laws, so that a stiffer bushing carries the same preload
        self.bushing_preload = {
            b.name: (np.asarray(bushing_preload[b.name], float) if bushing_preload and
                     b.name in bushing_preload else
                     np.array([law(u) for law, u in zip(b.laws, b.initial_deflection)]))
            for b in suspension.bushings
        }
        self._initial_deflection = {
            b.name: np.array([law.scaled(options.stiffness_scale).deflection_at(f)
                              for law, f in zip(b.laws, self.bushing_preload[b.name])])
            for b in suspension.bushings
        }
        self._spring_force = {s.name: (spring_force_N or {}).get(s.name, s.design_force_N())
                              for s in suspension.springs}
        self._keep_alive: list = []  # symbolic rig paths of the current run
        self._bushing_functions: list = []
        self._build()

    # ------------------------------------------------------------------ building
    def _build(self) -> None:
        s = self.suspension
        self.SC = exu.SystemContainer()
        mbs = self.mbs = self.SC.AddSystem()
        self.ground = mbs.AddObject(ObjectGround())
        self.body: dict[str, int] = {}
        self.ref: dict[str, np.ndarray] = {s.ground: np.zeros(3)}
        points = self._part_points()
        for name, part in s.parts.items():
            if not points.get(name):
                raise ModelError(f"{s.source}: part '{name}' is not connected to anything")
            if part.centre_of_mass is not None:
                ref = np.asarray(s.hardpoints[part.centre_of_mass] if isinstance(
                    part.centre_of_mass, str) else part.centre_of_mass, float)
            else:
                ref = np.mean(points[name], axis=0)
            self.ref[name] = ref
            mass_t = (part.mass_kg or 1.0) * 1e-3  # tonne in the mm-N-s system
            self.body[name] = mbs.CreateRigidBody(
                referencePosition=ref,
                inertia=InertiaCuboid(density=mass_t / 1e6, sideLengths=[100.0] * 3),
                nodeType=exu.NodeType.RotationRxyz,
                name=f"part:{name}",
            )
        self.node = {n: mbs.GetObject(b)["nodeNumber"] for n, b in self.body.items()}
        self._links: dict[str, int] = {}
        self._joints = {j.name: self._add_joint(j.name, j.parts, j.position_mm, j.frame,
                                                j.constrained, j.offset_mm, j.part_shift_mm)
                        for j in s.joints}
        for link in s.links:
            m0 = self._position_marker(link.parts[0], link.points_mm[0])
            m1 = self._position_marker(link.parts[1], link.points_mm[1])
            length = float(np.linalg.norm(link.points_mm[1] - link.points_mm[0]))
            self._links[link.name] = mbs.AddObject(ObjectConnectorDistance(
                markerNumbers=[m0, m1], distance=length, name=f"link:{link.name}"))
        self._bushings = {b.name: self._add_bushing(b) for b in s.bushings}
        self._friction = {name: self._add_friction(name, torque)
                          for name, torque in self._friction_spec.items()}
        self._springs = {}
        for sp in s.springs:
            m0 = self._position_marker(sp.parts[0], sp.seats_mm[0])
            m1 = self._position_marker(sp.parts[1], sp.seats_mm[1])
            # compression force P at the installed length L: reference length L + P / k
            ref_len = sp.installed_length_mm + self._spring_force[sp.name] / sp.rate_N_per_mm
            self._springs[sp.name] = mbs.AddObject(ObjectConnectorSpringDamper(
                markerNumbers=[m0, m1], referenceLength=ref_len, stiffness=sp.rate_N_per_mm,
                damping=0.0, name=f"spring:{sp.name}"))
        # rig pad at the contact patch: vertical position constraint (x, y free) + loads
        w = s.wheel
        self.patch_local = w.contact_patch_mm - self.ref[w.part]
        self.centre_local = w.centre_mm - self.ref[w.part]
        pad_g = mbs.AddMarker(MarkerBodyRigid(bodyNumber=self.ground,
                                              localHT=exu.HT(np.eye(3), w.contact_patch_mm)))
        pad_w = mbs.AddMarker(MarkerBodyRigid(bodyNumber=self.body[w.part],
                                              localHT=exu.HT(np.eye(3), self.patch_local)))
        self.pad = mbs.AddObject(ObjectJointGeneric(
            markerNumbers=[pad_g, pad_w], constrainedAxes=[0, 0, 1, 0, 0, 0],
            activeConnector=False, name="rig:pad"))
        centre_w = mbs.AddMarker(MarkerBodyRigid(bodyNumber=self.body[w.part],
                                                 localHT=exu.HT(np.eye(3), self.centre_local)))
        self._loads = {
            "pad_force": mbs.AddLoad(LoadForceVector(markerNumber=pad_w, loadVector=[0, 0, 0])),
            "centre_force": mbs.AddLoad(LoadForceVector(markerNumber=centre_w,
                                                        loadVector=[0, 0, 0])),
            "centre_torque": mbs.AddLoad(LoadTorqueVector(markerNumber=centre_w,
                                                          loadVector=[0, 0, 0])),
        }
        self._add_sensors()
        _exudyn_call(mbs.Assemble, f"{s.source}: assembling the model")

    def _part_points(self) -> dict[str, list[np.ndarray]]:
        s = self.suspension
        pts: dict[str, list[np.ndarray]] = {n: [] for n in s.parts}
        items = [(j.parts, (j.position_mm, j.position_mm)) for j in s.joints]
        items += [(lk.parts, lk.points_mm) for lk in s.links]
        items += [(b.parts, (b.position_mm, b.position_mm)) for b in s.bushings]
        items += [(sp.parts, sp.seats_mm) for sp in s.springs]
        for parts, (p0, p1) in items:
            for part, p in zip(parts, (p0, p1)):
                if part in pts:
                    pts[part].append(p)
        if s.wheel.part in pts:
            pts[s.wheel.part].append(s.wheel.centre_mm)
        return pts

    def _body_or_ground(self, part: str) -> int:
        return self.ground if part == self.suspension.ground else self.body[part]

    def _rigid_marker(self, part: str, position: np.ndarray, frame: np.ndarray) -> int:
        local = np.asarray(position) - self.ref[part]
        return self.mbs.AddMarker(MarkerBodyRigid(bodyNumber=self._body_or_ground(part),
                                                  localHT=exu.HT(np.asarray(frame), local)))

    def _position_marker(self, part: str, position: np.ndarray) -> int:
        local = np.asarray(position) - self.ref[part]
        return self.mbs.AddMarker(MarkerBodyPosition(bodyNumber=self._body_or_ground(part),
                                                     localPosition=local))

    def _add_joint(self, name, parts, position, frame, constrained, offset_mm=0.0,
                   part_shift_mm=None, prefix="joint") -> int:
        # part_shift_mm: where each part's attachment sits relative to ``position`` (an
        # as-built joint with assembly clearance); the static solve closes the gap
        shift0, shift1 = (np.zeros(3), np.zeros(3)) if part_shift_mm is None else \
            (np.asarray(part_shift_mm[0], float), np.asarray(part_shift_mm[1], float))
        if list(constrained) == [1, 1, 1, 0, 0, 0] and not offset_mm:
            # 3 algebraic equations instead of the generic joint's 6
            return self.mbs.AddObject(ObjectJointSpherical(
                markerNumbers=[self._position_marker(parts[0], position + shift0),
                               self._position_marker(parts[1], position + shift1)],
                name=f"{prefix}:{name}"))
        # an offset along the joint's z (a rack held at travel_mm) moves part 0's marker:
        # the constraint then puts part 1 there
        frame = np.asarray(frame, float)
        m0 = self._rigid_marker(parts[0], position + float(offset_mm) * frame[:, 2] + shift0,
                                frame)
        m1 = self._rigid_marker(parts[1], position + shift1, frame)
        return self.mbs.AddObject(ObjectJointGeneric(
            markerNumbers=[m0, m1], constrainedAxes=list(constrained), name=f"{prefix}:{name}"))

    def _add_bushing(self, b: Bushing) -> dict:
        from elastokin.physics.joints import CONSTRAINED

        mbs = self.mbs
        m0 = self._rigid_marker(b.parts[0], b.position_mm, b.frame)
        m1 = self._rigid_marker(b.parts[1], b.position_mm, b.frame)
        rates = np.array([law.rate_at_zero for law in b.laws]) * self.options.stiffness_scale
        rates_rad = rates.copy()
        rates_rad[3:] /= _DEG  # N*mm/deg -> N*mm/rad
        entry = {"markers": (m0, m1), "ideal": None}
        if self.options.kinematic or self._balancing:
            constrained = np.array(CONSTRAINED[b.ideal_joint])
            kr = np.where(constrained[3:], 0.0, REGULARISATION * rates_rad[3:])
            if self._balancing:
                # translations held exactly (constraint reactions are the bushing forces);
                # rotations held by stiff springs, whose torques Exudyn reports in the
                # bushing frame
                kr = np.where(constrained[3:], _BALANCING_ROTATION, kr)
                constrained[3:] = 0
            entry["ideal"] = mbs.AddObject(ObjectJointGeneric(
                markerNumbers=[m0, m1], constrainedAxes=constrained.tolist(),
                name=f"ideal:{b.name}"))
            stiffness = np.diag(np.r_[0.0, 0.0, 0.0, kr])
            entry["object"] = mbs.AddObject(ObjectConnectorRigidBodySpringDamper(
                markerNumbers=[m0, m1], stiffness=stiffness, damping=np.zeros((6, 6)),
                name=f"bushing:{b.name}"))
            entry["linear"] = True
            return entry
        laws = [law.scaled(self.options.stiffness_scale) for law in b.laws]
        u0 = self._initial_deflection[b.name]
        if all(law.is_linear for law in laws) and self.options.user_functions == "symbolic":
            # linear laws: Exudyn's own K * (u - offset), no user function at all
            offset = -np.r_[u0[:3], u0[3:] * _DEG]
            obj = mbs.AddObject(ObjectConnectorRigidBodySpringDamper(
                markerNumbers=[m0, m1], stiffness=np.diag(rates_rad), damping=np.zeros((6, 6)),
                offset=offset.tolist(), name=f"bushing:{b.name}"))
            entry.update(object=obj, linear=True, laws=laws, u0=u0)
            return entry
        obj = mbs.AddObject(ObjectConnectorRigidBodySpringDamper(
            markerNumbers=[m0, m1], stiffness=np.diag(rates_rad), damping=np.zeros((6, 6)),
            name=f"bushing:{b.name}"))
        symbolic = self.options.user_functions == "symbolic"
        uf = make_bushing_function(laws, u0, symbolic=symbolic)
        if symbolic:
            uf = CreateSymbolicUserFunction(mbs, uf, "springForceTorqueUserFunction", obj)
            self._bushing_functions.append(uf)  # the expression tree must outlive the model
        mbs.SetObjectParameter(obj, "springForceTorqueUserFunction", uf)
        entry.update(object=obj, linear=False, laws=laws, u0=u0)
        return entry

    def _add_friction(self, name: str, torque_Nmm: float) -> dict:
        """Dry friction in a spherical joint as a Jenkins element: a rotational stick spring
        between the two parts (stiffness = breakaway torque / presliding rotation) whose
        anchor slips so that the torque never exceeds the breakaway torque (return mapping
        after every solved step, see :meth:`_slip`). Rate-independent hysteresis."""
        joint = next((j for j in self.suspension.joints if j.name == name), None)
        if joint is None or joint.kind != "spherical":
            raise ModelError(f"{self.suspension.source}: ball-joint friction on '{name}': "
                             "expected the name of a spherical joint")
        if not torque_Nmm > 0:
            raise ModelError(f"{self.suspension.source}: ball-joint friction on '{name}': "
                             f"breakaway torque must be positive, got {torque_Nmm}")
        k = torque_Nmm / self._presliding_rad  # N*mm/rad
        m0 = self._rigid_marker(joint.parts[0], joint.position_mm, np.eye(3))
        m1 = self._rigid_marker(joint.parts[1], joint.position_mm, np.eye(3))
        obj = self.mbs.AddObject(ObjectConnectorRigidBodySpringDamper(
            markerNumbers=[m0, m1], stiffness=np.diag([0.0, 0.0, 0.0, k, k, k]),
            damping=np.zeros((6, 6)), offset=[0.0] * 6, name=f"friction:{name}"))
        return {"object": obj, "k": k, "torque": float(torque_Nmm), "anchor": np.zeros(3)}

    def _slip(self) -> float:
        """Return mapping of every friction element at the current state: where the stick
        torque exceeds the breakaway torque the anchor moves so that it equals it. Returns
        the largest excess torque relative to the breakaway torque (0 when all stick)."""
        ovt = exu.OutputVariableType
        worst = 0.0
        for e in self._friction.values():
            theta = np.asarray(self.mbs.GetObjectOutput(e["object"], ovt.Rotation), float)
            trial = e["k"] * (theta - e["anchor"])
            size = float(np.linalg.norm(trial))
            if size > e["torque"]:
                worst = max(worst, size / e["torque"] - 1.0)
                e["anchor"] = theta - (e["torque"] / e["k"]) * trial / size
                self.mbs.SetObjectParameter(e["object"], "offset",
                                            [0.0, 0.0, 0.0, *e["anchor"].tolist()])
        return worst

    def _friction_active(self, on: bool) -> None:
        for e in self._friction.values():
            k = e["k"] if on else 0.0
            self.mbs.SetObjectParameter(e["object"], "stiffness",
                                        np.diag([0.0, 0.0, 0.0, k, k, k]))

    def _friction_at_rest(self) -> None:
        """Anchor every friction element at its current rotation (no stick torque)."""
        ovt = exu.OutputVariableType
        for e in self._friction.values():
            e["anchor"] = np.asarray(self.mbs.GetObjectOutput(e["object"], ovt.Rotation), float)
            self.mbs.SetObjectParameter(e["object"], "offset",
                                        [0.0, 0.0, 0.0, *e["anchor"].tolist()])

    def _reset_friction(self) -> None:
        for e in self._friction.values():
            e["anchor"] = np.zeros(3)
            self.mbs.SetObjectParameter(e["object"], "offset", [0.0] * 6)

    def _add_sensors(self) -> None:
        """Record every output in C++ at each load step (no Python call per step)."""
        mbs = self.mbs
        ovt = exu.OutputVariableType
        b = self.body[self.suspension.wheel.part]

        def body(output, local=(0.0, 0.0, 0.0)):
            return mbs.AddSensor(SensorBody(bodyNumber=b, localPosition=list(local),
                                            outputVariableType=output, storeInternal=True,
                                            writeToFile=False))

        def obj(number, output):
            return mbs.AddSensor(SensorObject(objectNumber=number, outputVariableType=output,
                                              storeInternal=True, writeToFile=False))

        self._sensors = {
            "rotation": body(ovt.RotationMatrix),
            "centre": body(ovt.Position, self.centre_local),
            "patch": body(ovt.Position, self.patch_local),
            "pad": obj(self.pad, ovt.ForceLocal),
        }
        for name, o in self._springs.items():
            self._sensors[f"spring:{name}"] = obj(o, ovt.ForceLocal)
        for name, e in self._bushings.items():
            for key, output in (("d", ovt.DisplacementLocal), ("r", ovt.Rotation),
                                ("f", ovt.ForceLocal), ("t", ovt.TorqueLocal)):
                self._sensors[f"bushing:{name}:{key}"] = obj(e["object"], output)
        for name, number in (self.body if self.options.part_poses else {}).items():
            for key, output in (("R", ovt.RotationMatrix), ("disp", ovt.Displacement)):
                self._sensors[f"part:{name}:{key}"] = mbs.AddSensor(SensorBody(
                    bodyNumber=number, localPosition=[0.0, 0.0, 0.0], outputVariableType=output,
                    storeInternal=True, writeToFile=False))
        self._pose_refs = {name: self.ref[name] for name in self.body}  # shared, read-only

    # ------------------------------------------------------------------ rig inputs
    def _set_path(self, kind: str, item: int, ts: np.ndarray, values: np.ndarray) -> None:
        """Make a rig input follow the piecewise-linear path ``values`` (n+1, k) over load
        time ``ts``: a constant when it is constant, otherwise a user function of t."""
        mbs = self.mbs
        set_param = mbs.SetObjectParameter if kind == "offset" else mbs.SetLoadParameter
        uf_name = "offsetUserFunction" if kind == "offset" else "loadVectorUserFunction"
        const = np.allclose(values, values[0], rtol=0.0, atol=0.0)
        if const and kind != "offset":
            set_param(item, uf_name, 0)
            set_param(item, "loadVector", values[0].tolist())
            return
        fn = make_path_function(ts, values, kind, symbolic=self.options.user_functions
                                == "symbolic")
        if self.options.user_functions == "symbolic":
            fn = CreateSymbolicUserFunction(mbs, fn, uf_name, item)
            self._keep_alive.append(fn)
        set_param(item, uf_name, fn)

    # ------------------------------------------------------------------ solving
    def _settings(self, steps: int):
        sv = self.suspension.solver
        ss = exu.SimulationSettings()
        ss.solution.file.write = False
        ss.solution.sensors.active = True  # internal storage only: every sensor has no file
        ss.solution.sensors.writePeriod = 0.0
        st = ss.staticSolver
        st.numberOfLoadSteps = steps
        st.useLoadFactor = False  # loads follow their user functions of t, not a load factor
        st.adaptiveStep = sv.adaptive_step
        st.verboseMode = 0
        st.stepInformation = 0
        st.newton.useModifiedNewton = sv.modified_newton
        st.newton.relativeTolerance = sv.newton_tolerance
        st.newton.absoluteTolerance = ABSOLUTE_TOLERANCE
        st.newton.maxIterations = sv.max_newton_iterations
        ss.linearSolver.solverType = exu.LinearSolverType.EigenDense
        return ss

    def solver_settings(self) -> dict:
        """Solver settings recorded with every result (traceability)."""
        sv = self.suspension.solver
        return {
            "solver": "exudyn SolveStatic (Newton, load steps along the rig path)",
            "newton_relative_tolerance": sv.newton_tolerance,
            "newton_absolute_tolerance": ABSOLUTE_TOLERANCE,
            "max_newton_iterations": sv.max_newton_iterations,
            "modified_newton": sv.modified_newton,
            "adaptive_step": sv.adaptive_step,
            "linear_solver": "EigenDense",
            "node_type": "RotationRxyz",
            "user_functions": self.options.user_functions,
            "kinematic": self.options.kinematic,
            "stiffness_scale": self.options.stiffness_scale,
        }

    def run(self, pad_z_mm: Sequence[float] | None = None,
            pad_loads: np.ndarray | None = None,
            centre_loads: np.ndarray | None = None,
            what: str = "static solve", solve_per_step: bool = False,
            substeps: int | None = None) -> list[StepState]:
        """Solve a sequence of quasi-static steps from the design position.

        pad_z_mm: prescribed vertical displacement of the contact patch per step (mm), or None
            for force control (then the patch is free and ``pad_loads`` must carry Fz).
        pad_loads: (n, 3) forces at the contact patch per step, N, config frame.
        centre_loads: (n, 6) forces (N) and torques (N*mm) at the wheel centre per step.
        solve_per_step: one Exudyn ``SolveStatic`` per step (the slow, straightforward way,
            kept for benchmarks) instead of one solve over all steps. A model with ball-joint
            friction always solves per step (the friction anchors are updated between steps).
        substeps: solver steps per returned step (the rig path subdivided linearly; friction
            models need them to follow the slip); default: the model's ``substeps``.
        Returns one :class:`StepState` per step. Raises :class:`SolverError` naming the step
        that did not converge.
        """
        if pad_z_mm is None and pad_loads is None:
            raise ModelError("run: give pad_z_mm (displacement control) or pad_loads")
        n = len(pad_z_mm) if pad_z_mm is not None else len(pad_loads)
        pl = np.asarray(pad_loads, float).reshape(n, 3) if pad_loads is not None \
            else np.zeros((n, 3))
        cl = np.asarray(centre_loads, float).reshape(n, 6) if centre_loads is not None \
            else np.zeros((n, 6))
        substeps = self.substeps if substeps is None else int(substeps)
        if substeps > 1:
            def refine(v, start):
                path = np.vstack([start, v])
                s = np.linspace(0.0, n, n * substeps + 1)
                return np.array([np.interp(s, np.arange(n + 1), c) for c in path.T]).T[1:]
            pl, cl = refine(pl, pl[:1]), refine(cl, cl[:1])
            if pad_z_mm is not None:
                pad_z_mm = refine(np.asarray(pad_z_mm, float)[:, None], [[0.0]])[:, 0]
            states = self.run(pad_z_mm, pl, cl, what, solve_per_step, substeps=1)
            return states[substeps - 1::substeps]
        settle = bool(self._friction)
        if settle:
            # the rig starts from the settled suspension: a first step to the path's start
            # (pad at the design height, or the first pad load) with friction released, then
            # every ball joint at rest there (no stick torque); that step is not returned
            solve_per_step = True
            self._reset_friction()
            if pad_z_mm is not None:
                pad_z_mm = np.r_[0.0, np.asarray(pad_z_mm, float)]
            pl, cl = np.vstack([pl[:1], pl]), np.vstack([np.zeros((1, 6)), cl])
            n += 1
        ts = np.linspace(0.0, 1.0, n + 1)
        # every path starts from the design state at t = 0 (offset 0, loads of the first step)
        pad_path = np.vstack([pl[:1], pl])
        centre_path = np.vstack([cl[:1], cl])
        mbs = self.mbs
        self._keep_alive.clear()
        self._set_path("load", self._loads["pad_force"], ts, pad_path)
        self._set_path("load", self._loads["centre_force"], ts, centre_path[:, :3])
        self._set_path("load", self._loads["centre_torque"], ts, centre_path[:, 3:])
        active = pad_z_mm is not None
        if active:
            z = np.r_[0.0, np.asarray(pad_z_mm, float)]
            offset = np.zeros((n + 1, 6))
            offset[:, 2] = z
            self._set_path("offset", self.pad, ts, offset)
        mbs.SetObjectParameter(self.pad, "activeConnector", active)
        initial = exu.ConfigurationType.Initial
        q0 = mbs.systemData.GetODE2Coordinates(initial)
        mbs.systemData.SetODE2Coordinates(q0, exu.ConfigurationType.Current)
        mbs.Assemble()
        ss = self._settings(n)
        label = f"{self.suspension.source}: {what}"

        def solve() -> tuple[bool, str]:
            try:
                return _exudyn_call(lambda: mbs.SolveStatic(ss), label) is not False, ""
            except SolverError as exc:
                return False, f" (Exudyn: {str(exc).removeprefix(label + ': ')})"

        if not solve_per_step:
            ok, detail = solve()
            rows = self._recorded(ts)
        else:
            ss.staticSolver.numberOfLoadSteps = 1
            ss.staticSolver.loadStepDuration = 1.0 / n
            rows, ok, detail = [], True, ""
            try:
                for k in range(n):
                    ss.staticSolver.loadStepStart = ts[k]
                    if settle and k == 0:  # friction released, then at rest where it settled
                        self._friction_active(False)
                        ok, detail = solve()
                        self._friction_active(True)
                        if ok:
                            self._friction_at_rest()
                    else:
                        for _ in range(FRICTION_ITERATIONS):
                            ok, detail = solve()
                            # friction: re-solve the step until no anchor has to slip further
                            if not ok or not self._friction or \
                                    self._slip() < FRICTION_TOLERANCE:
                                break
                        else:
                            ok, detail = False, (f" (ball-joint friction: anchors still "
                                                 f"slipping after {FRICTION_ITERATIONS} "
                                                 "re-solves)")
                    if not ok:
                        break
                    rows.append(self._recorded(ts[k:k + 2])[-1])
                    mbs.systemData.SetODE2Coordinates(mbs.systemData.GetODE2Coordinates(),
                                                      initial)
            finally:
                mbs.systemData.SetODE2Coordinates(q0, initial)
        if not ok or len(rows) < n:
            raise SolverError(
                f"{label}: static solve did not converge after step {len(rows)} of {n} "
                f"(Newton tolerance {self.suspension.solver.newton_tolerance:g}, at most "
                f"{self.suspension.solver.max_newton_iterations} iterations){detail}; check the "
                "geometry and the loads, or the solver settings")
        pad_applied = pad_path[1:]
        states = [self._state(row, pad_applied[i], active) for i, row in enumerate(rows)]
        return states[1:] if settle else states

    def _recorded(self, ts: np.ndarray) -> list[dict[str, np.ndarray]]:
        """Sensor values at the load-step times ``ts[1:]`` that were reached (adaptive
        sub-steps skipped), one dict of arrays per step."""
        data = {k: np.asarray(self.mbs.GetSensorStoredData(v)) for k, v in self._sensors.items()}
        t = data["rotation"][:, 0]
        rows = []
        for tk in ts[1:]:
            hit = np.flatnonzero(np.abs(t - tk) < 1e-9)
            if hit.size == 0:
                break
            rows.append(hit[-1])
        idx = np.asarray(rows, int)
        for name in self._bushings:  # bushing deflection: mm and deg in one 6-vector
            data[f"bushing:{name}:u"] = np.concatenate(
                [data.pop(f"bushing:{name}:d")[:, 1:], data.pop(f"bushing:{name}:r")[:, 1:] / _DEG],
                axis=1)
            data[f"bushing:{name}:load"] = np.concatenate(
                [data.pop(f"bushing:{name}:f")[:, 1:], data.pop(f"bushing:{name}:t")[:, 1:]],
                axis=1)
        picked = {k: (v[idx] if k.endswith((":u", ":load")) else v[idx, 1:])
                  for k, v in data.items()}
        return [{k: v[i] for k, v in picked.items()} for i in range(idx.size)]

    def _state(self, row: dict[str, np.ndarray], pad_load: np.ndarray,
               pad_active: bool) -> StepState:
        R = row["rotation"].reshape(3, 3)
        pad = pad_load.copy()
        if pad_active:
            pad[2] += row["pad"][2]
        springs = {n: -float(row[f"spring:{n}"][0]) for n in self._springs}
        defl, load = {}, {}
        for name, e in self._bushings.items():
            u = row[f"bushing:{name}:u"]
            if e.get("ideal") is None:
                u = u + self._initial_deflection[name]
                f = row[f"bushing:{name}:load"]
            else:
                f = np.full(6, np.nan)
            defl[name], load[name] = u, f
        poses = None if not self.options.part_poses else PartPoses(
            {n: row[f"part:{n}:R"].reshape(3, 3) for n in self.body},
            {n: row[f"part:{n}:disp"] for n in self.body}, self._pose_refs)
        return StepState(row["centre"], R @ self.suspension.wheel.spin_axis, R,
                         row["patch"], pad, springs, defl, load, poses)

    def balancing_bushing_loads(self) -> dict[str, np.ndarray]:
        """Balancing model: the load each bushing carries in the current state (Fx Fy Fz N,
        Tx Ty Tz N*mm, bushing frame, +K*u convention): the reaction force of its translational
        constraint and the torque of its stiff rotational springs."""
        if not self._balancing:
            raise ModelError("balancing_bushing_loads: not a balancing model")
        ovt = exu.OutputVariableType
        out = {}
        for name, e in self._bushings.items():
            spring = np.r_[self.mbs.GetObjectOutput(e["object"], ovt.ForceLocal),
                           self.mbs.GetObjectOutput(e["object"], ovt.TorqueLocal)]
            # the constraint's reaction on parts[0] is opposite to a spring's +K*u
            spring[:3] -= np.asarray(self.mbs.GetObjectOutput(e["ideal"], ovt.ForceLocal))
            out[name] = spring
        return out

    def forces_on_part(self, part: str) -> dict[str, np.ndarray]:
        """Force (N, config frame) that each connector and rig input applies to ``part`` in
        the current (last solved) state. Joint torques are not included."""
        mbs = self.mbs
        ovt = exu.OutputVariableType
        s = self.suspension
        out: dict[str, np.ndarray] = {}

        def marker_rotation(obj: int, k: int) -> np.ndarray:
            m = mbs.GetObject(obj)["markerNumbers"][k]
            marker = mbs.GetMarker(m)
            body = marker["bodyNumber"]
            local = np.asarray(marker["localHT"])[:3, :3] if "localHT" in marker else np.eye(3)
            if body == self.ground:
                return local
            R = np.asarray(mbs.GetObjectOutputBody(body, ovt.RotationMatrix, [0, 0, 0]))
            return R.reshape(3, 3) @ local

        def sign(parts: tuple[str, str]) -> float:
            return (-1.0 if parts[0] == part else 1.0) if part in parts else 0.0

        def marker_position(obj: int, k: int) -> np.ndarray:
            m = mbs.GetObject(obj)["markerNumbers"][k]
            return np.asarray(mbs.GetMarkerOutput(m, exu.OutputVariableType.Position))

        for j in s.joints:
            obj = self._joints[j.name]
            if sign(j.parts):
                if mbs.GetObject(obj)["objectType"] == "JointSpherical":
                    f1 = np.asarray(mbs.GetObjectOutput(obj, ovt.Force))  # on body 1, global
                else:
                    f1 = marker_rotation(obj, 0) @ np.asarray(mbs.GetObjectOutput(
                        obj, ovt.ForceLocal))
                out[j.name] = sign(j.parts) * f1
        for lk in s.links:
            if sign(lk.parts):
                obj = self._links[lk.name]
                d = marker_position(obj, 1) - marker_position(obj, 0)
                # the distance constraint's multiplier is positive in compression
                compression = float(np.asarray(mbs.GetObjectOutput(obj, ovt.Force)).ravel()[0])
                out[lk.name] = sign(lk.parts) * compression * d / np.linalg.norm(d)
        for b in s.bushings:
            if sign(b.parts):
                e = self._bushings[b.name]
                f0 = marker_rotation(e["object"], 0) @ np.asarray(
                    mbs.GetObjectOutput(e["object"], ovt.ForceLocal))  # +K*u: on body 0
                total = -f0
                if e.get("ideal") is not None:
                    total = total + marker_rotation(e["ideal"], 0) @ np.asarray(
                        mbs.GetObjectOutput(e["ideal"], ovt.ForceLocal))
                out[b.name] = sign(b.parts) * total
        for sp in s.springs:
            if sign(sp.parts):
                obj = self._springs[sp.name]
                d = marker_position(obj, 1) - marker_position(obj, 0)
                tension = float(mbs.GetObjectOutput(obj, ovt.ForceLocal))
                out[sp.name] = -sign(sp.parts) * tension * d / np.linalg.norm(d)
        if part == s.wheel.part:
            pad = np.asarray(mbs.GetObjectOutput(self.pad, ovt.ForceLocal)) if \
                mbs.GetObjectParameter(self.pad, "activeConnector") else np.zeros(3)
            applied = np.asarray(mbs.GetLoadValues(self._loads["pad_force"]))
            applied = applied + np.asarray(mbs.GetLoadValues(self._loads["centre_force"]))
            out["rig"] = pad + applied
        return out

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

    def check_assembly(self) -> None:
        """Raise :class:`ModelError` when the ideal joints are redundant (over-constrained) or,
        with the rig pad holding the contact patch height, leave the wheel free to move
        (under-constrained: e.g. a missing tie rod or joint). Use on a kinematic model."""
        src = self.suspension.source
        redundant = int(self.degrees_of_freedom(pad=False)["redundantConstraints"])
        if redundant > 0:
            raise ModelError(
                f"{src}: the assembly is over-constrained: {redundant} redundant constraint "
                "equation(s) among the joints (in the kinematic model each bushing counts as "
                "its ideal_joint); remove a joint or free one of its axes")
        if self.degrees_of_freedom(pad=True)["redundantConstraints"] > 0:
            raise ModelError(
                f"{src}: the joints hold the wheel part '{self.suspension.wheel.part}' rigidly "
                "(bushings counted as their ideal_joint): it cannot travel vertically")
        mbs = self.mbs
        mbs.SetObjectParameter(self.pad, "activeConnector", True)
        mbs.Assemble()
        try:
            solver = exu.MainSolverStatic()
            ss = self._settings(1)
            _exudyn_call(lambda: solver.InitializeSolver(mbs, ss), f"{src}: assembly check")
            _exudyn_call(lambda: solver.ComputeNewtonJacobian(mbs, ss),
                         f"{src}: assembly check")
            jac = np.asarray(solver.GetSystemJacobian())
        finally:
            mbs.SetObjectParameter(self.pad, "activeConnector", False)
            mbs.Assemble()
        n2 = mbs.systemData.ODE2Size()
        cq = jac[n2:, :n2]
        _, sv, vt = np.linalg.svd(cq)
        rank = int(np.sum(sv > 1e-9 * sv[0]))
        null = vt[rank:].T  # free motions of the joints' skeleton (incl. idle spins)
        wheel = self.suspension.wheel.part
        i0 = mbs.GetNodeODE2Index(self.node[wheel])
        if null.size and np.max(np.linalg.norm(null[i0:i0 + 6], axis=0)) > 1e-6:
            raise ModelError(
                f"{src}: the assembly is under-constrained: with bushings replaced by their "
                f"ideal joints and the contact patch held, the wheel part '{wheel}' can still "
                "move; a joint, link or the steering (tie rod / rack) is missing")

    def degrees_of_freedom(self, pad: bool = True) -> dict:
        """Exudyn's numerical DOF count of the constraints, with or without the rig pad
        holding the contact patch height."""
        mbs = self.mbs
        mbs.SetObjectParameter(self.pad, "activeConnector", pad)
        mbs.Assemble()
        try:
            return _exudyn_call(lambda: mbs.ComputeSystemDegreeOfFreedom(verbose=0),
                                "counting degrees of freedom")
        finally:
            mbs.SetObjectParameter(self.pad, "activeConnector", False)
            mbs.Assemble()


def path_hinges(ts: np.ndarray, values: np.ndarray) -> list[tuple[float, float, list]]:
    """Each column of the piecewise-linear path ``values`` (n+1, k) over ``ts`` (n+1,) as
    (c, k0, [(t_i, dk_i)]) with v(t) = c + k0*t + sum dk_i*max(t - t_i, 0); hinges whose
    slope change is negligible are dropped."""
    ts = np.asarray(ts, float)
    values = np.asarray(values, float).reshape(ts.size, -1)
    out = []
    for v in values.T:
        slopes = np.diff(v) / np.diff(ts)
        k0 = float(slopes[0])
        tol = 1e-12 * max(1.0, float(np.max(np.abs(slopes))))
        hinges = [(float(ts[i]), float(slopes[i] - slopes[i - 1]))
                  for i in range(1, slopes.size) if abs(slopes[i] - slopes[i - 1]) > tol]
        out.append((float(v[0] - k0 * ts[0]), k0, hinges))
    return out


def make_path_function(ts: np.ndarray, values: np.ndarray, kind: str, symbolic: bool):
    """A rig input path as an Exudyn user function of load time t: ``kind`` "load" gives a
    ``loadVectorUserFunction`` (3 values), "offset" a generic joint ``offsetUserFunction``
    (6 values). Written with hinge functions so that it converts to a symbolic function."""
    columns = path_hinges(ts, values)
    maxf = exu.symbolic.max if symbolic else _max

    def value(i, t):
        c, k0, hinges = columns[i]
        out = c + k0 * t
        for ti, dk in hinges:
            out = out + dk * maxf(t - ti, 0.0)
        return out

    if kind == "offset":
        def offset(mbs, t, itemNumber, offsetUserFunctionParameters):
            return [value(0, t), value(1, t), value(2, t), value(3, t), value(4, t),
                    value(5, t)]
        return offset

    def load(mbs, t, loadVector):
        return [value(0, t), value(1, t), value(2, t)]
    return load


def _max(a, b):
    return a if a > b else b


def make_bushing_function(laws: Sequence, initial_deflection: np.ndarray, symbolic: bool):
    """The bushing's 6 loads (N, N*mm) as an Exudyn ``springForceTorqueUserFunction``.

    Deflection in the bushing frame: displacement (mm) and Tait-Bryan rotation (rad, converted
    to deg), plus the initial deflection; each direction's law is written in closed form (hinge
    functions, times a polynomial for a progressive law; see :mod:`elastokin.laws`), so the
    same closure is converted to a symbolic function.
    """
    u0 = [float(x) for x in initial_deflection]
    maxf = exu.symbolic.max if symbolic else _max

    def evaluate(i, v):
        return laws[i].expression(v, maxf)

    def bushing_loads(mbs, t, itemNumber, displacement, rotation, velocity, angularVelocity,
                      stiffness, damping, rotJ0, rotJ1, offset):
        return [evaluate(0, displacement[0] + u0[0]),
                evaluate(1, displacement[1] + u0[1]),
                evaluate(2, displacement[2] + u0[2]),
                evaluate(3, rotation[0] * 57.29577951308232 + u0[3]),
                evaluate(4, rotation[1] * 57.29577951308232 + u0[4]),
                evaluate(5, rotation[2] * 57.29577951308232 + u0[5])]

    return bushing_loads


@dataclass(frozen=True)
class DesignState:
    """Preloads that make the design hardpoints the static equilibrium under the wheel load.

    spring_force_N: compression force of each spring at its installed length.
    bushing_preload: loads (Fx Fy Fz N, Tx Ty Tz N*mm, bushing frame, +K*u convention) each
    bushing carries at the design position.
    """

    spring_force_N: dict[str, float]
    bushing_preload: dict[str, np.ndarray]


def design_state(suspension: Suspension) -> DesignState:
    """Spring and bushing preloads for the design position (see ``design`` in the config).

    With ``balance_bushing_preloads`` every bushing is held in its ideal joint's directions
    (translations by exact constraints, rotations by stiff springs), so the design position is
    a structure whose loads are linear in the balanced spring's force P: two solves give the P
    at which the rig pad carries the wheel load, a third the loads each bushing transmits at
    that P, which become the bushing preloads. Otherwise the compliant model is used and P
    found by the secant method.
    """
    s = suspension
    check_assembly(s)
    d = s.design
    springs = {sp.name: sp.design_force_N() for sp in s.springs}
    preload = {b.name: np.array([law(u) for law, u in zip(b.laws, b.initial_deflection)])
               for b in s.bushings}
    if d.balance_spring is None and not d.balance_bushing_preloads:
        return DesignState(springs, preload)
    ideal = d.balance_bushing_preloads  # bushings held by their ideal joints

    def solve(p: float):
        forces = dict(springs)
        if d.balance_spring is not None:
            forces[d.balance_spring] = p
        model = SuspensionModel(s, ModelOptions(), bushing_preload=preload,
                                spring_force_N=forces, _balancing=ideal)
        state = model.run(pad_z_mm=[0.0], what="balancing the design position")[0]
        if ideal:
            state.bushing_load = model.balancing_bushing_loads()
        return state.pad_force_N[2], state

    if d.balance_spring is None:
        _, state = solve(0.0)
        return DesignState(springs, {n: v.copy() for n, v in state.bushing_load.items()})
    w = d.wheel_load_N
    p0, p1 = 0.0, w
    r0, _ = solve(p0)
    r1, state = solve(p1)
    for _ in range(1 if ideal else 20):
        if abs(r1 - r0) < 1e-9:
            raise ModelError(f"{s.source}: design.balance_spring: the force of spring "
                             f"'{d.balance_spring}' does not reach the wheel: cannot balance")
        p2 = p1 + (w - r1) * (p1 - p0) / (r1 - r0)
        p0, r0 = p1, r1
        p1 = p2
        r1, state = solve(p1)
        if abs(r1 - w) < 1e-6 * w:
            break
    else:
        raise SolverError(f"{s.source}: design.balance_spring: no spring preload found that "
                          f"carries the {w:g} N wheel load (last pad load {r1:.6g} N)")
    springs[d.balance_spring] = float(p1)
    if ideal:
        preload = {n: v.copy() for n, v in state.bushing_load.items()}
    return DesignState(springs, preload)


def check_assembly(suspension: Suspension) -> None:
    """Check, on the kinematic model, that the joints neither over- nor under-constrain the
    suspension (see :meth:`SuspensionModel.check_assembly`)."""
    SuspensionModel(suspension, ModelOptions(kinematic=True)).check_assembly()


def build_model(suspension: Suspension, options: ModelOptions = ModelOptions(),
                design: DesignState | None = None) -> SuspensionModel:
    """The model of ``suspension`` with the design preloads applied (computed, after the
    assembly check, when not given)."""
    design = design or design_state(suspension)
    return SuspensionModel(suspension, options, bushing_preload=design.bushing_preload,
                           spring_force_N=design.spring_force_N)
