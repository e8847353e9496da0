"""The virtual K&C rig's load cases as drives (plain data, pure numpy): what the rig does to
every wheel in one load case, step by step.

A :class:`Drive` holds, per step, each wheel's pad height (displacement control, x and y free)
or none (force control, the patch free), the forces at its contact patch and the loads at its
wheel centre (:class:`~elastokin.rig.pad.WheelInputs`), and on an axle the steering rack's
travel and, for roll, the heave beam's load; with the input channel and branch label of every
step and which steps are recorded.

Corner load cases keep their meaning on an axle by loading every wheel in phase (the same
force in the vehicle frame; the vertical cases on every wheel): on an axle ``lateral_force`` is
ADAMS/Car's lateral force in phase, ``longitudinal_force_patch`` braking and
``longitudinal_force_centre`` traction on both wheels, ``aligning_torque`` aligning torque in
phase. The axle load cases (opposite, single wheel and roll travel, steering, static load,
lateral force in anti-phase) run on axles only.

Frames and units: the config frame, mm, N, N*mm, deg; forces and torques are those the rig
applies to the tyre (ISO 8855 vehicle axes).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field

import numpy as np

from elastokin.config.schema.rig import (
    ForceSweepSpec,
    RigSpec,
    RollSpec,
    SteeringSweepSpec,
    TorqueSweepSpec,
    TravelSpec,
    VehicleLoadCaseSpec,
    VerticalForceSpec,
)
from elastokin.config.suspension import Suspension
from elastokin.errors import ConfigError
from elastokin.physics.vehicle_loads import VehicleData, lifted_wheels, wheel_loads
from elastokin.rig.axle_channels import design_track_mm, iso_rotation
from elastokin.rig.channels import FORCE_CASES, LOAD_CASES, VEHICLE_LOAD_CASE
from elastokin.rig.pad import WheelInputs
from elastokin.rig.paths import leg, sweep_path, travel_path, vertical_force_path

#: the load cases a kinematic model runs (:func:`drives`)
KINEMATIC_CASES = ("parallel_travel", "vertical_force", "opposite_travel",
                   "single_wheel_travel", "roll_vertical_force", "steering", "vehicle_loads")
#: the axle's load cases, in the order they run (after the corner cases)
AXLE_CASES = ("opposite_travel", "single_wheel_travel", "roll_vertical_force", "steering",
              "static_load", "lateral_force_anti_phase", "vehicle_loads")


@dataclass(frozen=True)
class Drive:
    """One load case as the rig drives it (config frame, mm, N, N*mm).

    ``inputs``: the rig input per step (column ``input_column`` of the sweeps); ``branch``:
    each step's branch label; ``wheels``: each wheel's inputs by side; ``rack_travel_mm``:
    the steering rack's travel per step (None: held); ``heave_load_N``: roll, the heave beam's
    total vertical load per step (the pads' heights then relative to it); ``columns``: more
    columns of the sweeps the drive defines (e.g. the steering-wheel angle); ``recorded``:
    which steps the sweeps keep (None: all); ``side_inputs``: a wheel's own input where it
    differs from ``inputs`` (opposite and single wheel travel: its pad height; lateral force
    in anti-phase: the right wheel's force), its sweep's input column.
    """

    load_case: str
    input_column: str
    inputs: np.ndarray
    branch: np.ndarray
    wheels: dict[str, WheelInputs]
    rack_travel_mm: np.ndarray | None = None
    heave_load_N: np.ndarray | None = None
    columns: dict[str, np.ndarray] = field(default_factory=dict)
    recorded: np.ndarray | None = None
    side_inputs: dict[str, np.ndarray] = field(default_factory=dict)


def _wheels(s: Suspension, n: int, z=None, pad=None) -> dict[str, WheelInputs]:
    """Every wheel with the same inputs (in phase): pad height ``z`` (None: force control),
    patch forces ``pad`` (default the design wheel load), no centre loads."""
    pad = np.tile(s.up * s.design.wheel_load_N, (n, 1)) if pad is None else pad
    return {side: WheelInputs(z, pad, np.zeros((n, 6))) for side in s.wheels}


def parallel_travel_drive(suspension: Suspension, spec: TravelSpec | None = None,
                          approach_step_mm: float | None = None,
                          record_approach: bool = True) -> Drive:
    """Displacement-controlled parallel wheel travel (every wheel's pad moves together) at
    the design wheel load: the approach from the design position to rebound (in steps of
    ``approach_step_mm``, default the stroke's), the stroke and the return. Without
    ``record_approach`` the sweeps start at the rebound point."""
    s = suspension
    spec = spec or s.rig.parallel_travel
    z, branch = travel_path(spec.rebound_mm, spec.bump_mm, spec.step_mm, spec.unloading,
                            approach_step_mm)
    n = z.size
    return Drive("parallel_travel", "pad_z_mm", z, branch,
                 _wheels(s, n, z, np.zeros((n, 3))),
                 recorded=None if record_approach else branch != "approach")


def other_travel_drive(suspension: Suspension, case: str, spec: TravelSpec) -> Drive:
    """Opposite wheel travel (the left pad follows the travel, the right one the opposite) or
    single wheel travel (the ``moving`` wheel's pad follows it, the other is held at its
    design height), displacement control. The sides are the vehicle's, whichever the
    config describes."""
    s = _axle(suspension, case)
    z, branch = travel_path(spec.rebound_mm, spec.bump_mm, spec.step_mm, spec.unloading)
    n = z.size
    zero = np.zeros((n, 3))
    if case == "opposite_travel":
        pads = {"left": z, "right": -z}
    else:
        pads = {side: z if side == spec.moving else np.zeros(n) for side in s.sides}
    return Drive(case, "pad_z_mm", z, branch, {
        side: WheelInputs(pads[side], zero, np.zeros((n, 6))) for side in s.sides},
        side_inputs=pads)


def roll_drive(suspension: Suspension, spec: RollSpec) -> Drive:
    """Roll and vertical force: body roll swept 0 -> +A -> -A -> 0 (deg, + when the body's
    left side rises: the left pad goes down, the right one up, by half the track times the
    tangent), the pads on the heave beam that carries twice the design wheel load."""
    s = _axle(suspension, "roll_vertical_force")
    roll, branch = sweep_path(spec.amplitude_deg, spec.step_deg)
    half = 0.5 * design_track_mm(s) * np.tan(np.radians(roll))
    n = roll.size
    zero = np.zeros((n, 3))
    wheels = {"left": WheelInputs(-half, zero, np.zeros((n, 6))),
              "right": WheelInputs(half, zero, np.zeros((n, 6)))}
    return Drive("roll_vertical_force", "roll_angle_deg", roll, branch, wheels,
                 heave_load_N=np.full(n, 2.0 * s.design.wheel_load_N))


def steering_wheel_room_deg(steering) -> float:
    """The steering-wheel angle (deg) the steering sweep may reach each way: the rack moves
    from its held travel by the ratio's travel either way (the pinion's sense is probed
    later), so ``|travel_mm| + |rack travel|`` must stay within ``limit_mm``."""
    room = steering.limit_mm - abs(steering.travel_mm)
    if not room > 0:
        return 0.0
    return float(min(abs(steering.ratio.deflection_at(room)),
                     abs(steering.ratio.deflection_at(-room))))


def steering_drive(suspension: Suspension, spec: SteeringSweepSpec) -> Drive:
    """Steering: the steering wheel turned 0 -> +A -> -A -> 0 (deg; A: ``amplitude_deg`` or
    lock to lock: the rack at its travel limit, :func:`steering_wheel_room_deg`), the rack
    following from its held travel through the ratio, every wheel at the design load (force
    control)."""
    s = _axle(suspension, "steering")
    st = s.axle.steering
    if st is None:
        raise ConfigError(f"{s.rig_key('steering')}: the axle has no steering "
                          "(axle.steering); leave the load case out (steering: null)")
    limit = steering_wheel_room_deg(st)
    held = f", the rack held at {st.travel_mm:g} mm" if st.travel_mm else ""
    if not limit > 0:
        raise ConfigError(f"{s.rig_key('steering')}: the rack is held at its travel "
                          f"limit ({st.travel_mm:g} mm, axle.steering.limit_mm "
                          f"{st.limit_mm:g} mm): no room to steer")
    amplitude = spec.amplitude_deg if spec.amplitude_deg is not None else limit
    if amplitude > limit * (1.0 + 1e-9):
        raise ConfigError(f"{s.rig_key('steering.amplitude_deg')}: {amplitude:g} deg "
                          f"takes the rack beyond its travel limit (axle.steering.limit_mm "
                          f"{st.limit_mm:g} mm{held}: {limit:.4g} deg of steering wheel)")
    swa, branch = sweep_path(amplitude, spec.step_deg)
    rack = st.travel_mm + st.rack_travel_mm(swa)
    return Drive("steering", "steering_wheel_angle_deg", swa, branch, _wheels(s, swa.size),
                 rack_travel_mm=rack, columns={"rack_travel_mm": rack})


def static_load_drive(suspension: Suspension, spec) -> Drive:
    """Static load: from the design wheel loads to the given loads at each contact patch in
    equal steps (force control; ``load_fraction`` 0..1)."""
    s = _axle(suspension, "static_load")
    frac = leg(0.0, 1.0, 1.0 / spec.steps)
    n = frac.size
    design = s.up * s.design.wheel_load_N
    wheels = {}
    for side in s.sides:
        given = getattr(spec, side)
        pad = design + frac[:, None] * (np.asarray(given.force_N) - design)
        centre = np.zeros((n, 6))
        centre[:, 3:] = frac[:, None] * np.asarray(given.torque_Nmm)
        wheels[side] = WheelInputs(None, pad, centre)
    return Drive("static_load", "load_fraction", frac, np.array(["rise"] * n), wheels)


def vehicle_data(suspension: Suspension) -> VehicleData:
    """The vehicle data of the static-load analysis (``axle.vehicle`` with its
    ``axle_mass_kg``; the design track at the contact points)."""
    s = _axle(suspension, "vehicle_loads")
    v = s.axle.vehicle
    if v is None or v.axle_mass_kg is None:
        raise ConfigError(f"{s.rig_key('vehicle_loads')}: the static-load analysis needs the "
                          "vehicle data axle.vehicle with its axle_mass_kg: {front: KG, rear: "
                          "KG}")
    return VehicleData(v.axle_mass_kg.front, v.axle_mass_kg.rear, v.position, v.wheelbase_mm,
                       v.cg_height_mm, design_track_mm(s), v.brake_fraction,
                       v.drive_fraction, v.lateral_transfer_fraction, v.brakes, v.drive)


def vehicle_load_drive(suspension: Suspension, name: str, case: VehicleLoadCaseSpec,
                       steps: int) -> Drive:
    """One static-load case from vehicle accelerations (:mod:`elastokin.physics.vehicle_loads`):
    from the design wheel loads to the case's contact-patch forces (and wheel-centre forces of
    inboard brakes or drive) in ``steps`` equal steps, force control (``load_fraction`` 0..1;
    load case ``vehicle_loads:<name>``)."""
    s = suspension
    loads = wheel_loads(vehicle_data(s), case.longitudinal_g, case.lateral_g, case.bump_g)
    lifted = lifted_wheels(loads)
    if lifted:
        raise ConfigError(f"{s.rig_key(f'vehicle_loads.cases.{name}')}: the "
                          f"{' and '.join(lifted)} wheel would lift off (vertical load "
                          f"{loads[lifted[0]].patch[2]:.0f} N): lower the accelerations")
    frac = leg(0.0, 1.0, 1.0 / steps)
    n = frac.size
    T = iso_rotation(s).T  # ISO vehicle axes -> config frame
    design = s.up * s.design.wheel_load_N
    wheels = {}
    for side, w in loads.items():
        pad = design + frac[:, None] * (T @ w.patch - design)
        centre = np.zeros((n, 6))
        centre[:, :3] = frac[:, None] * (T @ w.centre)
        wheels[side] = WheelInputs(None, pad, centre)
    return Drive(VEHICLE_LOAD_CASE.format(name), "load_fraction", frac,
                 np.array(["rise"] * n), wheels)


def vehicle_load_table(suspension: Suspension) -> dict[str, dict]:
    """summary.json ``vehicle_loads``: each static-load case's accelerations (g) and the
    forces they put on each tyre (N, config frame), at the contact patch and at the wheel
    centre (the longitudinal force of inboard brakes or drive)."""
    s = suspension
    spec = s.rig.vehicle_loads
    if spec is None:
        return {}
    T = iso_rotation(s).T
    out = {}
    for name, case in spec.cases.items():
        loads = wheel_loads(vehicle_data(s), case.longitudinal_g, case.lateral_g, case.bump_g)
        out[VEHICLE_LOAD_CASE.format(name)] = {
            **case.model_dump(),
            "contact_patch_force_N": {side: (T @ w.patch).tolist() for side, w in loads.items()},
            "wheel_centre_force_N": {side: (T @ w.centre).tolist() for side, w in loads.items()}}
    return out


def vertical_force_drive(suspension: Suspension,
                         spec: VerticalForceSpec | None = None) -> Drive:
    """Vertical force at every contact patch (force control, patch free): from the design
    wheel load down to ``min_N`` (approach), up to ``max_N`` (rise) and back to ``min_N``."""
    s = suspension
    spec = spec or s.rig.vertical_force
    fz, branch = vertical_force_path(s.design.wheel_load_N, spec.min_N, spec.max_N,
                                     spec.step_N)
    return Drive("vertical_force", "vertical_force_N", fz, branch,
                 _wheels(s, fz.size, pad=fz[:, None] * s.up))


def force_drive(suspension: Suspension, case: str,
                spec: ForceSweepSpec | TorqueSweepSpec | None = None) -> Drive:
    """A force (or aligning torque) swept 0 -> +A -> -A -> 0 at the design wheel load on
    every wheel in phase (``lateral_force_anti_phase``: the right wheel's force opposite),
    the contact patches free (force control)."""
    s = suspension
    lc = LOAD_CASES[case]
    spec = spec or getattr(s.rig, case)
    if isinstance(spec, TorqueSweepSpec):
        values, branch = sweep_path(spec.amplitude_Nmm, spec.step_Nmm)
    else:
        values, branch = sweep_path(spec.amplitude_N, spec.step_N)
    axis = getattr(s, lc.direction)
    n = values.size
    wheels, own = {}, {}
    for side in s.sides:
        sign = -1.0 if (case == "lateral_force_anti_phase" and side == "right") else 1.0
        if sign < 0:
            own[side] = sign * values
        pad = np.tile(s.up * s.design.wheel_load_N, (n, 1))
        centre = np.zeros((n, 6))
        if lc.where == "patch":
            pad = pad + sign * values[:, None] * axis
        elif lc.where == "centre":
            centre[:, :3] = sign * values[:, None] * axis
        else:
            centre[:, 3:] = sign * values[:, None] * axis
        wheels[side] = WheelInputs(None, pad, centre)
    return Drive(case, lc.input, values, branch, wheels, side_inputs=own)


def why_not_run(suspension: Suspension, case: str, fitted: bool = False) -> str | None:
    """Why no model of ``suspension`` runs the load case ``case``: an axle's case on a
    corner, steering without a steering rack, a force case when every model is kinematic, or
    a case the rig leaves out (unless ``fitted``: the stiffness fit runs the test's corner
    cases whatever the rig); None when some model runs it."""
    s = suspension
    lc = LOAD_CASES[case]
    if not lc.corner and s.axle is None:
        return "an axle load case, and the config is one corner (no 'axle' section)"
    if case == "steering" and s.axle.steering is None:
        return "the axle has no steering (axle.steering)"
    if s.kinematic and case not in KINEMATIC_CASES:
        return "every model is kinematic (kinematic: true): they run the travel, vertical " \
               "force, roll and steering cases only"
    if getattr(s.rig, case) is None and not (fitted and lc.corner):
        return f"the rig leaves the load case out ({s.rig_key(case)} is null)"
    return None


def check_rig(suspension: Suspension, rig: RigSpec | None = None) -> None:
    """Warn (:class:`RigWarning`) of a load case the rig (default the suspension's) gives
    explicitly that no model of ``suspension`` can run (:func:`why_not_run`): the K&C job
    leaves it out (:func:`drives` skips it), and says so once. Every drive is built (pure,
    cheap): a case that cannot be built (a wheel lifted by vehicle accelerations) is an error
    before any solve."""
    rig = rig or suspension.rig
    drives(suspension, rig)
    for case in sorted(rig.model_fields_set):
        if getattr(rig, case) is None:
            continue
        why = why_not_run(suspension, case)
        if why is not None:
            warnings.warn(RigWarning(f"{suspension.rig_key(case)}: given, but {why}: the "
                                     "load case is left out"), stacklevel=2)


class RigWarning(UserWarning):
    """A load case of the rig that is given but cannot run."""


def _axle(suspension: Suspension, case: str) -> Suspension:
    if suspension.axle is None:
        raise ConfigError(f"{suspension.rig_key(case)}: an axle load case; the config is one "
                          "corner (add an 'axle' section)")
    return suspension


def drives(suspension: Suspension, rig: RigSpec | None = None,
           kinematic: bool = False) -> list[Drive]:
    """Every load case of ``rig`` (default: the config's), parallel travel first, the axle's
    cases last (on an axle). A kinematic model runs the travel, vertical and steering cases
    and the static loads from vehicle accelerations only: without bushings its answer to a
    lateral or longitudinal load is rigid-body statics, not compliance (but loads)."""
    s = suspension
    rig = rig or s.rig
    out = [parallel_travel_drive(s, rig.parallel_travel)]
    if rig.vertical_force is not None:
        out.append(vertical_force_drive(s, rig.vertical_force))
    if not kinematic:
        out += [force_drive(s, case, getattr(rig, case)) for case in FORCE_CASES
                if getattr(rig, case) is not None and LOAD_CASES[case].corner]
    if s.axle is None:
        return out
    for case in ("opposite_travel", "single_wheel_travel"):
        if getattr(rig, case) is not None:
            out.append(other_travel_drive(s, case, getattr(rig, case)))
    if rig.roll_vertical_force is not None:
        out.append(roll_drive(s, rig.roll_vertical_force))
    if rig.steering is not None and s.axle.steering is not None:
        out.append(steering_drive(s, rig.steering))
    if not kinematic and rig.static_load is not None:
        out.append(static_load_drive(s, rig.static_load))
    if not kinematic and rig.lateral_force_anti_phase is not None:
        out.append(force_drive(s, "lateral_force_anti_phase", rig.lateral_force_anti_phase))
    if rig.vehicle_loads is not None:  # rigid-body statics too: the loads of a kinematic model
        out += [vehicle_load_drive(s, name, case, rig.vehicle_loads.steps)
                for name, case in rig.vehicle_loads.cases.items()]
    return out
