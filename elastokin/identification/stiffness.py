"""Bushing-stiffness identification from K&C test data (beyond the reference paper): per
fitted bushing every direction's law becomes ``F(u) = scale * f(u) * (1 + cubic * u^2)``
(translations and rotations share a scale and a cubic), fitted by least squares to the test
curves (changes from the static state, weighted per curve), with 95 % intervals and
identifiability. The method, the weighting and the statistics are in docs/stiffness.md.

Units: deflections mm and deg, loads N and N*mm; scales dimensionless, cubics 1/mm^2, 1/deg^2.
"""

from __future__ import annotations

import dataclasses
import sys
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from scipy import optimize

from elastokin.config.schema import StiffnessIdentificationSpec
from elastokin.config.suspension import Suspension
from elastokin.config.variants import DesignState, with_bushing_laws
from elastokin.errors import ConfigError, ElastokinError, SolverError
from elastokin.identification.stiffness_results import (
    REWEIGHTING_TOLERANCE,
    StiffnessFit,
    fit_warnings,
    hidden_comparison,
    jacobian_statistics,
    largest_deflections,
    parameter_results,
)
from elastokin.mbs.model import ModelOptions, SuspensionModel
from elastokin.physics.laws import ProgressiveLaw
from elastokin.rig.channels import CHANNELS, FITTED_CHANNELS, LOAD_CASES
from elastokin.rig.comparison import curve_residuals, model_errors, rig_for_test
from elastokin.rig.load_cases import run_load_cases
from elastokin.rig.sweeps import Sweep

#: parameter -> (first direction, kind, unit); translations are directions 0-2, rotations 3-5
PARAMETERS = {
    "translation_scale": (0, "scale", "-"),
    "rotation_scale": (3, "scale", "-"),
    "translation_cubic": (0, "cubic", "1/mm^2"),
    "rotation_cubic": (3, "cubic", "1/deg^2"),
}
#: bounds of the optimisation variables: ln(scale) and stiffening at 1 mm / 1 deg
_LOG_SCALE_BOUNDS = (np.log(0.05), np.log(20.0))
_STIFFENING_BOUNDS = (0.0, 100.0)
_DIFF_STEP = 1e-3


@dataclass(frozen=True)
class Parameter:
    """One fitted quantity: ``bushing``'s ``name`` (a key of :data:`PARAMETERS`)."""

    bushing: str
    name: str

    @property
    def kind(self) -> str:
        return PARAMETERS[self.name][1]

    @property
    def unit(self) -> str:
        return PARAMETERS[self.name][2]

    @property
    def directions(self) -> range:
        first = PARAMETERS[self.name][0]
        return range(first, first + 3)

    @property
    def label(self) -> str:
        return f"{self.bushing}.{self.name}"

    @property
    def nominal(self) -> float:
        return 1.0 if self.kind == "scale" else 0.0

    def to_x(self, value: float) -> float:
        return float(np.log(value)) if self.kind == "scale" else float(value)

    def from_x(self, x: float) -> float:
        return float(np.exp(x)) if self.kind == "scale" else float(x)

    @property
    def bounds(self) -> tuple[float, float]:
        return _LOG_SCALE_BOUNDS if self.kind == "scale" else _STIFFENING_BOUNDS


def bushing_laws(laws, values: dict[str, float]) -> tuple:
    """A bushing's six laws with ``values`` (parameter name -> value) applied; directions
    without a fitted parameter keep the config's law."""
    out = []
    for k, law in enumerate(laws):
        group = "translation" if k < 3 else "rotation"
        scale = values.get(f"{group}_scale", 1.0)
        cubic = values.get(f"{group}_cubic", 0.0)
        out.append(law if scale == 1.0 and cubic == 0.0 else
                   ProgressiveLaw(getattr(law, "base", law), scale, cubic))
    return tuple(out)


def with_stiffness(suspension: Suspension, values: dict[str, dict[str, float]]) -> Suspension:
    """``suspension`` with the bushing laws of ``values`` (bushing -> parameter -> value)."""
    return with_bushing_laws(suspension, {b.name: bushing_laws(b.laws, values[b.name])
                                          for b in suspension.bushings if b.name in values})


def stiffness_model(suspension: Suspension, design: DesignState,
                    part_poses: bool = True) -> SuspensionModel:
    """The compliant model of ``suspension`` (fitted laws) carrying the loads of ``design``
    (``part_poses``: see :class:`~elastokin.mbs.model.ModelOptions`)."""
    return SuspensionModel(suspension, ModelOptions(part_poses=part_poses), design)


