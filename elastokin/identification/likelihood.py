"""Least squares with an unknown error level per curve, by maximum likelihood (pure numpy and
scipy; the stiffness fit's ``weighting: residual``, :mod:`elastokin.identification.stiffness`).

The residuals r (m) fall into curves c of n_c residuals each (one K&C channel of one load
case), each with its own unknown standard deviation sigma_c, never below a floor f_c (the rig's
resolution). With the mean square ms_c = |r_c|^2 / n_c, the negative log-likelihood profiled
over the sigmas (constants left out) is

    L(x) = sum_c n_c (ln s_c + ms_c / s_c),   s_c = max(ms_c, f_c^2) = sigma_c^2,

continuous with a continuous gradient. Its stationary points are exactly the fixed points of
iteratively reweighted least squares (each curve divided by its own residual RMS), found here
directly: at every iterate the curve scales are updated in closed form (s_c at the current
residuals) and the step minimises L of the linearised residuals r + J dx in a trust region
(:func:`maximum_likelihood_fit`), so no reweighting passes are needed.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np


@dataclass(frozen=True)
class Curves:
    """The residual vector's curves: ``sizes`` (residuals per curve, in vector order) and each
    curve's floor of the standard deviation (mm or deg)."""

    sizes: np.ndarray
    floors: np.ndarray

    @property
    def starts(self) -> np.ndarray:
        return np.r_[0, np.cumsum(self.sizes)[:-1]].astype(int)

    def variances(self, r: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(mean square per curve, variance per curve max(ms, floor^2))."""
        ms = np.add.reduceat(r * r, self.starts) / self.sizes
        return ms, np.maximum(ms, np.asarray(self.floors) ** 2)

    def scales(self, r: np.ndarray) -> np.ndarray:
        """Each curve's maximum-likelihood standard deviation at residuals ``r``."""
        return np.sqrt(self.variances(r)[1])

    def nll(self, r: np.ndarray) -> float:
        """The profiled negative log-likelihood L (module docstring)."""
        ms, var = self.variances(r)
        return float(np.sum(self.sizes * (np.log(var) + ms / var)))

    def gradient(self, r: np.ndarray, jac: np.ndarray) -> np.ndarray:
        """dL/dx for residuals ``r`` with Jacobian ``jac`` (m, n)."""
        _, var = self.variances(r)
        return 2.0 * jac.T @ (r / np.repeat(var, self.sizes.astype(int)))


def linearised_step(curves: Curves, r: np.ndarray, jac: np.ndarray, lower: np.ndarray,
                    upper: np.ndarray, size: np.ndarray | None = None
                    ) -> tuple[np.ndarray, float]:
    """The step dx in the box [lower, upper] minimising L(r + jac dx), and the decrease of L
    it predicts (truncated Newton with bounds; ``size``: the variables' typical sizes, for
    the minimiser's scaling)."""
    from scipy import optimize

    size = np.ones(jac.shape[1]) if size is None else np.asarray(size, float)

    def fun(z):
        e = r + jac @ (z * size)
        return curves.nll(e), curves.gradient(e, jac) * size

    best = optimize.minimize(fun, np.zeros(jac.shape[1]), jac=True, method="TNC",
                             bounds=list(zip(lower / size, upper / size)),
                             options={"xtol": 1e-12, "maxfun": 2000})
    return best.x * size, curves.nll(r) - float(best.fun)


@dataclass
class LikelihoodFit:
    """Where :func:`maximum_likelihood_fit` ended: parameters, residuals, Jacobian, the
    iterations' history, the evaluations made and whether it converged."""

    x: np.ndarray
    r: np.ndarray
    jac: np.ndarray
    history: list[dict] = field(default_factory=list)
    evaluations: int = 0
    converged: bool = False


def maximum_likelihood_fit(evaluate: Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]],
                           x0: np.ndarray, bounds: tuple[np.ndarray, np.ndarray],
                           size: np.ndarray, curves: Curves, xtol: float = 1e-6,
                           ftol: float = 1e-8, max_evaluations: int = 50) -> LikelihoodFit:
    """Minimise L (module docstring) over ``x`` in ``bounds``: ``evaluate(x)`` gives the
    residuals and their exact Jacobian; ``size`` the typical size of each variable. A
    trust-region Gauss-Newton method: each step minimises L of the linearised residuals within
    +-radius * size (radius 1 at first, halved or doubled by how well the decrease was
    predicted). Converged when a step moves no variable by more than ``xtol`` * size or L
    by less than ``ftol`` (relative to the number of residuals)."""
    lo, hi = bounds
    x = np.clip(np.asarray(x0, float), lo, hi)
    r, jac = evaluate(x)
    fit = LikelihoodFit(x, r, jac, evaluations=1)
    value, radius = curves.nll(r), 1.0
    scale = curves.scales(r)
    while fit.evaluations < max_evaluations:
        step, predicted = linearised_step(curves, r, jac, np.maximum(lo - x, -radius * size),
                                          np.minimum(hi - x, radius * size), size)
        moved = float(np.max(np.abs(step) / size))
        if moved <= xtol or predicted <= ftol * r.size:
            fit.converged = True
            break
        r_new, jac_new = evaluate(x + step)
        fit.evaluations += 1
        new_value = curves.nll(r_new)
        ratio = (value - new_value) / predicted
        if ratio < 0.25:
            radius *= 0.25
        elif ratio > 0.75 and moved >= 0.99 * radius:
            radius *= 2.0
        if ratio > 0.0:
            new_scale = curves.scales(r_new)
            fit.history.append({"nll": new_value, "largest_scale_change":
                                float(np.max(np.abs(new_scale / scale - 1.0)))})
            x, r, jac, value, scale = x + step, r_new, jac_new, new_value, new_scale
            fit.x, fit.r, fit.jac = x, r, jac
    return fit
