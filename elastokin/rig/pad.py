"""The K&C rig's wheel pads, attached to any built model: per wheel a support under the
contact patch (vertical position prescribed, x and y free: displacement control) and loads at
the contact patch and at the wheel centre (force control); on an axle also the steering input
(the rack's travel) and, for roll, a heave beam carrying both pads (free to move vertically
under the axle's total vertical load, the pads' heights prescribed relative to it). The model
knows nothing of it.

The contact patch is the tyre's contact point, the wheel's lowest point at the loaded radius
in the wheel plane (:func:`~elastokin.physics.steering_geometry.contact_point`), recomputed at
every step: the wheel rolls on the pad, which holds and loads it there
(:mod:`elastokin.mbs.contact`), and every channel reads the same point.

Config frame, mm / N / N*mm. Contact-patch forces are the forces the pad applies to the tyre
(Fz > 0 pushes the wheel up); the pad's vertical reaction is added to them under displacement
control.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from elastokin.errors import ModelError
from elastokin.physics.states import ModelState, StepState, WheelArrays
from elastokin.physics.steering_geometry import contact_point

if TYPE_CHECKING:
    from elastokin.mbs.model import SuspensionModel

#: the heave beam of the roll load case (a rig body) and its load
HEAVE, HEAVE_LOAD = "rig:heave", "rig:heave_load"
HELD, HEAVING = (1, 1, 1, 1, 1, 1), (1, 1, 0, 1, 1, 1)
#: a pad holds the contact point's height, x and y free
HOLD_Z = (0, 0, 1, 0, 0, 0)


def names(side: str) -> dict[str, str]:
    """The rig's attachments and point sensors of the wheel on ``side``."""
    return {"pad": f"rig:pad:{side}", "roll_pad": f"rig:roll_pad:{side}",
            "patch_force": f"rig:contact_patch_force:{side}",
            "centre_force": f"rig:wheel_centre_force:{side}",
            "centre_torque": f"rig:wheel_centre_torque:{side}",
            "centre": f"rig:wheel_centre:{side}"}


def patch_item(side: str) -> tuple[str, str]:
    """The reported load (:mod:`elastokin.mbs.loads`) of everything the rig applies to the
    wheel on ``side`` (pad, patch and wheel-centre loads), reduced to the contact patch."""
    return f"contact_patch_{side}", "contact_patch"


@dataclass(frozen=True)
class WheelInputs:
    """What the rig does to one wheel per step (config frame): the pad height (mm,
    displacement control; relative to the heave beam in roll) or None (force control),
    forces at the contact patch (n, 3) N, forces and torques at the wheel centre (n, 6)."""

    pad_z_mm: np.ndarray | None
    pad_loads: np.ndarray
    centre_loads: np.ndarray


def attach_pads(model: SuspensionModel) -> None:
    """Attach a pad and the wheel loads to every wheel of ``model`` (once): the pad holds and
    loads the wheel at its contact point (:mod:`elastokin.mbs.contact`)."""
    from elastokin.mbs.contact import add_contact_load, contact_arm

    for side, w in model.suspension.wheels.items():
        n = names(side)
        if n["pad"] in model.supports:
            continue
        item = patch_item(side)
        # the points as functions of the suspension: a design's twin moves them in place
        patch, centre = contact_patch(side), wheel_centre(side)
        model.add_support(n["pad"], contact_arm(model, side, item), patch, HOLD_Z, item=item)
        add_contact_load(model, n["patch_force"], side, item)
        model.add_load(n["centre_force"], w.part, centre, "force", item=item)
        model.add_load(n["centre_torque"], w.part, centre, "torque",
                       marker_of=n["centre_force"], item=item)
        model.add_point_sensor(n["centre"], w.part, centre)


def contact_patch(side: str):
    """The design contact point of the wheel on ``side`` of a suspension (mm): its lowest
    point (``Wheel.contact_patch_mm``)."""
    return lambda s: s.wheels[side].contact_patch_mm


def wheel_centre(side: str):
    """The design wheel centre of the wheel on ``side`` of a suspension (mm)."""
    return lambda s: s.wheels[side].centre_mm


