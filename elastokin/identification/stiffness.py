"""Bushing-stiffness identification from K&C test data (beyond the reference paper).

The paper ends where geometry stops helping: lateral and longitudinal behaviour are governed by
bushing stiffness. This module fits bushing laws so that a model (the geometrically identified
one in ``elastokin kc``) matches the K&C test data across every load case.

**Parameter set.** For each fitted bushing, every direction's law becomes

    F(u) = scale * f(u) * (1 + cubic * u^2)

with ``f`` the config's law (Table 1) and ``u`` the deflection (mm, deg) incl. the preload
deflection. The three translations share ``translation_scale`` (-) and ``translation_cubic``
(1/mm^2), the three rotations ``rotation_scale`` and ``rotation_cubic`` (1/deg^2); a bushing
datasheet's "radial/axial ratio" is kept from the config. ``cubic`` makes the law progressive
(the secant stiffness at deflection u is ``1 + cubic * u^2`` times the scaled one;
``progression = cubic^-1/2`` is the deflection at which it has doubled). Which of the four are
fitted, and for which bushings, is ``kc_test.stiffness_identification`` in the config.

Every fitted model keeps the loads its bushings carry at the design position (the measured,
loaded state): changing a law changes its preload deflection, not the static equilibrium the
CMM measured.

**Residuals.** For every test file (load case) and channel (toe, camber, wheel-centre
longitudinal and lateral displacement, and wheel travel under forces): the model minus the
test at each test point, branch by branch (:func:`elastokin.comparison.curve_residuals`), less
its mean over the curve (a static offset is not a stiffness), divided by the curve's scale:
with ``weighting: range`` the range of the test curve, never less than the rig's uncertainty
(``residual_scale_deg`` / ``residual_scale_mm``), so that every chart counts alike; with
``weighting: uncertainty`` that uncertainty alone; with ``weighting: residual`` the curve's
own residual RMS at the previous fit (iteratively reweighted least squares from the range
weights: maximum likelihood with an unknown error level per curve, so that curves no
frictionless model follows - friction hysteresis - lose weight), refitted until no curve's
scale changes by more than 5 % or ``reweighting_passes`` fits were made.

**Fit.** ``scipy.optimize.least_squares`` (trust-region reflective, bounds), on ln(scale) and
on the stiffening at a reference deflection of 1 mm or 1 deg (``cubic * 1^2``), forward
differences with a 1e-3 step (far above the static solver's tolerance); the Jacobian's model
runs spread over worker processes (same result for any number).

**Uncertainty and identifiability.** At the solution, J the residual Jacobian (m residuals,
n parameters): covariance ``s^2 (J^T J)^-1 * m / m_eff`` with ``s^2 = |r|^2 / (m - n)``, where
``m_eff`` counts the independent residuals: model error and friction hysteresis are smooth
along a curve, so each curve of n residuals with lag-1 autocorrelation rho is worth
``n (1 - rho) / (1 + rho)`` (AR(1) effective sample size; white noise keeps m_eff = m);
95 % intervals with Student's t on ``m_eff - n`` degrees of freedom. Also the condition number
of J with unit-norm columns (collinearity of the parameters' effects) and the correlations.

A parameter is **determined** when its 95 % half-width, as a stiffness effect, is at most
``determined_within`` (default 10 %): for a scale, the relative half-width; for a cubic, the
half-width times the largest deflection that bushing direction reaches in the load cases,
squared (the uncertainty of the stiffening where the data are). Every parameter is fitted;
those not determined are reported with a warning (fix them by leaving them out of
``parameters``).
"""

from __future__ import annotations

import dataclasses
import sys
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
from scipy import optimize, stats

from elastokin.config.schema import StiffnessIdentificationSpec
from elastokin.config.suspension import Suspension
from elastokin.errors import ConfigError, ElastokinError, SolverError
from elastokin.mbs.model import DesignState, ModelOptions, SuspensionModel
from elastokin.physics.laws import ProgressiveLaw
from elastokin.rig.load_cases import Sweep, run_load_cases
from elastokin.studies.comparison import INPUT_COLUMNS, curve_residuals, model_errors, rig_for_test

