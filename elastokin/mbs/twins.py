"""Exact sensitivities of a model's static steps to its design (hardpoints, rates, preloads,
the steering ratio: any change of the suspension), through **twin models**.

At every converged static step R(y, p) = 0 (y the parts' coordinates and the joints'
multipliers), so ``dy/dp = -(dR/dy)^-1 dR/dp`` with no re-solve (as
:mod:`elastokin.mbs.sensitivity` does for bushing laws). A change of the design moves
Exudyn's reference configuration, the markers' local positions, link lengths, spring
reference lengths, bushing frames and the rig's attachment points all at once; rather than
follow each of these, dR/dp is the residual of a **twin** (:class:`Twin`): the model with the
changed suspension's geometry and preloads, with the **same parts' reference positions**, so
that a coordinate vector means the same pose in both (a part's pose is its reference plus its
displacement, its rotation from the identity), evaluated at the model's own converged state.
A twin is the model itself with its design-dependent parameters set in place
(:mod:`elastokin.mbs.geometry`: no model is built), or, for a change the model cannot take in
place (a nonlinear bushing's law, idle-spin springs), a model built again from the changed
suspension (``SuspensionModel(references=...)``). Central differences, ``p +- step``: the
residual is smooth in the design, and the twin's residual differs from the model's only in
the terms the design changes. Only the steps a sweep keeps get derivatives.

The channels depend on the design explicitly as well (a point sensor's local position, the
wheel centre a travel is measured from, the design toe): every output of a step is
evaluated on the twins at ``y +- step * dy/dp`` (:func:`sensor_arrays`: the parts' poses,
points, supports' reactions and spring and stop forces from the coordinates as Exudyn
defines them, vectorised; the other sensors read from Exudyn in that configuration), so
that a channel computed from these two states by the rig's own code differs by exactly its
derivative times ``2 step``.

Units: mm, rad inside (coordinates); the design variables in their own units.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field

import numpy as np

from elastokin.errors import ModelError
from elastokin.mbs.contact import set_contact_function
from elastokin.mbs.exudyn_api import exu
from elastokin.mbs.geometry import item_preloads, same, set_parameter
from elastokin.mbs.model import SuspensionModel
from elastokin.mbs.sensitivity import (
    Residual,
    part_coordinates,
    recorded_solve,
    rxyz_matrix,
    solve_tangents,
    system_matrices,
)
from elastokin.mbs.solve import combined_sensors, state_arrays
from elastokin.physics.states import ModelState


class Twin:
    """A model at another design (module docstring): ``suspension`` and its preloads
    (:class:`~elastokin.config.variants.DesignState`; a balancing model's stiff springs'
    ``balancing_offsets``), evaluated on ``model`` itself with its design-dependent
    parameters set in place (:meth:`applied`), or on a model ``build`` makes when the change
    cannot be made in place. Other attributes are the evaluated model's (its attachments,
    options, ...)."""

    def __init__(self, model: SuspensionModel, suspension, preloads,
                 build: Callable[[], SuspensionModel], balancing_offsets=None):
        self.base, self.suspension = model, suspension
        self.preloads = item_preloads(suspension, model.options.stiffness_scale, preloads,
                                      model.balancing_offsets if balancing_offsets is None
                                      else balancing_offsets)
        in_place = model.geometry.shares_fixed(model.suspension, model.preloads, suspension,
                                               self.preloads)
        self.model = model if in_place else build()
        self._fixed = len(model.geometry.fixed)  # the fixed values checked so far
        self._values: list = []
        self._changed: list[int] = []  # the entries whose values differ from the model's

    def __getattr__(self, name):
        model = self.__dict__.get("model")
        if model is None:
            raise AttributeError(name)
        return getattr(model, name)

    @property
    def in_place(self) -> bool:
        return self.model is self.base

    @contextmanager
    def applied(self):
        """The evaluated model with this twin's design (in place: set on entry, the model's
        own restored on exit)."""
        if not self.in_place:
            yield self.model
            return
        model, g = self.base, self.base.geometry
        if len(g.fixed) > self._fixed:  # items added since the twin was made (the rig's)
            if not g.shares_fixed(model.suspension, model.preloads, self.suspension,
                                  self.preloads, self._fixed):
                raise ModelError(f"{self.suspension.source}: a design variable changes what "
                                 "the rig attached to the model after its twins were made "
                                 "cannot take in place (e.g. a wheel's loaded radius)")
            self._fixed = len(g.fixed)
        start = len(self._values)
        self._values += g.values(self.suspension, self.preloads, start)
        own = base_values(model)
        self._changed += [i for i in range(start, len(own))
                          if not same(own[i], self._values[i])]
        changed, kept = self._changed, model.preloads
        try:
            for i in changed:
                set_parameter(model, *g.entries[i][:3], self._values[i])
            _use_preloads(model, self.preloads)
            yield model
        finally:
            for i in changed:
                set_parameter(model, *g.entries[i][:3], own[i])
            _use_preloads(model, kept)


def base_values(model: SuspensionModel) -> list:
    """The model's own values of its design-dependent parameters (computed once per entry)."""
    g = model.geometry
    g.own += g.values(model.suspension, model.design_preloads, len(g.own))
    return g.own