def patches_midpoint(s) -> np.ndarray:
    """The midpoint of a suspension's design contact points (mm): the heave beam's."""
    return np.mean([w.contact_patch_mm for w in s.wheels.values()], axis=0)


def attach_heave(model: SuspensionModel) -> None:
    """The heave beam under the contact patches and the pads on it (once)."""
    from elastokin.mbs.contact import contact_arm

    if HEAVE in model.rig_bodies:
        return
    s = model.suspension
    model.add_rig_body(HEAVE, patches_midpoint(s), HELD)
    model.add_load(HEAVE_LOAD, HEAVE, patches_midpoint, "force")
    for side in s.wheels:
        model.add_support(names(side)["roll_pad"], contact_arm(model, side, patch_item(side)),
                          contact_patch(side), HOLD_Z, base=HEAVE, item=patch_item(side))


def run_rig(model: SuspensionModel, wheels: Mapping[str, WheelInputs],
            rack_travel_mm: np.ndarray | None = None, heave_load_N: np.ndarray | None = None,
            what: str = "static solve", solve_per_step: bool = False,
            substeps: int | None = None, variations: Sequence | None = None,
            twins: Sequence | None = None, bushings: bool = True,
            keep: np.ndarray | None = None) -> list[dict[str, StepState]]:
    """Quasi-static steps of the rig from the design position, one dict of wheel states (by
    side) per step.

    wheels: the inputs of every wheel of the model (:class:`WheelInputs`).
    rack_travel_mm: the steering rack's travel per step (mm along its axis; default: held).
    heave_load_N: roll: the total vertical force on the heave beam per step (N); the pads'
        heights are then relative to the beam, which is free to move vertically.
    solve_per_step, substeps: see :func:`elastokin.mbs.solve.solve_path`.
    variations: parameters of the model's parametric bushings
        (:class:`~elastokin.mbs.sensitivity.LawVariation`): every step then carries the
        derivatives of each wheel centre, contact patch and spin axis with respect to them.
    twins: design sensitivities: per design variable a pair of twin models
        (:class:`~elastokin.mbs.twins.TwinPair`) and, by sign (+1, -1), the arguments
        ``(wheels, rack_travel_mm, heave_load_N)`` of the same load case on that twin's
        suspension; the returned :class:`RigSteps` then carry ``design``, the wheels' states
        on the twins; ``bushings``: with the bushings' deflections on the twins; ``keep``:
        the steps (a mask) with derivatives, default all
        (:func:`~elastokin.mbs.twins.solve_path_with_twins`).
    """
    from elastokin.mbs.sensitivity import solve_path_with_sensitivities
    from elastokin.mbs.solve import solve_path
    from elastokin.mbs.twins import solve_path_with_twins

    s = model.suspension
    missing = sorted(set(s.wheels) - set(wheels))
    if missing:
        raise ModelError(f"{s.source}: the rig needs inputs for the wheel(s) on the "
                         f"{', '.join(missing)} side")
    inputs, settle = rig_inputs(model, wheels, rack_travel_mm, heave_load_N)
    roll = heave_load_N is not None
    twins = list(twins or ())
    for pair, per_sign in twins:
        pair.inputs = {sign: rig_inputs(m, *per_sign[sign])[0] for sign, m in pair.models()}
    heaving = [model, *(m.model for pair, _ in twins for _, m in pair.models()
                        if not m.in_place)] if roll else []
    for m in heaving:
        m.set_support_axes(HEAVE, HEAVING)
    design = []
    try:
        if twins:
            states, design = solve_path_with_twins(model, inputs, what, [p for p, _ in twins],
                                                   bushings, keep)
        elif variations:
            states = solve_path_with_sensitivities(model, inputs, what, variations)
        else:
            # with ball-joint friction the suspension first settles under the first loads
            states = solve_path(model, inputs, what, settle=settle,
                                solve_per_step=solve_per_step, substeps=substeps)
    finally:
        for m in heaving:
            m.set_support_axes(HEAVE, HELD)
    contact = {side: contact_points(model, states, side) for side in wheels}
    out = RigSteps({side: wheel_state(model, st, side, wi.pad_z_mm is not None, roll,
                                      contact[side][i])
                    for side, wi in wheels.items()} for i, st in enumerate(states))
    out.design = [({sign: {side: wheel_arrays(m, d.states[sign], side,
                                              wheels[side].pad_z_mm is not None, roll)
                           for side in wheels} for sign, m in pair.models()}, d.step)
                  for (pair, _), d in zip(twins, design)]
    return out


