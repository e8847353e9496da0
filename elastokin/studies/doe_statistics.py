"""Statistics of a DOE study (docs/doe.md): distributions of every characteristic over the
samples that solved, and each joint's share of their variance (standardised regression
coefficients). Units of the characteristics (summary.json names)."""

from __future__ import annotations

import math
from collections.abc import Iterable
from typing import NamedTuple

import numpy as np

#: what doe.json's numbers mean (written into doe.json as ``definitions``)
DEFINITIONS = {
    "sampling": "unit-cube samples (lhs / sobol / mc, from seed) mapped uniformly onto each "
                "joint's clearance region of radius dL_max: bushing disc normal to the housing "
                "axis r = R sqrt(u1), phi = 2 pi u2 along the bushing frame's x, y; other "
                "joints ball r = R u1^(1/3), cos(theta) = 1 - 2 u2, phi = 2 pi u3 in the "
                "joint frame",
    "statistics": "over the samples that solved: mean, std (ddof 1), p05 / p95 (linear "
                  "interpolation), min, max, n",
    "sensitivity": "sum over a joint's shift components of the squared standardised "
                   "regression coefficients (linear least squares of the characteristic on "
                   "all components, method 'src'), i.e. the joint's share of the variance "
                   "explained linearly; with fewer samples than components + 2, the R^2 of a "
                   "regression on the joint's own components (method 'src_per_joint', with a "
                   "warning: inflated by chance, not shares); a warning too when an SRC's "
                   "standard error exceeds 0.1 or the shares add up to more than 0.1 away "
                   "from R^2 (shift components correlated in the sample)",
    "characteristics": "as in elastokin kc summary.json (same names and units); parallel "
                       "travel: steer amplitude and bump steer over the stroke, bump camber "
                       "fitted over the stroke (rebound to bump)",
}

#: statistics reported for every characteristic
STATISTICS = ("mean", "std", "p05", "p95", "min", "max")


def statistics(values: Iterable[float]) -> dict[str, float | None]:
    """mean, sample standard deviation (ddof 1), 5th / 95th percentile (linear
    interpolation), min, max and count of the finite values; None where undefined."""
    x = np.array([v for v in values if v is not None and math.isfinite(v)], float)
    if x.size == 0:
        return {k: None for k in STATISTICS} | {"n": 0}
    return {"mean": float(np.mean(x)),
            "std": float(np.std(x, ddof=1)) if x.size > 1 else None,
            "p05": float(np.percentile(x, 5)), "p95": float(np.percentile(x, 95)),
            "min": float(np.min(x)), "max": float(np.max(x)), "n": int(x.size)}


class Regression(NamedTuple):
    """A standardised regression (:func:`standardised_regression`): the SRCs, the R^2 of the
    fit and the SRCs' standard errors."""

    src: np.ndarray
    r2: float
    src_standard_error: np.ndarray


def standardised_regression(X: np.ndarray, y: np.ndarray) -> Regression:
    """Standardised regression coefficients of y (n,) on the columns of X (n, p) by least
    squares with an intercept: SRC_i = b_i std(x_i) / std(y); the R^2 of the fit; and the
    SRCs' standard errors (ordinary least squares: s^2 (A^T A)^-1 with s^2 the residual
    variance over n - p - 1 degrees of freedom, scaled as the SRCs). Needs n >= p + 2 (a
    degree of freedom left). A constant y gives zeros, R^2 = 0 and zero standard errors."""
    X = np.asarray(X, float)
    y = np.asarray(y, float)
    n, p = X.shape
    if n < p + 2:
        raise ValueError(f"{n} samples cannot fit {p} inputs (need at least {p + 2})")
    sx, sy = X.std(axis=0, ddof=1), y.std(ddof=1)
    if not sy > 0:
        return Regression(np.zeros(p), 0.0, np.zeros(p))
    A = np.c_[np.ones(n), X - X.mean(axis=0)]
    coef, *_ = np.linalg.lstsq(A, y, rcond=None)
    resid = y - A @ coef
    rss = float(resid @ resid)
    r2 = 1.0 - rss / float(((y - y.mean()) ** 2).sum())
    cov = rss / (n - p - 1) * np.linalg.pinv(A.T @ A)
    return Regression(coef[1:] * sx / sy, r2, np.sqrt(np.diag(cov)[1:]) * sx / sy)


#: the largest standard error of an SRC the sensitivity ranking is reported without a warning
SRC_STANDARD_ERROR_MAX = 0.1
#: the largest difference between the sum of the joints' shares and the fit's R^2 (both 1 for
#: a linear response to uncorrelated inputs) reported without a warning
SHARES_MISMATCH_MAX = 0.1


