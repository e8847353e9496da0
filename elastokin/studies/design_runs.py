"""One model run at a design point, with the exact derivatives of every channel and
characteristic with respect to the design variables (the optimiser's and the sensitivity
table's unit of work).

A design point is a template suspension with design variables at values
(:func:`~elastokin.config.design_variables.design_suspension`). Its run: the design preloads
and their derivatives (:func:`~elastokin.mbs.design_tangents.design_state_tangents`), each
model (``initial``: the bushings; ``initial_kinematic``: ideal joints) built with them, a twin
pair per variable (:mod:`elastokin.mbs.twins`), the load cases with the tangents of every
column (``Sweep.tangents``) and the compliance matrix with its derivatives; the summary
figures of :class:`~elastokin.studies.kc_job.ModelResult` and their derivatives, by central
differences of the summary along each column's tangent (the summary is a function of the
columns, the compliance matrix and the suspension).

Units: the variables' own (mm, -, N/mm, N, mm/rev); every derivative per unit of its
variable.
"""

from __future__ import annotations

import functools
from collections.abc import Sequence
from dataclasses import dataclass, field, replace

import numpy as np

from elastokin.config.design_variables import DesignVariable, design_suspension
from elastokin.config.schema.rig import RigSpec
from elastokin.config.suspension import Suspension
from elastokin.config.variants import DesignState, ModelVariant, kinematic
from elastokin.mbs.design import build_model, design_state
from elastokin.mbs.design_tangents import design_state_tangents
from elastokin.mbs.twins import TwinPair, check_rigid, twin_model
from elastokin.rig.load_cases import run_load_cases_sides, wheel_compliance
from elastokin.rig.sweeps import Sweep
from elastokin.studies.kc_job import ModelResult

#: central-difference step of a hardpoint or the rack's position for the twins (mm): small
#: against any design change (1e-4 of a suspension's lengths: the central differences' error is
#: 1e-8), large against rounding (the compliance matrix differences states twice)
POINT_STEP_MM = 1e-2
#: the step of the other variables, relative to their value: the residual is linear in a
#: rate, a preload, a scale or a ratio, and a step this size keeps the twins' states clear of
#: the rounding of the rig's post-processing (the steering axis, from null spaces)
RELATIVE_STEP = 1e-3
MODELS = ("initial", "initial_kinematic")


@dataclass
class DesignRun:
    """The models at one design point: ``values`` of the variables, the ``suspension`` they
    make, every model's results (sweeps with ``tangents`` when run with derivatives) and
    summary figures flattened (``"bump_steer_deg_per_m"``, ``"right.camber_deg"``,
    ``"axle.roll_centre_height_mm"``), with their derivatives ``(variables,)`` by the same
    keys."""

    values: np.ndarray
    suspension: Suspension
    design: DesignState
    models: dict[str, ModelResult]
    #: per variable (the suspension at p + step, at p - step, step): with derivatives
    variations: list = field(default_factory=list)
    summary: dict[str, dict[str, float]] = field(default_factory=dict)
    summary_tangents: dict[str, dict[str, np.ndarray]] = field(default_factory=dict)

    def sweep(self, label: str, load_case: str, side: str | None = None) -> Sweep | None:
        r = self.models[label]
        sweeps = r.sweeps if side in (None, self.suspension.side) else r.other_sides[side]
        return next((sw for sw in sweeps if sw.load_case == load_case), None)


def variable_step(v: DesignVariable, value: float) -> float:
    """The twins' step of ``v`` at ``value`` (its unit)."""
    if v.unit == "mm":
        return POINT_STEP_MM
    return RELATIVE_STEP * max(abs(float(value)), 1.0)


def flat_summary(summary: dict, prefix: str = "") -> dict[str, float]:
    """The numeric figures of a summary (nested dicts) by dotted key (the compliance
    matrices left out); a figure not determined (null) is NaN."""
    out: dict[str, float] = {}
    for k, v in summary.items():
        key = f"{prefix}{k}"
        if isinstance(v, dict) and "values" not in v:
            out.update(flat_summary(v, key + "."))
        elif v is None:
            out[key] = float("nan")
        elif isinstance(v, (int, float)) and not isinstance(v, bool):
            out[key] = float(v)
    return out


