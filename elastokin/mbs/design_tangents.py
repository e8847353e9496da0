"""Exact derivatives of the design preloads (:func:`~elastokin.mbs.design.design_state`) with
respect to design variables: the spring force and the bushing loads that make the design
hardpoints the equilibrium under the design wheel load move with the hardpoints, and a model
of a changed design carries its own (a full re-run balances again).

The balancing is a static solve with the balanced springs' forces P as unknowns beside the
coordinates and multipliers y, and the contact patches' vertical loads as equations:
``R(y, P; p) = 0``, ``pad(y) = W``. At its solution, per design variable p_k,

    [dR/dy  dR/dP] [dy/dp_k]     [dR/dp_k  ]
    [dpad/dy  0  ] [dP/dp_k] = - [dpad/dp_k]

with dR/dy from Exudyn's residual (:func:`~elastokin.mbs.sensitivity.system_matrices`), dR/dP
from the springs' reference lengths (the residual is linear in P), dpad/dy by central
differences of the pads' reaction, and dR/dp_k, dpad/dp_k from twin balancing models at
``p +- step`` (:mod:`elastokin.mbs.twins`). The bushing preloads are the balancing model's
bushing loads, read on the twins at ``y +- step dy/dp``. With the stiff rotational springs
relaxed in a further pass (their offsets from the pass before's torques; twice), each
pass's derivatives move the next one's offsets. Springs and bushings that are not balanced keep the
loads their config gives, whose derivatives are explicit.

Units: N (springs), N and N*mm (bushing loads, bushing frame), per unit of each variable.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from elastokin.config.suspension import Suspension
from elastokin.config.variants import DesignState, compliant
from elastokin.mbs.bushings import BALANCING_ROTATION
from elastokin.mbs.design import (
    BalancingSolve,
    balanced_springs,
    design_state,
    hold_contact_patches,
)
from elastokin.mbs.exudyn_api import exu
from elastokin.mbs.idle import hold_idle_spins
from elastokin.mbs.model import ModelOptions, SuspensionModel
from elastokin.mbs.sensitivity import Residual, solve_tangents, system_matrices
from elastokin.mbs.twins import Twin, check_rigid, twin_residuals
from elastokin.physics.joints import CONSTRAINED

WHAT = "design preload sensitivities"


def config_preloads(suspension: Suspension) -> DesignState:
    """The preloads a config gives by itself: each spring's design force (its preload or
    free length), each bushing's load at its initial deflection."""
    s = compliant(suspension)
    return DesignState(
        {sp.name: sp.design_force_N() for sp in s.springs},
        {b.name: np.array([law(u) for law, u in zip(b.laws, b.initial_deflection)])
         for b in s.bushings})


def design_state_tangents(suspension: Suspension,
                          variations: Sequence[tuple[Suspension, Suspension, float]]
                          ) -> tuple[DesignState, list[DesignState]]:
    """The design preloads of ``suspension`` and, per design variable (the suspension at
    ``p + step``, at ``p - step``, and ``step``), their derivatives (a
    :class:`~elastokin.config.variants.DesignState` of derivatives; module docstring)."""
    check_rigid(suspension)
    record: list[BalancingSolve] = []
    state = design_state(suspension, record)
    s = compliant(suspension)
    explicit = [_difference(config_preloads(a), config_preloads(b), h)
                for a, b, h in variations]
    if not record:
        return state, explicit
    final = {r.pass_index: r for r in record}  # the last solve of each pass
    ideal = s.design.balance_bushing_preloads
    balanced = balanced_springs(s)
    offsets = [{b.name: np.zeros(3) for b in s.bushings} for _ in variations]
    out = explicit
    twins: dict = {}  # the balancing twins, built once, their offsets moved for each pass
    for index in sorted(final):
        rec = final[index]
        d_force, d_loads = _pass_tangents(rec, variations, explicit, offsets, ideal, balanced,
                                          twins)
        out = []
        for k, (expl, dP) in enumerate(zip(explicit, d_force)):
            springs = dict(expl.spring_force_N)
            springs.update(zip(balanced, (float(v) for v in dP)))
            preload = d_loads[k] if ideal else expl.bushing_preload
            out.append(DesignState(springs, preload))
            if ideal:
                offsets[k] = {b.name: np.where(np.array(CONSTRAINED[b.ideal_joint][3:], bool),
                                               -d_loads[k][b.name][3:] / BALANCING_ROTATION,
                                               0.0) for b in s.bushings}
    return state, out


def _difference(a: DesignState, b: DesignState, h: float) -> DesignState:
    return DesignState({k: (a.spring_force_N[k] - b.spring_force_N[k]) / (2 * h)
                        for k in a.spring_force_N},
                       {k: (a.bushing_preload[k] - b.bushing_preload[k]) / (2 * h)
                        for k in a.bushing_preload})


def _pads(model: SuspensionModel, supports: dict[str, str]) -> np.ndarray:
    """The contact patches' vertical support forces (N) in the current configuration."""
    current = exu.ConfigurationType.Current
    return np.array([np.asarray(model.mbs.GetSensorValues(model.sensors[f"support:{name}"],
                                                          current))[2]
                     for name in supports.values()])


