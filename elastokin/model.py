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
  of 1e-6 times its rates on the joint's free rotations (it only fixes idle spins, e.g. of a link
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

from .config import Bushing, Suspension
from .errors import ModelError, SolverError

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
)
from exudyn.rigidBodyUtilities import InertiaCuboid  # noqa: E402

exu.config.printToConsole = False
EXUDYN_VERSION = exu.__version__

_DEG = np.pi / 180.0
#: stiffness of the regularising springs on an ideal joint's free rotations, relative to the
#: bushing's rotational rates (kinematic model only)
REGULARISATION = 1e-6
#: stiffness used to hold a bushing rigid in its ideal directions while balancing preloads
_PENALTY_TRANSLATION = 1e6  # N/mm
_PENALTY_ROTATION = 1e9  # N*mm/rad


@dataclass(frozen=True)
class ModelOptions:
    """How a suspension is turned into an Exudyn model.

    kinematic: bushings replaced by their ideal joints.
    stiffness_scale: every bushing law's load multiplied by this factor.
    bushing_user_function: ``"symbolic"`` (C++ evaluation) or ``"python"`` (reference/naive).
    """

    kinematic: bool = False
    stiffness_scale: float = 1.0
    bushing_user_function: str = "symbolic"


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


@dataclass
class PartPoses:
    """Rigid-body poses of every moving part at one step: rotation (3, 3) and the displacement
    (mm) of its reference point."""

    rotation: dict[str, np.ndarray] = field(default_factory=dict)
    displacement_mm: dict[str, np.ndarray] = field(default_factory=dict)


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
                 spring_force_N: dict[str, float] | None = None,
                 _penalty_bushings: bool = False):
        self.suspension = suspension
        self.options = options
        self._penalty = _penalty_bushings
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
        self._keep_alive: list = []
        self._pad_mode = "force"
        self._pad_path: tuple[np.ndarray, np.ndarray] = (np.array([0.0, 1.0]), np.zeros(2))
        self._load_path: tuple[np.ndarray, np.ndarray] = (np.array([0.0, 1.0]), np.zeros((2, 6)))
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
        self._joints = {j.name: self._add_joint(j.name, j.parts, j.position_mm, j.frame,
                                                j.constrained, j.offset_mm) for j in s.joints}
        for link in s.links:
            m0 = self._position_marker(link.parts[0], link.points_mm[0])
            m1 = self._position_marker(link.parts[1], link.points_mm[1])
            length = float(np.linalg.norm(link.points_mm[1] - link.points_mm[0]))
            mbs.AddObject(ObjectConnectorDistance(markerNumbers=[m0, m1], distance=length,
                                                  name=f"link:{link.name}"))
        self._bushings = {b.name: self._add_bushing(b) for b in s.bushings}
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
            offsetUserFunction=self._pad_offset, activeConnector=False, name="rig:pad"))
        centre_w = mbs.AddMarker(MarkerBodyRigid(bodyNumber=self.body[w.part],
                                                 localHT=exu.HT(np.eye(3), self.centre_local)))
        self.pad_force = mbs.AddLoad(LoadForceVector(
            markerNumber=pad_w, loadVector=[0, 0, 0], loadVectorUserFunction=self._pad_load))
        self.centre_force = mbs.AddLoad(LoadForceVector(
            markerNumber=centre_w, loadVector=[0, 0, 0],
            loadVectorUserFunction=self._centre_load))
        self.centre_torque = mbs.AddLoad(LoadTorqueVector(
            markerNumber=centre_w, loadVector=[0, 0, 0],
            loadVectorUserFunction=self._centre_torque))
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
                   prefix="joint") -> int:
        m0 = self._rigid_marker(parts[0], position, frame)
        m1 = self._rigid_marker(parts[1], position, frame)
        kwargs = {}
        if offset_mm:
            params = [0.0, 0.0, float(offset_mm), 0.0, 0.0, 0.0]
            kwargs = dict(offsetUserFunctionParameters=params, offsetUserFunction=_const_offset)
        return self.mbs.AddObject(ObjectJointGeneric(
            markerNumbers=[m0, m1], constrainedAxes=list(constrained), name=f"{prefix}:{name}",
            **kwargs))

    def _add_bushing(self, b: Bushing) -> dict:
        from .config import CONSTRAINED

        mbs = self.mbs
        m0 = self._rigid_marker(b.parts[0], b.position_mm, b.frame)
        m1 = self._rigid_marker(b.parts[1], b.position_mm, b.frame)
        rates = np.array([law.rate_at_zero for law in b.laws]) * self.options.stiffness_scale
        rates_rad = rates.copy()
        rates_rad[3:] /= _DEG  # N*mm/deg -> N*mm/rad
        entry = {"markers": (m0, m1), "ideal": None}
        if self.options.kinematic or self._penalty:
            constrained = np.array(CONSTRAINED[b.ideal_joint])
            if self._penalty:
                k = np.where(constrained[:3], _PENALTY_TRANSLATION, 0.0)
                kr = np.where(constrained[3:], _PENALTY_ROTATION, REGULARISATION * rates_rad[3:])
                stiffness = np.diag(np.r_[k, kr])
            else:
                entry["ideal"] = mbs.AddObject(ObjectJointGeneric(
                    markerNumbers=[m0, m1], constrainedAxes=constrained.tolist(),
                    name=f"ideal:{b.name}"))
                kr = np.where(constrained[3:], 0.0, REGULARISATION * rates_rad[3:])
                stiffness = np.diag(np.r_[0.0, 0.0, 0.0, kr])
            entry["object"] = mbs.AddObject(ObjectConnectorRigidBodySpringDamper(
                markerNumbers=[m0, m1], stiffness=stiffness, damping=np.zeros((6, 6)),
                name=f"bushing:{b.name}"))
            entry["linear"] = True
            return entry
        laws = [law.scaled(self.options.stiffness_scale) for law in b.laws]
        u0 = self._initial_deflection[b.name]
        obj = mbs.AddObject(ObjectConnectorRigidBodySpringDamper(
            markerNumbers=[m0, m1], stiffness=np.diag(rates_rad), damping=np.zeros((6, 6)),
            name=f"bushing:{b.name}"))
        uf = make_bushing_function(laws, u0, symbolic=self.options.bushing_user_function
                                   == "symbolic")
        if self.options.bushing_user_function == "symbolic":
            sym = CreateSymbolicUserFunction(mbs, uf, "springForceTorqueUserFunction", obj)
            self._keep_alive.append(sym)
            mbs.SetObjectParameter(obj, "springForceTorqueUserFunction", sym)
        elif self.options.bushing_user_function == "python":
            mbs.SetObjectParameter(obj, "springForceTorqueUserFunction", uf)
        else:
            raise ModelError(f"unknown bushing_user_function "
                             f"'{self.options.bushing_user_function}' (symbolic or python)")
        entry.update(object=obj, linear=False, laws=laws, u0=u0)
        return entry

    # ------------------------------------------------------------------ rig inputs
    def _interp(self, path, t):
        ts, vs = path
        if vs.ndim == 1:
            return float(np.interp(t, ts, vs))
        return np.array([np.interp(t, ts, vs[:, i]) for i in range(vs.shape[1])])

    def _pad_offset(self, mbs, t, itemNumber, params):
        return [0.0, 0.0, self._interp(self._pad_path, t), 0.0, 0.0, 0.0]

    def _pad_load(self, mbs, t, load):
        return list(self._interp(self._load_path, t)[0:3])

    def _centre_load(self, mbs, t, load):
        return list(self._interp(self._centre_path, t)[0:3])

    def _centre_torque(self, mbs, t, load):
        return list(self._interp(self._centre_path, t)[3:6])

    _centre_path: tuple[np.ndarray, np.ndarray] = (np.array([0.0, 1.0]), np.zeros((2, 6)))

    # ------------------------------------------------------------------ solving
    def _settings(self, steps: int):
        sv = self.suspension.solver
        ss = exu.SimulationSettings()
        ss.solution.file.write = False
        ss.solution.sensors.active = False
        st = ss.staticSolver
        st.numberOfLoadSteps = steps
        st.useLoadFactor = False  # loads follow their user functions of t, not a load factor
        st.adaptiveStep = sv.adaptive_step
        st.verboseMode = 0
        st.stepInformation = 0
        st.newton.useModifiedNewton = sv.modified_newton
        st.newton.relativeTolerance = sv.newton_tolerance
        st.newton.absoluteTolerance = 1e-6  # N, N*mm, mm: residual noise floor
        st.newton.maxIterations = sv.max_newton_iterations
        ss.linearSolver.solverType = exu.LinearSolverType.EigenDense
        return ss

    def solver_settings(self) -> dict:
        """Solver settings recorded with every result (traceability)."""
        sv = self.suspension.solver
        return {
            "solver": "exudyn SolveStatic (Newton, load steps along the rig path)",
            "newton_tolerance": sv.newton_tolerance,
            "max_newton_iterations": sv.max_newton_iterations,
            "modified_newton": sv.modified_newton,
            "adaptive_step": sv.adaptive_step,
            "linear_solver": "EigenDense",
            "node_type": "RotationRxyz",
            "bushing_user_function": self.options.bushing_user_function,
            "kinematic": self.options.kinematic,
            "stiffness_scale": self.options.stiffness_scale,
        }

    def run(self, pad_z_mm: Sequence[float] | None = None,
            pad_loads: np.ndarray | None = None,
            centre_loads: np.ndarray | None = None,
            what: str = "static solve") -> list[StepState]:
        """Solve a sequence of quasi-static steps from the design position, one Exudyn solve.

        pad_z_mm: prescribed vertical displacement of the contact patch per step (mm), or None
            for force control (then the patch is free and ``pad_loads`` must carry Fz).
        pad_loads: (n, 3) forces at the contact patch per step, N, config frame.
        centre_loads: (n, 6) forces (N) and torques (N*mm) at the wheel centre per step.
        Returns one :class:`StepState` per step.
        """
        n = len(pad_z_mm) if pad_z_mm is not None else len(pad_loads)
        ts = np.linspace(0.0, 1.0, n + 1)
        zeros = np.zeros((n, 3))
        pl = np.asarray(pad_loads, float) if pad_loads is not None else zeros
        cl = np.asarray(centre_loads, float) if centre_loads is not None else np.zeros((n, 6))
        # the path starts from the design state at t = 0 (offset 0, loads of the first step)
        self._load_path = (ts, np.vstack([pl[:1], pl]))
        self._centre_path = (ts, np.vstack([cl[:1], cl]))
        mbs = self.mbs
        if pad_z_mm is not None:
            self._pad_path = (ts, np.r_[0.0, np.asarray(pad_z_mm, float)])
            mbs.SetObjectParameter(self.pad, "activeConnector", True)
        else:
            mbs.SetObjectParameter(self.pad, "activeConnector", False)
        mbs.systemData.SetODE2Coordinates(mbs.systemData.GetODE2Coordinates(
            exu.ConfigurationType.Initial), exu.ConfigurationType.Current)
        mbs.Assemble()
        grid = {round(t * n): None for t in ts[1:]}
        states: dict[int, StepState] = {}

        def record(mbs_, t):
            k = t * n
            i = int(round(k))
            if abs(k - i) < 1e-9 and i >= 1:
                states[i] = self._state()
            return True

        mbs.SetPostStepUserFunction(record)
        ss = self._settings(n)
        try:
            ok = _exudyn_call(lambda: mbs.SolveStatic(ss), f"{self.suspension.source}: {what}")
        finally:
            mbs.SetPostStepUserFunction(0)
        if ok is False or len(states) < len(grid):
            last = max(states) if states else 0
            raise SolverError(
                f"{self.suspension.source}: {what}: static solve did not converge after step "
                f"{last} of {n} (Newton tolerance {self.suspension.solver.newton_tolerance:g}); "
                "check the geometry and the loads, or loosen solver.newton_tolerance")
        return [states[i] for i in range(1, n + 1)]

    def _state(self) -> StepState:
        mbs = self.mbs
        w = self.suspension.wheel
        ovt = exu.OutputVariableType
        b = self.body[w.part]
        R = np.asarray(mbs.GetObjectOutputBody(b, ovt.RotationMatrix, [0, 0, 0])).reshape(3, 3)
        centre = np.asarray(mbs.GetObjectOutputBody(b, ovt.Position, self.centre_local))
        patch = np.asarray(mbs.GetObjectOutputBody(b, ovt.Position, self.patch_local))
        if mbs.GetObjectParameter(self.pad, "activeConnector"):
            pad = np.asarray(mbs.GetObjectOutput(self.pad, ovt.ForceLocal))
            pad = np.array([0.0, 0.0, pad[2]])
        else:
            pad = np.zeros(3)
        pad = pad + np.asarray(self._pad_load(mbs, mbs.systemData.GetTime(), None))
        springs = {n: -float(mbs.GetObjectOutput(o, ovt.ForceLocal))
                   for n, o in self._springs.items()}
        defl, load = {}, {}
        for name, e in self._bushings.items():
            obj = e["object"]
            d = np.asarray(mbs.GetObjectOutput(obj, ovt.DisplacementLocal))
            r = np.asarray(mbs.GetObjectOutput(obj, ovt.Rotation)) / _DEG
            u = np.r_[d, r]
            if e.get("ideal") is None:
                u = u + self._initial_deflection[name] * (0.0 if self._penalty else 1.0)
                f = np.r_[mbs.GetObjectOutput(obj, ovt.ForceLocal),
                          mbs.GetObjectOutput(obj, ovt.TorqueLocal)]
            else:
                f = np.full(6, np.nan)
            defl[name], load[name] = u, np.asarray(f, float)
        return StepState(centre, R @ self._spin_local, R, patch, pad, springs, defl, load)

    @property
    def _spin_local(self) -> np.ndarray:
        return self.suspension.wheel.spin_axis

    def part_poses(self) -> PartPoses:
        """Poses of every moving part in the current (last solved) state."""
        ovt = exu.OutputVariableType
        poses = PartPoses()
        for name, b in self.body.items():
            poses.rotation[name] = np.asarray(
                self.mbs.GetObjectOutputBody(b, ovt.RotationMatrix, [0, 0, 0])).reshape(3, 3)
            poses.displacement_mm[name] = np.asarray(
                self.mbs.GetObjectOutputBody(b, ovt.Displacement, [0, 0, 0]))
        return poses

    def degrees_of_freedom(self) -> dict:
        """Exudyn's numerical DOF count with the rig pad active (0 for a well-posed rig)."""
        mbs = self.mbs
        mbs.SetObjectParameter(self.pad, "activeConnector", True)
        mbs.Assemble()
        try:
            return _exudyn_call(lambda: mbs.ComputeSystemDegreeOfFreedom(verbose=0),
                                "counting degrees of freedom")
        finally:
            mbs.SetObjectParameter(self.pad, "activeConnector", False)
            mbs.Assemble()