def run_design(template: Suspension, variables: Sequence[DesignVariable], values,
               labels: Sequence[str] = ("initial",), rig: RigSpec | None = None,
               derivatives: bool = True, detail: str = "summary", compliance: bool = True
               ) -> DesignRun:
    """The models ``labels`` (of :data:`MODELS`) at ``values`` of ``variables`` on ``rig``'s
    load cases (default: the template's), with the derivatives of every column and summary
    figure when ``derivatives`` (``detail``: which columns' tangents,
    :func:`~elastokin.rig.load_cases.run_drive_sides`; ``compliance``: with the compliant
    models' compliance matrix and the figures from it, anti-dive among them). Dense linear
    algebra on one thread: the systems here are small (~100 unknowns), and OpenBLAS's
    threads on a busy machine turned a 0.2 ms solve into 0.2 s (measured)."""
    with one_blas_thread():
        return _run_design(template, variables, values, labels, rig, derivatives, detail,
                           compliance)


def one_blas_thread():
    """A context in which BLAS and LAPACK run on one thread (threadpoolctl)."""
    return _threads().limit(limits=1, user_api="blas")


@functools.lru_cache(maxsize=1)
def _threads():
    from threadpoolctl import ThreadpoolController

    return ThreadpoolController()


def _run_design(template, variables, values, labels, rig, derivatives, detail, compliance
                ) -> DesignRun:
    values = np.asarray(values, float)
    with_compliance = compliance
    s = design_suspension(template, variables, values)
    if derivatives:
        check_rigid(s)
    moved = []
    if derivatives:
        for k, v in enumerate(variables):
            h = variable_step(v, values[k])
            e = h * np.eye(values.size)[k]
            moved.append((design_suspension(template, variables, values + e),
                           design_suspension(template, variables, values - e), h))
        design, d_design = design_state_tangents(s, moved)
    else:
        design, d_design = design_state(s), []
    run = DesignRun(values, s, design, {}, moved)
    for label in labels:
        kin = label.endswith("_kinematic")
        view = kinematic(s) if kin else s
        model = build_model(ModelVariant(label, view, design))
        pairs = [TwinPair(*(twin_model(model, kinematic(m) if kin else m,
                                       shifted(design, dd, sign * h))
                            for m, sign in ((plus, 1), (minus, -1))), h)
                 for (plus, minus, h), dd in zip(moved, d_design)]
        by_side = run_load_cases_sides(model, label, rig, twins=pairs, detail=detail)
        compliance, d_compliance = None, None
        if not kin and with_compliance:
            compliance = wheel_compliance(model, twins=pairs or None)
            if pairs:
                compliance, d_compliance = compliance
        result = ModelResult(label, kin, by_side.pop(s.side), model.solver_settings(),
                             compliance, by_side, view)
        run.models[label] = result
        run.summary[label] = flat_summary(result.summary())
        if pairs:
            run.summary_tangents[label] = summary_tangents(result, pairs, d_compliance)
    return run


def shifted(design: DesignState, tangent: DesignState, shift: float) -> DesignState:
    """``design + shift * tangent``."""
    return DesignState(
        {k: v + shift * tangent.spring_force_N[k] for k, v in design.spring_force_N.items()},
        {k: np.asarray(v, float) + shift * tangent.bushing_preload[k]
         for k, v in design.bushing_preload.items()})


def summary_tangents(result: ModelResult, pairs: Sequence[TwinPair],
                     d_compliance: np.ndarray | None) -> dict[str, np.ndarray]:
    """Derivatives of every summary figure of ``result`` (its sweeps carrying tangents): the
    summary of the columns moved along each variable's tangent, on that variable's twin
    suspensions, by central differences."""
    base = flat_summary(result.summary())
    out = {k: np.zeros(len(pairs)) for k in base}
    for k, pair in enumerate(pairs):
        figures = []
        for sign, twin in pair.models():
            h = sign * pair.step
            moved = replace(
                result, sweeps=[_moved(sw, k, h) for sw in result.sweeps],
                other_sides={side: [_moved(sw, k, h) for sw in sweeps]
                             for side, sweeps in result.other_sides.items()},
                compliance=None if d_compliance is None else
                result.compliance + h * d_compliance[:, :, k],
                suspension=twin.suspension)
            figures.append(flat_summary(moved.summary()))
        for key in out:
            a, b = figures[0].get(key), figures[1].get(key)
            out[key][k] = np.nan if a is None or b is None else (a - b) / (2 * pair.step)
    return out


def _moved(sweep: Sweep, k: int, h: float) -> Sweep:
    cols = {name: (np.asarray(v, float) + h * sweep.tangents[name][:, k]
                   if name in sweep.tangents else v) for name, v in sweep.columns.items()}
    return Sweep(sweep.model, sweep.load_case, cols, {}, sweep.side)
