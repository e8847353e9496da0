"""The K&C rig's wheel pad, attached to any built model: a support under the contact patch
(vertical position prescribed, x and y free: displacement control) and loads at the contact
patch and at the wheel centre (force control). The model knows nothing of it.

Config frame, mm / N / N*mm. Contact-patch forces are the forces the pad applies to the tyre
(Fz > 0 pushes the wheel up); the pad's vertical reaction is added to them under displacement
control.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from elastokin.errors import ModelError
from elastokin.physics.states import ModelState, StepState

if TYPE_CHECKING:
    from elastokin.mbs.model import SuspensionModel

PAD = "rig:pad"
PATCH_FORCE = "rig:contact_patch_force"
CENTRE_FORCE = "rig:wheel_centre_force"
CENTRE_TORQUE = "rig:wheel_centre_torque"
#: recorded points of the wheel part
CENTRE, PATCH = "rig:wheel_centre", "rig:contact_patch"


def attach_pad(model: SuspensionModel) -> None:
    """Attach the pad and the wheel loads to ``model`` (once; again is a no-op)."""
    if PAD in model.supports:
        return
    w = model.suspension.wheel
    model.add_support(PAD, w.part, w.contact_patch_mm, (0, 0, 1, 0, 0, 0))
    model.add_load(PATCH_FORCE, w.part, w.contact_patch_mm, "force", marker_of=PAD)
    model.add_load(CENTRE_FORCE, w.part, w.centre_mm, "force")
    model.add_load(CENTRE_TORQUE, w.part, w.centre_mm, "torque", marker_of=CENTRE_FORCE)
    model.add_point_sensor(CENTRE, w.part, w.centre_mm)
    model.add_point_sensor(PATCH, w.part, w.contact_patch_mm)


def run_pad(model: SuspensionModel, pad_z_mm: Sequence[float] | None = None,
            pad_loads: np.ndarray | None = None, centre_loads: np.ndarray | None = None,
            what: str = "static solve", solve_per_step: bool = False,
            substeps: int | None = None, variations: Sequence | None = None
            ) -> list[StepState]:
    """Quasi-static steps of the rig from the design position.

    pad_z_mm: prescribed vertical displacement of the contact patch per step (mm), or None
        for force control (then the patch is free and ``pad_loads`` must carry Fz).
    pad_loads: (n, 3) forces at the contact patch per step, N, config frame.
    centre_loads: (n, 6) forces (N) and torques (N*mm) at the wheel centre per step.
    solve_per_step, substeps: see :func:`elastokin.mbs.solve.solve_path`.
    variations: parameters of the model's parametric bushings
        (:class:`~elastokin.mbs.sensitivity.LawVariation`): every step then carries the
        derivatives of the wheel centre, contact patch and spin axis with respect to them.
    Returns one :class:`StepState` per step.
    """
    from elastokin.mbs.sensitivity import solve_path_with_sensitivities
    from elastokin.mbs.solve import solve_path

    if pad_z_mm is None and pad_loads is None:
        raise ModelError("run_pad: give pad_z_mm (displacement control) or pad_loads")
    attach_pad(model)
    n = len(pad_z_mm) if pad_z_mm is not None else len(pad_loads)
    pl = np.asarray(pad_loads, float).reshape(n, 3) if pad_loads is not None \
        else np.zeros((n, 3))
    cl = np.asarray(centre_loads, float).reshape(n, 6) if centre_loads is not None \
        else np.zeros((n, 6))
    inputs = {PATCH_FORCE: pl, CENTRE_FORCE: cl[:, :3], CENTRE_TORQUE: cl[:, 3:]}
    if pad_z_mm is not None:
        offset = np.zeros((n, 6))
        offset[:, 2] = np.asarray(pad_z_mm, float)
        inputs[PAD] = offset
    if variations:
        states = solve_path_with_sensitivities(model, inputs, what, variations)
    else:
        # with ball-joint friction the suspension first settles under the first pad load
        states = solve_path(model, inputs, what, settle={PATCH_FORCE: pl[0]},
                            solve_per_step=solve_per_step, substeps=substeps)
    return [wheel_state(model, st, pad_z_mm is not None) for st in states]


def wheel_state(model: SuspensionModel, state: ModelState, displacement_control: bool
                ) -> StepState:
    """The rig's view of a solved model state: wheel centre and contact patch (recorded
    points), spin axis and rotation from the wheel part's pose; the pad force (applied, plus
    the pad's vertical reaction under displacement control)."""
    w = model.suspension.wheel
    poses = state.poses
    R = poses.rotation[w.part]
    pad = state.applied[PATCH_FORCE].copy()
    if displacement_control:
        pad[2] += state.support_force_N[PAD][2]
    sens = state.sensitivity
    derivatives = None if sens is None else {
        "wheel_centre_mm": sens.points[CENTRE], "contact_patch_mm": sens.points[PATCH],
        "spin_axis": np.einsum("abp,b->ap", sens.rotation[w.part], w.spin_axis)}
    return StepState(state.points[CENTRE], R @ w.spin_axis, R, state.points[PATCH], pad,
                     state.spring_force_N,
                     state.bushing_deflection, state.bushing_load,
                     poses if model.options.part_poses else None, derivatives)