def parameters(suspension: Suspension, spec: StiffnessIdentificationSpec,
               key: str = "kc_test.stiffness_identification") -> list[Parameter]:
    """The fitted parameters of a config's spec (bushing order of the config)."""
    names = [b.name for b in suspension.bushings]
    if not names:
        raise ConfigError(f"{suspension.source}: key '{key}': the suspension has no bushing "
                          "whose stiffness could be identified")
    chosen = spec.bushings if spec.bushings is not None else names
    for b in chosen:
        if b not in names:
            raise ConfigError(f"{suspension.source}: key '{key}.bushings': no bushing '{b}' "
                              f"(bushings: {', '.join(names)})")
    return [Parameter(b, p) for b in names if b in chosen for p in spec.parameters]


def _values(params: list[Parameter], x: np.ndarray) -> dict[str, dict[str, float]]:
    out: dict[str, dict[str, float]] = {}
    for p, xi in zip(params, x):
        out.setdefault(p.bushing, {})[p.name] = p.from_x(xi)
    return out


class Residuals:
    """Weighted residuals of a stiffness variant of ``suspension`` against the test sweeps.

    ``design`` holds the preloads the variants keep (those of the unfitted model).
    """

    def __init__(self, suspension: Suspension, design: DesignState, test: list[Sweep],
                 spec: StiffnessIdentificationSpec):
        self.suspension = suspension
        self.design = design
        self.test = test
        floor = self.floor = {"deg": spec.residual_scale_deg, "mm": spec.residual_scale_mm}
        # each (load case, channel) curve divided by the range of its test curve, never
        # finer than the rig's uncertainty: every chart counts alike
        self.scale = {}
        for sw in test:
            for c in self.channels(sw):
                y = sw.columns[c]
                span = (float(np.nanmax(y) - np.nanmin(y))
                        if spec.weighting in ("range", "residual") else 0.0)
                self.scale[(sw.load_case, c)] = max(span, floor[CHANNELS[c].unit])
        self.evaluations = 0

    def model(self, values: dict[str, dict[str, float]]) -> SuspensionModel:
        # the residuals use no steering-axis columns: no part poses recorded (faster)
        return stiffness_model(with_stiffness(self.suspension, values), self.design,
                               part_poses=False)

    def sweeps(self, values: dict[str, dict[str, float]]) -> list[Sweep]:
        self.evaluations += 1
        return run_load_cases(self.model(values), "fit")

    def channels(self, test: Sweep) -> list[str]:
        x = LOAD_CASES[test.load_case].input
        return [c for c in FITTED_CHANNELS if c != x and c in test.columns]

    def _curves(self, sweeps: list[Sweep], clamp: bool):
        """(load case, channel, unweighted residuals) per test curve the sweeps answer."""
        by_case = {sw.load_case: sw for sw in sweeps}
        for t in self.test:
            m = by_case.get(t.load_case)
            for c in self.channels(t) if m is not None else []:
                r = curve_residuals(m, t, LOAD_CASES[t.load_case].input, c, clamp=clamp)
                if r is not None:
                    yield t.load_case, c, r

    def vector(self, sweeps: list[Sweep]) -> np.ndarray:
        """All residuals, divided by their curve's scale (the fit's objective)."""
        parts = []
        self.blocks: list[int] = []  # residuals per curve, in vector order
        self.keys: list[tuple[str, str]] = []  # (load case, channel) per curve, same order
        for case, c, r in self._curves(sweeps, clamp=True):
            # a free offset per curve (the mean) instead of the test's static value: one
            # noisy test point must not shift a whole curve
            parts.append((r - r.mean()) / self.scale[(case, c)])
            self.blocks.append(r.size)
            self.keys.append((case, c))
        return np.concatenate(parts)

    def reweighted(self, vector: np.ndarray) -> dict[tuple[str, str], float]:
        """Each curve's scale for the next pass of ``weighting: residual``: the RMS of its
        residuals in ``vector`` (made by :meth:`vector` with the current scales), never
        finer than the rig's uncertainty."""
        out, start = {}, 0
        for key, n in zip(self.keys, self.blocks):
            rms = float(np.sqrt(np.mean(vector[start:start + n] ** 2))) * self.scale[key]
            out[key] = max(rms, self.floor[CHANNELS[key[1]].unit])
            start += n
        return out

    def rms(self, sweeps: list[Sweep]) -> dict[str, dict[str, float]]:
        """RMS of the unweighted residuals per load case and channel (deg or mm)."""
        out: dict[str, dict[str, float]] = {}
        for case, c, r in self._curves(sweeps, clamp=False):
            if r.size:
                out.setdefault(case, {})[c] = float(np.sqrt(np.mean(r ** 2)))
        return out