#: parameter -> (first direction, kind, unit); translations are directions 0-2, rotations 3-5
PARAMETERS = {
    "translation_scale": (0, "scale", "-"),
    "rotation_scale": (3, "scale", "-"),
    "translation_cubic": (0, "cubic", "1/mm^2"),
    "rotation_cubic": (3, "cubic", "1/deg^2"),
}
#: fitted channels (kc.csv column -> unit); wheel travel only where it is not the rig input
CHANNELS = {
    "toe_deg": "deg",
    "camber_deg": "deg",
    "wheel_centre_longitudinal_mm": "mm",
    "wheel_centre_lateral_mm": "mm",
    "wheel_travel_mm": "mm",
}
#: bounds of the optimisation variables: ln(scale) and stiffening at 1 mm / 1 deg
_LOG_SCALE_BOUNDS = (np.log(0.05), np.log(20.0))
_STIFFENING_BOUNDS = (0.0, 100.0)
_DIFF_STEP = 1e-3
#: weighting "residual": stop reweighting when no curve's scale changes by more than this
_REWEIGHTING_TOLERANCE = 0.05
_BUSHING_COLUMNS = ("x_mm", "y_mm", "z_mm", "rx_deg", "ry_deg", "rz_deg")


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
    bushings = tuple(dataclasses.replace(b, laws=bushing_laws(b.laws, values[b.name]))
                     if b.name in values else b for b in suspension.bushings)
    return dataclasses.replace(suspension, bushings=bushings)


def stiffness_model(suspension: Suspension, design: DesignState,
                    part_poses: bool = True) -> SuspensionModel:
    """The compliant model of ``suspension`` (fitted laws) carrying the loads of ``design``
    (``part_poses``: see :class:`~elastokin.model.ModelOptions`)."""
    return SuspensionModel(suspension, ModelOptions(part_poses=part_poses),
                           bushing_preload=design.bushing_preload,
                           spring_force_N=design.spring_force_N)


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
                self.scale[(sw.load_case, c)] = max(span, floor[CHANNELS[c]])
        self.evaluations = 0

    def model(self, values: dict[str, dict[str, float]]) -> SuspensionModel:
        # the residuals use no steering-axis columns: no part poses recorded (faster)
        return stiffness_model(with_stiffness(self.suspension, values), self.design,
                               part_poses=False)

    def sweeps(self, values: dict[str, dict[str, float]]) -> list[Sweep]:
        self.evaluations += 1
        return run_load_cases(self.model(values), "fit")

    def channels(self, test: Sweep) -> list[str]:
        x = INPUT_COLUMNS[test.load_case]
        return [c for c in CHANNELS if c != x and c in test.columns]

    def _curves(self, sweeps: list[Sweep], clamp: bool):
        """(load case, channel, unweighted residuals) per test curve the sweeps answer."""
        by_case = {sw.load_case: sw for sw in sweeps}
        for t in self.test:
            m = by_case.get(t.load_case)
            for c in self.channels(t) if m is not None else []:
                r = curve_residuals(m, t, INPUT_COLUMNS[t.load_case], c, clamp=clamp)
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
            out[key] = max(rms, self.floor[CHANNELS[key[1]]])
            start += n
        return out

    def rms(self, sweeps: list[Sweep]) -> dict[str, dict[str, float]]:
        """RMS of the unweighted residuals per load case and channel (deg or mm)."""
        out: dict[str, dict[str, float]] = {}
        for case, c, r in self._curves(sweeps, clamp=False):
            if r.size:
                out.setdefault(case, {})[c] = float(np.sqrt(np.mean(r ** 2)))
        return out


@dataclass
class ParameterResult:
    """A parameter's fitted value (physical units), 95 % interval and identifiability."""

    bushing: str
    name: str
    unit: str
    value: float
    ci95: tuple[float, float]
    std: float
    effect_halfwidth: float  # 95 % half-width as a relative stiffness effect
    determined: bool
    reference_deflection: float | None = None  # cubic: the largest deflection seen (mm, deg)

    def to_json(self) -> dict:
        d = dataclasses.asdict(self)
        d["ci95"] = list(self.ci95)
        if self.name.endswith("cubic"):
            d["progression"] = None if self.value <= 0 else float(self.value ** -0.5)
        return d


