"""The virtual K&C rig's load cases run on any built model.

:func:`run_drive` attaches the pads (:mod:`elastokin.rig.pad`) to a model, solves the steps of
a :class:`~elastokin.rig.drives.Drive` (what the rig does to every wheel) and returns the
recorded sweeps, one per wheel, with every channel of :mod:`elastokin.rig.channels`; on an axle
each sweep also carries the axle's channels (:mod:`elastokin.rig.axle_channels`). Steering is
locked except in the steering load case.

Frames and units: the config frame, mm, N, N*mm, deg; forces and torques are those the rig
applies to the tyre (ISO 8855 vehicle axes).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np

from elastokin.config.schema_rig import (
    ForceSweepSpec,
    RigSpec,
    TorqueSweepSpec,
    TravelSpec,
    VerticalForceSpec,
)
from elastokin.physics.states import LoadTable, PoseSeries
from elastokin.physics.wheel import toe_deg
from elastokin.rig.axle_channels import axle_columns
from elastokin.rig.channels import LOAD_CASES
from elastokin.rig.characteristics import (
    bushing_table,
    characteristics,
    motion_ratio_columns,
    steer_sign,
    wheel_column_tangents,
)
from elastokin.rig.drives import (
    Drive,
    drives,
    force_drive,
    parallel_travel_drive,
    vertical_force_drive,
)
from elastokin.rig.pad import WheelInputs, run_pad, run_rig
from elastokin.rig.paths import travel_path
from elastokin.rig.sweeps import Sweep

__all__ = ["Drive", "StaticResult", "compliance_matrix", "drives", "force_drive",
           "force_sweep", "parallel_travel", "parallel_travel_drive", "run_drive",
           "run_drive_sides", "run_load_cases", "run_load_cases_sides", "static_equilibrium",
           "travel_path", "vertical_force", "vertical_force_drive", "wheel_compliance"]

if TYPE_CHECKING:
    from elastokin.mbs.model import SuspensionModel
    from elastokin.physics.states import StepState


def run_drive_sides(model: SuspensionModel, label: str, drive: Drive,
                    variations: Sequence | None = None) -> list[Sweep]:
    """The sweeps of ``drive`` on ``model``, one per wheel (the config side's first; the
    pads attached when they are not yet); with ``variations`` (parameters of the model's
    parametric bushings, :class:`~elastokin.mbs.sensitivity.LawVariation`) every sweep
    carries the tangents of its wheel's columns (``Sweep.tangents``)."""
    s = model.suspension
    rig = s.rig_source
    what = f"model '{label}', {drive.load_case}" + (f" (rig file {rig})" if rig else "")
    if drive.load_case == "steering":
        drive = left_turning(model, drive, what)
    steps = run_rig(model, drive.wheels, drive.rack_travel_mm, drive.heave_load_N, what=what,
                    variations=variations)
    cols = {"branch": drive.branch, drive.input_column: drive.inputs, **drive.columns}
    own = dict(drive.side_inputs)  # a wheel's own input, where it is not the drive's
    keep = drive.recorded
    if keep is not None:
        steps = [st for st, k in zip(steps, keep) if k]
        cols = {k: v[keep] for k, v in cols.items()}
        own = {k: v[keep] for k, v in own.items()}
    by_side = {side: [st[side] for st in steps] for side in s.sides}
    first = by_side[s.side]
    loads = LoadTable.stack([st.loads for st in first]) if first and first[0].loads else None
    poses = PoseSeries.stack([st.poses for st in first]) if first and first[0].poses else None
    shared = axle_columns(by_side, s, drive) if s.axle is not None else {}
    sweeps = []
    for side in s.sides:
        view = s.on_side(side)
        mine = {drive.input_column: own[side]} if side in own else {}
        columns = {**cols, **mine, **characteristics(by_side[side], view), **shared}
        case = LOAD_CASES.get(drive.load_case)  # vehicle loads are not in the table
        if case is not None and case.input == "wheel_travel_mm":  # the travel cases
            columns.update(motion_ratio_columns(columns))
        tangents = wheel_column_tangents(by_side[side], view) if variations else {}
        sweeps.append(Sweep(label, drive.load_case, columns, tangents, side,
                            loads=loads if side == s.side else None, poses=poses))
    return sweeps


#: rack travel (mm) of the probe step that finds the pinion's sense (:func:`left_turning`)
STEERING_PROBE_MM = 0.1


def left_turning(model: SuspensionModel, drive: Drive, what: str) -> Drive:
    """The steering ``drive`` with the pinion's sense that turns the wheels to the left for a
    positive steering-wheel angle (ISO 8855, as ADAMS/Car). Rack travel + along the rack's
    axis turns the wheels left or right depending on whether the tie rods are behind or
    ahead of the wheel centres: one probe step of :data:`STEERING_PROBE_MM` decides, and the
    rack's travel is mirrored about its held position when it turns them right."""
    t0 = model.suspension.axle.steering.travel_mm
    probe = {side: WheelInputs(None, np.repeat(np.asarray(wi.pad_loads)[:1], 2, axis=0),
                               np.repeat(np.asarray(wi.centre_loads)[:1], 2, axis=0))
             for side, wi in drive.wheels.items()}
    steps = run_rig(model, probe, np.array([t0, t0 + STEERING_PROBE_MM]),
                    what=what + ", steering sense probe")
    s = model.suspension
    toe = toe_deg(np.array([st[s.side].spin_axis for st in steps]), s.forward, s.outboard)
    left_turn = (toe[1] - toe[0]) * steer_sign(s.side)
    if left_turn >= 0.0:
        return drive
    rack = 2.0 * t0 - drive.rack_travel_mm
    return replace(drive, rack_travel_mm=rack, columns={**drive.columns, "rack_travel_mm": rack})


