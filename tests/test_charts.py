"""The K&C charts tell what the errors measure (issue 19): force cases as changes from the
static state with the static values and each model's RMS error in the legend, a residual panel
under every chart with test data, torques in N*m, the paper's figure numbers, names that say
what is plotted. No solver: sweeps made by hand."""

from __future__ import annotations

import numpy as np
import pytest

from elastokin.report.charts import (
    CHARTS,
    ChartCanvas,
    chart_data,
    draw_chart,
    kc_charts,
    save_chart,
)
from elastokin.rig.comparison import curve_error_rms, static_value
from elastokin.rig.sweeps import Sweep

from .figure_checks import texts_outside_the_figure

PROV = {"elastokin_version": "0", "exudyn_version": "0", "config_file": "c.yaml",
        "config_sha256": "0" * 64}


def _force_path(amplitude: float, step: float) -> tuple[np.ndarray, np.ndarray]:
    """0 -> +a (rise), +a -> -a (fall), -a -> 0 (return): the rig's force sweep."""
    rise = np.arange(step, amplitude + step / 2, step)
    fall = np.arange(amplitude - step, -amplitude - step / 2, -step)
    ret = np.arange(-amplitude + step, step / 2, step)
    x = np.concatenate([rise, fall, ret])
    branch = np.array(["rise"] * rise.size + ["fall"] * fall.size + ["return"] * ret.size)
    return x, branch


def _sweep(model, case, x_name, x, branch, **columns):
    return Sweep(model, case, {"branch": branch, x_name: x,
                               **{k: np.asarray(v, float) for k, v in columns.items()}})


def _lateral(model: str, static: float, slope: float) -> Sweep:
    x, br = _force_path(2000.0, 50.0)
    return _sweep(model, "lateral_force", "lateral_force_N", x, br,
                  toe_deg=static + slope * x)


def test_force_case_plots_changes_from_static_with_static_value_and_rms_in_legend():
    test, model = _lateral("test", 0.203, 2.0e-5), _lateral("identified", 0.188, 1.5e-5)
    data = chart_data(CHARTS["steer_vs_lateral_force"], [test, model])
    lines = {m: (legend, x, y) for m, legend, x, y in data.lines}
    for sw in (test, model):
        legend, x, y = lines[sw.model]
        # the static value as the errors take it (the rig's first step, 50 N, when the sweep
        # starts one step from zero)
        static = static_value(sw, "lateral_force_N", "toe_deg")
        assert static == pytest.approx(sw.columns["toe_deg"][0])
        assert f"static {static:.3f} deg" in legend
        # the curve is the change from the static state
        assert np.allclose(y, sw.columns["toe_deg"] - static, atol=1e-15)
    rms = curve_error_rms(model, test, "lateral_force_N", "toe_deg")
    assert rms > 0.001
    assert f"RMS {rms:.4f} deg" in lines["identified"][0] and "RMS" not in lines["test"][0]
    # the static offset (0.015 deg) is not in the residuals: only the slope difference
    # (measured from the static value at the first step, 50 N)
    r = np.concatenate([p[2] for p in data.residuals["identified"]])
    xs = np.concatenate([p[1] for p in data.residuals["identified"]])
    assert np.allclose(r, -0.5e-5 * (xs - 50.0), atol=1e-12)
    assert "change from the static state" in data.ylabel
    assert data.title.endswith("(Fig. 9b)")


def test_summary_errors_label_the_fig9_legends():
    test, model = _lateral("test", 0.2, 2.0e-5), _lateral("initial", 0.2, 1.0e-5)
    data = chart_data(CHARTS["steer_vs_lateral_force"], [test, model],
                      {"initial": {"steer_vs_lateral_force_rms_deg": 0.1234}})
    assert "RMS 0.1234 deg" in data.lines[1][1]


def test_aligning_torque_in_newton_metres():
    x, br = _force_path(1.0e5, 2500.0)
    sw = _sweep("initial", "aligning_torque", "aligning_torque_Nmm", x, br,
                toe_deg=-2.0e-7 * x)
    data = chart_data(CHARTS["steer_vs_aligning_torque"], [sw])
    assert "[N*m]" in data.xlabel and "N*mm" not in data.xlabel
    assert np.max(np.abs(data.lines[0][2])) == pytest.approx(100.0)
    assert not data.residuals  # no test: no residual panel


def test_chart_names_and_titles():
    assert CHARTS["steer_vs_travel"].title.endswith("(Fig. 9a)")
    assert CHARTS["steer_vs_lateral_force"].title.endswith("(Fig. 9b)")
    assert CHARTS["longitudinal_displacement_vs_force"].title.endswith("(Fig. 9c)")
    assert "track_vs_travel" not in CHARTS
    spec = CHARTS["wheel_centre_lateral_vs_travel"]
    assert spec.y == "wheel_centre_lateral_mm" and "Wheel-centre lateral" in spec.title