@dataclass
class StiffnessFit:
    """The result of :func:`identify_stiffness`."""

    parameters: list[ParameterResult]
    values: dict[str, dict[str, float]]  # bushing -> parameter -> fitted value
    suspension: Suspension  # with the fitted laws
    design: DesignState  # the preloads every variant keeps
    labels: list[str]  # the parameters' labels (rows and columns of correlation)
    correlation: np.ndarray
    condition_number: float
    residual_rms_before: float  # weighted (dimensionless) RMS before / after
    residual_rms_after: float
    channel_rms_before: dict[str, dict[str, float]]
    channel_rms_after: dict[str, dict[str, float]]
    errors_before: dict[str, float | None]  # the kc contract errors (comparison.ERRORS)
    errors_after: dict[str, float | None]
    residual_count: int
    effective_residual_count: float  # independent residuals the smooth curves are worth
    evaluations: int
    status: str
    warnings: list[str] = field(default_factory=list)
    hidden: dict = field(default_factory=dict)  # synthetic data: fitted against the truth
    settings: dict = field(default_factory=dict)

    def to_json(self) -> dict:
        return {
            "parameter_set": "per bushing: F(u) = scale * f_config(u) * (1 + cubic * u^2); "
                             "translations share translation_scale / translation_cubic "
                             "(1/mm^2), rotations rotation_scale / rotation_cubic (1/deg^2)",
            "parameters": {f"{p.bushing}.{p.name}": p.to_json() for p in self.parameters},
            "values": self.values,
            "identifiability": {
                "condition_number": self.condition_number,
                "parameters": self.labels,
                "correlation": np.round(self.correlation, 6).tolist(),
            },
            "residuals": {
                "count": self.residual_count,
                "weighted_rms_before": self.residual_rms_before,
                "weighted_rms_after": self.residual_rms_after,
                "rms_before": self.channel_rms_before,
                "rms_after": self.channel_rms_after,
            },
            "errors_before": self.errors_before,
            "errors_after": self.errors_after,
            "evaluations": self.evaluations,
            "effective_residual_count": self.effective_residual_count,
            "status": self.status,
            "warnings": self.warnings,
            "hidden_comparison": self.hidden,
            "settings": self.settings,
        }

    def table(self) -> str:
        """A readable report (plain text)."""
        s = self.suspension
        out = [f"Bushing-stiffness identification of {s.name} against the K&C test data",
               "  law per fitted bushing: F(u) = scale * f_config(u) * (1 + cubic * u^2); "
               "units mm, N, N*mm, deg", "",
               f"  {'parameter':<24}{'value':>10}{'95 % interval':>22}{'+-stiffness':>13}"
               f"{'determined':>12}{'hidden':>10}"]
        for p in self.parameters:
            key = f"{p.bushing}.{p.name}"
            h = self.hidden.get(key, {}).get("hidden")
            state = "yes" if p.determined else "no"
            out.append(f"  {key:<24}{p.value:>10.4g}   [{p.ci95[0]:>8.4g}, {p.ci95[1]:>8.4g}]"
                       f"{100 * p.effect_halfwidth:>11.1f} %{state:>12}"
                       f"{'' if h is None else format(h, '.4g'):>10}")
        out += ["", f"Identifiability: condition number {self.condition_number:.3g} "
                "(Jacobian with unit-norm columns)"]
        if len(self.labels) > 1:
            out.append("  correlations: " + ", ".join(
                f"{self.labels[a]}/{self.labels[b]} {self.correlation[a, b]:+.2f}"
                for a in range(len(self.labels)) for b in range(a + 1, len(self.labels))))
        secants = {k: v for k, v in self.hidden.items() if k.endswith("_stiffness")}
        if secants:
            out += ["", "Against the hidden (synthetic) laws: largest secant-stiffness error "
                    "over the deflections the load cases reach"]
            out += [f"  {k:<28}{100 * v['secant_stiffness_error_max']:>7.1f} %  "
                    f"(|u| <= {v['deflection_range']:.2f})" for k, v in secants.items()]
        out += ["", "RMS error against the test (before -> after): "]
        for k, v in self.errors_before.items():
            a = self.errors_after.get(k)
            if v is not None and a is not None:
                change = (f"{100 * (1 - a / v):.0f} % cut" if a <= v
                          else f"{100 * (a / v - 1):.0f} % larger")
                out.append(f"  {k:<36}{v:>9.4f} -> {a:.4f}  ({change})")
        out.append(f"  weighted residual RMS {self.residual_rms_before:.4g} -> "
                   f"{self.residual_rms_after:.4g} over {self.residual_count} residuals, "
                   f"({self.effective_residual_count:.0f} independent), "
                   f"{self.evaluations} model runs")
        if self.warnings:
            out += ["", "Warnings:"] + [f"  - {w}" for w in self.warnings]
        return "\n".join(out) + "\n"


