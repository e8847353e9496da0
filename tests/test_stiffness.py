"""Bushing-stiffness identification (elastokin.stiffness) and its progressive law."""

import dataclasses

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from elastokin.config.schema.suspension import StiffnessIdentificationSpec
from elastokin.errors import ConfigError
from elastokin.identification.stiffness import Residuals, identify_stiffness, with_stiffness
from elastokin.identification.stiffness_results import effective_residual_count, stiffness_config
from elastokin.mbs.design import design_state
from elastokin.physics.laws import DirectionLaw, ProgressiveLaw
from elastokin.rig.load_cases import run_load_cases

from .conftest import make_suspension


# ------------------------------------------------------------------ the progressive law
def test_progressive_law_by_hand():
    law = ProgressiveLaw(DirectionLaw.linear(300.0), scale=1.5, cubic=0.01)
    # F = 1.5 * 300 * 2 * (1 + 0.01 * 4) = 936 N at 2 mm
    assert law(2.0) == pytest.approx(936.0)
    assert law(-2.0) == pytest.approx(-936.0)
    assert law.rate_at_zero == pytest.approx(450.0)
    assert not law.is_linear
    assert ProgressiveLaw(DirectionLaw.linear(300.0), 2.0).is_linear
    assert law.scaled(2.0)(2.0) == pytest.approx(1872.0)


@given(st.floats(-30.0, 30.0), st.floats(0.2, 5.0), st.floats(0.0, 0.5))
@settings(max_examples=80, deadline=None)
def test_progressive_law_inverse_and_closed_form(u, scale, cubic):
    base = DirectionLaw((-4.0, -2.0, 0.0, 2.0, 4.0), (-3000.0, -800.0, 0.0, 800.0, 3000.0))
    law = ProgressiveLaw(base, scale, cubic)
    assert law.deflection_at(law(u)) == pytest.approx(u, abs=1e-8)
    assert law.expression(u) == pytest.approx(law(u), rel=1e-12, abs=1e-9)


def test_progressive_law_tabulation_and_bad_parameters():
    law = ProgressiveLaw(DirectionLaw.linear(650.0), 1.2, 1.0 / 144.0)
    tab = law.tabulated(span=40.0)
    u = np.linspace(-8.0, 8.0, 33)
    # 81 points, denser near 0: piecewise-linear within 0.5 % of the cubic over +-8 mm
    assert np.allclose(tab(u), law(u), rtol=5e-3, atol=1e-6)
    with pytest.raises(ValueError, match="positive"):
        ProgressiveLaw(DirectionLaw.linear(1.0), 0.0)
    with pytest.raises(ValueError, match=">= 0"):
        ProgressiveLaw(DirectionLaw.linear(1.0), 1.0, -0.1)


# ------------------------------------------------------------------ statistics
def test_effective_residual_count():
    rng = np.random.default_rng(0)
    white = rng.normal(size=2000)
    # white noise: every residual independent (AR(1) estimate ~ n)
    assert effective_residual_count(white, [2000]) == pytest.approx(2000, rel=0.1)
    # a smooth curve is worth about one residual; two curves about two
    smooth = np.r_[np.linspace(0.0, 1.0, 500), np.sin(np.linspace(0.0, 3.0, 500))]
    assert effective_residual_count(smooth, [500, 500]) < 5


# ------------------------------------------------------------------ fitting
@pytest.fixture(scope="module")
def coarse():
    """The nominal pseudo-McPherson on a coarse rig (fast sweeps) and its design preloads."""
    from elastokin.config.loading import read_yaml

    from .conftest import CASE

    data = read_yaml(CASE)[0]
    data.pop("measurements")
    data.pop("axle")  # the stiffness fit works on a corner
    data.pop("kc_test")
    data["rig"] = {"parallel_travel": {"step_mm": 10.0},
                   "vertical_force": {"step_N": 500.0},
                   "lateral_force": {"step_N": 250.0},
                   "longitudinal_force_patch": {"step_N": 250.0},
                   "longitudinal_force_centre": None,
                   "aligning_torque": None}
    s = make_suspension(data, "coarse.yaml")
    return s, design_state(s)


HIDDEN = {"J1": {"translation_scale": 1.3}, "J2": {"translation_scale": 0.85},
          "J4": {"translation_scale": 1.15}}