def _pass_tangents(rec: BalancingSolve, variations, explicit, offsets, ideal, balanced,
                   cache: dict):
    """(dP per variable (m,), bushing-load derivatives per variable) of one balancing pass."""
    model = rec.model
    step = (1.0, rec.coordinates, rec.multipliers)
    res = Residual(model, 1, WHAT)
    try:
        A, r0 = system_matrices(res, [step])
        n, n2 = res.n, res.n2
        m = len(balanced)
        M = np.zeros((n + m, n + m))
        M[:n, :n] = A[0]
        for i, name in enumerate(balanced):  # the residual is linear in each force
            obj = model.springs[name]
            length = model.mbs.GetObjectParameter(obj, "referenceLength")
            rate = model.mbs.GetObjectParameter(obj, "stiffness")
            model.mbs.SetObjectParameter(obj, "referenceLength", length + 1.0 / rate)
            res.set_state(*step)
            M[:n, n + i] = res.residual() - r0[0]
            model.mbs.SetObjectParameter(obj, "referenceLength", length)
        y0 = np.r_[rec.coordinates, rec.multipliers]
        # a pad's reaction is its support's multipliers (Exudyn's ForceLocal of a generic
        # joint, in the fixed frame of its ground marker): only those columns
        sd = model.mbs.systemData
        for j in sorted(n2 + int(i) for sup in rec.supports.values()
                        for i in sd.GetObjectLTGAE(model.supports[sup]["object"])):
            dj = 1e-6 * max(1.0, abs(y0[j]))
            pads = []
            for sign in (1.0, -1.0):
                y = y0.copy()
                y[j] += sign * dj
                res.set_state(1.0, y[:n2], y[n2:])
                pads.append(_pads(model, rec.supports))
            M[n:, j] = (pads[0] - pads[1]) / (2 * dj)
        res.set_state(*step)
    finally:
        res.close()
    zero = {sup: np.zeros((1, 6)) for sup in rec.supports.values()}
    twins = []
    rhs = np.zeros((n + m, len(variations)))
    for k, (plus, minus, h) in enumerate(variations):
        twins.append({})
        r, pads = {}, {}
        for sign, sus in ((1, plus), (-1, minus)):
            shifted = {b: v + sign * h * offsets[k].get(b, 0.0) for b, v in rec.offsets.items()}
            twin = twins[k][sign] = _balancing_twin(rec, sus, shifted, ideal, cache, (k, sign))
            with twin.applied() as evaluated:
                r[sign] = twin_residuals(evaluated, zero, [step], WHAT)[0]
                pads[sign] = _pads(evaluated, rec.supports)
        rhs[:n, k] = (r[1] - r[-1]) / (2 * h)
        rhs[n:, k] = (pads[1] - pads[-1]) / (2 * h)
    dz = solve_tangents(M[None], rhs[None])[0]  # one factorisation for every variable
    d_force, d_loads = [], []
    for k, (_, _, h) in enumerate(variations):
        d_force.append(dz[n:, k])
        if ideal:
            loads = {}
            for sign, twin in twins[k].items():
                with twin.applied() as evaluated:
                    twin_state(evaluated, y0 + sign * h * dz[:n, k], n2)
                    loads[sign] = evaluated.balancing_bushing_loads()
            d_loads.append({b: (loads[1][b] - loads[-1][b]) / (2 * h) for b in loads[1]})
    return d_force, d_loads


def twin_state(model: SuspensionModel, y: np.ndarray, n2: int) -> None:
    """Put ``model`` in the configuration of coordinates and multipliers ``y`` (time 1)."""
    sd, current = model.mbs.systemData, exu.ConfigurationType.Current
    sd.SetODE2Coordinates(y[:n2], current)
    sd.SetAECoordinates(y[n2:], current)
    sd.SetTime(1.0, current)


def set_balancing_offsets(model: SuspensionModel, offsets: dict) -> None:
    """Move a balancing model's stiff rotational springs' offsets (rad) in place."""
    for name, v in offsets.items():
        e = model.bushings[name]
        model.mbs.SetObjectParameter(e["object"], "offset", [0.0, 0.0, 0.0, *map(float, v)])
        model.preloads.balancing_offsets[name] = np.asarray(v, float)


def _balancing_twin(rec: BalancingSolve, suspension: Suspension, offsets: dict,
                    ideal: bool, cache: dict, key) -> Twin:
    """The balancing model of ``rec`` for ``suspension`` (the design moved along one
    variable): the balanced springs at the same forces, the others and the bushings at the
    config's own, the stiff springs at ``offsets``; in place on ``rec``'s model, or a model
    built for it once (``cache``: by ``key``; its offsets moved for a later pass)."""
    s = compliant(suspension)
    own = config_preloads(s)
    forces = dict(own.spring_force_N)
    forces.update(zip(balanced_springs(s), (float(v) for v in rec.spring_force_N)))
    preloads = DesignState(forces, own.bushing_preload)

    def build() -> SuspensionModel:
        if key in cache:
            set_balancing_offsets(cache[key], offsets)
            return cache[key]
        twin = cache[key] = SuspensionModel(s, ModelOptions(), preloads, balancing=ideal,
                                            balancing_offsets=offsets,
                                            references=rec.model.ref)
        if rec.idle:
            hold_idle_spins(twin)
        hold_contact_patches(twin)
        return twin

    return Twin(rec.model, s, preloads, build, balancing_offsets=offsets)
