"""The axle's charts (issue 18, item 8): toe and camber vs roll angle per wheel, roll moment vs
roll angle with the roll stiffness, left and right steer vs steering-wheel angle with the
ideal Ackermann curve, kinematic roll centre height vs travel; the test overlaid by its
wheel. No solver: sweeps made by hand, the data checked (not the pixels)."""

from __future__ import annotations

import numpy as np
import pytest

from elastokin.physics.ackermann import ackermann_partner_steer_deg
from elastokin.report.axle_charts import (
    AXLE_CHART_LIST,
    AXLE_CHARTS,
    AxleChartInputs,
    axle_chart_caption,
    axle_chart_data,
    axle_chart_inputs,
    draw_axle_chart,
)
from elastokin.report.chart_canvas import ChartCanvas, save_chart
from elastokin.report.charts import CHARTS, chart_data, chart_jobs, draw_chart, kc_charts
from elastokin.rig.comparison import curve_error_rms
from elastokin.rig.sweeps import Sweep

from .figure_checks import texts_outside_the_figure

PROV = {"elastokin_version": "0", "exudyn_version": "0", "config_file": "c.yaml",
        "config_sha256": "0" * 64}
L_MM, T_MM = 2700.0, 1500.0
FIGURES = {"initial": {"roll_steer_left_deg_per_deg": 0.05,
                       "roll_steer_right_deg_per_deg": -0.05,
                       "roll_stiffness_Nmm_per_deg": 512345.0, "anti_roll_bar_share": None,
                       "percent_ackermann_lock": 42.04,
                       "roll_centre_height_mm": 100.0,
                       "roll_centre_height_force_based_mm": 101.5}}


def _path(amplitude: float, step: float) -> tuple[np.ndarray, np.ndarray]:
    """0 -> +a (rise), +a -> -a (fall), -a -> 0 (return): the rig's roll and steering path."""
    rise = np.arange(step, amplitude + step / 2, step)
    fall = np.arange(amplitude - step, -amplitude - step / 2, -step)
    ret = np.arange(-amplitude + step, step / 2, step)
    branch = np.array(["rise"] * rise.size + ["fall"] * fall.size + ["return"] * ret.size)
    return np.concatenate([rise, fall, ret]), branch


def roll(model: str, side: str, slope: float) -> Sweep:
    """Roll and vertical force: toe and camber of the wheel change by ``slope`` per deg on the
    left wheel, the opposite on the right; the roll moment (an axle channel) is in both."""
    phi, br = _path(2.0, 0.25)
    sign = 1.0 if side in ("left", "") else -1.0
    return Sweep(model, "roll_vertical_force",
                 {"branch": br, "roll_angle_deg": phi,
                  "toe_deg": 0.1 + sign * slope * phi + 0.002 * phi ** 2,
                  "camber_deg": -0.5 + sign * 6 * slope * phi,
                  "roll_moment_Nmm": 5.0e5 * phi}, side=side)


def steering(model: str, side: str) -> Sweep:
    """Steering: the left wheel steers 1/16 of the steering wheel, the right wheel 1/17 (more
    than 100 % Ackermann to the left, less to the right)."""
    swa, br = _path(400.0, 25.0)
    ratio = 16.0 if side == "left" else 17.0
    return Sweep(model, "steering", {"branch": br, "steering_wheel_angle_deg": swa,
                                     "steer_angle_deg": swa / ratio}, side=side)


def travel(model: str, side: str) -> Sweep:
    """Parallel travel with its approach (0 to -40 mm), the stroke and the return."""
    x = np.concatenate([np.arange(-4.0, -41.0, -4.0), np.arange(-40.0, 41.0, 4.0),
                        np.arange(36.0, -41.0, -4.0)])
    br = np.array(["approach"] * 10 + ["stroke"] * 21 + ["return"] * 20)
    return Sweep(model, "parallel_travel",
                 {"branch": br, "wheel_travel_mm": x, "pad_z_mm": x, "toe_deg": -0.003 * x,
                  "roll_centre_height_mm": 100.0 - 0.5 * x}, side=side)