def sensitivity_warning(result: dict, n: int, p: int, groups: list[str]) -> str | None:
    """Why a sensitivity result (:func:`joint_sensitivity`) of ``n`` samples and ``p`` shift
    components should not be read as shares of the variance, or None: too few samples for
    the multiple regression (each joint's figure is then its own regression's R^2, inflated
    by chance correlation, and the figures overlap), SRCs whose standard error exceeds
    :data:`SRC_STANDARD_ERROR_MAX`, or shares that do not add up to the fit's R^2 (inputs
    correlated in the sample; :data:`SHARES_MISMATCH_MAX`)."""
    joints = {j: v for j, v in result["joints"].items() if v is not None}
    if result["method"] == "src_per_joint":
        k = max(groups.count(j) for j in dict.fromkeys(groups))
        chance = f", a joint without effect about {k / max(n - 1, 1):.2f}" if n > 1 else ""
        return (f"{n} samples are too few for the sensitivity measure: the regression on all "
                f"{p} shift components needs at least {p + 2} samples; each joint's figure is "
                f"the R^2 of a regression on its own components alone, inflated by chance "
                f"correlation{chance}, and the figures overlap (sum "
                f"{sum(joints.values()):.2f}, not shares of the variance); extend the study "
                f"to {p + 2} samples or more (--samples; sobol and mc designs extend in "
                "place)")
    se = result.get("src_standard_error")
    if se and max(se) > SRC_STANDARD_ERROR_MAX:
        return (f"the sensitivity of {n} samples is uncertain: the standardised regression "
                f"coefficients have standard errors up to {max(se):.2f} (R^2 "
                f"{result['r2']:.2f}); more samples narrow them")
    total = sum(joints.values())
    if result["r2"] is not None and abs(total - result["r2"]) > SHARES_MISMATCH_MAX:
        return (f"the joints' figures add up to {total:.2f}, not to the R^2 {result['r2']:.2f} "
                f"of the fit: with {n} samples the {p} shift components are correlated in the "
                "sample, and squared SRCs are shares of the variance only for uncorrelated "
                "inputs; more samples decorrelate them")
    return None


def joint_sensitivity(X: np.ndarray, y: np.ndarray, groups: list[str]) -> dict:
    """Each joint's share of the variance of y explained linearly by its shift components.

    ``groups[i]`` names the joint of column i of X (n, p). With n >= p + 2 samples, one
    multiple regression on every component (``method: src``): a joint's figure is the sum of
    the squared SRCs of its components. With fewer samples, one regression per joint on its
    own components (``method: src_per_joint``): the figure is that regression's R^2 (the same
    quantity when the inputs are independent, noisier). Joints whose figure cannot be
    estimated (too few samples) get None.
    """
    X = np.asarray(X, float)
    y = np.asarray(y, float)
    names = list(dict.fromkeys(groups))
    cols = {j: [i for i, g in enumerate(groups) if g == j] for j in names}
    n, p = X.shape
    if n >= p + 2:
        src, r2, se = standardised_regression(X, y)
        joints = {j: float(np.sum(src[cols[j]] ** 2)) for j in names}
        out = {"method": "src", "r2": r2, "joints": joints, "src": [float(v) for v in src],
               "src_standard_error": [float(v) for v in se]}
    else:
        joints = {}
        for j in names:
            if n >= len(cols[j]) + 2:
                joints[j] = float(standardised_regression(X[:, cols[j]], y).r2)
            else:
                joints[j] = None
        out = {"method": "src_per_joint", "r2": None, "joints": joints, "src": None,
               "src_standard_error": None}
    out["warning"] = sensitivity_warning(out, n, p, groups)
    return out


def json_safe(x):
    """JSON-safe: numpy scalars to Python, NaN/inf to None."""
    if isinstance(x, dict):
        return {k: json_safe(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [json_safe(v) for v in x]
    if isinstance(x, (np.floating, float)):
        return float(x) if math.isfinite(x) else None
    if isinstance(x, np.integer):
        return int(x)
    return x


def aggregate(study, records: list[dict], nominal: dict | None = None) -> dict:
    """The study's results (the body of ``doe.json`` without provenance): counts, the
    distribution of every characteristic over the samples that solved, the sensitivity of
    each to each joint, and the failures. ``records`` in sample order."""
    ok = [r for r in records if r["status"] == "ok"]
    found = {k for r in ok for k in r["characteristics"]}
    names = [k for k in (nominal or {}) if k in found] + sorted(found - set(nominal or {}))
    idx = [r["sample"] for r in ok]
    X = study.components[idx] if idx else np.zeros((0, study.components.shape[1]))
    groups = [j.name for j in study.joints for _ in range(j.dimensions)]
    dists, sens = {}, {}
    for name in names:
        y = np.array([r["characteristics"].get(name, np.nan) for r in ok], float)
        dists[name] = statistics(y)
        good = np.isfinite(y)
        sens[name] = joint_sensitivity(X[good], y[good], groups) if good.sum() > 0 else {
            "method": None, "r2": None, "joints": {j.name: None for j in study.joints},
            "src": None, "src_standard_error": None, "warning": None}
    steer = dists.get("steer_amplitude_deg", statistics([]))
    steer_sens = sens.get("steer_amplitude_deg", {"joints": {j.name: None
                                                             for j in study.joints}})
    out = {
        "samples": study.samples,
        "completed": len(records),
        "failed": len(records) - len(ok),
        "seed": study.seed,
        "method": study.method,
        "load_cases": study.load_cases,
        "steer_amplitude_deg": steer,
        "sensitivity": steer_sens["joints"],
        "sensitivity_method": steer_sens.get("method"),
        "sensitivity_r2": steer_sens.get("r2"),
        "warnings": [w for w in [steer_sens.get("warning")] if w],
        "characteristics": dists,
        "sensitivity_by_characteristic": {k: {"joints": v["joints"], "method": v["method"],
                                              "r2": v["r2"], "warning": v["warning"]}
                                          for k, v in sens.items()},
        "src_components": {"inputs": [c for j in study.joints for c in j.components],
                           **{k: v["src"] for k, v in sens.items()}},
        "nominal": nominal,
        "clearances": {j.name: {"region": j.kind, "max_shift_mm": j.max_shift_mm,
                                "axes": j.axes.T.tolist()} for j in study.joints},
        "failures": [{"sample": r["sample"], "error": r["error"]} for r in records
                     if r["status"] != "ok"],
    }
    return json_safe(out)
