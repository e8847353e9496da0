"""Charts of a K&C run (matplotlib is imported in this package only, lazily). Every chart
carries its provenance in a footer; labels, units and signs come from the channel table.

Force-case charts plot each curve's **change from its static state** (its value at zero input
as the errors against the test take it, :mod:`elastokin.rig.comparison`: the rig's first step
when a sweep starts one step from zero), with each curve's static value in the legend; travel
charts plot absolute values. Every legend entry of a model carries its RMS error against the
test, and with test data a residual panel (model minus test, changes from the static state, at
the test points: what the RMS is taken over) sits under the chart. On an axle these charts show
the config side's wheel; the axle's own charts are :mod:`elastokin.report.axle_charts`'s. The
canvas, styles and file writer are :mod:`elastokin.report.chart_canvas`'s.
"""

from __future__ import annotations

import os
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from elastokin.report.axle_charts import (
    AXLE_CHART_LIST,
    AxleChartInputs,
    axle_chart_data,
    axle_chart_inputs,
    draw_axle_chart,
    wheel_sweeps,
)
from elastokin.report.chart_canvas import (
    DPI,
    LEGEND_FORMATS,
    STYLE,
    ChartCanvas,
    floor_y_span,
    footer_text,
    legend_corner,
    provenance_footer,
    residual_rms,
    save_chart,
)
from elastokin.report.load_charts import LOAD_CHART, LoadChartData, draw_load_chart
from elastokin.rig.channels import ERROR_LIST, LOAD_CASES, channel, display_label, display_unit
from elastokin.rig.characteristics import steer_amplitude_deg
from elastokin.rig.comparison import residual_points, static_value
from elastokin.rig.sweeps import Sweep, find_sweep

#: what other modules take from here (the canvas's names stay importable from this module)
__all__ = ["CHARTS", "CHART_LIST", "DPI", "ChartCanvas", "ChartData", "ChartSpec",
           "axis_label", "chart_caption", "chart_data", "draw_chart", "kc_charts",
           "legend_corner", "provenance_footer", "save_chart"]


@dataclass(frozen=True)
class ChartSpec:
    """One chart of a K&C run: ``y`` against ``x`` of ``load_case``, every model overlaid;
    ``stroke_only``: the travel stroke only, each model's steer amplitude in the legend."""

    name: str
    load_case: str
    x: str
    y: str
    title: str
    stroke_only: bool = False

    @property
    def relative(self) -> bool:
        """A force case: every curve is plotted as its change from the static state."""
        return LOAD_CASES[self.load_case].where is not None


#: the charts of every K&C run, in order; axis labels from the channel table (the load
#: case's input label on x)
CHART_LIST = (
    ChartSpec("steer_vs_travel", "parallel_travel", "wheel_travel_mm", "toe_deg",
              "Steer vs parallel wheel travel (Fig. 9a)", stroke_only=True),
    ChartSpec("steer_vs_lateral_force", "lateral_force", "lateral_force_N", "toe_deg",
              "Steer vs lateral force (Fig. 9b)"),
    ChartSpec("longitudinal_displacement_vs_force", "longitudinal_force_patch",
              "longitudinal_force_N", "wheel_centre_longitudinal_mm",
              "Longitudinal displacement vs braking force (Fig. 9c)"),
    ChartSpec("camber_vs_travel", "parallel_travel", "wheel_travel_mm", "camber_deg",
              "Camber vs parallel wheel travel"),
    ChartSpec("wheel_centre_lateral_vs_travel", "parallel_travel", "wheel_travel_mm",
              "wheel_centre_lateral_mm",
              "Wheel-centre lateral displacement vs parallel wheel travel"),
    ChartSpec("vertical_force_vs_travel", "vertical_force", "wheel_travel_mm",
              "vertical_force_N", "Vertical force vs wheel travel"),
    ChartSpec("steer_vs_traction_force", "longitudinal_force_centre", "longitudinal_force_N",
              "toe_deg", "Steer vs traction force at the wheel centre"),
    ChartSpec("steer_vs_aligning_torque", "aligning_torque", "aligning_torque_Nmm", "toe_deg",
              "Steer vs aligning torque"),
)
CHARTS = {c.name: c for c in CHART_LIST}


