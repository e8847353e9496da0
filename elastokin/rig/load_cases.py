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

import warnings
from collections.abc import Sequence
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np

from elastokin.config.schema.rig import (
    ForceSweepSpec,
    RigSpec,
    TorqueSweepSpec,
    TravelSpec,
    VerticalForceSpec,
)
from elastokin.errors import SolverError
from elastokin.physics.states import LoadTable, PoseSeries, StepState, WheelArrays
from elastokin.physics.wheel import toe_deg
from elastokin.rig.axle_channels import axle_columns
from elastokin.rig.channels import LOAD_CASES, STEERING_AXIS_COLUMNS
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
from elastokin.rig.pad import WheelInputs, run_rig
from elastokin.rig.paths import travel_path
from elastokin.rig.steering import stacked_steering_axis_columns
from elastokin.rig.sweeps import Sweep, static_rows

__all__ = ["Drive", "StaticResult", "compliance_matrix", "drives", "force_drive",
           "force_sweep", "parallel_travel", "parallel_travel_drive", "run_drive",
           "run_drive_sides", "run_load_cases", "run_load_cases_sides", "static_equilibrium",
           "static_states", "travel_path", "vertical_force", "vertical_force_drive",
           "wheel_compliance"]

if TYPE_CHECKING:
    from elastokin.mbs.model import SuspensionModel


class StaticStateWarning(UserWarning):
    """A model without a spring has no static equilibrium under the design wheel load: its
    changes are then from the design position (the message says so)."""


class StaticStates(dict):
    """The model's static state by side (:func:`static_states`) and, solved with design
    sensitivities, ``design``: per design variable ``{sign: {side: StepState}}``, the static
    state on its twins (:class:`~elastokin.mbs.twins.TwinPair`) at ``y +- step dy/dp``."""

    def __init__(self, states=(), design: list | None = None):
        super().__init__(states)
        self.design = design or []


def static_states(model: SuspensionModel, variations: Sequence | None = None,
                  twins: Sequence | None = None) -> StaticStates:
    """The model's own static state under the design wheel load, by side: every wheel's
    contact patch carrying the design wheel load, patches free (force control), steering
    held. It is the zero of the rig: every change-from-static channel
    (:func:`elastokin.rig.characteristics.characteristics`) and every pad height
    (:func:`run_drive_sides`) is referenced to it. A model without a spring that has no such
    equilibrium (e.g. a kinematic one: nothing carries the load) is referenced to its design
    position, with a :class:`StaticStateWarning`; any other failed solve raises
    :class:`~elastokin.errors.SolverError` (a start far from equilibrium: the DOE then
    solves it by continuation). ``variations``: with its sensitivities
    (:func:`~elastokin.rig.pad.run_rig`); ``twins``: with its states on each
    :class:`~elastokin.mbs.twins.TwinPair` (``StaticStates.design``: the static state moves
    with the design, and every change from it with it)."""
    s = model.suspension
    twins = list(twins or ())
    try:
        return _design_load_states(model, variations, twins)
    except SolverError as exc:
        if s.springs:
            raise
        warnings.warn(StaticStateWarning(
            f"{exc}: the changes (wheel travel, wheel-centre displacements, track and "
            "wheelbase change, steer angle) and the rig's pad heights are from the design "
            "position"), stacklevel=2)
    # the design position does not move with the parameters of ``variations``
    fixed = None if not variations else {k: np.zeros((3, len(variations)))
                                         for k in ("wheel_centre_mm", "spin_axis")}
    return StaticStates(_design_states(s, fixed), [
        {sign: _design_states(m.suspension) for sign, m in pair.models()} for pair in twins])


def _design_states(s, sensitivity=None) -> dict[str, StepState]:
    """Every wheel at the design position of ``s`` (no load)."""
    return {side: StepState(w.centre_mm, w.spin_axis, np.eye(3), w.contact_patch_mm,
                            np.zeros(3), {}, {}, {}, sensitivity=sensitivity)
            for side, w in s.wheels.items()}


