"""Charts of a K&C run (matplotlib is imported in this package only, lazily). Every chart
carries its provenance in a footer; labels, units and signs come from the channel table.

Force-case charts plot each curve's **change from its static state** (its value at zero input
as the errors against the test take it, :mod:`elastokin.rig.comparison`: the rig's first step
when a sweep starts one step from zero), with each curve's static value in the legend; travel
charts plot absolute values. Every legend entry of a model carries its RMS error against the
test, and with test data a residual panel (model minus test, changes from the static state, at
the test points: what the RMS is taken over) sits under the chart.
"""

from __future__ import annotations

import os
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from elastokin.rig.channels import ERROR_LIST, LOAD_CASES, channel, display_label, display_unit
from elastokin.rig.characteristics import steer_amplitude_deg
from elastokin.rig.comparison import residual_points, static_value
from elastokin.rig.sweeps import Sweep, find_sweep

STYLE = {
    "test": {"color": "black", "linestyle": "-", "linewidth": 2.0},
    "initial": {"color": "tab:blue", "linestyle": "-"},
    "identified": {"color": "tab:red", "linestyle": "-"},
    "initial_kinematic": {"color": "tab:blue", "linestyle": ":"},
    "identified_stiffness": {"color": "tab:green", "linestyle": "--"},
}
#: number formats of the legend by unit: (static value, RMS error)
_FMT = {"deg": (".3f", ".4f"), "mm": (".2f", ".3f"), "N": (".0f", ".1f")}


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


def new_figure(panels: int = 1):
    """A figure with room for the provenance footer: (pyplot, figure, axes); with two panels
    a 3:1 chart over a residual panel sharing its x axis (axes a pair)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    # fixed margins (room for long axis labels and the footer): a layout engine costs about
    # as much as drawing the chart
    if panels == 1:
        fig, ax = plt.subplots(figsize=(7.0, 5.0))
        fig.subplots_adjust(left=0.13, right=0.975, bottom=0.135, top=0.93)
        return plt, fig, ax
    fig, axes = plt.subplots(2, 1, figsize=(7.0, 6.6), sharex=True,
                             gridspec_kw={"height_ratios": (3, 1)})
    fig.subplots_adjust(left=0.155, right=0.975, bottom=0.105, top=0.945, hspace=0.07)
    return plt, fig, axes


def provenance_footer(fig, provenance: dict) -> None:
    """The versions and config hash every chart carries."""
    fig.text(0.01, 0.005, f"elastokin {provenance['elastokin_version']}, exudyn "
             f"{provenance['exudyn_version']}, config {provenance['config_file']} sha256 "
             f"{provenance['config_sha256'][:12]}", fontsize=6, color="0.4",
             ha="left", va="bottom")


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
    if not points:
        return None
    r = np.concatenate([p[2] for p in points])
    return float(np.sqrt(np.mean(r ** 2))) if r.size else None


def _legend(sw: Sweep, spec: ChartSpec, y0: float | None, rms: float | None) -> str:
    unit, factor = display_unit(channel(spec.y).unit)
    f_static, f_rms = _FMT.get(unit, (".4g", ".3g"))
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


def _draw(spec: ChartSpec, sweeps: list[Sweep], out_dir: Path, provenance: dict,
          errors: dict | None) -> list[Path]:
    """One chart (PNG and SVG): every model's sweep of ``spec.load_case`` overlaid, with a
    residual panel (model - test) when the test is among them."""
    data = chart_data(spec, sweeps, errors)
    plt, fig, axes = new_figure(2 if data.residuals else 1)
    ax, axr = (axes[0], axes[1]) if data.residuals else (axes, None)
    for model, legend, xs, ys in data.lines:
        ax.plot(xs, ys, **STYLE.get(model, {}), label=legend)
    ax.set_ylabel(data.ylabel, fontsize=9)
    ax.set_title(data.title)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    if axr is not None:
        for model, points in data.residuals.items():
            style = {k: v for k, v in STYLE.get(model, {}).items() if k != "linewidth"}
            for _, xt, r in points:
                axr.plot(xt, r, linewidth=1.0, **style)
        axr.axhline(0.0, color="black", linewidth=0.8)
        axr.set_ylabel(data.residual_label, fontsize=8)
        axr.grid(True, alpha=0.3)
    (axr if axr is not None else ax).set_xlabel(data.xlabel)
    fig.align_ylabels()
    provenance_footer(fig, provenance)
    paths = [out_dir / f"{spec.name}.png", out_dir / f"{spec.name}.svg"]
    fig.savefig(paths[0], dpi=150)
    with plt.rc_context({"svg.hashsalt": "elastokin"}):  # reproducible SVG ids
        fig.savefig(paths[1], metadata={"Date": None})
    plt.close(fig)
    return paths


def kc_charts(sweeps: list[Sweep], out_dir: Path, provenance: dict,
              errors: dict | None = None) -> list[Path]:
    """Every chart of a K&C run whose load case was run (:data:`CHART_LIST`), each overlaying
    all models (PNG and SVG); ``errors``: summary.json's ``errors`` (model -> metric -> RMS),
    for the legends of the Fig. 9 charts (other RMS errors are computed from the sweeps, the
    same way). Drawn in two forked processes where the platform forks (Linux), about twice as
    fast. Returns the files written, in chart order."""
    jobs = []
    for spec in CHART_LIST:
        chosen = [sw for sw in sweeps if sw.load_case == spec.load_case
                  and spec.x in sw.columns and spec.y in sw.columns]
        if chosen:
            jobs.append((spec, chosen, out_dir, provenance, errors))
    if len(jobs) > 2 and sys.platform.startswith("linux") and (os.cpu_count() or 1) > 1:
        import multiprocessing

        new_figure()[0].close("all")  # pyplot imported once, before the fork

        with multiprocessing.get_context("fork").Pool(2) as pool:
            done = pool.starmap(_draw, jobs)
    else:
        done = [_draw(*job) for job in jobs]
    return [path for paths in done for path in paths]