def chart_caption(spec: ChartSpec, with_test: bool) -> str:
    """What a chart shows, in a sentence or three (the report's figure caption)."""
    lc = LOAD_CASES[spec.load_case]
    y = channel(spec.y).label.split(" [")[0]
    x = (lc.label if spec.x == lc.input else channel(spec.x).label).split(" [")[0]
    models = "every model and the test" if with_test else "every model"
    if spec.stroke_only:
        what = (f"{y} against {x} over the travel stroke (rebound to bump), {models}; the "
                "legend gives each curve's steer amplitude")
    elif spec.relative:
        what = (f"{y} against {x} ({lc.meaning}), {models}, each curve as its change from "
                "its static state (the static values in the legend)")
    else:
        what = f"{y} against {x} ({lc.meaning}), {models}, every measured row"
    if with_test:
        what += (" and each model's RMS error against the test. Lower panel: model minus "
                 "test at the test points (changes from the static state), what the RMS "
                 "error is taken over")
    return f"{spec.title}: {what}."


def axis_label(load_case: str, column: str) -> str:
    """A column's axis label in the unit charts show: the load case's input label for its
    input, else the channel's."""
    lc = LOAD_CASES[load_case]
    label = lc.label if column == lc.input else channel(column).label
    return display_label(label, channel(column).unit)


def _relative_label(label: str) -> str:
    """The y label of a force-case chart: the channel's label over "change from static"."""
    return f"{label}\nchange from the static state"


def _curve(sw: Sweep, spec: ChartSpec) -> tuple[np.ndarray, np.ndarray]:
    """The rows a chart draws: the stroke, or every measured row (the approach left out)."""
    if spec.stroke_only:
        return sw.stroke(spec.x), sw.stroke(spec.y)
    keep = sw.columns["branch"] != "approach"
    return sw.columns[spec.x][keep], sw.columns[spec.y][keep]


def _rms(model: str, spec: ChartSpec, points, errors: dict | None) -> float | None:
    """The model's RMS error on this chart: summary.json's where it has one, else from the
    residual points (the same definition)."""
    for e in ERROR_LIST:
        if (e.load_case, e.x, e.y) == (spec.load_case, spec.x, spec.y) and errors:
            value = (errors.get(model) or {}).get(e.name)
            if value is not None:
                return value
    return residual_rms(points)


def _legend(sw: Sweep, spec: ChartSpec, y0: float | None, rms: float | None) -> str:
    unit, factor = display_unit(channel(spec.y).unit)
    f_static, f_rms = LEGEND_FORMATS.get(unit, (".4g", ".3g"))
    bits = []
    if spec.stroke_only:
        bits.append(f"amplitude {steer_amplitude_deg(sw):.3f} deg")
    if y0 is not None:
        bits.append(f"static {y0 * factor:{f_static}} {unit}")
    if rms is not None:
        bits.append(f"RMS {rms * factor:{f_rms}} {unit}")
    return f"{sw.model}: {', '.join(bits)}" if bits else sw.model


@dataclass
class ChartData:
    """What one chart draws, in the units it shows (:func:`display_unit`): per sweep
    ``(model, legend, x, y)`` (y the change from the static state on a force case), per model
    the residual points ``(branch, x, model - test)``, the axis labels and the title."""

    lines: list[tuple[str, str, np.ndarray, np.ndarray]]
    residuals: dict[str, list[tuple[str, np.ndarray, np.ndarray]]]
    xlabel: str
    ylabel: str
    residual_label: str
    title: str