def _design_load_wheels(s) -> dict[str, WheelInputs]:
    load = (s.up * s.design.wheel_load_N)[None, :]
    return {side: WheelInputs(None, load, np.zeros((1, 6))) for side in s.wheels}


def _design_load_states(model: SuspensionModel, variations: Sequence | None = None,
                        twins: Sequence = ()) -> StaticStates:
    pairs = [(pair, {sign: (_design_load_wheels(m.suspension), None, None)
                     for sign, m in pair.models()}) for pair in twins]
    steps = run_rig(model, _design_load_wheels(model.suspension),
                    what="static equilibrium under the design wheel load",
                    variations=variations, twins=pairs)
    design = [{sign: {side: a.step(0) for side, a in by_side.items()}
               for sign, by_side in moved.items()} for moved, _ in steps.design]
    return StaticStates(steps[0], design)


def pads_from_static(drive: Drive, suspension, static: dict[str, StepState]
                     ) -> dict[str, WheelInputs]:
    """The drive's wheel inputs with every pad height taken from the static state (a rig
    moves its pads from where the car rests): each wheel's pad height plus its contact
    point's height at ``static`` above the design position's."""
    out = {}
    for side, wi in drive.wheels.items():
        if wi.pad_z_mm is not None:
            rest = (static[side].contact_patch_mm - suspension.wheels[side].contact_patch_mm)
            wi = replace(wi, pad_z_mm=np.asarray(wi.pad_z_mm, float) + rest @ suspension.up)
        out[side] = wi
    return out


def run_drive_sides(model: SuspensionModel, label: str, drive: Drive,
                    variations: Sequence | None = None, twins: Sequence | None = None,
                    detail: str = "full", static: StaticStates | None = None
                    ) -> list[Sweep]:
    """The sweeps of ``drive`` on ``model``, one per wheel (the config side's first; the
    pads attached when they are not yet); with ``variations`` (parameters of the model's
    parametric bushings, :class:`~elastokin.mbs.sensitivity.LawVariation`) every sweep
    carries the tangents of its wheel's columns (``Sweep.tangents``); with ``twins`` (per
    design variable a :class:`~elastokin.mbs.twins.TwinPair` and, by sign, the same load
    case's drive on that twin's suspension: :func:`twin_drives`) the tangents of every
    column (``Sweep.tangents``: column -> (steps, variables)); ``detail``: ``full`` (every
    column at every step) or ``summary`` (what the summary figures read: no bushing
    columns, the steering axis at the static state only, no approach from the design
    position; the others NaN). ``static``: the model's :func:`static_states` (solved here,
    with the same sensitivities or twins, when not given or given without them): the pads
    move from it (:func:`pads_from_static`; ``pad_z_mm`` is the change from it) and every
    change-from-static channel is referenced to it."""
    s = model.suspension
    rig = s.rig_source
    twins = list(twins or ())
    if static is None or (variations and any(st.sensitivity is None
                                              for st in static.values())) \
            or len(getattr(static, "design", ())) != len(twins):
        # the tangents need its own
        static = static_states(model, variations, [pair for pair, _ in twins])
    what = f"model '{label}', {drive.load_case}" + (f" (rig file {rig})" if rig else "")
    if drive.load_case == "steering":
        drive, mirrored = left_turning(model, drive, what)
        twins = [(pair, {sign: mirrored_rack(d, pair.models()[0 if sign > 0 else 1][1])
                         if mirrored else d for sign, d in per_sign.items()})
                 for pair, per_sign in twins]
    rig_twins = [(pair, {sign: (pads_from_static(per_sign[sign], m.suspension,
                                                 static.design[k][sign]),
                                per_sign[sign].rack_travel_mm, per_sign[sign].heave_load_N)
                         for sign, m in pair.models()})
                 for k, (pair, per_sign) in enumerate(twins)]
    keep = drive.recorded
    kept = np.ones(len(drive.branch), bool) if keep is None else np.asarray(keep, bool)
    derived = kept & ((np.asarray(drive.branch) != "approach") | (detail == "full"))
    steps = run_rig(model, pads_from_static(drive, s, static), drive.rack_travel_mm,
                    drive.heave_load_N, what=what, variations=variations, twins=rig_twins,
                    bushings=detail == "full", keep=derived)
    design = steps.design
    if keep is not None:
        steps = [st for st, k in zip(steps, keep) if k]
    columns = sweep_columns({side: [st[side] for st in steps] for side in s.sides}, s, drive,
                            static)
    tangents = design_tangents(columns, twins, design, derived, kept, detail, s, static)
    first = [st[s.side] for st in steps]
    loads = LoadTable.stack([st.loads for st in first]) if first and first[0].loads else None
    poses = PoseSeries.stack([st.poses for st in first]) if first and first[0].poses else None
    sweeps = []
    for side in s.sides:
        if variations:
            tangents[side] = wheel_column_tangents([st[side] for st in steps], s.on_side(side),
                                                   static[side])
        sweeps.append(Sweep(label, drive.load_case, columns[side], tangents[side], side,
                            loads=loads if side == s.side else None, poses=poses))
    return sweeps


