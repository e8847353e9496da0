"""Nothing in elastokin is specific to the pseudo-McPherson: a double wishbone with revolute
joints, a revolute-type bushing with a nonlinear torsion curve, a steering rack and a spring
on the lower arm builds, balances and runs through ``elastokin kc``."""

import json
from pathlib import Path

import numpy as np
from click.testing import CliRunner

from elastokin.cli import main
from elastokin.config import load_suspension
from elastokin.geometry import slope
from elastokin.kc import parallel_travel, static_equilibrium
from elastokin.model import ModelOptions, build_model, design_state

DW = Path(__file__).parent / "data" / "double_wishbone.yaml"


def test_double_wishbone_runs_and_is_balanced():
    s = load_suspension(DW)
    design = design_state(s)
    model = build_model(s, ModelOptions(), design)
    static = static_equilibrium(model)
    np.testing.assert_allclose(static.state.wheel_centre_mm, s.wheel.centre_mm, atol=1e-3)
    assert static.wheel_assembly_force_residual_N < 1e-3
    sweep = parallel_travel(model, "initial")
    travel = sweep.stroke("wheel_travel_mm")
    assert travel.min() < -55 and travel.max() > 55
    # a short upper arm over a long lower arm gains negative camber in bump; the steering
    # rack behind the axle with its tie rod below the ball-joint line toes out in bump
    camber_gain = slope(travel, sweep.stroke("camber_deg"), (-10, 10))
    bump_steer = slope(travel, sweep.stroke("toe_deg"), (-10, 10))
    assert camber_gain < 0 and bump_steer < 0


def test_double_wishbone_cli(tmp_path):
    out = tmp_path / "dw"
    result = CliRunner().invoke(main, ["kc", "--config", str(DW), "--out", str(out), "--quiet"])
    assert result.exit_code == 0, result.output
    summary = json.loads((out / "summary.json").read_text())
    assert set(summary["models"]) == {"initial", "initial_kinematic"}
    assert "lca_bushing" in summary["static"]["bushings"]