@pytest.fixture
def sweeps() -> list[Sweep]:
    """The initial model on both wheels; after it (the charts draw the test first) the test
    of the config (left) side with side "" as a corner's test data have it, and of the right
    wheel with its side."""
    out = []
    for side in ("left", "right"):
        out += [roll("initial", side, 0.05), steering("initial", side),
                travel("initial", side)]
    return out + [roll("test", "", 0.06), roll("test", "right", 0.07)]


def find(sweeps: list[Sweep], model: str, case: str, side: str) -> Sweep:
    return next(sw for sw in sweeps if (sw.model, sw.load_case, sw.side) == (model, case, side))


INPUTS = AxleChartInputs("left", T_MM, L_MM, FIGURES)


def test_toe_vs_roll_angle_a_panel_per_wheel_with_its_test_and_rms(sweeps):
    spec = AXLE_CHARTS["toe_vs_roll_angle"]
    data = axle_chart_data(spec, sweeps, INPUTS)
    assert [p.title for p in data.panels] == ["left wheel", "right wheel"]
    assert data.legend_title == "roll steer [deg/deg]"
    assert data.xlabel.startswith("roll angle [deg]") and data.ylabel.startswith("toe [deg]")
    for panel, side, test_side in zip(data.panels, ("left", "right"), ("", "right")):
        assert [line[0] for line in panel.lines] == ["test", "initial"]
        test = find(sweeps, "test", "roll_vertical_force", test_side)
        model = find(sweeps, "initial", "roll_vertical_force", side)
        _, legend, x, y = panel.lines[1]
        assert np.array_equal(x, model.columns["roll_angle_deg"])  # every row, absolute
        assert np.array_equal(y, model.columns["toe_deg"])
        # this wheel's test: the config side's test has side "", the right one its own
        rms = curve_error_rms(model, test, "roll_angle_deg", "toe_deg")
        assert rms > 1e-3
        figure = FIGURES["initial"][f"roll_steer_{side}_deg_per_deg"]
        assert legend == f"initial: {figure:.4f}, RMS {rms:.4f} deg"
        assert panel.lines[0][1] == "test" and not panel.ideal
    # the test's slope differs by wheel (0.06 left, 0.07 right): two different errors
    assert data.panels[0].lines[1][1] != data.panels[1].lines[1][1].replace("-0.05", "0.05")


def test_a_test_sweep_without_side_is_the_config_sides_wheel(sweeps):
    right_config = AxleChartInputs("right", T_MM, L_MM, FIGURES)
    only_blank = [sw for sw in sweeps if not (sw.model == "test" and sw.side == "right")]
    data = axle_chart_data(AXLE_CHARTS["camber_vs_roll_angle"], only_blank, right_config)
    assert [m for m, *_ in data.panels[0].lines] == ["initial"]
    assert [m for m, *_ in data.panels[1].lines] == ["test", "initial"]
    data = axle_chart_data(AXLE_CHARTS["camber_vs_roll_angle"], only_blank, INPUTS)
    assert [m for m, *_ in data.panels[0].lines] == ["test", "initial"]
    assert [m for m, *_ in data.panels[1].lines] == ["initial"]
    assert "RMS" not in data.panels[1].lines[0][1]  # no test of that wheel: no error


def test_roll_moment_one_panel_in_newton_metres_with_the_roll_stiffness(sweeps):
    data = axle_chart_data(AXLE_CHARTS["roll_moment_vs_roll_angle"], sweeps, INPUTS)
    assert len(data.panels) == 1 and data.legend_title is None
    assert "[N*m]" in data.ylabel
    lines = {m: (legend, x, y) for m, legend, x, y in data.panels[0].lines}
    legend, x, y = lines["initial"]
    assert np.allclose(y, 500.0 * x)  # 5e5 N*mm/deg = 500 N*m/deg, the slope drawn
    # the summary's roll stiffness in N*m/deg; a figure that is None is left out
    assert legend.startswith("initial: roll stiffness 512.3 N*m/deg, RMS ")
    assert "anti-roll bar" not in legend
    assert "roll stiffness" in data.title