def design_tangents(columns: dict, twins: list, design: list, derived: np.ndarray,
                    kept: np.ndarray, detail: str, s, static: StaticStates
                    ) -> dict[str, dict[str, np.ndarray]]:
    """Per side, the tangents (rows, variables) of every column of a sweep (``columns`` by
    side) from its states on each variable's twins (``design``, by variable), solved at the
    steps ``derived`` (a mask over the solver's steps, within those ``kept``; the other rows
    NaN); every change from each twin's own static state (``static.design``: the static state
    moves with the design)."""
    rows = np.flatnonzero(derived[kept])
    n = int(kept.sum())
    at_static = np.arange(rows.size) if detail == "full" else static_rows(
        {k: np.asarray(v)[rows] for k, v in columns[s.side].items()})
    # the columns on every twin, the steering axis left out: it is computed for all of them
    # at once (stacked_steering_axis_columns: its fixed cost once)
    moved = [{sign: sweep_columns(design[k][0][sign], m.suspension,
                                  replace(per_sign[sign], recorded=derived),
                                  static.design[k][sign], np.zeros(0, int))
              for sign, m in pair.models()} for k, (pair, per_sign) in enumerate(twins)]
    if at_static.size and any(STEERING_AXIS_COLUMNS[0] in m[1][s.side] for m in moved):
        for side in s.sides:
            cases = [(k, sign, m.suspension.on_side(side)) for k, (pair, _) in
                     enumerate(twins) for sign, m in pair.models()]
            axes = stacked_steering_axis_columns(
                [([design[k][0][sign][side].step(i) for i in at_static], view)
                 for k, sign, view in cases])
            for (k, sign, _), cols in zip(cases, axes):
                for name, values in cols.items():
                    moved[k][sign][side][name][at_static] = values
    tangents: dict[str, dict[str, np.ndarray]] = {side: {} for side in s.sides}
    for k, (pair, _) in enumerate(twins):
        for side in s.sides:
            plus, minus = moved[k][1][side], moved[k][-1][side]
            for name in columns[side]:
                if name == "branch" or name not in plus:
                    continue
                t = tangents[side].setdefault(name, np.full((n, len(twins)), np.nan))
                t[rows, k] = (np.asarray(plus[name], float)
                              - np.asarray(minus[name], float)) / (2.0 * pair.step)
    return tangents


