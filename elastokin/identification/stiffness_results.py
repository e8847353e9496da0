"""Results of the bushing-stiffness identification (:mod:`elastokin.identification.stiffness`):
each parameter's value, interval and identifiability, the fit's statistics (effective residual
count, covariance, condition number), the comparison with a synthetic truth, and the fitted
config. Units: scales dimensionless, cubics 1/mm^2 or 1/deg^2, deflections mm or deg."""

from __future__ import annotations

import copy
import dataclasses
from dataclasses import dataclass, field

import numpy as np

from elastokin.config.schema.suspension import StiffnessIdentificationSpec
from elastokin.config.suspension import Suspension
from elastokin.config.variants import DesignState
from elastokin.rig.item_channels import bushing_columns
from elastokin.rig.sweeps import Sweep


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
    passes: int = 1  # fits made: always 1 (earlier versions made one per curve scaling)
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
            "passes": self.passes,
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


def jacobian_statistics(jac: np.ndarray, residual: np.ndarray, n: int, blocks: list[int]):
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
    from scipy import stats  # imported when a fit is made (0.35 s), not for its results

    t = float(stats.t.ppf(0.975, max(m_eff - n, 1.0)))
    return cov, np.nan_to_num(corr), cond, t, m_eff


def largest_deflections(sweeps: list[Sweep], bushings: set[str]) -> dict[tuple[str, int], float]:
    """Largest |deflection| per bushing and group (0 translations mm, 3 rotations deg)."""
    out: dict[tuple[str, int], float] = {}
    for sw in sweeps:
        for b in bushings:
            for first in (0, 3):
                cols = [sw.columns.get(c) for c in bushing_columns(b)[first:first + 3]]
                vals = [np.max(np.abs(c)) for c in cols if c is not None]
                if vals:
                    out[(b, first)] = max(out.get((b, first), 0.0), float(max(vals)))
    return out


def parameter_results(params, x: np.ndarray, cov: np.ndarray, t: float, reach: dict,
                      spec: StiffnessIdentificationSpec
                      ) -> tuple[list[ParameterResult], list[str]]:
    """Each parameter's value, 95 % interval (Student's t ``t``) and identifiability, from the
    optimisation variables ``x`` and their covariance ``cov`` (see the module docstring)."""
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
    return results, warnings


def fit_warnings(labels: list[str], corr: np.ndarray) -> list[str]:
    """Warnings on the fit: strongly correlated parameters."""
    warnings = []
    for a in range(len(labels)):
        for b in range(a + 1, len(labels)):
            if abs(corr[a, b]) > 0.95:
                warnings.append(f"{labels[a]} and {labels[b]} are strongly correlated "
                                f"({corr[a, b]:+.3f}): the data tell mainly their combination")
    return warnings


def hidden_comparison(results: list[ParameterResult], values: dict, reach: dict,
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