def test_steer_vs_steering_wheel_angle_with_the_ideal_ackermann_curves(sweeps):
    spec = AXLE_CHARTS["steer_vs_steering_wheel_angle"]
    data = axle_chart_data(spec, sweeps, INPUTS)
    left, right = data.panels
    assert left.lines[0][1] == "initial: 42.0"
    (model, x, ideal), = left.ideal
    # the left wheel's ideal angle from the right wheel's, over the fall (lock to lock)
    swa, br = _path(400.0, 25.0)
    fall = br == "fall"
    assert model == "initial" and np.array_equal(x, swa[fall])
    assert np.allclose(ideal, ackermann_partner_steer_deg(swa[fall] / 17.0, "right", L_MM,
                                                          T_MM))
    (_, x, ideal), = right.ideal
    assert np.allclose(ideal, ackermann_partner_steer_deg(swa[fall] / 16.0, "left", L_MM,
                                                          T_MM))
    # turning left (+) the outer (right) wheel's ideal is less than the inner's angle
    assert np.all(ideal[x > 0] < x[x > 0] / 16.0)
    # no wheelbase (no axle.vehicle): no ideal curve, and the caption says why
    bare = axle_chart_data(spec, sweeps, AxleChartInputs("left", T_MM, None, FIGURES))
    assert not bare.panels[0].ideal and not bare.panels[1].ideal
    assert "no axle.vehicle wheelbase" in axle_chart_caption(spec, False, False)
    assert "100 % Ackermann" in axle_chart_caption(spec, False, True)


def test_roll_centre_height_kinematic_without_the_approach(sweeps):
    data = axle_chart_data(AXLE_CHARTS["roll_centre_height_vs_travel"], sweeps, INPUTS)
    (model, legend, x, y), = data.panels[0].lines  # the axle's channel: the config side's
    sw = find(sweeps, "initial", "parallel_travel", "left")
    keep = sw.columns["branch"] != "approach"
    assert np.array_equal(x, sw.columns["wheel_travel_mm"][keep]) and x.size == 41
    assert np.allclose(y, 100.0 - 0.5 * x)
    assert legend == "initial: kinematic at static 100.0 mm, force-based 101.5 mm"
    assert "kinematic" in data.title
    caption = axle_chart_caption(AXLE_CHARTS["roll_centre_height_vs_travel"], False, False)
    assert "kinematic roll centre" in caption and "force-based" in caption


def test_charts_only_for_an_axle_and_the_load_cases_run(sweeps, tmp_path):
    # a corner (no axle inputs): the corner's charts only
    names = [p.name for p in kc_charts(sweeps, tmp_path, PROV)]
    assert names == ["steer_vs_travel.png"]
    # an axle: the corner's chart of the config side's wheel, then the axle's
    (tmp_path / "axle").mkdir()
    paths = kc_charts(sweeps, tmp_path / "axle", PROV, axle=INPUTS, svg=True)
    # (an independent axle: its roll centre from parallel travel, none in opposite travel)
    assert [p.name for p in paths if p.suffix == ".png"] == [
        "steer_vs_travel.png", *(f"{s.name}.png" for s in AXLE_CHART_LIST
                                 if s.name != "roll_centre_height_vs_opposite_travel")]
    assert all(p.stat().st_size > 1000 for p in paths) and len(paths) == 12
    jobs = chart_jobs(sweeps, tmp_path, PROV, None, False, INPUTS)
    corner = jobs[0][1]
    assert [m for m, *_ in corner.lines] == ["initial"]  # not the right wheel again
    # without the steering case, no steering chart
    no_steering = [sw for sw in sweeps if sw.load_case != "steering"]
    assert axle_chart_data(AXLE_CHARTS["steer_vs_steering_wheel_angle"], no_steering,
                           INPUTS) is None


