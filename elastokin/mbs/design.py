"""The design position and the assembly check.

:func:`design_state`: spring and bushing preloads that make the design hardpoints the static
equilibrium under the design wheel load (config ``design``). :func:`check_assembly`: the
joints neither over- nor under-constrain the suspension. Both hold the wheel's contact patch
with a support of their own (the model knows no rig). :func:`build_model`: the model of a
variant with its design preloads. Units mm, N, N*mm; config frame.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from elastokin.config.suspension import Suspension
from elastokin.config.variants import DesignState, ModelVariant, compliant, kinematic
from elastokin.errors import ModelError, SolverError
from elastokin.mbs.assembly import system_jacobian
from elastokin.mbs.bushings import BALANCING_ROTATION
from elastokin.mbs.contact import contact_arm
from elastokin.mbs.exudyn_api import exudyn_call
from elastokin.mbs.idle import hold_idle_spins
from elastokin.mbs.model import ModelOptions, SuspensionModel
from elastokin.mbs.solve import simulation_settings, solve_path
from elastokin.physics.joints import CONSTRAINED

#: the support holding the contact patch height (design balancing, assembly check)
PATCH_SUPPORT = "design:contact_patch"
#: secant steps at most when balancing the spring preload
BALANCE_ITERATIONS = 20
#: the balanced pad loads match the wheel load to this fraction of it (the static solves'
#: own accuracy is ~1e-10 of it: their Newton tolerance is 1e-8 of residuals ~1e2 N)
BALANCE_TOLERANCE = 1e-8
HOLD_Z = (0, 0, 1, 0, 0, 0)


def hold_contact_patches(model: SuspensionModel) -> dict[str, str]:
    """Supports holding every wheel's contact point (its lowest point, as the rig's pad:
    :mod:`elastokin.mbs.contact`) at its design height (x, y free), by side (the config
    side's named :data:`PATCH_SUPPORT`)."""
    s = model.suspension
    return {side: model.add_support(PATCH_SUPPORT if side == s.side
                                    else f"{PATCH_SUPPORT}:{side}", contact_arm(model, side),
                                    lambda x, side=side: x.wheels[side].contact_patch_mm,
                                    HOLD_Z)
            for side, w in s.wheels.items()}


def balanced_springs(suspension: Suspension) -> tuple[str, ...]:
    """The springs whose preloads are solved for the design position, one per wheel (the
    config's ``design.balance_spring`` and, on an axle, its mirror), in wheel order."""
    s = suspension
    if s.design.balance_spring is None:
        return ()
    return s.axle.balance_springs if s.axle is not None else (s.design.balance_spring,)


@dataclass
class BalancingSolve:
    """One solve of the design balancing (:func:`design_state` with ``record``): the pass
    (0, then 1 and 2 after each relaxation of the stiff springs), the model and its
    contact-patch supports by side, the balanced springs' forces (N), the stiff springs'
    offsets (rad), whether the idle spins were held, and the converged coordinates and
    multipliers."""

    pass_index: int
    model: SuspensionModel
    supports: dict[str, str]
    spring_force_N: np.ndarray
    offsets: dict[str, np.ndarray]
    idle: bool
    coordinates: np.ndarray
    multipliers: np.ndarray


def design_state(suspension: Suspension, record: list | None = None) -> DesignState:
    """Spring and bushing preloads for the design position (see ``design`` in the config).

    With ``balance_bushing_preloads`` every bushing is held in its ideal joint's directions
    (translations by exact constraints, rotations by stiff springs), so the design position is
    a structure whose loads are linear in the balanced spring's force P: two solves give the P
    at which the contact patch carries the wheel load, a third the loads each bushing
    transmits at that P, which become the bushing preloads; the balance is solved again with
    the stiff springs relaxed at the rotations their torques caused (twice). Otherwise the
    compliant model is used and P found by the secant method. ``record``: every balancing
    solve is appended to it (:class:`BalancingSolve`; the design sensitivities,
    :mod:`elastokin.mbs.design_tangents`).
    """
    s = compliant(suspension)  # a bushing modelled kinematically keeps its design load
    check_assembly(s)
    d = s.design
    springs = {sp.name: sp.design_force_N() for sp in s.springs}
    preload = {b.name: np.array([law(u) for law, u in zip(b.laws, b.initial_deflection)])
               for b in s.bushings}
    if d.balance_spring is None and not d.balance_bushing_preloads:
        return DesignState(springs, preload)
    run = _Balancing(s, springs, preload, record)
    try:
        p1, loads = run.balance()
    except SolverError:
        # e.g. spring seats off the strut axis turn the strut rod, which only the ideal
        # joints' regularising rates hold: again with the idle spins held (mbs.idle)
        if not run.ideal:
            raise
        run.idle = True
        p1, loads = run.balance()
    if run.ideal:
        # the stiff springs' rotation under the bushings' design torques moves the parts off
        # the design position (a 1.3e6 N*mm torque turns 1.3e-3 rad: 0.3 mm at a 250 mm
        # arm); balanced again with the springs relaxed at those rotations, it is ~1e-3 of it,
        # and after a second relaxation ~1e-6: the pad holds the tyre's lowest point, which
        # the knuckle's pitch moves by the loaded radius times it (1e-6 rad left the double
        # wishbone's static pad load 2.6e-3 N and its wheel centre 7e-5 mm off the design)
        for _ in range(2):
            if run.relax(loads):
                p1, loads = run.balance()
    if not run.balanced:
        return DesignState(springs, {n: v.copy() for n, v in loads.items()})
    springs.update(zip(run.balanced, (float(v) for v in p1)))
    if run.ideal:
        preload = {n: v.copy() for n, v in loads.items()}
    return DesignState(springs, preload)


class _Balancing:
    """The solves of :func:`design_state` on suspension ``s`` (compliant) with the springs'
    and bushings' preloads of its config: one balancing model per pass (built once, the
    balanced springs' forces set in place between its solves)."""

    def __init__(self, s: Suspension, springs: dict, preload: dict, record: list | None):
        self.s, self.springs, self.preload, self.record = s, springs, preload, record
        self.ideal = s.design.balance_bushing_preloads  # bushings held by their ideal joints
        self.idle = False  # idle spins held: only when the plain balancing does not solve
        self.offsets: dict[str, np.ndarray] = {}  # the stiff rotational springs' (rad)
        self.relaxed = 0  # the relaxations of the stiff springs so far (the pass)
        self.balanced = balanced_springs(s)
        self.built: dict = {}

    def model(self, forces: dict) -> tuple[SuspensionModel, dict[str, str]]:
        """This pass's balancing model with the springs at ``forces`` (N), and its supports."""
        key = (self.idle, self.relaxed)  # the offsets change between the passes
        if key in self.built:
            model, supports = self.built[key]
            set_spring_forces(model, {name: forces[name] for name in self.balanced})
            return model, supports
        model = SuspensionModel(self.s, ModelOptions(), DesignState(forces, self.preload),
                                balancing=self.ideal, balancing_offsets=self.offsets)
        if self.idle:
            hold_idle_spins(model)
        self.built[key] = model, hold_contact_patches(model)
        return self.built[key]

    def solve(self, p: np.ndarray):
        """(the pads' vertical loads by wheel (N), the bushings' loads) with the balanced
        springs at forces ``p`` (N)."""
        forces = dict(self.springs)
        forces.update(zip(self.balanced, (float(v) for v in p)))
        model, supports = self.model(forces)
        state = solve_path(model, {sup: np.zeros((1, 6)) for sup in supports.values()},
                           "balancing the design position")[0]
        loads = model.balancing_bushing_loads() if self.ideal else state.bushing_load
        pads = np.array([0.0 + state.support_force_N[supports[side]][2]
                         for side in self.s.sides])
        if self.record is not None:
            sd = model.mbs.systemData
            self.record.append(BalancingSolve(
                self.relaxed, model, supports, np.asarray(p, float).copy(),
                {k: v.copy() for k, v in self.offsets.items()}, self.idle,
                np.array(sd.GetODE2Coordinates()), np.array(sd.GetAECoordinates())))
        return pads, loads

    def balance(self):
        """(the balanced springs' forces, the bushings' loads) of one pass."""
        if not self.balanced:
            return np.zeros(0), self.solve(np.zeros(0))[1]
        if len(self.balanced) == 1:
            p, loads = _balance_spring(self.s, lambda p: _first(self.solve(np.array([p]))))
            return np.array([p]), loads
        return _balance_springs(self.s, self.balanced, self.solve)

    def relax(self, loads: dict) -> bool:
        """Relax the stiff springs at the rotations the bushings' ``loads`` give them; whether
        any turns (then the next pass)."""
        for b in self.s.bushings:
            held = np.array(CONSTRAINED[b.ideal_joint][3:], bool)
            # Exudyn's spring torque is k (rotation - offset): -M/k carries M at rotation 0
            self.offsets[b.name] = np.where(held, -loads[b.name][3:] / BALANCING_ROTATION, 0.0)
        if not any(np.any(v) for v in self.offsets.values()):
            return False
        self.relaxed += 1
        return True


def set_spring_forces(model: SuspensionModel, forces: dict[str, float]) -> None:
    """Give springs of a built model other design forces (N): their reference lengths, set
    in place (as the model computes them when built)."""
    for sp in model.suspension.springs:
        if sp.name in forces:
            model.spring_force[sp.name] = forces[sp.name]
            model.mbs.SetObjectParameter(model.springs[sp.name], "referenceLength",
                                         sp.installed_length_mm + forces[sp.name]
                                         / sp.rate_N_per_mm)
    model.geometry.own.clear()


def _first(result):
    pads, loads = result
    return float(pads[0]), loads


def _balance_springs(s: Suspension, names: tuple[str, ...], solve):
    """The preloads of several springs (one per wheel) at which every contact patch carries
    the wheel load: Newton's method on the pad loads, the Jacobian from one solve per spring
    and then Broyden's update (the loads are nearly linear in the preloads), until every pad
    load is within BALANCE_TOLERANCE of the wheel load."""
    w = s.design.wheel_load_N
    target = np.full(len(names), w)
    r0, _ = solve(np.zeros(len(names)))
    jac = np.column_stack([(solve(w * e)[0] - r0) / w for e in np.eye(len(names))])
    p = np.zeros(len(names))
    r = r0
    for _ in range(BALANCE_ITERATIONS):
        try:
            step = np.linalg.solve(jac, target - r)
        except np.linalg.LinAlgError:
            raise ModelError(f"{s.source}: design.balance_spring: the forces of springs "
                             f"{', '.join(names)} do not reach the wheels: cannot balance"
                             ) from None
        p = p + step
        r_new, loads = solve(p)
        if np.max(np.abs(r_new - target)) < BALANCE_TOLERANCE * w:
            return p, loads
        jac += np.outer((r_new - r) - jac @ step, step) / (step @ step)
        r = r_new
    raise SolverError(f"{s.source}: design.balance_spring: no preloads of springs "
                      f"{', '.join(names)} found that carry the {w:g} N wheel loads (last pad "
                      f"loads {', '.join(f'{v:.6g}' for v in r)} N)")


def _balance_spring(s: Suspension, solve):
    """The balanced spring's preload at which the contact patch carries the wheel load
    (secant method, iterated until the pad load is within BALANCE_TOLERANCE of the wheel
    load: one step when the structure is linear in the preload, more when it is not, e.g. a
    spring on a skewed upper arm)."""
    d = s.design
    w = d.wheel_load_N
    p0, p1 = 0.0, w
    r0, _ = solve(p0)
    r1, loads = solve(p1)
    for _ in range(BALANCE_ITERATIONS):
        if abs(r1 - r0) < 1e-9:
            raise ModelError(f"{s.source}: design.balance_spring: the force of spring "
                             f"'{d.balance_spring}' does not reach the wheel: cannot balance")
        p2 = p1 + (w - r1) * (p1 - p0) / (r1 - r0)
        p0, r0 = p1, r1
        p1 = p2
        r1, loads = solve(p1)
        if abs(r1 - w) < BALANCE_TOLERANCE * w:
            break
    else:
        raise SolverError(f"{s.source}: design.balance_spring: no spring preload found that "
                          f"carries the {w:g} N wheel load (last pad load {r1:.6g} N)")
    return p1, loads


def degrees_of_freedom(model: SuspensionModel, supports: list[str], held: bool) -> dict:
    """Exudyn's numerical DOF count of the constraints, with or without ``supports``."""
    mbs = model.mbs
    objs = [model.supports[name]["object"] for name in supports]
    _activate(model, objs, held)
    try:
        return exudyn_call(lambda: mbs.ComputeSystemDegreeOfFreedom(verbose=0),
                           "counting degrees of freedom")
    finally:
        _activate(model, objs, False)


def _activate(model: SuspensionModel, objects: list[int], on: bool) -> None:
    """Switch supports on or off (the model's locks always on) and assemble."""
    for obj in objects:
        model.mbs.SetObjectParameter(obj, "activeConnector", on)
    for name in model.locks:
        model.mbs.SetObjectParameter(model.supports[name]["object"], "activeConnector", True)
    model.mbs.Assemble()


def redundant_joints(model: SuspensionModel, supports: list[str]) -> list[str]:
    """The joints (and links) taking part in a redundancy at the design position: the rows of
    the constraint Jacobian with weight in its left null space (combinations of equations
    that add up to nothing)."""
    mbs = model.mbs
    _activate(model, [model.supports[name]["object"] for name in supports], False)
    jac = _constraint_jacobian(model)
    n2 = mbs.systemData.ODE2Size()
    cq = jac[n2:, :n2]
    u, sv, _ = np.linalg.svd(cq)
    rank = int(np.sum(sv > 1e-9 * sv[0]))
    weight = np.linalg.norm(u[:, rank:], axis=1)
    involved = set(np.flatnonzero(weight > 1e-6).tolist())
    owners = {f"joint {n}": o for n, o in model.joints.items()}
    owners.update({f"link {n}": o for n, o in model.links.items()})
    for b in model.suspension.bushings:
        ideal = model.bushings[b.name].get("ideal")
        if ideal is not None:
            owners[f"bushing {b.name} (as {b.ideal_joint})"] = ideal
    return [name for name, o in owners.items()
            if involved & set(mbs.systemData.GetObjectLTGAE(o))]


def _constraint_jacobian(model: SuspensionModel) -> np.ndarray:
    return system_jacobian(model, simulation_settings(model, 1), "assembly check")


def check_assembly(suspension: Suspension) -> None:
    """Raise :class:`ModelError` when the ideal joints (every bushing counted as its ideal
    joint) are redundant (over-constrained) or, with the contact patch height held, leave the
    wheel free to move (under-constrained: e.g. a missing tie rod or joint)."""
    model = SuspensionModel(kinematic(suspension), ModelOptions())
    supports = list(hold_contact_patches(model).values())
    src = suspension.source
    redundant = int(degrees_of_freedom(model, supports, False)["redundantConstraints"])
    if redundant > 0:
        names = ", ".join(redundant_joints(model, supports)) or "unknown"
        raise ModelError(
            f"{src}: the assembly is over-constrained: {redundant} redundant constraint "
            f"equation(s) among the joints (in the kinematic model each bushing counts as "
            f"its ideal_joint); joints involved: {names}; remove a joint or free one of its "
            "axes")
    if degrees_of_freedom(model, supports, True)["redundantConstraints"] > 0:
        wheels = "', '".join(w.part for w in suspension.wheels.values())
        raise ModelError(
            f"{src}: the joints hold the wheel part '{wheels}' rigidly (bushings counted as "
            "their ideal_joint): it cannot travel vertically")
    _check_wheel_located(model, supports)


def _check_wheel_located(model: SuspensionModel, supports: list[str]) -> None:
    mbs, src = model.mbs, model.suspension.source
    objs = [model.supports[name]["object"] for name in supports]
    _activate(model, objs, True)
    try:
        jac = _constraint_jacobian(model)
    finally:
        _activate(model, objs, False)
    n2 = mbs.systemData.ODE2Size()
    cq = np.vstack([jac[n2:, :n2], model.rigid_beam_rows()])  # beams held rigid
    _, sv, vt = np.linalg.svd(cq)
    rank = int(np.sum(sv > 1e-9 * sv[0]))
    null = vt[rank:].T  # free motions of the joints' skeleton (incl. idle spins)
    for part, beam in model.beams.items():
        if null.size and np.max(np.linalg.norm(null[beam.coordinates()], axis=0)) > 1e-6:
            raise ModelError(
                f"{src}: the beam part '{part}' can move without deforming (with bushings "
                "replaced by their ideal joints and the contact patches held): attach it at "
                "more of its nodes or with joints that hold its rotations")
    for wheel in model.wheel_parts.values():
        i0 = mbs.GetNodeODE2Index(model.node[wheel])
        if not (null.size and np.max(np.linalg.norm(null[i0:i0 + 6], axis=0)) > 1e-6):
            continue
        free = null[:, np.argmax(np.linalg.norm(null[i0:i0 + 6], axis=0))]
        moving = [p for p, n in model.node.items()
                  if np.linalg.norm(free[mbs.GetNodeODE2Index(n):][:6]) > 1e-3 *
                  np.linalg.norm(free[i0:i0 + 6])]
        raise ModelError(
            f"{src}: the assembly is under-constrained: with bushings replaced by their "
            f"ideal joints and the contact patch held, the wheel part '{wheel}' can still "
            f"move (parts moving in the free motion: {', '.join(moving)}); a joint, link or "
            "the steering (tie rod / rack) is missing")


def build_model(variant: ModelVariant | Suspension, options: ModelOptions = ModelOptions(),
                design: DesignState | None = None) -> SuspensionModel:
    """The model of a variant (or a plain suspension) with its design preloads (computed,
    after the assembly check, when neither the variant nor ``design`` gives them)."""
    if isinstance(variant, Suspension):
        variant = ModelVariant("model", variant)
    preloads = design or variant.preloads or design_state(variant.suspension)
    model = SuspensionModel(variant.suspension, options, preloads, variant.friction)
    if any(b.kinematic for b in variant.suspension.bushings):
        hold_idle_spins(model)
    return model


def settle_by_continuation(models: list[SuspensionModel]) -> SuspensionModel:
    """Continuation from one geometry to another (e.g. nominal to as-built in a few steps):
    each model's static state with the contact patch held at its design height is solved
    starting where the previous one settled, and the last model then starts every solve
    there. The models must have the same parts. Returns the last model."""
    start = None
    for model in models:
        if start is not None:
            model.start_from(start)
        supports = hold_contact_patches(model).values()
        solve_path(model, {sup: np.zeros((1, 6)) for sup in supports},
                   "settling by continuation")
        start = model.coordinates()
    models[-1].start_from(start)
    return models[-1]
