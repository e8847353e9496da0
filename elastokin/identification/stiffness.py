"""Bushing-stiffness identification from K&C test data (beyond the reference paper): per
fitted bushing every direction's law becomes ``F(u) = scale * f(u) * (1 + cubic * u^2)``
(translations and rotations share a scale and a cubic), fitted by least squares to the test
curves (changes from the static state, weighted per curve), with 95 % intervals and
identifiability. The Jacobian is exact: every model run also gives the derivatives of every
channel at every step (:mod:`elastokin.mbs.sensitivity`). The method, the weighting and the
statistics are in docs/stiffness.md.

Units: deflections mm and deg, loads N and N*mm; scales dimensionless, cubics 1/mm^2, 1/deg^2.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from elastokin.config.schema.suspension import StiffnessIdentificationSpec
from elastokin.config.suspension import Suspension
from elastokin.config.variants import DesignState, with_bushing_laws
from elastokin.errors import ConfigError, ElastokinError, SolverError
from elastokin.identification.likelihood import Curves, maximum_likelihood_fit
from elastokin.identification.stiffness_results import (
    StiffnessFit,
    fit_warnings,
    hidden_comparison,
    jacobian_statistics,
    largest_deflections,
    parameter_results,
)
from elastokin.identification.stiffness_runs import FitRuns, fit_workers
from elastokin.mbs.model import ModelOptions, SuspensionModel
from elastokin.mbs.sensitivity import LawVariation
from elastokin.physics.laws import ProgressiveLaw
from elastokin.rig.channels import CHANNELS, FITTED_CHANNELS, LOAD_CASES
from elastokin.rig.comparison import curve_residuals, model_errors, rig_for_test
from elastokin.rig.load_cases import drives, run_drive, static_states
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
#: step of the residuals' forward differences in each optimisation variable at fixed
#: coordinates (the sensitivities' dR/dp; no re-solve, so far below the solver's tolerance)
PARAMETER_STEP = 1e-7


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


def values_of(params: list[Parameter], x: np.ndarray) -> dict[str, dict[str, float]]:
    """bushing -> parameter name -> value (physical units) of the optimisation variables."""
    out: dict[str, dict[str, float]] = {}
    for p, xi in zip(params, x):
        out.setdefault(p.bushing, {})[p.name] = p.from_x(xi)
    return out


class Residuals:
    """Weighted residuals of a stiffness variant of ``suspension`` against the test sweeps.

    ``design`` holds the preloads the variants keep (those of the unfitted model). The
    variants are one model whose fitted bushings are parametric (built once per process,
    :meth:`model`), so a new parameter value changes named variables, not the model.
    """

    def __init__(self, suspension: Suspension, design: DesignState, test: list[Sweep],
                 spec: StiffnessIdentificationSpec, fitted: Sequence[str] = ()):
        self.suspension = suspension
        self.design = design
        self.test = test
        self.fitted = tuple(fitted) or tuple(b.name for b in suspension.bushings)
        self.base_laws = {b.name: b.laws for b in suspension.bushings}
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
        self.drives = drives(suspension, suspension.rig, suspension.kinematic)
        self.evaluations = 0
        self._model: SuspensionModel | None = None

    def __getstate__(self) -> dict:  # worker processes build their own model
        return {**self.__dict__, "_model": None}

    def laws(self, values: dict[str, dict[str, float]]) -> dict[str, tuple]:
        """The laws of every fitted bushing for ``values`` (bushing -> parameter -> value)."""
        return {b: bushing_laws(self.base_laws[b], values.get(b, {})) for b in self.fitted}

    def model(self, values: dict[str, dict[str, float]]) -> SuspensionModel:
        """The model with the laws of ``values`` (no part poses recorded: the residuals use
        no steering-axis columns)."""
        if self._model is None:
            self._model = SuspensionModel(self.suspension, ModelOptions(
                part_poses=False, parametric_bushings=self.fitted), self.design)
        self._model.set_bushing_laws(self.laws(values))
        return self._model

    def variations(self, params: list[Parameter], x: np.ndarray) -> list[LawVariation]:
        """Each parameter as a change of its bushing's laws at ``x`` (a forward step, backward
        at an upper bound), for the sensitivities."""
        out = []
        for j, p in enumerate(params):
            h = PARAMETER_STEP if x[j] + PARAMETER_STEP <= p.bounds[1] else -PARAMETER_STEP
            moved = self.laws(values_of(params, x + h * np.eye(x.size)[j]))[p.bushing]
            out.append(LawVariation({p.bushing: moved}, h))
        return out

    def point(self, params: list[Parameter], x: np.ndarray
              ) -> tuple[dict[str, dict[str, float]], list[LawVariation]]:
        """The parameter values at ``x`` and the variations of the sensitivities there."""
        return values_of(params, x), self.variations(params, x)

    def sweeps(self, values: dict[str, dict[str, float]],
               variations: Sequence[LawVariation] | None = None,
               indices: Sequence[int] | None = None) -> list[Sweep]:
        """The test's load cases (``indices`` of :attr:`drives`: only those) on the model
        with ``values``; with ``variations`` the sweeps carry tangents."""
        self.evaluations += 1
        model = self.model(values)
        chosen = range(len(self.drives)) if indices is None else indices
        static = static_states(model)
        return [run_drive(model, "fit", self.drives[i], variations, static) for i in chosen]

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

    def curve_blocks(self, sweeps: list[Sweep], tangents: bool = False
                     ) -> list[tuple[tuple[str, str], np.ndarray, np.ndarray | None]]:
        """Per test curve the sweeps answer: its key (load case, channel), its residuals
        (model - test, mm or deg) less their mean and, with ``tangents``, their derivatives
        (residuals x parameters) from the sweep's tangents: central differences along each
        parameter's tangent of the sweep's channels, with a step that moves no channel by more
        than 1e-6 (mm or deg). The residuals are piecewise linear in the channels
        (interpolation), so this is exact to rounding. Each sweep is treated on its own, so
        the blocks do not depend on how sweeps are grouped (worker processes)."""
        out = []
        for sw in sweeps:
            # a free offset per curve (the mean) instead of the test's static value: one
            # noisy test point must not shift a whole curve
            base = {(case, c): r - r.mean() for case, c, r in self._curves([sw], clamp=True)}
            columns: dict[tuple[str, str], list] = {key: [] for key in base}
            n = next(iter(sw.tangents.values())).shape[1] if tangents and sw.tangents else 0
            for j in range(n):
                size = max(float(np.max(np.abs(t[:, j]))) for t in sw.tangents.values())
                h = 1e-6 / max(size, 1e-300)
                plus, minus = ({(case, c): r for case, c, r in
                                self._curves([_moved(sw, j, sign * h)], clamp=True)}
                               for sign in (1.0, -1.0))
                for key in base:
                    # less the mean: the derivative of the mean's removal
                    d = (plus[key] - minus[key]) / (2.0 * h)
                    columns[key].append(d - d.mean())
            out += [(key, r, np.column_stack(columns[key]) if n else None)
                    for key, r in base.items()]
        return out

    def assemble(self, blocks) -> tuple[np.ndarray, np.ndarray | None]:
        """The residual vector (and Jacobian, when the blocks have one) from
        :meth:`curve_blocks`, in the test's curve order (recorded in :attr:`keys` and
        :attr:`blocks`)."""
        order = {(t.load_case, c): i for i, (t, c) in
                 enumerate((t, c) for t in self.test for c in self.channels(t))}
        blocks = sorted(blocks, key=lambda b: order[b[0]])
        self.keys = [b[0] for b in blocks]  # (load case, channel) per curve
        self.blocks = [b[1].size for b in blocks]  # residuals per curve, in vector order
        r = np.concatenate([b[1] for b in blocks])
        jac = (np.vstack([b[2] for b in blocks]) if blocks and blocks[0][2] is not None
               else None)
        return r, jac

    def differences(self, sweeps: list[Sweep]) -> np.ndarray:
        """All residuals (model - test, mm or deg), each curve less its mean, in vector order
        (recorded in :attr:`keys` and :attr:`blocks`)."""
        return self.assemble(self.curve_blocks(sweeps))[0]

    def vector(self, sweeps: list[Sweep]) -> np.ndarray:
        """All residuals, divided by their curve's scale (the fit's objective)."""
        r = self.differences(sweeps)
        return r / self.scale_vector()

    def jacobian(self, sweeps: list[Sweep]) -> np.ndarray:
        """d :meth:`differences` / d parameters from the sweeps' tangents
        (:meth:`curve_blocks`)."""
        return self.assemble(self.curve_blocks(sweeps, tangents=True))[1]

    def run(self, values: dict[str, dict[str, float]], variations: Sequence[LawVariation],
            indices: Sequence[int] | None = None) -> tuple[list[Sweep], list]:
        """A run with sensitivities: the sweeps (without their tangents) and the curve blocks
        with their Jacobians (:meth:`curve_blocks`)."""
        sweeps = self.sweeps(values, variations, indices)
        blocks = self.curve_blocks(sweeps, tangents=True)
        return [dataclasses.replace(sw, tangents={}) for sw in sweeps], blocks

    def scale_vector(self) -> np.ndarray:
        """Each residual's curve scale (the last :meth:`vector`'s order)."""
        return np.repeat([self.scale[k] for k in self.keys], self.blocks)

    def curves(self) -> Curves:
        """The curves of the last :meth:`vector` with their floors (mm or deg)."""
        return Curves(np.array(self.blocks, int),
                      np.array([self.floor[CHANNELS[c].unit] for _, c in self.keys]))

    def rms(self, sweeps: list[Sweep]) -> dict[str, dict[str, float]]:
        """RMS of the unweighted residuals per load case and channel (deg or mm)."""
        out: dict[str, dict[str, float]] = {}
        for case, c, r in self._curves(sweeps, clamp=False):
            if r.size:
                out.setdefault(case, {})[c] = float(np.sqrt(np.mean(r ** 2)))
        return out


def _moved(sweep: Sweep, j: int, h: float) -> Sweep:
    cols = {k: (v + h * sweep.tangents[k][:, j] if k in sweep.tangents else v)
            for k, v in sweep.columns.items()}
    return Sweep(sweep.model, sweep.load_case, cols)


@dataclass
class FitOutcome:
    """Where the fit ended: the parameters ``x`` (optimisation variables), the weighted
    residuals and Jacobian there, the sweeps, the history of the curve scales, the
    optimizer's status message and warnings (a fit that stopped early keeps its last good
    point)."""

    x: np.ndarray
    fun: np.ndarray
    jac: np.ndarray
    sweeps: list[Sweep]
    reweighting: list[dict]
    status: str
    warnings: list[str]


def typical_sizes(params: list[Parameter], reach: dict) -> np.ndarray:
    """The typical size of each optimisation variable (its trust region's unit): a scale
    moves by about e^0.5; a cubic is measured by the stiffening it gives at the largest
    deflection ``reach`` its bushing reaches (1 / u_max^2 doubles the stiffness there)."""
    return np.array([0.5 if p.kind == "scale" else
                     1.0 / max(reach.get((p.bushing, p.directions[0]), 1.0), 1e-3) ** 2
                     for p in params])


def _fit(res: Residuals, params: list[Parameter], spec: StiffnessIdentificationSpec,
         runs: FitRuns, reach: dict, tolerances: dict) -> FitOutcome:
    """The fit with the exact Jacobian from the nominal laws: for ``weighting: residual``
    maximum likelihood with every curve's scale updated in closed form at each iterate
    (:mod:`elastokin.identification.likelihood`), otherwise least squares with the spec's
    fixed weights."""
    lo = np.array([p.bounds[0] for p in params])
    hi = np.array([p.bounds[1] for p in params])
    x = np.array([p.to_x(p.nominal) for p in params])
    size = typical_sizes(params, reach)
    if spec.weighting == "residual":
        return _likelihood_fit(res, runs, x, (lo, hi), size, tolerances)
    from scipy import optimize

    # trust-region reflective least squares needs a start inside the bounds: the cubics
    # start at 10 % stiffening at the largest deflection
    x = np.where([p.kind == "cubic" for p in params], x + 0.1 * size, x)
    try:
        sol = optimize.least_squares(runs.residuals, x, jac=runs.jacobian, bounds=(lo, hi),
                                     x_scale=size, gtol=1e-10, **tolerances)
    except SolverError as exc:
        return _stopped(runs, [], f"stopped: {exc}")
    if sol.status == 0:
        return _stopped(runs, [], f"did not converge in {tolerances['max_nfev']} model runs")
    return _outcome(runs, sol.x, [], sol.message, [])


def _likelihood_fit(res: Residuals, runs: FitRuns, x, bounds, size, tolerances
                    ) -> FitOutcome:
    try:
        ml = maximum_likelihood_fit(runs.differences, x, bounds, size, res.curves(),
                                    xtol=tolerances["xtol"], ftol=tolerances["ftol"],
                                    max_evaluations=tolerances["max_nfev"])
    except SolverError as exc:
        return _stopped(runs, [], f"stopped: {exc}")
    res.scale.update(zip(res.keys, res.curves().scales(ml.r).tolist()))
    history = [{"iteration": k + 1, **h} for k, h in enumerate(ml.history)]
    if not ml.converged:
        return _stopped(runs, history, "(maximum likelihood) did not converge in "
                                       f"{tolerances['max_nfev']} model runs", ml.x)
    return _outcome(runs, ml.x, history, f"maximum likelihood converged in {ml.evaluations} "
                    "model runs", [])


def _outcome(runs: FitRuns, x, history, status, warnings) -> FitOutcome:
    fun, jac, sweeps = runs.evaluate(x)  # weighted with the final curve scales
    return FitOutcome(x, fun, jac, sweeps, history, status, warnings)


def _stopped(runs: FitRuns, history, why: str, x=None) -> FitOutcome:
    """A fit that stopped early: ``x`` or the best point evaluated is kept, with a warning."""
    if x is None and runs.best is None:
        raise SolverError(f"stiffness identification {why}")
    x = runs.best[0] if x is None else x
    changes = [round(h["largest_scale_change"], 3) for h in history]
    return _outcome(runs, x, history, f"stiffness fit {why}",
                    [f"stiffness fit {why}; the last good values are kept"
                     + (f" (curve-scale changes per iteration {changes})" if changes else "")])


def identify_stiffness(suspension: Suspension, design: DesignState, test: list[Sweep],
                       spec: StiffnessIdentificationSpec | None = None,
                       progress: Callable[[str], None] = lambda msg: None,
                       ftol: float = 1e-8, xtol: float = 1e-8, max_iterations: int = 100,
                       hidden: dict[str, dict[str, float]] | None = None,
                       workers: int | None = None) -> StiffnessFit:
    """Fit the bushing laws of ``suspension`` (preloads of ``design`` kept) to the ``test``
    sweeps (see the module docstring), from the nominal laws. A fit that has not converged
    after ``max_iterations`` model runs keeps its best point, with a warning (``ftol``,
    ``xtol``: see :func:`scipy.optimize.least_squares` and
    :func:`~elastokin.identification.likelihood.maximum_likelihood_fit`). ``hidden``: the
    true values when the test data are synthetic (bushing -> parameter -> value), reported
    beside the fitted ones, never used in fitting. ``workers``: processes the load cases
    of a model run are spread over (default :func:`fit_workers`; 1 runs everything in this
    process); the result does not depend on it."""
    if suspension.axle is not None:
        raise ConfigError(f"{suspension.source}: the stiffness fit runs on one corner (its "
                          "test data are that wheel's): pass the axle's corner "
                          "(elastokin.config.variants.corner)")
    spec = spec or StiffnessIdentificationSpec()
    params = parameters(suspension, spec)
    # the fit runs the test's load cases over the test's ranges, whatever the report's rig
    fitted = {p.bushing for p in params}
    res = Residuals(dataclasses.replace(suspension, rig=rig_for_test(test, suspension.rig)),
                    design, test, spec, fitted=sorted(fitted))
    workers = fit_workers(len(res.drives)) if workers is None else workers
    runs = FitRuns(res, params, workers, progress)
    try:
        nominal = np.array([p.to_x(p.nominal) for p in params])
        before_sweeps = runs.last_sweeps(nominal)
        r0 = res.vector(before_sweeps)
        if r0.size <= len(params):
            raise ElastokinError(f"{suspension.source}: key 'kc_test': {r0.size} test "
                                 f"residuals cannot determine {len(params)} stiffness "
                                 "parameters")
        fit = _fit(res, params, spec, runs, largest_deflections(before_sweeps, fitted),
                   dict(ftol=ftol, xtol=xtol, max_nfev=max_iterations))
    finally:
        runs.close()
    x, after_sweeps = fit.x, fit.sweeps
    r0 = res.vector(before_sweeps)  # the residuals before the fit, with the final weights
    res.vector(after_sweeps)  # keys and blocks of the solution
    cov, corr, cond, t, m_eff = jacobian_statistics(fit.jac, fit.fun, len(params), res.blocks)
    reach = largest_deflections(after_sweeps, fitted)
    results, warnings = parameter_results(params, x, cov, t, reach, spec)
    warnings += fit.warnings + fit_warnings([p.label for p in params], corr)
    if spec.reweighting_passes is not None:
        warnings.append("kc_test.stiffness_identification.reweighting_passes is no longer "
                        "used (the curve scales are estimated by maximum likelihood in one "
                        "pass, docs/stiffness.md); remove the key")
    labels = [p.label for p in params]
    values = values_of(params, x)
    return StiffnessFit(
        parameters=results, values=values,
        suspension=with_stiffness(suspension, values), design=design, labels=labels,
        correlation=corr, condition_number=cond,
        residual_rms_before=float(np.sqrt(np.mean(r0 ** 2))),
        residual_rms_after=float(np.sqrt(np.mean(fit.fun ** 2))),
        channel_rms_before=res.rms(before_sweeps), channel_rms_after=res.rms(after_sweeps),
        errors_before=model_errors(before_sweeps, test),
        errors_after=model_errors(after_sweeps, test),
        residual_count=int(r0.size), effective_residual_count=m_eff,
        evaluations=res.evaluations, status=fit.status, warnings=warnings,
        hidden=hidden_comparison(results, values, reach, hidden),
        settings={"method": (
                      "maximum likelihood (an unknown error level per curve, trust-region "
                      "Gauss-Newton, elastokin.identification.likelihood)"
                      if spec.weighting == "residual" else
                      "scipy.optimize.least_squares (trf)") + " with the exact Jacobian "
                      "(sensitivities of every step, elastokin.mbs.sensitivity; parameter step "
                      f"{PARAMETER_STEP})",
                  "ftol": ftol, "xtol": xtol, "max_iterations": max_iterations,
                  "workers": workers, "passes": 1, "reweighting": fit.reweighting,
                  "curve_scales": {f"{case}.{c}": v for (case, c), v in res.scale.items()},
                  **spec.model_dump()})