def _test_sweeps(s, design, values, noise=None, seed=0):
    res = Residuals(s, design, [], StiffnessIdentificationSpec())
    sweeps = run_load_cases(res.model(values), "test")
    rng = np.random.default_rng(seed)
    out = []
    for sw in sweeps:
        cols = dict(sw.columns)
        for c, unit_sd in (noise or {}).items():
            if c in cols and c != "wheel_travel_mm" or (c == "wheel_travel_mm" and
                                                          sw.load_case != "parallel_travel"):
                cols[c] = cols[c] + rng.normal(scale=unit_sd, size=cols[c].size)
        out.append(dataclasses.replace(sw, columns=cols))
    return out


def test_recovers_known_scale_factors_without_noise(coarse):
    s, design = coarse
    test = _test_sweeps(s, design, HIDDEN)
    spec = StiffnessIdentificationSpec(parameters=["translation_scale"])
    fit = identify_stiffness(s, design, test, spec, ftol=1e-14, xtol=1e-14)
    for p in fit.parameters:
        # data made by the model itself: only the solver's tolerance is left
        assert p.value == pytest.approx(HIDDEN[p.bushing][p.name], rel=1e-6), p
    assert fit.residual_rms_after < 1e-6 * fit.residual_rms_before
    assert fit.errors_after["longitudinal_displacement_rms_mm"] < 1e-5


# rig noise: 0.005 deg on angles, 0.05 mm on displacements (white)
NOISE = {"toe_deg": 0.005, "camber_deg": 0.005, "wheel_centre_longitudinal_mm": 0.05,
         "wheel_centre_lateral_mm": 0.05, "wheel_travel_mm": 0.05}


def test_noisy_data_truth_inside_the_confidence_interval(coarse):
    s, design = coarse
    test = _test_sweeps(s, design, HIDDEN, noise=NOISE, seed=3)
    spec = StiffnessIdentificationSpec(parameters=["translation_scale"])
    fit = identify_stiffness(s, design, test, spec)
    for p in fit.parameters:
        truth = HIDDEN[p.bushing][p.name]
        assert p.ci95[0] <= truth <= p.ci95[1], p
        assert p.ci95[1] - p.ci95[0] < 0.2 * truth  # and the interval is informative
    assert np.all(np.abs(fit.correlation) <= 1.0 + 1e-12)
    assert np.isfinite(fit.condition_number) and fit.condition_number >= 1.0


def test_fit_is_the_same_on_one_or_two_worker_processes(coarse):
    """A model run's load cases spread over processes: each run is deterministic, so the fit
    (values, intervals, model-run count) must be identical, not merely close."""
    s, design = coarse
    test = _test_sweeps(s, design, HIDDEN, noise=NOISE, seed=5)
    spec = StiffnessIdentificationSpec(parameters=["translation_scale"])
    serial = identify_stiffness(s, design, test, spec, workers=1)
    pooled = identify_stiffness(s, design, test, spec, workers=2)
    assert pooled.settings["workers"] == 2 and serial.settings["workers"] == 1
    assert [p.value for p in pooled.parameters] == [p.value for p in serial.parameters]
    assert [p.ci95 for p in pooled.parameters] == [p.ci95 for p in serial.parameters]
    assert pooled.evaluations == serial.evaluations


def test_parameter_without_effect_is_flagged_not_determined(coarse):
    s, design = coarse
    test = _test_sweeps(s, design, {"J1": {"translation_scale": 1.2}}, noise=NOISE, seed=4)
    # J1's rotational rate barely moves any channel (the arm turns in its ball joint)
    spec = StiffnessIdentificationSpec(bushings=["J1"],
                                       parameters=["translation_scale", "rotation_scale"])
    fit = identify_stiffness(s, design, test, spec)
    by = {p.name: p for p in fit.parameters}
    assert by["translation_scale"].determined
    assert by["translation_scale"].ci95[0] <= 1.2 <= by["translation_scale"].ci95[1]
    assert not by["rotation_scale"].determined
    assert any("J1.rotation_scale: not determined" in w for w in fit.warnings)