def chart_data(spec: ChartSpec, sweeps: list[Sweep], errors: dict | None = None) -> ChartData:
    """The lines, legends and residuals of one chart from the sweeps of ``spec.load_case``
    (the model ``test`` among them gives the residuals); ``errors`` as :func:`kc_charts`."""
    sweeps = [sw for sw in sweeps if spec.x in sw.columns and spec.y in sw.columns]
    test = find_sweep([sw for sw in sweeps if sw.model == "test"], spec.load_case)
    fx = display_unit(channel(spec.x).unit)[1]
    unit, fy = display_unit(channel(spec.y).unit)
    residuals = {}
    if test is not None:
        for sw in sweeps:
            points = None if sw.model == "test" else residual_points(sw, test, spec.x, spec.y)
            if points and any(p[1].size for p in points):
                residuals[sw.model] = points
    lines = []
    for sw in sweeps:
        xs, ys = _curve(sw, spec)
        y0 = static_value(sw, spec.x, spec.y) if spec.relative else None
        rms = None if sw.model == "test" else _rms(sw.model, spec, residuals.get(sw.model),
                                                    errors)
        lines.append((sw.model, _legend(sw, spec, y0, rms), xs * fx,
                      (ys - (y0 or 0.0)) * fy))
    ylabel = axis_label(spec.load_case, spec.y)
    return ChartData(
        lines, {m: [(b, x * fx, r * fy) for b, x, r in pts] for m, pts in residuals.items()},
        axis_label(spec.load_case, spec.x), _relative_label(ylabel) if spec.relative else ylabel,
        f"model - test [{unit}]\n(change from static)", spec.title)


def draw_chart(canvas: ChartCanvas, data: ChartData, provenance: dict):
    """Draw one chart on ``canvas``: every model's curve, the legend in the least crowded
    corner, with the residual panel (model - test) under it when there are residuals.
    Returns the figure (saved by the caller, then reused)."""
    fig, ax, axr, footer = canvas.axes(2 if data.residuals else 1)
    for model, legend, xs, ys in data.lines:
        ax.plot(xs, ys, **STYLE.get(model, {}), label=legend)
    ax.set_ylabel(data.ylabel, fontsize=9)
    ax.set_title(data.title, fontsize=11, y=1.0, pad=7)
    ax.grid(True, alpha=0.3)
    floor_y_span(ax)
    corner = legend_corner(ax, [(xs, ys) for _, _, xs, ys in data.lines], len(data.lines))
    ax.legend(fontsize=8, loc=corner, framealpha=0.9)
    if axr is not None:
        for model, points in data.residuals.items():
            style = {k: v for k, v in STYLE.get(model, {}).items() if k != "linewidth"}
            for _, xt, r in points:
                axr.plot(xt, r, linewidth=1.0, **style)
        axr.axhline(0.0, color="black", linewidth=0.8)
        axr.set_ylabel(data.residual_label, fontsize=8)
        axr.grid(True, alpha=0.3)
    (axr if axr is not None else ax).set_xlabel(data.xlabel, fontsize=9)
    footer.set_text(footer_text(provenance))
    return fig


#: the charts to draw: (draw function, chart data, file, provenance, svg), and the shared
#: index of the next one to take; set before the worker process forks, so that the worker
#: receives nothing but inherits both
_JOBS: list[tuple] = []
_NEXT: list = []
_CANVAS: list[ChartCanvas] = []  # this process's canvas, made on first use


def _draw_jobs(order: list[int]) -> list[tuple[int, list[Path]]]:
    """Draw the charts of ``order`` not taken yet by the other process (``_NEXT``, a shared
    counter into ``order``; without one, all): (job index, files) of those drawn here."""
    if not _CANVAS:
        _CANVAS.append(ChartCanvas())
    out = []
    while True:
        if _NEXT:
            with _NEXT[0].get_lock():
                k = _NEXT[0].value
                _NEXT[0].value += 1
        else:
            k = len(out)
        if k >= len(order):
            return out
        draw, data, path, provenance, svg = _JOBS[order[k]]
        out.append((order[k], save_chart(draw(_CANVAS[0], data, provenance), path, svg)))