def stiffness_config(config: dict, fit: StiffnessFit) -> dict:
    """``config`` (the dict of the suspension that was fitted) with the fitted laws written
    as curves (or rates, when linear), every bushing's design load as its ``preload`` and the
    balanced spring's force as its ``preload_N`` (the loads ``fit.design`` kept): what
    ``elastokin kc`` loads as the identified-stiffness model."""
    import copy

    out = copy.deepcopy(config)
    reach = {p.bushing: p.reference_deflection for p in fit.parameters
             if p.reference_deflection}
    for b in fit.suspension.bushings:
        spec = out["connections"][b.name]
        if b.name in fit.values:
            span = max(10.0, 4.0 * (reach.get(b.name) or 0.0))
            stiffness = {}
            for d, law in zip(("x", "y", "z", "rx", "ry", "rz"), b.laws):
                if law.is_linear:
                    stiffness[d] = float(law.rate_at_zero)
                else:
                    tab = law.tabulated(span)
                    stiffness[d] = {"deflection": [round(v, 9) for v in tab.deflection],
                                    "load": [round(v, 9) for v in tab.load]}
            spec["stiffness"] = stiffness
        spec.pop("initial_deflection", None)
        load = fit.design.bushing_preload[b.name]
        spec["preload"] = {"force_N": [float(v) for v in load[:3]],
                           "torque_Nmm": [float(v) for v in load[3:]]}
    for name, force in fit.design.spring_force_N.items():
        spring = out["springs"][name]
        spring.pop("free_length_mm", None)
        spring["preload_N"] = float(force)
    out["design"] = {"wheel_load_N": out["design"]["wheel_load_N"]}
    return out


def effective_residual_count(residual: np.ndarray, blocks: list[int]) -> float:
    """Independent residuals a vector of smooth curves is worth: per curve of n residuals
    with lag-1 autocorrelation rho, ``n (1 - rho) / (1 + rho)`` (AR(1) effective sample
    size), at least 1 per curve."""
    total, start = 0.0, 0
    for n in blocks:
        r = residual[start:start + n]
        start += n
        d = r - r.mean()
        if n < 3 or not d @ d > 0:
            total += max(n, 1)
            continue
        rho = float(np.clip((d[1:] @ d[:-1]) / (d @ d), 0.0, 1.0))
        total += max(1.0, n * (1.0 - rho) / (1.0 + rho))
    return total


def _jacobian_statistics(jac: np.ndarray, residual: np.ndarray, n: int, blocks: list[int]):
    """(covariance, correlation, condition number of the unit-column Jacobian, t-value,
    effective residual count); see the module docstring."""
    m = residual.size
    m_eff = effective_residual_count(residual, blocks)
    s2 = float(residual @ residual) / max(m - n, 1)  # residual variance
    inflation = m / m_eff  # each residual carries 1 / inflation of independent information
    norms = np.linalg.norm(jac, axis=0)
    safe = np.where(norms > 0, norms, 1.0)
    Jn = jac / safe
    sv = np.linalg.svd(Jn, compute_uv=False)
    cond = float(sv[0] / sv[-1]) if sv[-1] > 0 else float("inf")
    # covariance through the scaled Jacobian's pseudo-inverse (singular columns -> huge)
    cov_n = np.linalg.pinv(Jn.T @ Jn, rcond=1e-15)
    cov = s2 * inflation * cov_n / np.outer(safe, safe)
    cov[norms == 0, :] = np.inf
    cov[:, norms == 0] = np.inf
    d = np.sqrt(np.abs(np.diag(cov_n)))
    with np.errstate(invalid="ignore", divide="ignore"):
        corr = cov_n / np.outer(d, d)
    t = float(stats.t.ppf(0.975, max(m_eff - n, 1.0)))
    return cov, np.nan_to_num(corr), cond, t, m_eff


