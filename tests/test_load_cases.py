"""The virtual K&C rig's force load cases, gradients and compliance matrix."""

import numpy as np
import pytest

from elastokin.mbs.design import build_model
from elastokin.mbs.model import ModelOptions
from elastokin.rig.channels import GRADIENTS
from elastokin.rig.load_cases import (
    compliance_matrix,
    force_sweep,
    run_load_cases,
    static_equilibrium,
)
from elastokin.rig.paths import sweep_path
from elastokin.studies.kc_job import ModelResult


@pytest.fixture(scope="module")
def model(case, case_design):
    return build_model(case, ModelOptions(), case_design)


@pytest.fixture(scope="module")
def sweeps(model):
    return run_load_cases(model, "initial")


def test_sweep_path_by_hand():
    values, branch = sweep_path(100.0, 50.0)
    np.testing.assert_allclose(values, [50, 100, 50, 0, -50, -100, -50, 0])
    assert list(branch) == ["rise"] * 2 + ["fall"] * 4 + ["return"] * 2


def test_every_load_case_runs(sweeps):
    """The corner's cases, then the axle's (the case study is a mirrored axle without
    steering; no static loads are given)."""
    assert [sw.load_case for sw in sweeps] == [
        "parallel_travel", "vertical_force", "lateral_force", "longitudinal_force_patch",
        "longitudinal_force_centre", "aligning_torque", "opposite_travel",
        "single_wheel_travel", "roll_vertical_force", "lateral_force_anti_phase"]


def test_loading_and_unloading_coincide_without_friction(sweeps):
    """An elastic model has no hysteresis: at the same lateral force the rise and fall
    branches give the same toe (to the Newton tolerance)."""
    sw = next(s for s in sweeps if s.load_case == "lateral_force")
    f, toe, branch = sw.columns["lateral_force_N"], sw.columns["toe_deg"], sw.columns["branch"]
    for value in (1000.0, 500.0):
        rise = toe[(branch == "rise") & np.isclose(f, value)]
        fall = toe[(branch == "fall") & np.isclose(f, value)]
        assert rise.size == fall.size == 1
        assert rise[0] == pytest.approx(fall[0], abs=1e-7)


def test_zero_load_steps_are_the_static_equilibrium(model, sweeps):
    static = static_equilibrium(model)
    sw = next(s for s in sweeps if s.load_case == "longitudinal_force_patch")
    last = {k: v[-1] for k, v in sw.columns.items()}  # back at 0 N
    assert last["longitudinal_force_N"] == 0
    np.testing.assert_allclose([last["wheel_centre_x_mm"], last["wheel_centre_y_mm"],
                                last["wheel_centre_z_mm"]], static.state.wheel_centre_mm,
                               atol=1e-6)


@pytest.fixture(scope="module")
def compliance(model):
    return compliance_matrix(model)


def test_compliance_matrix_is_reciprocal(compliance):
    """Maxwell-Betti: an elastic structure loaded at one point has a symmetric compliance
    (rotations in rad against torques in N*mm); an independent check of the solver, the
    loads and the output signs. 1e-3 relative: central differences of a nonlinear model."""
    C = compliance.copy()
    C[3:, :] = np.radians(C[3:, :])
    scale = np.sqrt(np.outer(np.abs(np.diag(C)), np.abs(np.diag(C))))
    assert np.max(np.abs(C - C.T) / scale) < 1e-3
    assert np.all(np.diag(C) > 0)  # every load moves the wheel with it


def test_compliance_matrix_predicts_a_small_load(case, model, compliance):
    """Linearisation consistency: C times the first step of the traction sweep (50 N at the
    wheel centre) gives the sweep's displacement; 1 % allows for the nonlinearity (0.1 %
    measured)."""
    sw = force_sweep(model, "initial", "longitudinal_force_centre")
    static = static_equilibrium(model)
    force = sw.columns["longitudinal_force_N"][0]
    moved = np.array([sw.columns[f"wheel_centre_{a}_mm"][0] for a in "xyz"])
    predicted = compliance[:3, :3] @ (force * case.forward)
    actual = moved - static.state.wheel_centre_mm
    assert np.linalg.norm(predicted - actual) < 0.01 * np.linalg.norm(actual)


def test_gradients_in_the_summary(sweeps, compliance):
    summary = ModelResult("initial", False, sweeps, {}, compliance).summary()
    for name in GRADIENTS:
        assert isinstance(summary[name], float), name
    # signs that physics fixes: the wheel gives way in the direction of a load
    assert summary["longitudinal_compliance_mm_per_kN"] > 0
    assert summary["lateral_compliance_mm_per_kN"] > 0
    assert summary["wheel_rate_N_per_mm"] > 0
    assert len(summary["compliance_matrix"]["values"]) == 6