def test_axle_chart_inputs_from_the_summary():
    summary = {"axle": {"config_side": "left", "track_mm": T_MM, "wheelbase_mm": L_MM},
               "models": {"test": {}, "initial": {"axle": FIGURES["initial"]}}}
    inputs = axle_chart_inputs(summary)
    assert inputs == AxleChartInputs("left", T_MM, L_MM, FIGURES)
    assert axle_chart_inputs({"models": {}}) is None  # a corner


def _pixels(path):
    from PIL import Image

    return np.asarray(Image.open(path).convert("RGB"))


def test_a_reused_canvas_draws_the_pair_as_a_new_one(sweeps, tmp_path):
    """The pair layout on the reused canvas: drawn after a corner chart and an axle chart of
    one panel, pixel for pixel the chart drawn on a new canvas."""
    pair = axle_chart_data(AXLE_CHARTS["steer_vs_steering_wheel_angle"], sweeps, INPUTS)
    single = axle_chart_data(AXLE_CHARTS["roll_moment_vs_roll_angle"], sweeps, INPUTS)
    corner = chart_data(CHARTS["steer_vs_travel"], [find(sweeps, "initial", "parallel_travel",
                                                          "left")])
    reused = ChartCanvas()
    save_chart(draw_axle_chart(reused, pair, PROV), tmp_path / "a.png")
    save_chart(draw_chart(reused, corner, PROV), tmp_path / "b.png")
    save_chart(draw_axle_chart(reused, single, PROV), tmp_path / "c.png")
    save_chart(draw_axle_chart(reused, pair, PROV), tmp_path / "d.png")
    save_chart(draw_axle_chart(ChartCanvas(), single, PROV), tmp_path / "c_new.png")
    assert np.array_equal(_pixels(tmp_path / "a.png"), _pixels(tmp_path / "d.png"))
    assert np.array_equal(_pixels(tmp_path / "c.png"), _pixels(tmp_path / "c_new.png"))
    assert _pixels(tmp_path / "a.png").shape == (750, 1050, 3)  # 7 x 5 in at 150 dpi


def opposite_travel(model: str) -> Sweep:
    """Opposite wheel travel of an axle joined by a flexible beam (the config side's wheel)
    with its roll centre."""
    sw = travel(model, "left")
    return Sweep(model, "opposite_travel", {**sw.columns, "roll_centre_height_mm":
                                            200.0 - 0.2 * sw.columns["wheel_travel_mm"]},
                 side="left")


def test_roll_centre_height_in_roll_on_a_twist_beam(sweeps):
    """On an axle joined by a flexible beam (a twist beam) the kinematic roll centre comes
    from opposite wheel travel: the parallel-travel chart is left out, the opposite-travel one
    drawn."""
    twist = [sw for sw in sweeps if sw.load_case != "parallel_travel"]
    twist += [opposite_travel("initial")]
    assert axle_chart_data(AXLE_CHARTS["roll_centre_height_vs_travel"], twist,
                           INPUTS) is None
    spec = AXLE_CHARTS["roll_centre_height_vs_opposite_travel"]
    data = axle_chart_data(spec, twist, INPUTS)
    (model, legend, x, y), = data.panels[0].lines
    assert np.allclose(y, 200.0 - 0.2 * x) and x.size == 41
    assert legend == "initial: kinematic at static 100.0 mm, force-based 101.5 mm"
    assert "in roll" in data.title
    assert "opposite wheel travel" in axle_chart_caption(spec, False, False)
    assert axle_chart_data(spec, sweeps, INPUTS) is None  # an independent axle: none


@pytest.mark.parametrize("name", [s.name for s in AXLE_CHART_LIST])
def test_every_label_of_an_axle_chart_lies_inside_the_figure(sweeps, name):
    sweeps = sweeps + [opposite_travel("initial")]
    data = axle_chart_data(AXLE_CHARTS[name], sweeps, INPUTS)
    assert texts_outside_the_figure(draw_axle_chart(ChartCanvas(), data, PROV)) == []
