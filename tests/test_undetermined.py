"""Not determined is not zero (issue 24, item 5): a least-squares slope with fewer than three
distinct points in its window is NaN in memory, null in summary.json, a dash in the console
and the report, with a warning naming the model, the characteristic, the window and the
remedy. One rule (elastokin.physics.wheel.slope) for every windowed characteristic: bump
steer, the gradients (compliances, wheel rate), the roll slopes, the on-centre steering
ratio. Hand-made data, and one K&C job on the double wishbone axle with a coarse rig."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from elastokin.config.loading import load_suspension_with_rig
from elastokin.physics import axle_sweeps
from elastokin.physics.wheel import (
    UndeterminedSlopeWarning,
    distinct_count,
    slope,
    windowed_slope,
)
from elastokin.report.files import summary_dict
from elastokin.report.text import kc_table
from elastokin.rig.characteristics import summary_figures
from elastokin.rig.sweeps import Sweep
from elastokin.studies.kc_job import run_kc

from .conftest import ROOT


def test_three_distinct_points_or_nan():
    x, y = np.array([-1.0, 0.0, 2.0]), np.array([1.0, 2.0, 5.0])
    assert slope(x, y) == pytest.approx(np.polyfit(x, y, 1)[0], rel=1e-14)
    with pytest.warns(UndeterminedSlopeWarning, match=r"^wheel rate not determined \(null\): "
                      r"2 distinct points within -1 <= x <= 1, a least-squares slope needs "
                      r"at least 3; finer steps$"):
        assert np.isnan(slope(x, y, (-1.0, 1.0), what="wheel rate", remedy="finer steps"))


def test_loading_and_unloading_at_one_input_count_once():
    """A rig's rise and fall through one force give wheel travels equal to the solver's
    rounding: one point, not two (the vertical force swept 1000 -> 7500 -> 1000 N in one step
    fitted a 'slope' through two points)."""
    travel = np.array([-20.0, 30.0, -20.0 + 3e-12])
    assert distinct_count(travel) == 2
    with pytest.warns(UndeterminedSlopeWarning, match="2 distinct points"):
        assert np.isnan(slope(travel, [1000.0, 7500.0, 1000.0]))
    assert distinct_count(np.array([0.0, 1e-6, 2e-6])) == 3  # small, but the data's scale


def test_a_coarse_grid_leaves_the_bump_steer_window_undetermined():
    x = np.array([-90.0, -30.0, 30.0, 90.0])  # 60 mm steps: two points within +-50 mm
    with pytest.warns(UndeterminedSlopeWarning, match=r"2 distinct points within \|x\| <= 50"):
        assert np.isnan(windowed_slope(x, 0.004 * x, 50.0))
    x = np.array([-90.0, -45.0, 0.0, 45.0, 90.0])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert windowed_slope(x, 0.004 * x, 50.0) == pytest.approx(0.004, rel=1e-12)


def test_roll_slopes_follow_the_rule():
    with pytest.warns(UndeterminedSlopeWarning, match=r"^model 'm': roll stiffness not "
                      r"determined \(null\): 1 distinct point of roll angle"):
        assert np.isnan(axle_sweeps.roll_stiffness_Nmm_per_deg([0.0, 0.0], [1.0, 2.0],
                                                               subject="model 'm': "))


def _sweep(case: str, columns: dict, branch: list[str]) -> Sweep:
    return Sweep("initial", case, {"branch": np.array(branch),
                                   **{k: np.asarray(v, float) for k, v in columns.items()}},
                 side="right")


def test_summary_figures_null_with_the_reason():
    """Wheel rate from a one-step vertical force sweep and bump steer from a 60 mm travel
    grid: None, each with a warning naming the model, the wheel, the figure and the remedy;
    a determined figure beside them is a number."""
    z = np.array([0.0, -60.0, 0.0, 60.0, 0.0, -60.0])
    travel = _sweep("parallel_travel", {"pad_z_mm": z, "wheel_travel_mm": z, "toe_deg": 1e-3 * z,
                                        "camber_deg": -2e-3 * z},
                    ["approach", "stroke", "stroke", "stroke", "return", "return"])
    force = _sweep("vertical_force", {"vertical_force_N": [4000, 1000, 7500, 1000],
                                      "wheel_travel_mm": [0.0, -20.0, 30.0, -20.0]},
                   ["approach", "rise", "rise", "fall"])
    with pytest.warns(UndeterminedSlopeWarning) as caught:
        out = summary_figures([travel, force], False)
    assert out["bump_steer_deg_per_m"] is None and out["wheel_rate_N_per_mm"] is None
    assert out["bump_camber_deg_per_m"] == pytest.approx(-2.0)
    text = [str(w.message) for w in caught]
    assert any(m.startswith("model 'initial', right wheel: wheel rate (wheel_rate_N_per_mm) "
                            "not determined (null): 2 distinct points of wheel_travel_mm in "
                            "the vertical_force sweep") and "a finer step of the rig's "
                            "vertical_force gives it" in m for m in text), text
    assert any("bump steer" in m and "1 distinct point of wheel travel within +-50 mm" in m
               for m in text), text


def test_coarse_rig_through_the_job(tmp_path):
    """The on-centre steering ratio with a steering step wider than its +-20 deg window
    printed 0.00; now null in summary.json and '-' in the console table, with the warning in
    summary.json (the report's dash: tests/test_report.py). The roll stiffness beside it is
    a number."""
    rig = tmp_path / "coarse.yaml"
    rig.write_text(
        "parallel_travel: {rebound_mm: -60, bump_mm: 60, step_mm: 60, unloading: false}\n"
        "roll_vertical_force: {amplitude_deg: 1.0, step_deg: 0.5}\n"
        "steering: {amplitude_deg: 100.0, step_deg: 50.0}\n" + "".join(
            f"{c}: null\n" for c in ("vertical_force", "lateral_force",
                                     "longitudinal_force_patch", "longitudinal_force_centre",
                                     "aligning_torque", "opposite_travel",
                                     "single_wheel_travel", "lateral_force_anti_phase")))
    s = load_suspension_with_rig(ROOT / "configs" / "double_wishbone_axle.yaml", rig)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UndeterminedSlopeWarning)
        summary = summary_dict(run_kc(s, models=["initial"]), [])
    m = summary["models"]["initial"]
    assert m["bump_steer_deg_per_m"] is None and m["right"]["bump_steer_deg_per_m"] is None
    assert m["axle"]["steering_ratio_centre"] is None
    assert m["axle"]["roll_stiffness_Nmm_per_deg"] > 0
    why = [w for w in summary["warnings"] if "steering ratio on centre" in w]
    assert len(why) == 1 and ("1 distinct point with the steering-wheel angle within +-20 deg"
                              in why[0] and "finer step of the rig's steering" in why[0]), why
    assert sum("bump steer" in w for w in summary["warnings"]) == 2  # both wheels
    table = kc_table(summary, tmp_path).splitlines()
    assert next(ln for ln in table if ln.startswith("  initial ")).split()[-1] == "-"
    assert not any(ln.strip().startswith("steering ratio on centre") for ln in table)