_WORKER_RESIDUALS: Residuals | None = None  # a worker process' copy (see _Runs)


def _start_worker(residuals: Residuals) -> None:
    global _WORKER_RESIDUALS
    _WORKER_RESIDUALS = residuals


def _worker_vector(values: dict[str, dict[str, float]]) -> np.ndarray:
    return _WORKER_RESIDUALS.vector(_WORKER_RESIDUALS.sweeps(values))


class _Runs:
    """The fit's model runs: one at a time in this process, and the Jacobian's columns (each
    an independent model run) over ``workers`` spawned processes holding a copy of the
    residuals. Each run is deterministic, so the fit is the same for any number of workers."""

    def __init__(self, res: Residuals, params: list[Parameter], workers: int,
                 progress: Callable[[str], None]):
        self.res, self.params, self.progress = res, params, progress
        self.pool = None
        if workers > 1:
            import multiprocessing
            from concurrent.futures import ProcessPoolExecutor

            # fork where it is safe (Linux): no re-import of the caller's main module (a
            # script without a main guard) and no import cost; elsewhere spawn
            method = "fork" if sys.platform.startswith("linux") else "spawn"
            self.pool = ProcessPoolExecutor(workers, multiprocessing.get_context(method),
                                            initializer=_start_worker, initargs=(res,))
        self.last: tuple[np.ndarray, np.ndarray] | None = None

    def close(self) -> None:
        if self.pool is not None:
            self.pool.shutdown(cancel_futures=True)

    def _failed(self, x: np.ndarray, exc: SolverError) -> SolverError:
        vals = ", ".join(f"{p.label}={p.from_x(v):.4g}" for p, v in zip(self.params, x))
        return SolverError(f"stiffness identification: the model does not solve at {vals}: "
                           f"{exc}")

    def fun(self, x: np.ndarray) -> np.ndarray:
        if self.last is not None and np.array_equal(self.last[0], x):
            return self.last[1]  # least_squares asks for the Jacobian where it just evaluated
        self.progress(f"stiffness fit: model run {self.res.evaluations + 1}")
        try:
            r = self.res.vector(self.res.sweeps(_values(self.params, x)))
        except SolverError as exc:
            raise self._failed(x, exc) from None
        self.last = (x.copy(), r)
        return r

    def many(self, xs: list[np.ndarray]) -> list[np.ndarray]:
        if self.pool is None:
            return [self.fun(x) for x in xs]
        futures = [self.pool.submit(_worker_vector, _values(self.params, x)) for x in xs]
        out = []
        for x, fut in zip(xs, futures):
            try:
                out.append(fut.result())
            except SolverError as exc:
                raise self._failed(x, exc) from None
            self.res.evaluations += 1
            self.progress(f"stiffness fit: model run {self.res.evaluations}")
        return out


def fit_workers(n_parameters: int) -> int:
    """Default worker processes of the fit: one per Jacobian column, at most one per core."""
    import os

    return max(1, min(n_parameters, len(os.sched_getaffinity(0))
                      if hasattr(os, "sched_getaffinity") else os.cpu_count() or 1))


def _fit(res: Residuals, params: list[Parameter], spec: StiffnessIdentificationSpec,
         workers: int, progress: Callable[[str], None], tolerances: dict):
    """The least-squares fit, repeated with each curve's scale re-estimated for ``weighting:
    residual`` until no scale changes by more than 5 %. Returns (solution, the reweighting
    history, the passes allowed)."""
    lo = np.array([p.bounds[0] for p in params])
    hi = np.array([p.bounds[1] for p in params])
    runs = _Runs(res, params, workers, progress)

    def jac(x):
        # forward differences with an absolute step in the optimisation variables (scipy's
        # relative step vanishes at 0 and drowns in the static solver's tolerance)
        f0 = runs.fun(x)
        steps = [_DIFF_STEP if x[j] + _DIFF_STEP <= hi[j] else -_DIFF_STEP
                 for j in range(x.size)]
        shifted = [x + h * np.eye(x.size)[j] for j, h in enumerate(steps)]
        return np.column_stack([(f - f0) / h for f, h in zip(runs.many(shifted), steps)])

    x = np.array([p.to_x(p.nominal) for p in params])
    passes = spec.reweighting_passes if spec.weighting == "residual" else 1
    reweighting, sol = [], None
    for k in range(passes):
        if k:  # weighting "residual": each curve's scale from the last pass' residuals
            scales = res.reweighted(sol.fun)
            change = max(abs(scales[key] / res.scale[key] - 1.0) for key in scales)
            reweighting.append({"pass": k + 1, "largest_scale_change": change})
            if change < REWEIGHTING_TOLERANCE:
                break
            res.scale.update(scales)
            runs = _Runs(res, params, workers, progress)  # workers copy the new scales
        try:
            sol = optimize.least_squares(runs.fun, x, bounds=(lo, hi), jac=jac,
                                         x_scale="jac", gtol=1e-10, **tolerances)
        finally:
            runs.close()
        if sol.status == 0:
            raise SolverError(f"{res.suspension.source}: stiffness identification did not "
                              f"converge in {tolerances['max_nfev']} iterations "
                              f"({res.evaluations} model runs); fit fewer parameters "
                              "(kc_test.stiffness_identification.parameters)")
        x = sol.x
    return sol, reweighting, passes