def chart_jobs(sweeps: list[Sweep], out_dir: Path, provenance: dict, errors: dict | None,
               svg: bool, axle: AxleChartInputs | None,
               loads: LoadChartData | None = None) -> list[tuple]:
    """(draw function, chart data, file, provenance, svg) of every chart the sweeps have
    data for: the corner's (:data:`CHART_LIST`; on an axle the config side's wheel), then
    with ``axle`` the axle's (:data:`~elastokin.report.axle_charts.AXLE_CHART_LIST`), then
    with ``loads`` the largest loads per element
    (:mod:`elastokin.report.load_charts`)."""
    jobs = []
    for spec in CHART_LIST:
        chosen = [sw for sw in sweeps if spec.x in sw.columns and spec.y in sw.columns]
        chosen = (wheel_sweeps(chosen, spec.load_case, axle.config_side, axle.config_side)
                  if axle is not None else
                  [sw for sw in chosen if sw.load_case == spec.load_case])
        if chosen:
            jobs.append((draw_chart, chart_data(spec, chosen, errors),
                         out_dir / f"{spec.name}.png", provenance, svg))
    for spec in AXLE_CHART_LIST if axle is not None else ():
        data = axle_chart_data(spec, sweeps, axle)
        if data is not None:
            jobs.append((draw_axle_chart, data, out_dir / f"{spec.name}.png", provenance,
                         svg))
    if loads is not None:
        jobs.append((draw_load_chart, loads, out_dir / f"{LOAD_CHART}.png", provenance, svg))
    return jobs


def kc_charts(sweeps: list[Sweep], out_dir: Path, provenance: dict,
              errors: dict | None = None, svg: bool = False,
              axle: AxleChartInputs | None = None,
              loads: LoadChartData | None = None, meanwhile=None) -> list[Path]:
    """Every chart of a K&C run whose load case was run (:data:`CHART_LIST`; with ``axle``,
    :func:`~elastokin.report.axle_charts.axle_chart_inputs`, the config side's wheel and the
    axle's charts too), each overlaying all models, as PNG (and SVG with ``svg``);
    ``errors``: summary.json's ``errors`` (model -> metric -> RMS), for the legends of the
    Fig. 9 charts (other RMS errors are computed from the sweeps, the same way); ``loads``:
    the largest loads per element (:func:`~elastokin.report.load_charts.load_chart_data`).
    Where the platform forks (Linux) and has two cores, a forked process and this one take
    the charts in turn, each the next not taken, this one after ``meanwhile()`` (other work,
    e.g. the files the charts do not need; without a fork it runs first). Returns the files
    written, in chart order."""
    jobs = chart_jobs(sweeps, out_dir, provenance, errors, svg, axle, loads)
    # the largest-loads chart, the longest to draw (a bar per element), first
    order = sorted(range(len(jobs)), key=lambda i: jobs[i][0] is not draw_load_chart)
    _JOBS[:] = jobs
    try:
        if len(jobs) > 2 and sys.platform.startswith("linux") and (os.cpu_count() or 1) > 1:
            import multiprocessing

            ctx = multiprocessing.get_context("fork")
            ChartCanvas()  # matplotlib imported once, before the fork
            _NEXT[:] = [ctx.Value("i", 0)]
            with ctx.Pool(1) as pool:
                pending = pool.apply_async(_draw_jobs, (order,))
                if meanwhile is not None:
                    meanwhile()
                done = dict(_draw_jobs(order))
                done.update(pending.get())
        else:
            if meanwhile is not None:
                meanwhile()
            done = dict(_draw_jobs(order))
    finally:
        _JOBS.clear()
        _NEXT.clear()
    return [path for i in sorted(done) for path in done[i]]


def draw_kc_charts(summary: dict, sweeps: list[Sweep], folder: Path, svg: bool = False
                   ) -> list[Path]:
    """The charts of K&C results read back (:func:`elastokin.report.files.read_results`: the
    summary and the sweeps), drawn into ``folder`` as ``elastokin kc`` draws them (PNG; with
    ``svg`` also SVG; the axle's charts with the summary's axle figures). Returns the files
    written."""
    prov = {k: summary.get(k) for k in ("elastokin_version", "exudyn_version", "config_file",
                                          "config_sha256", "rig_file", "rig_sha256", "units")}
    return kc_charts(sweeps, Path(folder), prov, summary.get("errors"), svg,
                     axle_chart_inputs(summary))
