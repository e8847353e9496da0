"""Charts of an axle run (issue 18, item 8): toe and camber vs roll angle (each wheel in its
own panel), roll moment vs roll angle (its slope is the roll stiffness), left and right
road-wheel steer angle vs steering-wheel angle with the ideal (100 %) Ackermann curve, and the
kinematic roll centre height vs parallel wheel travel. Drawn only when the run has the load
case and the channel (an axle); labels, units and signs from the channel table.

Every curve is absolute (the roll, steering and travel cases move the wheels, as parallel
travel does); every measured row is drawn, loading and unloading (the approach left out). Each
model's legend entry carries the axle's figure of the chart from summary.json
(``models.<label>.axle``: roll steer, roll camber, roll stiffness, percent Ackermann, roll
centre heights) and, with test data of that wheel, the RMS error against the test (changes
from the static state at the test points, as every chart's:
:func:`elastokin.rig.comparison.residual_points`). A test sweep whose side is "" is the
config side's wheel.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from elastokin.physics.ackermann import ackermann_partner_steer_deg
from elastokin.report.chart_canvas import (
    LEGEND_FORMATS,
    STYLE,
    ChartCanvas,
    corner_counts,
    floor_y_span,
    footer_text,
    legend_height,
    residual_rms,
)
from elastokin.report.text import axle_models
from elastokin.rig.channels import (
    AXLE_CHARACTERISTICS,
    LOAD_CASES,
    channel,
    display_label,
    display_unit,
)
from elastokin.rig.comparison import residual_points
from elastokin.rig.sweeps import Sweep

SIDES = ("left", "right")


@dataclass(frozen=True)
class LegendFigure:
    """An axle figure a chart's legend gives per model: summary.json
    ``models.<label>.axle[key]`` (``{side}``: the panel's wheel), times ``factor`` in
    ``unit``."""

    key: str
    label: str
    unit: str
    fmt: str
    factor: float = 1.0

    @classmethod
    def as_reported(cls, key: str, label: str) -> LegendFigure:
        """The figure ``key`` as the report's table has it: in the unit the report shows
        (:func:`~elastokin.rig.channels.display_unit`), in the channel table's format."""
        c = AXLE_CHARACTERISTICS[key]
        unit, factor = display_unit(c.unit)
        return cls(key, label, unit, c.fmt, factor)


@dataclass(frozen=True)
class AxleChartSpec:
    """One axle chart: ``y`` against ``x`` of ``load_case``, every model overlaid;
    ``per_wheel``: a panel per wheel (left, right), else the axle's channel (the same in both
    wheels' sweeps) from the config side's; ``ideal_ackermann``: each model's 100 % Ackermann
    curve too (needs the wheelbase)."""

    name: str
    load_case: str
    x: str
    y: str
    title: str
    per_wheel: bool
    figures: tuple[LegendFigure, ...] = ()
    ideal_ackermann: bool = False


#: the axle's charts, in order (after the corner's)
AXLE_CHART_LIST = (
    AxleChartSpec("toe_vs_roll_angle", "roll_vertical_force", "roll_angle_deg", "toe_deg",
                  "Toe vs roll angle (roll and vertical force)", True,
                  (LegendFigure("roll_steer_{side}_deg_per_deg", "roll steer", "deg/deg",
                                ".4f"),)),
    AxleChartSpec("camber_vs_roll_angle", "roll_vertical_force", "roll_angle_deg",
                  "camber_deg", "Camber vs roll angle (roll and vertical force)", True,
                  (LegendFigure("roll_camber_{side}_deg_per_deg", "roll camber", "deg/deg",
                                ".4f"),)),
    AxleChartSpec("roll_moment_vs_roll_angle", "roll_vertical_force", "roll_angle_deg",
                  "roll_moment_Nmm", "Roll moment vs roll angle: the slope is the roll "
                  "stiffness", False,
                  (LegendFigure.as_reported("roll_stiffness_Nmm_per_deg", "roll stiffness"),
                   LegendFigure("anti_roll_bar_share", "anti-roll bar share", "%", ".0f",
                                100.0))),
    AxleChartSpec("steer_vs_steering_wheel_angle", "steering", "steering_wheel_angle_deg",
                  "steer_angle_deg", "Road-wheel steer angle vs steering-wheel angle", True,
                  (LegendFigure("percent_ackermann_lock", "Ackermann at the left lock", "%",
                                ".1f"),),
                  ideal_ackermann=True),
    AxleChartSpec("roll_centre_height_vs_travel", "parallel_travel", "wheel_travel_mm",
                  "roll_centre_height_mm",
                  "Roll centre height (kinematic) vs parallel wheel travel", False,
                  (LegendFigure("roll_centre_height_mm", "kinematic at static", "mm", ".1f"),
                   LegendFigure("roll_centre_height_force_based_mm", "force-based", "mm",
                                ".1f"))),
    # an axle joined by a flexible beam (a twist beam): the kinematic roll centre in roll
    AxleChartSpec("roll_centre_height_vs_opposite_travel", "opposite_travel",
                  "wheel_travel_mm", "roll_centre_height_mm",
                  "Roll centre height (kinematic, in roll) vs opposite wheel travel", False,
                  (LegendFigure("roll_centre_height_mm", "kinematic at static", "mm", ".1f"),
                   LegendFigure("roll_centre_height_force_based_mm", "force-based", "mm",
                                ".1f"))),
)
AXLE_CHARTS = {c.name: c for c in AXLE_CHART_LIST}


@dataclass(frozen=True)
class AxleChartInputs:
    """What the axle charts take from summary.json besides the sweeps: the config's side
    (a test sweep of side "" is its wheel's), the design track at the contact points [mm],
    the wheelbase [mm] (None: no vehicle data, no ideal Ackermann curve) and each model's
    axle figures (``models.<label>.axle``)."""

    config_side: str
    track_mm: float
    wheelbase_mm: float | None = None
    figures: dict[str, dict] = field(default_factory=dict)


def axle_chart_inputs(summary: dict) -> AxleChartInputs | None:
    """The axle charts' inputs from summary.json's content (None for a corner)."""
    axle = summary.get("axle")
    if not axle:
        return None
    return AxleChartInputs(axle["config_side"], axle["track_mm"], axle.get("wheelbase_mm"),
                           axle_models(summary))


@dataclass
class Panel:
    """One panel: its title (the wheel, or "" for the axle's channel), per sweep ``(model,
    legend, x, y)`` and per model the ideal Ackermann curve ``(model, x, y)``, in the units
    shown."""

    title: str
    lines: list[tuple[str, str, np.ndarray, np.ndarray]]
    ideal: list[tuple[str, np.ndarray, np.ndarray]] = field(default_factory=list)


@dataclass
class AxleChartData:
    """What one axle chart draws: one panel (the axle's channel) or two (left, right)."""

    panels: list[Panel]
    xlabel: str
    ylabel: str
    title: str
    legend_title: str | None = None


def wheel_sweeps(sweeps: list[Sweep], load_case: str, side: str,
                 config_side: str) -> list[Sweep]:
    """The sweeps of ``load_case`` on the wheel of ``side``, in the order given (a sweep of
    side "", e.g. a corner's test data, is the config side's wheel)."""
    return [sw for sw in sweeps if sw.load_case == load_case
            and (sw.side or config_side) == side]


def _label(column: str) -> str:
    c = channel(column)
    return display_label(c.label, c.unit)


def _rows(sw: Sweep, spec: AxleChartSpec) -> tuple[np.ndarray, np.ndarray]:
    """Every measured row (the approach left out), in the units shown."""
    keep = sw.columns["branch"] != "approach"
    fx = display_unit(channel(spec.x).unit)[1]
    fy = display_unit(channel(spec.y).unit)[1]
    return sw.columns[spec.x][keep] * fx, sw.columns[spec.y][keep] * fy


def _legend(model: str, spec: AxleChartSpec, side: str, figures: dict,
            rms: float | None) -> str:
    """A model's legend entry: its figures (on a wheel's panel, values only: the legend's
    title names them, :func:`legend_title`) and its RMS error against the test."""
    bits = []
    for f in spec.figures:
        value = figures.get(f.key.format(side=side))
        if isinstance(value, (int, float)):
            number = f"{value * f.factor:{f.fmt}}"
            bits.append(number if spec.per_wheel else f"{f.label} {number} {f.unit}")
    if rms is not None:
        unit, factor = display_unit(channel(spec.y).unit)
        bits.append(f"RMS {rms * factor:{LEGEND_FORMATS.get(unit, ('', '.3g'))[1]}} {unit}")
    return f"{model}: {', '.join(bits)}" if bits else model


def legend_title(spec: AxleChartSpec) -> str | None:
    """The legend's title of a wheel's panel: what its numbers are (None: one panel, whose
    entries say it)."""
    if not spec.per_wheel or not spec.figures:
        return None
    return ", ".join(f"{f.label} [{f.unit}]" for f in spec.figures)


def _panel(spec: AxleChartSpec, sweeps: list[Sweep], side: str, inputs: AxleChartInputs,
           title: str) -> Panel:
    here = [sw for sw in wheel_sweeps(sweeps, spec.load_case, side, inputs.config_side)
            if spec.x in sw.columns and spec.y in sw.columns]
    test = next((sw for sw in here if sw.model == "test"), None)
    here.sort(key=lambda sw: sw.model != "test")  # the test first, as in every chart
    lines = []
    for sw in here:
        rms = None
        if test is not None and sw.model != "test":
            rms = residual_rms(residual_points(sw, test, spec.x, spec.y))
        figures = inputs.figures.get(sw.model) or {}
        lines.append((sw.model, _legend(sw.model, spec, side, figures, rms), *_rows(sw, spec)))
    return Panel(title, lines)


def _ideal(spec: AxleChartSpec, sweeps: list[Sweep], side: str,
           inputs: AxleChartInputs) -> list[tuple[str, np.ndarray, np.ndarray]]:
    """Each model's ideal Ackermann steer angle of ``side``'s wheel from the other wheel's
    steer angle, step by step over the sweep's longest branch (lock to lock)."""
    other = SIDES[1 - SIDES.index(side)]
    mine = {sw.model: sw for sw in wheel_sweeps(sweeps, spec.load_case, side,
                                                inputs.config_side)}
    out = []
    for sw in wheel_sweeps(sweeps, spec.load_case, other, inputs.config_side):
        own = mine.get(sw.model)
        if sw.model == "test" or own is None or spec.y not in sw.columns:
            continue
        # one pass, the longest branch (lock to lock): a dash-dot line drawn over itself
        # on the way back would read as solid
        branch = sw.columns["branch"]
        names, sizes = np.unique(branch[branch != "approach"], return_counts=True)
        keep = branch == names[np.argmax(sizes)]
        fx = display_unit(channel(spec.x).unit)[1]
        out.append((sw.model, sw.columns[spec.x][keep] * fx, ackermann_partner_steer_deg(
            sw.columns[spec.y][keep], other, inputs.wheelbase_mm, inputs.track_mm)))
    return out


def axle_chart_data(spec: AxleChartSpec, sweeps: list[Sweep],
                    inputs: AxleChartInputs) -> AxleChartData | None:
    """The panels, legends and ideal curves of one axle chart from the run's sweeps (every
    model and side; the model ``test`` gives the RMS errors); None when no sweep of the
    load case has both columns."""
    if spec.per_wheel:
        panels = [_panel(spec, sweeps, side, inputs, f"{side} wheel") for side in SIDES]
        if spec.ideal_ackermann and inputs.wheelbase_mm:
            for side, panel in zip(SIDES, panels):
                panel.ideal = _ideal(spec, sweeps, side, inputs)
    else:
        panels = [_panel(spec, sweeps, inputs.config_side, inputs, "")]
    if not any(p.lines for p in panels):
        return None
    return AxleChartData(panels, _label(spec.x), _label(spec.y), spec.title,
                         legend_title(spec))


#: the style of the ideal Ackermann curves (each in its model's colour)
IDEAL_STYLE = {"linestyle": (0, (6, 2, 1, 2)), "linewidth": 1.1}
IDEAL_LABEL = "ideal: 100 % Ackermann"
#: ideal curves of one colour closer than this everywhere are drawn once (deg)
IDEAL_SAME_DEG = 1.0


def _legend_width(ax, texts: list[str], fontsize: float) -> float:
    """About how wide a legend of ``texts`` is, as a fraction of ``ax``'s width."""
    fig_width_in = ax.figure.get_figwidth()
    axes_in = ax.get_position().width * fig_width_in
    text_in = max((len(s) for s in texts), default=0) * 0.52 * fontsize / 72.0
    return min(1.0, (text_in + 0.45) / axes_in)


def _draw_panel(ax, panel: Panel) -> list[tuple[np.ndarray, np.ndarray]]:
    """Draw a panel's curves (each ideal Ackermann curve in its model's colour); returns
    every curve drawn."""
    colours = {}
    for model, legend, xs, ys in panel.lines:
        colours[model] = ax.plot(xs, ys, **STYLE.get(model, {}), label=legend)[0].get_color()
    drawn: list[tuple[str, np.ndarray, np.ndarray]] = []
    for model, xs, ys in panel.ideal:
        colour = colours.get(model, "0.4")
        # a same-coloured ideal curve on top of another (e.g. a model and its kinematic
        # twin) would fill the other's gaps and read as a solid line: drawn once
        if not any(c == colour and x.shape == xs.shape and np.allclose(y, ys, rtol=0.0,
                                                                       atol=IDEAL_SAME_DEG)
                   for c, x, y in drawn):
            ax.plot(xs, ys, color=colour, **IDEAL_STYLE)
            drawn.append((colour, xs, ys))
    if panel.ideal:
        ax.plot([], [], color="0.3", **IDEAL_STYLE, label=IDEAL_LABEL)
    ax.grid(True, alpha=0.3)
    if panel.title:
        ax.set_title(panel.title, fontsize=10, pad=5)
    return [(xs, ys) for _, _, xs, ys in panel.lines] + [(x, y) for _, x, y in panel.ideal]


def _place_legends(axes, data: AxleChartData, curves: list, fontsize: float) -> None:
    """Each panel's legend in its least crowded corner. Where a panel has no empty corner,
    the y range (shared by the panels) grows by the legend's height on one side, the top or
    the bottom, whichever holds fewer curve points, and every legend goes to that side."""
    boxes = []
    for ax, panel in zip(axes, data.panels):
        texts = [legend for _, legend, _, _ in panel.lines] + [data.legend_title or ""]
        texts += [IDEAL_LABEL] if panel.ideal else []
        entries = len(panel.lines) + bool(panel.ideal) + bool(data.legend_title)
        boxes.append((entries, _legend_width(ax, texts, fontsize)))
    counts = [corner_counts(ax, c, *box) for ax, c, box in zip(axes, curves, boxes)]
    side = None
    if any(min(n.values()) for n in counts):
        crowd = {s: sum(min(v for k, v in n.items() if k.startswith(s)) for n in counts)
                 for s in ("upper", "lower")}
        side = min(crowd, key=crowd.get)
        grow = max(legend_height(entries) for entries, _ in boxes) + 0.03
        y0, y1 = axes[0].get_ylim()
        span = (y1 - y0) / (1.0 - grow)
        axes[0].set_ylim(*((y0, y0 + span) if side == "upper" else (y1 - span, y1)))
    for ax, c, (entries, width) in zip(axes, curves, boxes):
        n = corner_counts(ax, c, entries, width)
        n = {k: v for k, v in n.items() if side is None or k.startswith(side)}
        ax.legend(fontsize=fontsize, framealpha=0.9, title=data.legend_title,
                  title_fontsize=fontsize, loc=min(n, key=n.get))


def draw_axle_chart(canvas: ChartCanvas, data: AxleChartData, provenance: dict):
    """Draw one axle chart on ``canvas``: a panel per wheel side by side (the y axis shared)
    or one panel, each with its legend in its least crowded corner (the y range grown to
    make room when every corner holds curve points). Returns the figure."""
    pair = len(data.panels) == 2
    fig, ax0, ax1, footer = canvas.axes("pair" if pair else 1)
    axes = (ax0, ax1) if pair else (ax0,)
    curves = [_draw_panel(ax, panel) for ax, panel in zip(axes, data.panels)]
    for ax in axes:
        ax.set_xlabel(data.xlabel, fontsize=9)
    floor_y_span(ax0)  # the panels share it
    _place_legends(axes, data, curves, 7 if pair else 8)
    ax0.set_ylabel(data.ylabel, fontsize=9)
    if pair:
        fig.suptitle(data.title, fontsize=11, y=0.965)
    else:
        ax0.set_title(data.title, fontsize=11, y=1.0, pad=7)
    footer.set_text(footer_text(provenance))
    return fig


def axle_chart_caption(spec: AxleChartSpec, with_test: bool, with_ideal: bool) -> str:
    """What an axle chart shows, in a sentence or three (the report's figure caption)."""
    lc = LOAD_CASES[spec.load_case]
    y = channel(spec.y).label.split(" [")[0]
    x = channel(spec.x).label.split(" [")[0]
    models = ("every model and the test where its files have this load case" if with_test
              else "every model")
    where = ("the left wheel's panel beside the right wheel's" if spec.per_wheel
             else "the axle's channel")
    figures = ", ".join(f.label for f in spec.figures)
    text = (f"{spec.title}: {y} against {x} ({lc.meaning}), {models}, {where}, every "
            f"measured row; the legend gives each model's {figures} (summary.json axle)")
    if spec.name == "roll_moment_vs_roll_angle":
        text += ", the least-squares slope of this curve"
    if spec.name == "roll_centre_height_vs_travel":
        text += ("; the curve is the kinematic roll centre (instant centres of both wheels in "
                 "the front view; on a solid axle, of the axle's roll motion), the force-based "
                 "one (12x12 compliance) is a figure of the static state only")
    if spec.name == "roll_centre_height_vs_opposite_travel":
        text += ("; an axle joined by a flexible beam (a twist beam) moves in roll otherwise "
                 "than in bump, as the beam's elasticity sets it, so its kinematic roll centre "
                 "comes from both wheels' motion in opposite wheel travel (x: the config side's "
                 "wheel travel; the other wheel's is opposite); the force-based one (12x12 "
                 "compliance) is a figure of the static state only")
    if spec.ideal_ackermann:
        text += (f"; dash-dot: {IDEAL_LABEL}, the steer angle that would put "
                 "both spindle lines through one point of the rear axle's line (wheelbase "
                 "and design track), in each model's colour" if with_ideal
                 else "; no ideal Ackermann curve: the config gives no axle.vehicle wheelbase")
    if spec.per_wheel:
        text += ("; a positive steering-wheel angle turns left: the left wheel is then the "
                 "inner one" if spec.ideal_ackermann else
                 "; a positive roll angle lifts the body's left side: the left wheel "
                 "rebounds, the right one bumps")
    if with_test:
        text += (". With test data the legend adds each model's RMS error against the test "
                 "of that wheel (changes from the static state at the test points)")
    return text + "."