def _use_preloads(model: SuspensionModel, preloads) -> None:
    model.preloads = preloads
    model.bushing_preload = preloads.bushing_preload
    model.initial_deflection = preloads.initial_deflection
    model.spring_force = preloads.spring_force


@dataclass
class TwinPair:
    """One design variable: the twins at ``p + step`` and ``p - step`` (:class:`Twin`), and
    the inputs each takes in the solve at hand (attachment name -> values per step, as
    :func:`~elastokin.mbs.solve.solve_path` takes them; the rig computes them from each
    twin's own suspension)."""

    plus: Twin
    minus: Twin
    step: float
    inputs: dict[int, Mapping[str, np.ndarray]] = field(default_factory=dict)

    def models(self) -> tuple[tuple[int, Twin], ...]:
        return (1, self.plus), (-1, self.minus)


@dataclass(frozen=True)
class DesignArrays:
    """A solve's states on the twins of one design variable, as arrays over the steps
    (:func:`~elastokin.mbs.solve.state_arrays`): by sign, ``+1`` at ``y + step dy/dp`` on
    the model at ``p + step``, ``-1`` likewise; a quantity q computed from them has
    ``dq/dp = (q(+1) - q(-1)) / (2 step)``."""

    states: dict[int, dict[str, object]]
    step: float


def check_rigid(suspension) -> None:
    """Design sensitivities take the parts' coordinates as rigid bodies' (6 each): refuse a
    model with flexible beam parts, naming them."""
    flexible = [b.part for b in getattr(suspension, "beams", ()) if not b.rigid]
    if flexible:
        raise ModelError(f"{suspension.source}: design sensitivities (optimize, sensitivity) "
                         f"need rigid parts; the flexible beam part(s) {', '.join(flexible)} "
                         "are not supported yet (without its 'beam' section a part is rigid)")


def twin_model(model: SuspensionModel, suspension, preloads) -> Twin:
    """A twin of ``model``: ``suspension`` (the design changed) with ``preloads``
    (:class:`~elastokin.config.variants.DesignState`): in place, or built as
    :func:`~elastokin.mbs.design.build_model` builds ``model``, with its parts' references."""
    from elastokin.mbs.idle import hold_idle_spins

    def build() -> SuspensionModel:
        twin = SuspensionModel(suspension, model.options, preloads, references=model.ref)
        if any(b.kinematic for b in suspension.bushings):
            hold_idle_spins(twin)
        return twin

    return Twin(model, suspension, preloads, build)


def solve_path_with_twins(model: SuspensionModel, inputs: Mapping[str, np.ndarray],
                          what: str, twins: Sequence[TwinPair], bushings: bool = True,
                          keep: np.ndarray | None = None
                          ) -> tuple[list[ModelState], list[DesignArrays]]:
    """:func:`~elastokin.mbs.solve.solve_path`, and per twin pair the states on its twins
    (:class:`DesignArrays`, module docstring) at the steps ``keep`` selects (a mask; default
    every step); ``bushings``: with the bushings' deflections and loads in the twins' states
    (else left out: they cost a call into Exudyn per bushing, state and variable). Friction
    is refused."""
    states, steps = recorded_solve(model, inputs, what)
    if not twins:
        return states, []
    rows = np.arange(len(steps)) if keep is None else np.flatnonzero(keep)
    steps = [steps[i] for i in rows]
    n = len(steps)
    res = Residual(model, n, what)
    own: dict[int, Residual] = {}  # the residuals of twins built as models of their own

    def residual_of(twin) -> Residual:
        if twin.in_place:
            return res
        key = id(twin.model)
        if key not in own:
            own[key] = Residual(twin.model, n, what)
        return own[key]

    own_inputs = {k: _rows(v, rows) for k, v in inputs.items()}

    def own_fed(tw, sign, twin) -> bool:
        values = tw.inputs[sign]
        return twin.in_place and values.keys() == own_inputs.keys() and all(
            np.array_equal(_rows(v, rows), own_inputs[k]) for k, v in values.items())

    def fed(tw, sign, twin) -> StepInputs | OwnInputs:
        if own_fed(tw, sign, twin):
            return OwnInputs(model, own_inputs, n)
        return StepInputs(twin.model, {k: _rows(v, rows) for k, v in tw.inputs[sign].items()},
                          n)

    try:
        A, _ = system_matrices(res, steps)
        B = np.empty((n, res.n, len(twins)))
        r: dict = {}
        # twins fed the model's own inputs first: the paths its solve set (at C++ speed, no
        # Python user function per residual) are still there
        order = sorted(((k, sign, twin) for k, tw in enumerate(twins)
                        for sign, twin in tw.models()),
                       key=lambda kst: not own_fed(twins[kst[0]], kst[1], kst[2]))
        for k, sign, twin in order:
            with twin.applied():
                feed = fed(twins[k], sign, twin)  # assembled before a residual is made
                r[k, sign] = _residuals(residual_of(twin), feed, steps)
        for k, tw in enumerate(twins):
            B[:, :, k] = (r[k, 1] - r[k, -1]) / (2.0 * tw.step)
        dy = solve_tangents(A, B)
        design = []
        for k, tw in enumerate(twins):
            out = {}
            for sign, twin in tw.models():
                with twin.applied():
                    feed = fed(tw, sign, twin)
                    out[sign] = _twin_state(twin, residual_of(twin), feed, steps,
                                            sign * tw.step * dy[:, :, k], bushings)
            design.append(DesignArrays(out, tw.step))
    finally:
        for r in (res, *own.values()):
            r.close()
    return states, design


