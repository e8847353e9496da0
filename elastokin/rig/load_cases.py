"""The virtual K&C rig's load cases as drives attached to any built model.

A :class:`Drive` says what the rig does in one load case: per step, the pad height
(displacement control, x and y free) or none (force control, the patch free), the forces at the
contact patch and the loads at the wheel centre; the input channel and branch label of every
step; which steps are recorded. :func:`run_drive` attaches the pad (:mod:`elastokin.rig.pad`) to
a model, solves the steps and returns the recorded sweep with every channel of
:mod:`elastokin.rig.channels`. Steering is locked in every case.

Frames and units: the config frame, mm, N, N*mm, deg; forces and torques are those the rig
applies to the tyre (ISO 8855 vehicle axes).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from elastokin.config.schema import (
    ForceSweepSpec,
    RigSpec,
    TorqueSweepSpec,
    TravelSpec,
    VerticalForceSpec,
)
from elastokin.config.suspension import Suspension
from elastokin.rig.channels import FORCE_CASES, LOAD_CASES
from elastokin.rig.characteristics import (
    bushing_table,
    characteristics,
    wheel_column_tangents,
)
from elastokin.rig.pad import run_pad
from elastokin.rig.paths import sweep_path, travel_path, vertical_force_path
from elastokin.rig.sweeps import Sweep

if TYPE_CHECKING:
    from elastokin.mbs.model import SuspensionModel
    from elastokin.physics.states import StepState


@dataclass(frozen=True)
class Drive:
    """One load case as the rig drives it (config frame, mm, N, N*mm).

    ``inputs``: the rig input per step (column ``input_column`` of the sweep); ``branch``: each
    step's branch label; ``pad_z_mm``: the pad height per step (displacement control) or None
    (force control); ``pad_loads`` (n, 3): forces at the contact patch; ``centre_loads``
    (n, 6): forces and torques at the wheel centre; ``recorded``: which steps the sweep keeps
    (None: all).
    """

    load_case: str
    input_column: str
    inputs: np.ndarray
    branch: np.ndarray
    pad_z_mm: np.ndarray | None
    pad_loads: np.ndarray
    centre_loads: np.ndarray
    recorded: np.ndarray | None = None


def parallel_travel_drive(suspension: Suspension, spec: TravelSpec | None = None,
                          approach_step_mm: float | None = None,
                          record_approach: bool = True) -> Drive:
    """Displacement-controlled parallel wheel travel (both wheels of an axle move together;
    here the one wheel of the model) at the design wheel load: the approach from the design
    position to rebound (in steps of ``approach_step_mm``, default the stroke's), the stroke
    and the return. Without ``record_approach`` the sweep starts at the rebound point."""
    spec = spec or suspension.rig.parallel_travel
    z, branch = travel_path(spec.rebound_mm, spec.bump_mm, spec.step_mm, spec.unloading,
                            approach_step_mm)
    n = z.size
    return Drive("parallel_travel", "pad_z_mm", z, branch, z, np.zeros((n, 3)),
                 np.zeros((n, 6)), None if record_approach else branch != "approach")


def vertical_force_drive(suspension: Suspension,
                         spec: VerticalForceSpec | None = None) -> Drive:
    """Vertical force at the contact patch (force control, patch free): from the design wheel
    load down to ``min_N`` (approach), up to ``max_N`` (rise) and back to ``min_N`` (fall)."""
    s = suspension
    spec = spec or s.rig.vertical_force
    fz, branch = vertical_force_path(s.design.wheel_load_N, spec.min_N, spec.max_N,
                                     spec.step_N)
    return Drive("vertical_force", "vertical_force_N", fz, branch, None, fz[:, None] * s.up,
                 np.zeros((fz.size, 6)))


def force_drive(suspension: Suspension, case: str,
                spec: ForceSweepSpec | TorqueSweepSpec | None = None) -> Drive:
    """A force (or aligning torque) swept 0 -> +A -> -A -> 0 at the design wheel load, the
    contact patch free (force control)."""
    s = suspension
    lc = LOAD_CASES[case]
    spec = spec or getattr(s.rig, case)
    if isinstance(spec, TorqueSweepSpec):
        values, branch = sweep_path(spec.amplitude_Nmm, spec.step_Nmm)
    else:
        values, branch = sweep_path(spec.amplitude_N, spec.step_N)
    axis = getattr(s, lc.direction)
    n = values.size
    pad = np.tile(s.up * s.design.wheel_load_N, (n, 1))
    centre = np.zeros((n, 6))
    if lc.where == "patch":
        pad = pad + values[:, None] * axis
    elif lc.where == "centre":
        centre[:, :3] = values[:, None] * axis
    else:
        centre[:, 3:] = values[:, None] * axis
    return Drive(case, lc.input, values, branch, None, pad, centre)


def drives(suspension: Suspension, rig: RigSpec | None = None,
           kinematic: bool = False) -> list[Drive]:
    """Every load case of ``rig`` (default: the config's), parallel travel first. A kinematic
    model runs the vertical cases only: without bushings its answer to a lateral or
    longitudinal load is rigid-body statics, not compliance."""
    rig = rig or suspension.rig
    out = [parallel_travel_drive(suspension, rig.parallel_travel)]
    if rig.vertical_force is not None:
        out.append(vertical_force_drive(suspension, rig.vertical_force))
    if not kinematic:
        out += [force_drive(suspension, case, getattr(rig, case)) for case in FORCE_CASES
                if getattr(rig, case) is not None]
    return out


def run_drive(model: SuspensionModel, label: str, drive: Drive,
              variations: Sequence | None = None) -> Sweep:
    """The sweep of ``drive`` on ``model`` (the pad attached when it is not yet); with
    ``variations`` (parameters of the model's parametric bushings,
    :class:`~elastokin.mbs.sensitivity.LawVariation`) the sweep carries the tangents of the
    wheel's columns (``Sweep.tangents``)."""
    rig = model.suspension.rig_source
    what = f"model '{label}', {drive.load_case}" + (f" (rig file {rig})" if rig else "")
    states = run_pad(model, drive.pad_z_mm, drive.pad_loads, drive.centre_loads, what=what,
                     variations=variations)
    cols = {"branch": drive.branch, drive.input_column: drive.inputs}
    keep = drive.recorded
    if keep is not None:
        states = [st for st, k in zip(states, keep) if k]
        cols = {k: v[keep] for k, v in cols.items()}
    cols.update(characteristics(states, model.suspension))
    tangents = wheel_column_tangents(states, model.suspension) if variations else {}
    return Sweep(label, drive.load_case, cols, tangents)


def run_load_cases(model: SuspensionModel, label: str, rig: RigSpec | None = None,
                   variations: Sequence | None = None) -> list[Sweep]:
    """Every load case of ``rig`` (default: the model's config's) on ``model``
    (``variations``: see :func:`run_drive`)."""
    return [run_drive(model, label, d, variations)
            for d in drives(model.suspension, rig, model.suspension.kinematic)]


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


def compliance_matrix(model: SuspensionModel, force_step_N: float = 10.0,
                      torque_step_Nmm: float = 1000.0) -> np.ndarray:
    """6x6 compliance of the wheel centre at the static equilibrium under the design wheel
    load (patch free), by central differences: columns = force x, y, z (N) and torque x, y, z
    (N*mm) at the wheel centre, rows = wheel-centre displacement x, y, z (mm) and rotation
    vector x, y, z (deg); config frame."""
    from scipy.spatial.transform import Rotation

    s = model.suspension
    steps = [np.zeros(6)]
    for k in range(6):
        h = np.zeros(6)
        h[k] = force_step_N if k < 3 else torque_step_Nmm
        steps += [h, -h]
    centre = np.array(steps)
    pad = np.tile(s.up * s.design.wheel_load_N, (len(steps), 1))
    states = run_pad(model, pad_loads=pad, centre_loads=centre, what="compliance matrix")
    R0, x0 = states[0].wheel_rotation, states[0].wheel_centre_mm

    def response(st):
        rot = Rotation.from_matrix(st.wheel_rotation @ R0.T).as_rotvec(degrees=True)
        return np.r_[st.wheel_centre_mm - x0, rot]

    C = np.empty((6, 6))
    for k in range(6):
        h = centre[1 + 2 * k, k]
        C[:, k] = (response(states[1 + 2 * k]) - response(states[2 + 2 * k])) / (2 * h)
    return C


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
