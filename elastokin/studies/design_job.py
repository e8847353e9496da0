"""Design to targets as named steps (``elastokin optimize``): ``targets`` (the file read and
checked against the config) -> ``start`` (the config's own design, with derivatives) ->
``optimise`` (scipy's SLSQP on the exact gradients, :mod:`elastokin.studies.design_runs`)
-> ``verify`` (a plain run of the written values); entry point :func:`run_optimize`.

The variables are scaled to their bounds (u = (x - x0) / half-width) for the optimiser. When
the targets cannot all be met, the study stops with its best point (the least constraint
violation, then the least objective) and names what binds: the targets missed, the
variables at their bounds and the constraints with the largest multipliers. Units: the
variables' own (mm, -, N/mm, N, mm/rev).
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from elastokin.config.design_variables import DesignVariable
from elastokin.config.suspension import Suspension
from elastokin.errors import ElastokinError, SolverError
from elastokin.formats.targets import Targets, load_targets
from elastokin.studies.design_runs import DesignRun, run_design
from elastokin.studies.design_targets import (
    TargetValues,
    needs_compliance,
    target_rig,
    target_values,
)

Progress = Callable[[str], None]
#: a scaled variable within this of a bound counts as at the bound
AT_BOUND = 1e-6
#: constraint violation (in tolerances) below which a target counts as met by the optimiser
FEASIBLE = 1e-6


def _quiet(msg: str) -> None:
    return None


@dataclass
class Iteration:
    """One model run of the optimiser: the variables' values, the objective and the largest
    constraint violation (in tolerances)."""

    run: int
    values: list[float]
    objective: float
    violation: float


@dataclass
class DesignResult:
    """The outcome: the variables, the start and the best design with their target values,
    every model run's figures, whether every target is met, the optimiser's message, what
    binds (when not met), model runs and time."""

    targets: Targets
    variables: list[DesignVariable]
    start: DesignRun
    start_values: TargetValues
    best: DesignRun
    best_values: TargetValues
    history: list[Iteration] = field(default_factory=list)
    met: bool = False
    message: str = ""
    binding: list[str] = field(default_factory=list)
    model_runs: int = 0
    seconds: float = 0.0
    label: str = "initial"


class _Evaluator:
    """Design runs at scaled points u, with derivatives, kept by point (SLSQP asks for the
    objective, the constraints and their gradients separately)."""

    def __init__(self, template, targets, x0, half, progress):
        self.template, self.targets = template, targets
        self.x0, self.half, self.progress = x0, half, progress
        self.kept: dict[bytes, tuple[DesignRun, TargetValues]] = {}
        self.history: list[Iteration] = []
        self.best: tuple[tuple[float, float], np.ndarray] | None = None

    def x(self, u: np.ndarray) -> np.ndarray:
        return self.x0 + self.half * np.asarray(u, float)

    def __call__(self, u: np.ndarray) -> tuple[DesignRun, TargetValues]:
        key = np.asarray(u, float).tobytes()
        if key not in self.kept:
            x = self.x(u)
            self.progress(f"design run {len(self.history) + 1}: "
                          + ", ".join(f"{v.name}={xi:.4f}" for v, xi in
                                      zip(self.targets.variables, x)))
            run, values = evaluate_targets(self.template, self.targets, x)
            self.kept[key] = (run, values)
            self.history.append(Iteration(len(self.history) + 1, x.tolist(),
                                          values.objective, values.violation))
            merit = (values.violation if values.violation > FEASIBLE else 0.0,
                     values.objective)
            if self.best is None or merit < self.best[0]:
                self.best = (merit, np.asarray(u, float).copy())
        return self.kept[key]

    # copies: the optimiser may write into the arrays it is given; the objective in units
    # of its value at the start (SLSQP's tolerances are relative to O(1) values)
    def objective(self, u):
        return float(self(u)[1].objective) / self.scale

    def gradient(self, u):
        return np.array(self(u)[1].gradient * self.half) / self.scale

    @property
    def scale(self) -> float:
        first = self.kept[np.zeros(self.x0.size).tobytes()][1].objective
        return first if first > 0 else 1.0

    def constraints(self, u):
        return np.array(self(u)[1].constraints)

    def constraint_jacobian(self, u):
        return np.array(self(u)[1].jacobian * self.half[None, :])


def evaluate_targets(suspension: Suspension, targets: Targets, values=None,
                     derivatives: bool = True) -> tuple[DesignRun, TargetValues]:
    """One design point of a study: the targets' model (``targets.spec.model``) with the
    targets' variables at ``values`` (their units: mm, -, N/mm, N, mm/rev; None: the
    config's own design) on the load cases the targets need. Returns the run and every
    target at it: the objective, the constraints (``g >= 0``), a verdict per target and,
    with ``derivatives``, their exact gradients per unit of each variable."""
    x = start(suspension, targets)[0] if values is None else np.asarray(values, float)
    label = targets.spec.model
    run = run_design(suspension, targets.variables, x, (label,),
                     target_rig(suspension, targets), derivatives=derivatives,
                     compliance=needs_compliance(targets))
    return run, target_values(run, targets, label, derivatives)


# ------------------------------------------------------------------------------- the steps
def targets_step(suspension: Suspension, path: str | Path) -> Targets:
    """Step ``targets``: the targets file read and checked against the config."""
    return load_targets(path, suspension)


def start(suspension: Suspension, targets: Targets) -> tuple[np.ndarray, np.ndarray]:
    """Step ``start``: the variables' values in the config and their scales (half the
    width of their bounds, or 10 of their unit when a bound is open)."""
    x0 = np.array([v.value(suspension.raw) for v in targets.variables])
    half = np.array([(v.upper - v.lower) / 2 if np.isfinite(v.upper - v.lower) else 10.0
                     for v in targets.variables])
    return x0, half


def optimise(suspension: Suspension, targets: Targets, progress: Progress = _quiet
             ) -> DesignResult:
    """Step ``optimise``: SLSQP from the config's design (module docstring)."""
    from scipy.optimize import minimize

    t0 = time.perf_counter()
    label = targets.spec.model
    x0, half = start(suspension, targets)
    ev = _Evaluator(suspension, targets, x0, half, progress)
    first_run, first = ev(np.zeros(x0.size))
    bounds = [((v.lower - x) / h, (v.upper - x) / h)
              for v, x, h in zip(targets.variables, x0, half)]
    constraints = [] if not first.labels else [{
        "type": "ineq", "fun": ev.constraints, "jac": ev.constraint_jacobian}]
    opts = targets.spec.optimizer
    message, multipliers = "", np.zeros(len(first.labels))
    try:
        res = minimize(ev.objective, np.zeros(x0.size), jac=ev.gradient, method="SLSQP",
                       bounds=bounds, constraints=constraints,
                       options={"maxiter": opts.max_iterations, "ftol": opts.tolerance})
        message = str(res.message)
        if getattr(res, "multipliers", None) is not None and len(res.multipliers):
            multipliers = np.asarray(res.multipliers, float)
    except (SolverError, ElastokinError) as exc:
        message = f"stopped: the model does not solve at a trial point ({exc})"
    u_best = ev.best[1]
    best_run, best = ev(u_best)
    result = DesignResult(targets, targets.variables, first_run, first, best_run, best,
                          ev.history, best.met and best.violation <= FEASIBLE, message,
                          label=label)
    if not result.met:
        result.binding = binding(targets.variables, u_best, bounds, best, multipliers)
    result.model_runs = len(ev.history)
    result.seconds = time.perf_counter() - t0
    return result