def _largest_deflections(sweeps: list[Sweep], bushings: set[str]) -> dict[tuple[str, int], float]:
    """Largest |deflection| per bushing and group (0 translations mm, 3 rotations deg)."""
    out: dict[tuple[str, int], float] = {}
    for sw in sweeps:
        for b in bushings:
            for first in (0, 3):
                cols = [sw.columns.get(f"bushing_{b}_{c}") for c in
                        _BUSHING_COLUMNS[first:first + 3]]
                vals = [np.max(np.abs(c)) for c in cols if c is not None]
                if vals:
                    out[(b, first)] = max(out.get((b, first), 0.0), float(max(vals)))
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
    lo = np.array([p.bounds[0] for p in params])
    hi = np.array([p.bounds[1] for p in params])
    workers = fit_workers(len(params)) if workers is None else workers
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
            if change < _REWEIGHTING_TOLERANCE:
                break
            res.scale.update(scales)
            runs = _Runs(res, params, workers, progress)  # workers copy the new scales
        try:
            sol = optimize.least_squares(runs.fun, x, bounds=(lo, hi), jac=jac,
                                         x_scale="jac", ftol=ftol, xtol=xtol, gtol=1e-10,
                                         max_nfev=max_iterations)
        finally:
            runs.close()
        if sol.status == 0:
            raise SolverError(f"{suspension.source}: stiffness identification did not "
                              f"converge in {max_iterations} iterations ({res.evaluations} "
                              "model runs); fit fewer parameters "
                              "(kc_test.stiffness_identification.parameters)")
        x = sol.x
    r0 = res.vector(before_sweeps)  # the residuals before the fit, with the final weights
    cov, corr, cond, t, m_eff = _jacobian_statistics(sol.jac, sol.fun, len(params), res.blocks)
    after_sweeps = res.sweeps(_values(params, x))
    reach = _largest_deflections(after_sweeps, {p.bushing for p in params})
    std_x = np.sqrt(np.abs(np.diag(cov)))
    results, warnings = [], []
    for i, p in enumerate(params):
        value = p.from_x(x[i])
        ref = reach.get((p.bushing, p.directions[0]))
        if p.kind == "scale":
            ci = (float(np.exp(x[i] - t * std_x[i])), float(np.exp(x[i] + t * std_x[i])))
            std, hw = float(value * std_x[i]), float(np.expm1(t * std_x[i]))
        else:
            ci = (max(0.0, value - t * std_x[i]), value + t * std_x[i])
            std, hw = float(std_x[i]), float(t * std_x[i] * (ref or 0.0) ** 2)
        determined = bool(hw <= spec.determined_within)
        results.append(ParameterResult(p.bushing, p.name, p.unit, value,
                                       (float(ci[0]), float(ci[1])), std, hw, determined,
                                       ref if p.kind == "cubic" else None))
        if not determined:
            warnings.append(f"{p.label}: not determined by the test data (95 % half-width "
                            f"{100 * hw:.0f} % of the stiffness > "
                            f"{100 * spec.determined_within:.0f} %)")
    last_change = reweighting[-1]["largest_scale_change"] if reweighting else 0.0
    if last_change >= _REWEIGHTING_TOLERANCE:
        warnings.append(f"weighting 'residual': stopped after {passes} passes with a curve's "
                        f"scale still changing by {100 * last_change:.0f} % at the last one "
                        "(weights not converged; more passes: reweighting_passes)")
    labels = [p.label for p in params]
    for a in range(len(labels)):
        for b in range(a + 1, len(labels)):
            if abs(corr[a, b]) > 0.95:
                warnings.append(f"{labels[a]} and {labels[b]} are strongly correlated "
                                f"({corr[a, b]:+.3f}): the data tell mainly their combination")
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
        hidden=_hidden_comparison(results, values, reach, hidden),
        settings={"method": "scipy.optimize.least_squares (trf, forward differences, step "
                            f"{_DIFF_STEP})", "ftol": ftol, "xtol": xtol,
                  "max_iterations": max_iterations, "workers": workers,
                  "reweighting": reweighting,
                  "curve_scales": {f"{case}.{c}": v for (case, c), v in res.scale.items()},
                  **spec.model_dump()})


def _hidden_comparison(results: list[ParameterResult], values: dict, reach: dict,
                       hidden: dict | None) -> dict:
    """Fitted against the synthetic truth: each parameter, and each bushing group's largest
    secant-stiffness error over the deflections the load cases reach."""
    out = {}
    for p in results:
        h = (hidden or {}).get(p.bushing, {}).get(p.name)
        if h is not None:
            out[f"{p.bushing}.{p.name}"] = {
                "hidden": h, "fitted": p.value,
                "relative_error": None if h == 0 else p.value / h - 1.0}
    for b in sorted({p.bushing for p in results}):
        h = (hidden or {}).get(b)
        for group, first in (("translation", 0), ("rotation", 3)):
            u_ref = reach.get((b, first), 0.0)
            if h is None or u_ref <= 0:
                continue
            fitted = values.get(b, {})
            u = np.linspace(0.0, u_ref, 101)
            secant_fit = fitted.get(f"{group}_scale", 1.0) * (
                1.0 + fitted.get(f"{group}_cubic", 0.0) * u ** 2)
            secant_true = h[f"{group}_scale"] * (1.0 + h[f"{group}_cubic"] * u ** 2)
            out[f"{b}.{group}_stiffness"] = {
                "deflection_range": u_ref,
                "secant_stiffness_error_max": float(np.max(np.abs(secant_fit / secant_true
                                                                  - 1.0)))}
    return out