def sweep_columns(by_side: dict, suspension, drive: Drive, static: dict[str, StepState],
                  steering_rows: np.ndarray | None = None) -> dict[str, dict[str, np.ndarray]]:
    """Every column of each wheel's sweep (by side) from the recorded rig steps of
    ``drive`` by side (lists of :class:`~elastokin.physics.states.StepState` or
    :class:`~elastokin.physics.states.WheelArrays`; its ``recorded`` selection applied),
    every change from ``static`` (by side, :func:`static_states`); ``steering_rows``: see
    :func:`~elastokin.rig.characteristics.characteristics`."""
    s = suspension
    keep = drive.recorded
    cols = {"branch": drive.branch, drive.input_column: drive.inputs, **drive.columns}
    own = dict(drive.side_inputs)  # a wheel's own input, where it is not the drive's
    if keep is not None:
        cols = {k: v[keep] for k, v in cols.items()}
        own = {k: v[keep] for k, v in own.items()}
    shared = axle_columns(by_side, s, drive, static) if s.axle is not None else {}
    out = {}
    for side in s.sides:
        view = s.on_side(side)
        mine = {drive.input_column: own[side]} if side in own else {}
        out[side] = {**cols, **mine, **characteristics(by_side[side], view, static[side],
                                                        steering_rows=steering_rows),
                     **shared}
        case = LOAD_CASES.get(drive.load_case)  # vehicle loads are not in the table
        if case is not None and case.input == "wheel_travel_mm":  # the travel cases
            out[side].update(motion_ratio_columns(out[side]))
    return out


def twin_drives(twins: Sequence, load_case: str, rig: RigSpec | None, kinematic: bool
                ) -> list[tuple]:
    """Per twin pair, by sign, the drive of ``load_case`` on that twin's suspension (the
    design may change a drive: the steering ratio its rack travel, the track its roll)."""
    out = []
    for pair in twins:
        per_sign = {}
        for sign, m in pair.models():
            per_sign[sign] = next(d for d in drives(m.suspension, rig, kinematic)
                                  if d.load_case == load_case)
        out.append((pair, per_sign))
    return out


#: rack travel (mm) of the probe step that finds the pinion's sense (:func:`left_turning`)
STEERING_PROBE_MM = 0.1


def left_turning(model: SuspensionModel, drive: Drive, what: str) -> tuple[Drive, bool]:
    """(the steering ``drive`` with the pinion's sense that turns the wheels to the left for a
    positive steering-wheel angle (ISO 8855, as ADAMS/Car). Rack travel + along the rack's
    axis turns the wheels left or right depending on whether the tie rods are behind or
    ahead of the wheel centres: one probe step of :data:`STEERING_PROBE_MM` decides, and the
    rack's travel is mirrored about its held position when it turns them right; whether it
    was)."""
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
        return drive, False
    return mirrored_rack(drive, model), True


def mirrored_rack(drive: Drive, model: SuspensionModel) -> Drive:
    """``drive`` with the rack's travel mirrored about its held position (the pinion's
    other sense, :func:`left_turning`)."""
    rack = 2.0 * model.suspension.axle.steering.travel_mm - drive.rack_travel_mm
    return replace(drive, rack_travel_mm=rack, columns={**drive.columns, "rack_travel_mm": rack})


def run_drive(model: SuspensionModel, label: str, drive: Drive,
              variations: Sequence | None = None,
              static: dict[str, StepState] | None = None) -> Sweep:
    """The config side's sweep of ``drive`` on ``model`` (:func:`run_drive_sides`)."""
    return run_drive_sides(model, label, drive, variations, static=static)[0]


