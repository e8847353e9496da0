"""Exact sensitivities of a model's static steps to its design (hardpoints, rates, preloads,
the steering ratio: any change of the suspension), through **twin models**.

At every converged static step R(y, p) = 0 (y the parts' coordinates and the joints'
multipliers), so ``dy/dp = -(dR/dy)^-1 dR/dp`` with no re-solve (as
:mod:`elastokin.mbs.sensitivity` does for bushing laws). A change of the design moves
Exudyn's reference configuration, the markers' local positions, link lengths, spring
reference lengths, bushing frames and the rig's attachment points all at once; rather than
follow each of these, dR/dp is the residual of a **twin**: the model built again from the
changed suspension, with the **same parts' reference positions** as the model
(``SuspensionModel(references=...)``), so that a coordinate vector means the same pose in
both (a part's pose is its reference plus its displacement, its rotation from the identity),
evaluated at the model's own converged state. Central differences, ``p +- step``: the
residual is smooth in the design, and the twin's residual differs from the model's only in
the terms the design changes.

The channels depend on the design explicitly as well (a point sensor's local position, the
wheel centre a travel is measured from, the design toe): every output of a step is
evaluated on the twins at ``y +- step * dy/dp`` (the sensors' values in that configuration),
so that a channel computed from these two states by the rig's own code differs by exactly
its derivative times ``2 step``.

Units: mm, rad inside (coordinates); the design variables in their own units.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

from elastokin.errors import ModelError
from elastokin.mbs.model import SuspensionModel
from elastokin.mbs.sensitivity import Recorder, Residual, solve_tangents, system_matrices
from elastokin.mbs.solve import current_row, model_state, set_attachment_paths, solve_path
from elastokin.physics.states import ModelState


@dataclass
class TwinPair:
    """One design variable: the models at ``p + step`` and ``p - step`` (built with the base
    model's references), and the inputs each takes in the solve at hand (attachment name ->
    values per step, as :func:`~elastokin.mbs.solve.solve_path` takes them; the rig computes
    them from each twin's own suspension)."""

    plus: SuspensionModel
    minus: SuspensionModel
    step: float
    inputs: dict[int, Mapping[str, np.ndarray]] = field(default_factory=dict)

    def models(self) -> tuple[tuple[int, SuspensionModel], ...]:
        return (1, self.plus), (-1, self.minus)


@dataclass(frozen=True)
class DesignStates:
    """A step's states on the twins of one design variable: ``plus`` at ``y + step dy/dp``
    on the model at ``p + step``, ``minus`` likewise; a quantity q computed from them has
    ``dq/dp = (q(plus) - q(minus)) / (2 step)``."""

    plus: ModelState
    minus: ModelState
    step: float


def twin_model(model: SuspensionModel, suspension, preloads) -> SuspensionModel:
    """A twin of ``model``: ``suspension`` (the design changed) with ``preloads``
    (:class:`~elastokin.config.variants.DesignState`), built as
    :func:`~elastokin.mbs.design.build_model` builds ``model``, with its parts' references."""
    from elastokin.mbs.idle import hold_idle_spins

    twin = SuspensionModel(suspension, model.options, preloads, references=model.ref)
    if any(b.kinematic for b in suspension.bushings):
        hold_idle_spins(twin)
    return twin


def solve_path_with_twins(model: SuspensionModel, inputs: Mapping[str, np.ndarray],
                          what: str, twins: Sequence[TwinPair]) -> list[ModelState]:
    """:func:`~elastokin.mbs.solve.solve_path`; each returned state carries ``design``: one
    :class:`DesignStates` per twin pair (module docstring). Friction is refused."""
    if model.friction or model.substeps != 1:
        raise ModelError(f"{model.suspension.source}: sensitivities need a frictionless model")
    recorder = Recorder()
    model.mbs.SetPostStepUserFunction(recorder)
    try:
        states = solve_path(model, inputs, what)
    finally:
        model.mbs.SetPostStepUserFunction(0)
    if not twins:
        return states
    n = len(states)
    steps = recorder.at(np.linspace(0.0, 1.0, n + 1)[1:])
    res = Residual(model, n, what)
    try:
        A, _ = system_matrices(res, steps)
    finally:
        res.close()
    B = np.empty((n, res.n, len(twins)))
    for k, tw in enumerate(twins):
        r = {sign: twin_residuals(twin, tw.inputs[sign], steps, what)
             for sign, twin in tw.models()}
        B[:, :, k] = (r[1] - r[-1]) / (2.0 * tw.step)
    dy = solve_tangents(A, B)
    per_twin = [_twin_states(tw, steps, dy[:, :, k], what) for k, tw in enumerate(twins)]
    for i, state in enumerate(states):
        state.design = [DesignStates(plus[i], minus[i], tw.step)
                        for tw, (plus, minus) in zip(twins, per_twin)]
    return states


def _prepared(twin: SuspensionModel, inputs, n: int, what: str):
    """The twin with the inputs' paths set for ``n`` steps: (residual, applied loads)."""
    ts = np.linspace(0.0, 1.0, n + 1)
    applied = set_attachment_paths(twin, {k: np.atleast_2d(np.asarray(v, float))
                                          for k, v in inputs.items()}, ts, n)
    twin.mbs.Assemble()
    return Residual(twin, n, what), applied


def twin_residuals(twin: SuspensionModel, inputs, steps, what: str) -> np.ndarray:
    """(n_steps, N): the twin's residual at each recorded step of the model (time,
    coordinates, multipliers), its inputs' paths set."""
    res, _ = _prepared(twin, inputs, len(steps), what)
    try:
        out = np.empty((len(steps), res.n))
        for i, step in enumerate(steps):
            res.set_state(*step)
            out[i] = res.residual()
        return out
    finally:
        res.close()


def _twin_states(tw: TwinPair, steps, dy: np.ndarray, what: str
                 ) -> tuple[list[ModelState], list[ModelState]]:
    """Each twin's states at the steps moved by ``+-step * dy`` (n_steps, N)."""
    out = []
    for sign, twin in tw.models():
        res, applied = _prepared(twin, tw.inputs[sign], len(steps), what)
        n2 = res.n2
        try:
            states = []
            for i, (t, q, lam) in enumerate(steps):
                y = sign * tw.step * dy[i]
                res.set_state(t, q + y[:n2], lam + y[n2:])
                states.append(model_state(twin, current_row(twin),
                                          {k: v[i] for k, v in applied.items()}))
        finally:
            res.close()
        out.append(states)
    return out[0], out[1]