def run_drive(model: SuspensionModel, label: str, drive: Drive,
              variations: Sequence | None = None) -> Sweep:
    """The config side's sweep of ``drive`` on ``model`` (:func:`run_drive_sides`)."""
    return run_drive_sides(model, label, drive, variations)[0]


def run_load_cases_sides(model: SuspensionModel, label: str, rig: RigSpec | None = None,
                         variations: Sequence | None = None) -> dict[str, list[Sweep]]:
    """Every load case of ``rig`` (default: the model's config's) on ``model``: the sweeps by
    side (the config side's first)."""
    out: dict[str, list[Sweep]] = {side: [] for side in model.suspension.sides}
    for d in drives(model.suspension, rig, model.suspension.kinematic):
        for sw in run_drive_sides(model, label, d, variations):
            out[sw.side].append(sw)
    return out


def run_load_cases(model: SuspensionModel, label: str, rig: RigSpec | None = None,
                   variations: Sequence | None = None) -> list[Sweep]:
    """Every load case of ``rig`` (default: the model's config's) on ``model``: the config
    side's sweeps (``variations``: see :func:`run_drive_sides`)."""
    return run_load_cases_sides(model, label, rig, variations)[model.suspension.side]


def parallel_travel(model: SuspensionModel, label: str, spec: TravelSpec | None = None) -> Sweep:
    """Parallel wheel travel on ``model`` (:func:`parallel_travel_drive`)."""
    return run_drive(model, label, parallel_travel_drive(model.suspension, spec))


def vertical_force(model: SuspensionModel, label: str,
                   spec: VerticalForceSpec | None = None) -> Sweep:
    """The vertical force sweep on ``model`` (:func:`vertical_force_drive`)."""
    return run_drive(model, label, vertical_force_drive(model.suspension, spec))


def force_sweep(model: SuspensionModel, label: str, case: str,
                spec: ForceSweepSpec | TorqueSweepSpec | None = None) -> Sweep:
    """A force or torque sweep on ``model`` (:func:`force_drive`)."""
    return run_drive(model, label, force_drive(model.suspension, case, spec))


def wheel_compliance(model: SuspensionModel, force_step_N: float = 10.0,
                     torque_step_Nmm: float = 1000.0) -> np.ndarray:
    """Compliance of every wheel centre at the static equilibrium under the design wheel
    loads (patches free), by central differences: (6 n, 6 n) for n wheels (the config side's
    first: on an axle ADAMS/Car's 12x12 matrix with the left wheel first when the config is a
    left corner); per wheel columns force x, y, z (N) and torque x, y, z (N*mm) at its centre,
    rows its centre's displacement x, y, z (mm) and rotation vector x, y, z (deg); config
    frame."""
    from scipy.spatial.transform import Rotation

    s = model.suspension
    n = len(s.sides)
    steps = [np.zeros(6 * n)]
    for k in range(6 * n):
        h = np.zeros(6 * n)
        h[k] = force_step_N if k % 6 < 3 else torque_step_Nmm
        steps += [h, -h]
    centre = np.array(steps)
    pad = np.tile(s.up * s.design.wheel_load_N, (len(steps), 1))
    wheels = {side: WheelInputs(None, pad, centre[:, 6 * i:6 * i + 6])
              for i, side in enumerate(s.sides)}
    states = run_rig(model, wheels, what="compliance matrix")
    base = states[0]

    def response(st):
        out = []
        for side in s.sides:
            R0, x0 = base[side].wheel_rotation, base[side].wheel_centre_mm
            rot = Rotation.from_matrix(st[side].wheel_rotation @ R0.T).as_rotvec(degrees=True)
            out.append(np.r_[st[side].wheel_centre_mm - x0, rot])
        return np.concatenate(out)

    C = np.empty((6 * n, 6 * n))
    for k in range(6 * n):
        h = centre[1 + 2 * k, k]
        C[:, k] = (response(states[1 + 2 * k]) - response(states[2 + 2 * k])) / (2 * h)
    return C


def compliance_matrix(model: SuspensionModel, force_step_N: float = 10.0,
                      torque_step_Nmm: float = 1000.0) -> np.ndarray:
    """6x6 compliance of the config side's wheel centre at the static equilibrium under the
    design wheel load(s) (patches free), by central differences: columns = force x, y, z (N)
    and torque x, y, z (N*mm) at the wheel centre, rows = wheel-centre displacement x, y, z
    (mm) and rotation vector x, y, z (deg); config frame. On an axle: the config side's block
    of :func:`wheel_compliance` (loads on that wheel only)."""
    return wheel_compliance(model, force_step_N, torque_step_Nmm)[:6, :6]


@dataclass
class StaticResult:
    """The static equilibrium under the design wheel load (force control at the patch)."""

    state: StepState
    wheel_load_N: float
    bushings: dict[str, dict[str, float]]
    wheel_assembly_force_residual_N: float


def static_equilibrium(model: SuspensionModel) -> StaticResult:
    """Solve the design load case: the wheel load applied at the contact patch, free patch;
    with the residual of the forces on the wheel part read back from every connector."""
    from elastokin.mbs.forces import forces_on_part

    s = model.suspension
    w = s.design.wheel_load_N
    state = run_pad(model, pad_loads=[s.up * w],
                    what="static equilibrium under the wheel load")[-1]
    forces = forces_on_part(model, s.wheel.part)
    residual = float(np.linalg.norm(sum(forces.values())))
    return StaticResult(state, w, bushing_table(state, s), residual)