def _const_offset(mbs, t, itemNumber, params):
    return list(params)


def make_bushing_function(laws: Sequence, initial_deflection: np.ndarray, symbolic: bool):
    """The bushing's 6 loads (N, N*mm) as an Exudyn ``springForceTorqueUserFunction``.

    Deflection in the bushing frame: displacement (mm) and Tait-Bryan rotation (rad, converted
    to deg), plus the initial deflection; each direction's law is written with hinge functions
    (see :mod:`elastokin.laws`), so the same closure is converted to a symbolic function.
    """
    hinges = [law.hinges() for law in laws]
    u0 = [float(x) for x in initial_deflection]
    if symbolic:
        maxf = exu.symbolic.max
    else:
        def maxf(a, b):
            return a if a > b else b

    def evaluate(i, v):
        k0, c, hs = hinges[i]
        out = c + k0 * v
        for ui, dk in hs:
            out = out + dk * maxf(v - ui, 0.0)
        return out

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

    With ``balance_bushing_preloads`` every bushing is held rigid in its ideal joint's
    directions (stiff penalty springs), so the design position is a structure whose loads are
    linear in the balanced spring's force P: two solves give the P at which the rig pad carries
    the wheel load, a third the bushing loads at that P. Otherwise the compliant model is used
    and P found by the secant method.
    """
    s = suspension
    d = s.design
    springs = {sp.name: sp.design_force_N() for sp in s.springs}
    preload = {b.name: np.array([law(u) for law, u in zip(b.laws, b.initial_deflection)])
               for b in s.bushings}
    if d.balance_spring is None and not d.balance_bushing_preloads:
        return DesignState(springs, preload)
    penalty = d.balance_bushing_preloads

    def solve(p: float):
        forces = dict(springs)
        if d.balance_spring is not None:
            forces[d.balance_spring] = p
        model = SuspensionModel(s, ModelOptions(), bushing_preload=preload,
                                spring_force_N=forces, _penalty_bushings=penalty)
        state = model.run(pad_z_mm=[0.0], what="balancing the design position")[0]
        return state.pad_force_N[2], state

    if d.balance_spring is None:
        _, state = solve(0.0)
        return DesignState(springs, {n: v.copy() for n, v in state.bushing_load.items()})
    w = d.wheel_load_N
    p0, p1 = 0.0, w
    r0, _ = solve(p0)
    r1, state = solve(p1)
    for _ in range(1 if penalty else 20):
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
    if penalty:
        preload = {n: v.copy() for n, v in state.bushing_load.items()}
    return DesignState(springs, preload)


def build_model(suspension: Suspension, options: ModelOptions = ModelOptions(),
                design: DesignState | None = None) -> SuspensionModel:
    """The model of ``suspension`` with the design preloads applied (computed if not given)."""
    design = design or design_state(suspension)
    return SuspensionModel(suspension, options, bushing_preload=design.bushing_preload,
                           spring_force_N=design.spring_force_N)
