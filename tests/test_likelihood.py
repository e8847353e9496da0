"""Maximum likelihood with an unknown error level per curve (identification/likelihood.py):
the profiled likelihood by hand, its gradient, and the fit against iteratively reweighted least
squares (whose fixed points it must find) on problems solved independently."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from elastokin.identification.likelihood import (
    Curves,
    linearised_step,
    maximum_likelihood_fit,
)


def test_scales_and_likelihood_by_hand():
    # curve 1: residuals 3, 4 -> mean square 12.5; curve 2: 0.001, -0.001, 0.001 -> 1e-6,
    # below its floor 0.01^2 = 1e-4
    curves = Curves(np.array([2, 3]), np.array([0.001, 0.01]))
    r = np.array([3.0, 4.0, 0.001, -0.001, 0.001])
    assert curves.scales(r) == pytest.approx([np.sqrt(12.5), 0.01])
    # L = 2 (ln 12.5 + 1) + 3 (ln 1e-4 + 1e-6 / 1e-4)
    expected = 2 * (np.log(12.5) + 1.0) + 3 * (np.log(1e-4) + 1e-2)
    assert curves.nll(r) == pytest.approx(expected, rel=1e-12)


@given(st.integers(0, 10_000))
@settings(max_examples=30, deadline=None)
def test_gradient_matches_finite_differences(seed):
    rng = np.random.default_rng(seed)
    curves = Curves(np.array([5, 7, 4]), np.array([0.01, 0.5, 0.1]))
    r0 = rng.normal(scale=[0.3] * 5 + [0.2] * 7 + [1.0] * 4)
    jac = rng.normal(size=(16, 3))
    x = rng.normal(scale=0.1, size=3)
    g = curves.gradient(r0 + jac @ x, jac)
    h = 1e-6
    fd = [(curves.nll(r0 + jac @ (x + h * e)) - curves.nll(r0 + jac @ (x - h * e))) / (2 * h)
          for e in np.eye(3)]
    assert g == pytest.approx(fd, rel=1e-5, abs=1e-7)


def _irls(A, b, curves, iterations=2000):
    """Iteratively reweighted least squares on a linear problem r = A x - b, to its fixed
    point: the reference the likelihood fit must agree with."""
    scale = np.ones(len(curves.sizes))
    x = np.zeros(A.shape[1])
    for _ in range(iterations):
        w = np.repeat(1.0 / scale, curves.sizes)
        x = np.linalg.lstsq(A * w[:, None], b * w, rcond=None)[0]
        new = curves.scales(A @ x - b)
        if np.max(np.abs(new / scale - 1.0)) < 1e-13:
            break
        scale = new
    return x


def test_linear_problem_matches_reweighted_least_squares():
    """Two curves of different noise levels on a straight line: the likelihood's stationary
    point is the fixed point of reweighting (each curve divided by its own residual RMS)."""
    rng = np.random.default_rng(7)
    t = np.linspace(0.0, 1.0, 40)
    A = np.vstack([np.column_stack([t, np.ones_like(t)])] * 2)
    b = A @ [2.0, -1.0] + np.r_[rng.normal(scale=0.01, size=40), rng.normal(scale=0.3,
                                                                             size=40)]
    curves = Curves(np.array([40, 40]), np.array([1e-3, 1e-3]))
    step, predicted = linearised_step(curves, -b, A, np.full(2, -10.0), np.full(2, 10.0))
    assert predicted > 0
    assert step == pytest.approx(_irls(A, b, curves), rel=1e-6)
    # weighted by residual level, the precise curve decides: closer to the truth than OLS
    ols = np.linalg.lstsq(A, b, rcond=None)[0]
    assert abs(step[0] - 2.0) < abs(ols[0] - 2.0)


def test_nonlinear_fit_finds_the_reweighting_fixed_point():
    """Exponential decays measured twice with different noise: the trust-region fit with
    exact Jacobians reaches the point where reweighted least squares stops moving."""
    rng = np.random.default_rng(3)
    t = np.linspace(0.0, 2.0, 30)
    noise = np.r_[rng.normal(scale=0.002, size=30), rng.normal(scale=0.05, size=30)]
    data = np.r_[1.5 * np.exp(-0.8 * t), 1.5 * np.exp(-0.8 * t)] + noise
    curves = Curves(np.array([30, 30]), np.array([1e-4, 1e-4]))
    tt = np.r_[t, t]

    def evaluate(x):
        model = x[0] * np.exp(-x[1] * tt)
        jac = np.column_stack([np.exp(-x[1] * tt), -x[0] * tt * np.exp(-x[1] * tt)])
        return model - data, jac

    fit = maximum_likelihood_fit(evaluate, np.array([1.0, 0.3]),
                                 (np.array([0.0, 0.0]), np.array([10.0, 10.0])),
                                 np.array([0.5, 0.5]), curves, xtol=1e-12, ftol=1e-14)
    assert fit.converged and fit.evaluations < 20
    # at the fixed point, weighted least squares with the curves' own scales does not move
    r, jac = evaluate(fit.x)
    w = np.repeat(1.0 / curves.scales(r), curves.sizes)
    dx = np.linalg.lstsq(jac * w[:, None], -r * w, rcond=None)[0]
    assert np.max(np.abs(dx)) < 1e-8
    assert fit.x == pytest.approx([1.5, 0.8], rel=5e-3)


def test_bounds_are_respected_and_an_unconverged_fit_says_so():
    curves = Curves(np.array([3]), np.array([1e-3]))

    def evaluate(x):  # wants x = -1, bounded below by 0
        return np.array([x[0] + 1.0, x[0] + 1.2, x[0] + 0.8]), np.ones((3, 1))

    fit = maximum_likelihood_fit(evaluate, np.array([0.5]), (np.array([0.0]),
                                                             np.array([5.0])),
                                 np.array([1.0]), curves)
    assert fit.converged and fit.x[0] == pytest.approx(0.0, abs=1e-9)
    short = maximum_likelihood_fit(evaluate, np.array([5.0]), (np.array([0.0]),
                                                               np.array([5.0])),
                                   np.array([0.01]), curves, max_evaluations=2)
    assert not short.converged and short.evaluations == 2