def _rows(values, rows: np.ndarray) -> np.ndarray:
    """An attachment's values (steps, k) at ``rows``."""
    v = np.asarray(values, float)
    return v.reshape(len(v), -1)[rows]


class OwnInputs:
    """A twin fed the model's own inputs: the paths the model's solve set stay (no Python
    user function per residual); :class:`StepInputs`' interface."""

    def __init__(self, model: SuspensionModel, values: Mapping[str, np.ndarray], n: int):
        self.applied = {name: values.get(name, np.zeros((n, 3))) for name in model.loads}

    def at(self, i: int) -> None:
        return None


class StepInputs:
    """A twin's attachments fed step by step (Python user functions returning the values of
    the step at hand: a residual at a recorded step needs no path, and a twin built for a
    few residuals should not compile symbolic ones): loads at their inputs (zero without),
    supports given inputs or locks active at them, the others inactive, as
    :func:`~elastokin.mbs.solve.set_attachment_paths` sets them for a solve."""

    def __init__(self, model: SuspensionModel, inputs: Mapping[str, np.ndarray], n: int):
        self.model = model
        mbs = model.mbs
        self.values = {}
        for name, e in model.loads.items():
            v = np.asarray(inputs.get(name, np.zeros((n, 3))), float).reshape(n, -1)
            self.values[name] = v
            if e.get("kind") == "contact":  # a force at the wheel's lowest point (mbs.contact)
                if np.any(v):
                    set_contact_function(model, name,
                                         lambda mbs, t, _, name=name: self.current[name])
                else:
                    mbs.SetObjectParameter(e["object"], "activeConnector", False)
                continue
            mbs.SetLoadParameter(e["load"], "loadVectorUserFunction",
                                 lambda mbs, t, vector, name=name: self.current[name])
        for name, e in model.supports.items():
            active = name in inputs or name in model.locks
            if active:
                v = inputs[name] if name in inputs else np.tile(model.locks[name], (n, 1))
                self.values[name] = np.asarray(v, float).reshape(n, 6)
                mbs.SetObjectParameter(e["object"], "offsetUserFunction",
                                       lambda mbs, t, item, par, name=name: self.current[name])
            mbs.SetObjectParameter(e["object"], "activeConnector", active)
        self.current = {k: v[0].tolist() for k, v in self.values.items()}
        mbs.Assemble()

    def at(self, i: int) -> None:
        self.current = {k: v[i].tolist() for k, v in self.values.items()}

    @property
    def applied(self) -> dict[str, np.ndarray]:
        return {k: self.values[k] for k in self.model.loads}


def twin_residuals(twin: SuspensionModel, inputs, steps, what: str) -> np.ndarray:
    """(n_steps, N): the twin's residual at each recorded step of the model (time,
    coordinates, multipliers), its inputs set (attachment name -> values per step)."""
    feed = StepInputs(twin, inputs, len(steps))
    res = Residual(twin, len(steps), what)
    try:
        return _residuals(res, feed, steps)
    finally:
        res.close()


def _residuals(res: Residual, feed: StepInputs, steps) -> np.ndarray:
    out = np.empty((len(steps), res.n))
    for i, step in enumerate(steps):
        feed.at(i)
        res.set_state(*step)
        out[i] = res.residual()
    return out