def run_load_cases_sides(model: SuspensionModel, label: str, rig: RigSpec | None = None,
                         variations: Sequence | None = None, twins: Sequence | None = None,
                         detail: str = "full") -> dict[str, list[Sweep]]:
    """Every load case of ``rig`` (default: the model's config's) on ``model``: the sweeps by
    side (the config side's first), every change from the model's :func:`static_states`
    (solved once); ``twins``: design sensitivities, a :class:`~elastokin.mbs.twins.TwinPair`
    per design variable (:func:`run_drive_sides`)."""
    out: dict[str, list[Sweep]] = {side: [] for side in model.suspension.sides}
    kinematic = model.suspension.kinematic
    static = static_states(model, variations, twins)
    for d in drives(model.suspension, rig, kinematic):
        pairs = twin_drives(twins, d.load_case, rig, kinematic) if twins else None
        for sw in run_drive_sides(model, label, d, variations, pairs, detail, static):
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
                     torque_step_Nmm: float = 1000.0, twins: Sequence | None = None):
    """Compliance of every wheel centre at the static equilibrium under the design wheel
    loads (patches free), by central differences: (6 n, 6 n) for n wheels (the config side's
    first: on an axle ADAMS/Car's 12x12 matrix with the left wheel first when the config is a
    left corner); per wheel columns force x, y, z (N) and torque x, y, z (N*mm) at its centre,
    rows its centre's displacement x, y, z (mm) and rotation vector x, y, z (deg); config
    frame. With ``twins`` (design sensitivities, :func:`run_drive_sides`): (the matrix, its
    derivatives (6 n, 6 n, variables))."""
    s = model.suspension
    loads = _compliance_loads(s, force_step_N, torque_step_Nmm)
    pairs = [(pair, {sign: (_compliance_loads(m.suspension, force_step_N, torque_step_Nmm),
                            None, None) for sign, m in pair.models()}) for pair in twins or ()]
    states = run_rig(model, loads, what="compliance matrix", twins=pairs)
    C = compliance_from_states({side: [st[side] for st in states] for side in s.sides}, s,
                               force_step_N, torque_step_Nmm)
    if twins is None:
        return C
    dC = np.zeros((*C.shape, len(pairs)))
    for k, (pair, _) in enumerate(pairs):
        moved, step = states.design[k]
        plus, minus = (compliance_from_states(moved[sign], m.suspension, force_step_N,
                                              torque_step_Nmm) for sign, m in pair.models())
        dC[:, :, k] = (plus - minus) / (2.0 * step)
    return C, dC


def _compliance_loads(s, force_step_N: float, torque_step_Nmm: float) -> dict:
    """The compliance matrix's rig inputs: each wheel at its design load, then every force
    and torque component at every wheel centre, + and - (central differences)."""
    n = len(s.sides)
    steps = [np.zeros(6 * n)]
    for k in range(6 * n):
        h = np.zeros(6 * n)
        h[k] = force_step_N if k % 6 < 3 else torque_step_Nmm
        steps += [h, -h]
    centre = np.array(steps)
    pad = np.tile(s.up * s.design.wheel_load_N, (len(steps), 1))
    return {side: WheelInputs(None, pad, centre[:, 6 * i:6 * i + 6])
            for i, side in enumerate(s.sides)}


def compliance_from_states(by_side: dict, suspension, force_step_N: float = 10.0,
                           torque_step_Nmm: float = 1000.0) -> np.ndarray:
    """The compliance matrix (:func:`wheel_compliance`) from the rig steps of its inputs, by
    side (lists of :class:`~elastokin.physics.states.StepState` or their
    :class:`~elastokin.physics.states.WheelArrays`)."""
    from scipy.spatial.transform import Rotation

    s = suspension
    n = len(s.sides)
    wheel = {side: WheelArrays.of(by_side[side]) for side in s.sides}

    def response(i):
        out = []
        for side in s.sides:
            a = wheel[side]
            R0, x0 = a.wheel_rotation[0], a.wheel_centre_mm[0]
            rot = Rotation.from_matrix(a.wheel_rotation[i] @ R0.T).as_rotvec(degrees=True)
            out.append(np.r_[a.wheel_centre_mm[i] - x0, rot])
        return np.concatenate(out)

    C = np.empty((6 * n, 6 * n))
    for k in range(6 * n):
        h = force_step_N if k % 6 < 3 else torque_step_Nmm
        C[:, k] = (response(1 + 2 * k) - response(2 + 2 * k)) / (2 * h)
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
    state = _design_load_states(model)[s.side]
    forces = forces_on_part(model, s.wheel.part)
    residual = float(np.linalg.norm(sum(forces.values())))
    return StaticResult(state, w, bushing_table(state, s), residual)