class RigSteps(list):
    """The rig's steps (a list: per step the wheel states by side) and, solved with design
    sensitivities, ``design``: per design variable ``({sign: {side: WheelArrays}}, step)``,
    the wheels' states on its twins (:func:`wheel_arrays`)."""

    def __init__(self, steps=(), design: list | None = None):
        super().__init__(steps)
        self.design = design or []


def wheel_arrays(model: SuspensionModel, state: dict, side: str, displacement_control: bool,
                 roll: bool = False) -> WheelArrays:
    """:func:`wheel_state` over many steps: the wheel on ``side`` from a model's states as
    arrays (:func:`~elastokin.mbs.solve.state_arrays`; the contact point its lowest point)."""
    w = model.suspension.wheels[side]
    n = names(side)
    R = state["poses"][w.part][0]
    pad = np.array(state["applied"][n["patch_force"]], float)
    if displacement_control:
        pad[:, 2] += state["support_force_N"][n["roll_pad" if roll else "pad"]][:, 2]
    centre, spin = state["points"][n["centre"]], R @ w.spin_axis
    return WheelArrays(centre, spin, R,
                       contact_point(centre, spin, w.loaded_radius_mm, model.suspension.up),
                       pad, state["spring_force_N"],
                       state["bushing_deflection"], state["bushing_load"], state["scalars"],
                       state["poses"] if model.options.part_poses else None,
                       state["reference_mm"])


def rig_inputs(model: SuspensionModel, wheels: Mapping[str, WheelInputs],
               rack_travel_mm: np.ndarray | None = None,
               heave_load_N: np.ndarray | None = None) -> tuple[dict, dict]:
    """The rig attached to ``model`` (pads, and the heave beam for roll) and its inputs as
    the solver takes them: (attachment name -> values per step, the loads the suspension
    settles under when it has friction)."""
    s = model.suspension
    attach_pads(model)
    inputs, settle = {}, {}
    roll = heave_load_N is not None
    for side, wi in wheels.items():
        n = names(side)
        inputs[n["patch_force"]] = np.asarray(wi.pad_loads, float).reshape(-1, 3)
        cl = np.asarray(wi.centre_loads, float).reshape(-1, 6)
        inputs[n["centre_force"]], inputs[n["centre_torque"]] = cl[:, :3], cl[:, 3:]
        settle[n["patch_force"]] = inputs[n["patch_force"]][0]
        if wi.pad_z_mm is not None:
            offset = np.zeros((len(wi.pad_z_mm), 6))
            offset[:, 2] = np.asarray(wi.pad_z_mm, float)
            inputs[n["roll_pad" if roll else "pad"]] = offset
    if rack_travel_mm is not None:
        inputs.update(_steering_inputs(model, rack_travel_mm))
    if roll:
        attach_heave(model)
        inputs[HEAVE_LOAD] = np.asarray(heave_load_N, float)[:, None] * s.up
        settle[HEAVE_LOAD] = inputs[HEAVE_LOAD][0]  # the beam carries the wheels as it settles
    return inputs, settle


def _steering_inputs(model: SuspensionModel, rack_travel_mm) -> dict[str, np.ndarray]:
    from elastokin.mbs.axle_elements import STEERING_LOCK

    if STEERING_LOCK not in model.supports:
        raise ModelError(f"{model.suspension.source}: the rig cannot steer: the axle has no "
                         "steering (axle.steering)")
    travel = np.asarray(rack_travel_mm, float)
    offset = np.zeros((travel.size, 6))
    offset[:, 2] = travel
    return {STEERING_LOCK: offset}