def _twin_state(twin: Twin, res: Residual, feed: StepInputs, steps, dy: np.ndarray,
                bushings: bool) -> dict[str, object]:
    """The twin's states (:func:`~elastokin.mbs.solve.state_arrays`; its design applied) at
    the steps moved by ``dy`` (n_steps, N)."""
    n2 = res.n2
    q = np.array([q for _, q, _ in steps]) + dy[:, :n2]
    lam = np.array([lam for _, _, lam in steps]) + dy[:, n2:]
    times = [t for t, _, _ in steps]
    model = twin.model
    return state_arrays(model, sensor_arrays(model, res, times, q, lam, bushings, feed),
                        feed.applied)


def sensor_arrays(model: SuspensionModel, res: Residual, times, q: np.ndarray,
                  lam: np.ndarray, bushings: bool = True, feed: StepInputs | None = None
                  ) -> dict[str, np.ndarray]:
    """The model's sensor values (steps, k) (as :func:`~elastokin.mbs.solve.recorded` reads
    them, bushings combined) at the states ``q`` (n, n2), ``lam`` (n, n_ae): the parts'
    poses, the point sensors, the supports' reactions, the springs' and stops' forces computed
    here, vectorised (the
    definitions of Exudyn's outputs: pose from the Tait-Bryan angles, a support's force its
    multipliers, a spring's force ``k (L - L0)``); the other sensors (bushings, the
    anti-roll bar) read from Exudyn in each state (the bushings only with ``bushings``)."""
    mbs = model.mbs
    coords = part_coordinates(model)
    rot = {p: rxyz_matrix(q[:, i[3:]]) for p, i in coords.items()}
    disp = {p: q[:, i[:3]] for p, i in coords.items()}
    part_of = {int(b): p for p, b in {**model.body, **model.rig_bodies}.items()}

    def marker_position(marker: int) -> np.ndarray:
        m = mbs.GetMarker(marker)
        local = np.asarray(m["localPosition"], float)
        part = part_of.get(int(m["bodyNumber"]))
        if part is None:  # the ground
            return np.tile(local, (q.shape[0], 1))
        return model.ref[part] + disp[part] + rot[part] @ local

    data: dict[str, np.ndarray] = {}
    # the parts' poses, and the rig bodies' where they are recorded (the load recorder's)
    for name in [*model.pose_refs, *(b for b in model.rig_bodies if b not in model.pose_refs
                                     and f"part:{b}:R" in model.sensors)]:
        data[f"part:{name}:R"] = rot[name].reshape(-1, 9)
        data[f"part:{name}:disp"] = disp[name]
    for name, (part, local) in model.point_sensors.items():
        data[f"point:{name}"] = model.ref[part] + disp[part] + rot[part] @ local
    for name, e in model.supports.items():
        data[f"support:{name}"] = lam[:, np.asarray(mbs.systemData.GetObjectLTGAE(
            e["object"]), int)[:3]]
    for key, number, law in _line_forces(model):
        obj = mbs.GetObject(number)
        m0, m1 = obj["markerNumbers"]
        length = np.linalg.norm(marker_position(m1) - marker_position(m0), axis=1)
        if law is None:  # a spring's or damper's length (Exudyn's Distance)
            data[key] = length[:, None]
        else:
            data[key] = law(length, obj)[:, None]
    rest = [k for k in model.sensors if k not in data and not k.startswith("load:")
            and (bushings or not k.startswith("bushing:"))]
    if rest:
        current = exu.ConfigurationType.Current
        values = {k: [] for k in rest}
        for i, (t, qi, li) in enumerate(zip(times, q, lam)):
            if feed is not None:
                feed.at(i)
            res.set_state(t, qi, li)
            for k in rest:
                values[k].append(np.atleast_1d(mbs.GetSensorValues(model.sensors[k], current)))
        data.update({k: np.array(v, float) for k, v in values.items()})
    return combined_sensors(data, model)


def _line_forces(model: SuspensionModel):
    """(sensor key, object, force law of its length) of every coil spring and stop: Exudyn's
    ``ForceLocal`` of a spring-damper, ``k (L - L0)``, and a stop's user function
    (:func:`~elastokin.mbs.axle_elements.stop_function`); and of the springs' and dampers'
    length sensors (law None: the length itself)."""
    out = [(f"{kind}_length:{name}", number, None)
           for kind, items in (("spring", model.springs), ("damper", model.dampers))
           for name, number in items.items() if f"{kind}_length:{name}" in model.sensors]
    for name, number in model.springs.items():
        out.append((f"spring:{name}", number,
                    lambda L, obj: obj["stiffness"] * (L - obj["referenceLength"])))
    for stop in model.suspension.stops:
        number = model.stops[stop.name]
        sign = -1.0 if stop.kind == "bump" else 1.0
        out.append((f"stop:{stop.name}", number,
                    lambda L, obj, law=stop.law, sign=sign: sign * law(
                        np.maximum(sign * (L - obj["referenceLength"]), 0.0))))
    return out