def identify_stiffness(suspension: Suspension, design: DesignState, test: list[Sweep],
                       spec: StiffnessIdentificationSpec | None = None,
                       progress: Callable[[str], None] = lambda msg: None,
                       ftol: float = 1e-8, xtol: float = 1e-8, max_iterations: int = 100,
                       hidden: dict[str, dict[str, float]] | None = None,
                       workers: int | None = None) -> StiffnessFit:
    """Fit the bushing laws of ``suspension`` (preloads of ``design`` kept) to the ``test``
    sweeps (see the module docstring). Stopping after ``max_iterations`` (each a Jacobian:
    one model run per parameter, plus one) without converging is an error. ``hidden``: the
    true values when the test data are synthetic (bushing -> parameter -> value), reported
    beside the fitted ones, never used in fitting. ``workers``: processes for the Jacobian's
    model runs (default :func:`fit_workers`; 1 runs everything in this process); the result
    does not depend on it."""
    spec = spec or StiffnessIdentificationSpec()
    params = parameters(suspension, spec)
    # the fit runs the test's load cases over the test's ranges, whatever the report's rig
    res = Residuals(dataclasses.replace(suspension, rig=rig_for_test(test, suspension.rig)),
                    design, test, spec)
    before_sweeps = res.sweeps({})
    r0 = res.vector(before_sweeps)
    if r0.size <= len(params):
        raise ElastokinError(f"{suspension.source}: key 'kc_test': {r0.size} test residuals "
                             f"cannot determine {len(params)} stiffness parameters")
    workers = fit_workers(len(params)) if workers is None else workers
    sol, reweighting, passes = _fit(res, params, spec, workers, progress,
                                    dict(ftol=ftol, xtol=xtol, max_nfev=max_iterations))
    x = sol.x
    r0 = res.vector(before_sweeps)  # the residuals before the fit, with the final weights
    cov, corr, cond, t, m_eff = jacobian_statistics(sol.jac, sol.fun, len(params), res.blocks)
    after_sweeps = res.sweeps(_values(params, x))
    reach = largest_deflections(after_sweeps, {p.bushing for p in params})
    results, warnings = parameter_results(params, x, cov, t, reach, spec)
    warnings += fit_warnings(reweighting, passes, [p.label for p in params], corr)
    labels = [p.label for p in params]
    values = _values(params, x)
    return StiffnessFit(
        parameters=results, values=values,
        suspension=with_stiffness(suspension, values), design=design, labels=labels,
        correlation=corr, condition_number=cond,
        residual_rms_before=float(np.sqrt(np.mean(r0 ** 2))),
        residual_rms_after=float(np.sqrt(np.mean(sol.fun ** 2))),
        channel_rms_before=res.rms(before_sweeps), channel_rms_after=res.rms(after_sweeps),
        errors_before=model_errors(before_sweeps, test),
        errors_after=model_errors(after_sweeps, test),
        residual_count=int(r0.size), effective_residual_count=m_eff,
        evaluations=res.evaluations, status=sol.message, warnings=warnings,
        hidden=hidden_comparison(results, values, reach, hidden),
        settings={"method": "scipy.optimize.least_squares (trf, forward differences, step "
                            f"{_DIFF_STEP})", "ftol": ftol, "xtol": xtol,
                  "max_iterations": max_iterations, "workers": workers,
                  "reweighting": reweighting,
                  "curve_scales": {f"{case}.{c}": v for (case, c), v in res.scale.items()},
                  **spec.model_dump()})