def run_pad(model: SuspensionModel, pad_z_mm: Sequence[float] | None = None,
            pad_loads: np.ndarray | None = None, centre_loads: np.ndarray | None = None,
            what: str = "static solve", solve_per_step: bool = False,
            substeps: int | None = None, variations: Sequence | None = None
            ) -> list[StepState]:
    """Quasi-static steps of the rig from the design position, the same inputs on every
    wheel (on an axle: in phase, the same vectors in the config frame); the config side's
    wheel states.

    pad_z_mm: prescribed vertical displacement of the contact patch per step (mm), or None
        for force control (then the patch is free and ``pad_loads`` must carry Fz).
    pad_loads: (n, 3) forces at the contact patch per step, N, config frame.
    centre_loads: (n, 6) forces (N) and torques (N*mm) at the wheel centre per step.
    solve_per_step, substeps, variations: see :func:`run_rig`.
    """
    if pad_z_mm is None and pad_loads is None:
        raise ModelError("run_pad: give pad_z_mm (displacement control) or pad_loads")
    n = len(pad_z_mm) if pad_z_mm is not None else len(pad_loads)
    pl = np.asarray(pad_loads, float).reshape(n, 3) if pad_loads is not None \
        else np.zeros((n, 3))
    cl = np.asarray(centre_loads, float).reshape(n, 6) if centre_loads is not None \
        else np.zeros((n, 6))
    z = None if pad_z_mm is None else np.asarray(pad_z_mm, float)
    wheels = {side: WheelInputs(z, pl, cl) for side in model.suspension.wheels}
    steps = run_rig(model, wheels, what=what, solve_per_step=solve_per_step,
                    substeps=substeps, variations=variations)
    return [step[model.suspension.side] for step in steps]


def contact_points(model: SuspensionModel, states: Sequence[ModelState], side: str
                   ) -> np.ndarray:
    """(steps, 3) the contact point of the wheel on ``side`` at each of ``states`` (mm): its
    lowest point (:func:`~elastokin.physics.steering_geometry.contact_point`) from the wheel
    centre and spin axis, in one computation for all steps."""
    w = model.suspension.wheels[side]
    centre = np.array([st.points[names(side)["centre"]] for st in states]).reshape(-1, 3)
    spin = np.array([st.poses.rotation[w.part] @ w.spin_axis for st in states]).reshape(-1, 3)
    return contact_point(centre, spin, w.loaded_radius_mm, model.suspension.up)


def wheel_state(model: SuspensionModel, state: ModelState, side: str,
                displacement_control: bool, roll: bool = False,
                contact: np.ndarray | None = None) -> StepState:
    """The rig's view of a solved model state for the wheel on ``side``: wheel centre
    (recorded point), spin axis and rotation from the wheel part's pose, the contact point
    from both (the wheel's lowest point,
    :func:`~elastokin.physics.steering_geometry.contact_point`, where the pad holds and loads
    the wheel; ``contact`` when computed already, :func:`contact_points`); the pad force
    (applied, plus the pad's vertical reaction under displacement control)."""
    s = model.suspension
    w = s.wheels[side]
    n = names(side)
    poses = state.poses
    R = poses.rotation[w.part]
    centre, spin = state.points[n["centre"]], R @ w.spin_axis
    pad = state.applied[n["patch_force"]].copy()
    if displacement_control:
        pad[2] += state.support_force_N[n["roll_pad" if roll else "pad"]][2]
    sens = state.sensitivity
    derivatives = None if sens is None else {
        "wheel_centre_mm": sens.points[n["centre"]],
        "spin_axis": np.einsum("abp,b->ap", sens.rotation[w.part], w.spin_axis)}
    if contact is None:
        contact = contact_point(centre, spin, w.loaded_radius_mm, s.up)
    return StepState(centre, spin, R, contact, pad, state.spring_force_N,
                     state.bushing_deflection, state.bushing_load,
                     poses if model.options.part_poses else None, derivatives,
                     state.scalars, state.loads)