def binding(variables, u, bounds, values: TargetValues, multipliers) -> list[str]:
    """What keeps the targets from being met: the targets missed (largest miss first), the
    variables at a bound, and the constraints the optimiser leaned on most."""
    out = [f"target '{r.name}' missed by {r.miss:.4g} {r.unit} (asked {r.asked}, model "
           f"{r.value:.6g})" for r in sorted(values.rows, key=lambda r: -r.miss) if not r.met]
    for v, ui, (lo, hi) in zip(variables, u, bounds):
        if ui <= lo + AT_BOUND:
            out.append(f"variable {v.name} at its lower bound {v.lower:g} {v.unit}")
        elif ui >= hi - AT_BOUND:
            out.append(f"variable {v.name} at its upper bound {v.upper:g} {v.unit}")
    if multipliers.size == len(values.labels):
        for i in np.argsort(-np.abs(multipliers))[:3]:
            if abs(multipliers[i]) > 1e-9:
                out.append(f"constraint '{values.labels[i]}' (multiplier "
                           f"{multipliers[i]:.3g})")
    return out


def verify(result: DesignResult, suspension: Suspension, decimals: int) -> DesignRun:
    """Step ``verify``: a plain run (no derivatives) at the best values rounded as written
    (``decimals``), on the targets' load cases; the report's figures are this run's."""
    x = np.round(result.best.values, decimals)
    run, result.best_values = evaluate_targets(suspension, result.targets, x,
                                               derivatives=False)
    result.best = run
    result.met = result.best_values.met
    return run


def run_optimize(suspension: Suspension, targets_path: str | Path,
                 progress: Progress = _quiet, decimals: int = 6) -> DesignResult:
    """The whole study: targets -> start -> optimise -> verify."""
    targets = targets_step(suspension, targets_path)
    result = optimise(suspension, targets, progress)
    verify(result, suspension, decimals)
    return result