def test_fitted_config_reproduces_the_fitted_model(coarse):
    from elastokin.config.loading import read_yaml
    from elastokin.mbs.design import build_model
    from elastokin.rig.load_cases import static_equilibrium

    from .conftest import CASE

    s, design = coarse
    values = {"J1": {"translation_scale": 1.3, "translation_cubic": 0.01}}
    fitted = with_stiffness(s, values)

    class Fit:  # the two fields stiffness_config reads
        suspension = fitted
        values = {"J1": {"translation_scale": 1.3, "translation_cubic": 0.01}}
        parameters = []

    Fit.design = design
    data = read_yaml(CASE)[0]
    data.pop("measurements")
    data.pop("axle")  # the stiffness fit works on a corner
    data.pop("kc_test")
    data["rig"] = s.raw["rig"]
    cfg = stiffness_config(data, Fit)
    assert isinstance(cfg["connections"]["J1"]["stiffness"]["x"], dict)  # a curve
    again = make_suspension(cfg, "fitted.yaml")
    a = static_equilibrium(Residuals(s, design, [], StiffnessIdentificationSpec())
                           .model(values)).state
    b = static_equilibrium(build_model(again)).state
    # the tabulated curve (81 points) against the exact cubic: same static state
    assert np.allclose(a.wheel_centre_mm, b.wheel_centre_mm, atol=1e-3)


def test_unknown_bushing_is_a_clear_error(coarse):
    s, design = coarse
    spec = StiffnessIdentificationSpec(bushings=["J9"])
    with pytest.raises(ConfigError, match=r"stiffness_identification.bushings.*J9.*J1"):
        identify_stiffness(s, design, [], spec)


def test_spec_rejects_unknown_and_repeated_parameters():
    with pytest.raises(ValueError):
        StiffnessIdentificationSpec(parameters=["translation_scale", "translation_scale"])
    with pytest.raises(ValueError):
        StiffnessIdentificationSpec(parameters=["radial_scale"])


def test_unconverged_fit_keeps_its_best_values_with_a_warning(coarse):
    """Two model runs cannot fit six parameters: the fit says so, keeps the best point it
    reached (better than the nominal laws) and still reports intervals."""
    s, design = coarse
    test = _test_sweeps(s, design, HIDDEN, noise=NOISE, seed=6)
    spec = StiffnessIdentificationSpec(parameters=["translation_scale", "translation_cubic"],
                                       weighting="residual")
    fit = identify_stiffness(s, design, test, spec, max_iterations=2)
    assert any("did not converge in 2 model runs" in w and "last good values" in w
               for w in fit.warnings)
    assert fit.residual_rms_after < fit.residual_rms_before
    assert all(np.isfinite(p.value) for p in fit.parameters)


def test_residual_weighting_recovers_the_truth_with_curves_of_different_noise(coarse):
    """weighting 'residual' (maximum likelihood with a noise level per curve): toe and
    camber with 0.002 deg, displacements with 0.2 mm of noise: every scale recovered within
    four standard errors (a 95 % interval misses the truth one time in twenty, and three
    parameters are checked), in one pass, and each curve's scale near its noise level."""
    s, design = coarse
    noise = {"toe_deg": 0.002, "camber_deg": 0.002, "wheel_centre_longitudinal_mm": 0.2,
             "wheel_centre_lateral_mm": 0.2, "wheel_travel_mm": 0.2}
    test = _test_sweeps(s, design, HIDDEN, noise=noise, seed=8)
    spec = StiffnessIdentificationSpec(parameters=["translation_scale"], weighting="residual",
                                       residual_scale_deg=1e-4, residual_scale_mm=1e-3)
    fit = identify_stiffness(s, design, test, spec)
    assert fit.passes == 1 and not [w for w in fit.warnings if "converge" in w]
    assert fit.to_json()["passes"] == fit.settings["passes"] == 1  # as the JSON has written it
    for p in fit.parameters:
        assert abs(p.value - HIDDEN[p.bushing][p.name]) <= 4 * p.std, p
        assert p.std < 0.01  # informative
    scales = fit.settings["curve_scales"]
    # a curve's maximum-likelihood scale is its residual RMS: the noise of its channel
    # (within 30 %: 8 to 30 points per curve on the coarse rig)
    assert scales["lateral_force.toe_deg"] == pytest.approx(0.002, rel=0.3)
    assert scales["lateral_force.wheel_centre_lateral_mm"] == pytest.approx(0.2, rel=0.3)