def test_travel_chart_absolute_with_amplitude_rms_and_residual_panel(tmp_path):
    x = np.concatenate([np.arange(-90.0, 91.0), np.arange(89.0, -91.0, -1.0)])
    br = np.array(["stroke"] * 181 + ["return"] * 180)
    test = _sweep("test", "parallel_travel", "wheel_travel_mm", x, br,
                  toe_deg=0.2 - 0.003 * x)
    model = _sweep("identified", "parallel_travel", "wheel_travel_mm", x, br,
                   toe_deg=0.19 - 0.0028 * x)
    data = chart_data(CHARTS["steer_vs_travel"], [test, model])
    legend, _, y = data.lines[1][1:]
    assert y[90] == pytest.approx(0.19)  # absolute toe at zero travel
    assert "amplitude" in legend and "RMS" in legend and "static" not in legend
    assert data.residuals["identified"]
    paths = kc_charts([test, model], tmp_path, PROV)
    # only the charts whose columns the sweeps have (no camber, no lateral displacement); PNG
    # by default, SVG beside it when asked for
    assert [p.name for p in paths] == ["steer_vs_travel.png"]
    (tmp_path / "svg").mkdir()
    paths = kc_charts([test, model], tmp_path / "svg", PROV, svg=True)
    assert [p.name for p in paths] == ["steer_vs_travel.png", "steer_vs_travel.svg"]
    assert all(p.stat().st_size > 1000 for p in paths)
    assert paths[1].read_text().lstrip().startswith("<?xml")


def _pixels(path):
    from PIL import Image

    return np.asarray(Image.open(path).convert("RGB"))


def test_a_reused_figure_draws_what_a_new_one_draws(tmp_path):
    """The canvas is reused from chart to chart: a chart drawn after another (other layout,
    other limits, legend elsewhere) is pixel for pixel the chart drawn on a new canvas."""
    x, br = _force_path(2000.0, 50.0)
    lateral = [_lateral("test", 0.2, 2.0e-5), _lateral("identified", 0.19, 1.5e-5)]
    torque = [_sweep("initial", "aligning_torque", "aligning_torque_Nmm", 50.0 * x, br,
                     toe_deg=-2.0e-7 * 50.0 * x)]
    first = chart_data(CHARTS["steer_vs_lateral_force"], lateral)
    second = chart_data(CHARTS["steer_vs_aligning_torque"], torque)
    reused = ChartCanvas()
    for data, name in ((first, "a"), (second, "b"), (first, "c")):
        save_chart(draw_chart(reused, data, PROV), tmp_path / f"{name}.png")
    save_chart(draw_chart(ChartCanvas(), second, PROV), tmp_path / "b_new.png")
    save_chart(draw_chart(ChartCanvas(), first, PROV), tmp_path / "c_new.png")
    assert np.array_equal(_pixels(tmp_path / "b.png"), _pixels(tmp_path / "b_new.png"))
    assert np.array_equal(_pixels(tmp_path / "c.png"), _pixels(tmp_path / "c_new.png"))
    assert np.array_equal(_pixels(tmp_path / "a.png"), _pixels(tmp_path / "c.png"))
    assert _pixels(tmp_path / "a.png").shape == (990, 1050, 3)  # 7 x 6.6 in at 150 dpi


def test_legend_goes_to_the_emptiest_corner():
    from elastokin.report.charts import legend_corner

    class Axes:  # the limits are all legend_corner reads
        def get_xlim(self):
            return (0.0, 1.0)

        def get_ylim(self):
            return (0.0, 1.0)

    rising = (np.linspace(0, 1, 50), np.linspace(0, 1, 50))  # lower left to upper right
    assert legend_corner(Axes(), [rising], 4) == "upper left"
    falling = (np.linspace(0, 1, 50), np.linspace(1, 0, 50))
    assert legend_corner(Axes(), [falling], 4) == "upper right"
    high = (np.linspace(0, 1, 50), np.full(50, 0.95))
    assert legend_corner(Axes(), [high], 4) == "lower left"


@pytest.mark.parametrize("with_test", [False, True])
@pytest.mark.parametrize("name", list(CHARTS))
def test_every_label_lies_inside_the_figure(name, with_test):
    """The layouts have fixed margins: every text of every chart (title, axis labels, tick
    labels, legend, footer) must lie inside the figure, in the one-panel layout (no test
    data) and over the residual panel (with test data). Values of a realistic size."""
    spec = CHARTS[name]
    x, br = _force_path(2000.0, 50.0)
    if spec.stroke_only:  # rebound to bump, then back
        br = np.where(br == "fall", "stroke", "return")
    rng = np.random.default_rng(1)

    def sweep(model, slope):
        y = -12345.6 + slope * x + 0.01 * rng.standard_normal(x.size)
        return _sweep(model, spec.load_case, spec.x, x, br, **{spec.y: y})

    sweeps = [sweep("identified_stiffness", 1.5), sweep("initial", 1.2)]
    if with_test:
        sweeps.insert(0, sweep("test", 1.4))
    fig = draw_chart(ChartCanvas(), chart_data(spec, sweeps), PROV)
    assert any(ax.get_title() == spec.title for ax in fig.axes)
    assert texts_outside_the_figure(fig) == [], name


def test_a_quantity_that_does_not_change_is_drawn_flat():
    """A chart of solver noise (the toe of an axle that cannot steer, ~1e-16 deg) spans at
    least MIN_Y_SPAN about its middle, so it reads as the flat line it is; a real range is
    left as matplotlib scales it."""
    from elastokin.report.chart_canvas import MIN_Y_SPAN, ChartCanvas, floor_y_span

    _, ax, _, _ = ChartCanvas().axes(1)
    ax.plot([0.0, 1.0, 2.0], [1e-16, -2e-16, 0.0])
    floor_y_span(ax)
    y0, y1 = ax.get_ylim()
    assert y1 - y0 == pytest.approx(MIN_Y_SPAN) and abs(y0 + y1) < 1e-15
    ax.plot([0.0, 1.0], [0.0, 0.5])
    ax.relim()
    ax.autoscale(True)
    before = ax.get_ylim()
    floor_y_span(ax)
    assert ax.get_ylim() == before
