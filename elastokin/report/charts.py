"""Charts of a K&C run (matplotlib is imported in this package only, lazily). Every chart
carries its provenance in a footer; labels, units and signs come from the channel table."""

from __future__ import annotations

import os
import sys
from pathlib import Path

from elastokin.rig.channels import LOAD_CASES, channel
from elastokin.rig.characteristics import steer_amplitude_deg
from elastokin.rig.sweeps import Sweep

STYLE = {
    "test": {"color": "black", "linestyle": "-", "linewidth": 2.0},
    "initial": {"color": "tab:blue", "linestyle": "-"},
    "identified": {"color": "tab:red", "linestyle": "-"},
    "initial_kinematic": {"color": "tab:blue", "linestyle": ":"},
    "identified_stiffness": {"color": "tab:green", "linestyle": "--"},
}


def new_figure():
    """A 7 x 5 in figure with room for the provenance footer: (pyplot, figure, axes)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    # fixed margins (room for long axis labels and the footer): a layout engine costs about
    # as much as drawing the chart
    fig, ax = plt.subplots(figsize=(7.0, 5.0))
    fig.subplots_adjust(left=0.13, right=0.975, bottom=0.135, top=0.93)
    return plt, fig, ax


def provenance_footer(fig, provenance: dict) -> None:
    """The versions and config hash every chart carries."""
    fig.text(0.01, 0.005, f"elastokin {provenance['elastokin_version']}, exudyn "
             f"{provenance['exudyn_version']}, config {provenance['config_file']} sha256 "
             f"{provenance['config_sha256'][:12]}", fontsize=6, color="0.4",
             ha="left", va="bottom")


def _legend(sw: Sweep, amplitude: bool) -> str:
    return f"{sw.model} (amplitude {steer_amplitude_deg(sw):.3f} deg)" if amplitude else sw.model


def _overlay(sweeps: list[Sweep], x: str, y: str, xlabel: str, ylabel: str, title: str,
             name: str, out_dir: Path, provenance: dict,
             stroke_only: bool = False) -> list[Path]:
    """One chart (PNG and SVG): ``y`` against ``x`` of every sweep; on the travel stroke only,
    with each model's steer amplitude in the legend, when ``stroke_only``."""
    plt, fig, ax = new_figure()
    for sw in sweeps:
        style = STYLE.get(sw.model, {})
        xs = sw.stroke(x) if stroke_only else sw.columns[x]
        ys = sw.stroke(y) if stroke_only else sw.columns[y]
        ax.plot(xs, ys, **style, label=_legend(sw, stroke_only))
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title)
    ax.grid(True, alpha=0.3)
    ax.legend()
    provenance_footer(fig, provenance)
    paths = [out_dir / f"{name}.png", out_dir / f"{name}.svg"]
    fig.savefig(paths[0], dpi=150)
    fig.savefig(paths[1], metadata={"Date": None})
    plt.close(fig)
    return paths


def _steer_vs_travel_args(sweeps: list[Sweep], out_dir: Path, provenance: dict) -> tuple:
    """Toe (steer) vs wheel travel, one line per model (measured stroke only; the paper's
    Fig. 9a)."""
    return ([sw for sw in sweeps if sw.load_case == "parallel_travel"], "wheel_travel_mm",
            "toe_deg", axis_label("parallel_travel", "wheel_travel_mm"),
            axis_label("parallel_travel", "toe_deg"), "Steer vs parallel wheel travel",
            "steer_vs_travel", out_dir, provenance, True)


#: the charts of every K&C run: file name -> (load case, x, y, title); axis labels from the
#: channel table (the load case's input label on x)
CHARTS = {
    "steer_vs_lateral_force": ("lateral_force", "lateral_force_N", "toe_deg",
                               "Steer vs lateral force (Fig. 9b)"),
    "longitudinal_displacement_vs_force": ("longitudinal_force_patch", "longitudinal_force_N",
                                           "wheel_centre_longitudinal_mm",
                                           "Longitudinal displacement vs force (Fig. 9c)"),
    "camber_vs_travel": ("parallel_travel", "wheel_travel_mm", "camber_deg",
                         "Camber vs parallel wheel travel"),
    "track_vs_travel": ("parallel_travel", "wheel_travel_mm", "wheel_centre_lateral_mm",
                        "Wheel-centre lateral displacement vs travel"),
    "vertical_force_vs_travel": ("vertical_force", "wheel_travel_mm", "vertical_force_N",
                                 "Vertical force vs wheel travel"),
    "steer_vs_traction_force": ("longitudinal_force_centre", "longitudinal_force_N", "toe_deg",
                                "Steer vs traction force"),
    "steer_vs_aligning_torque": ("aligning_torque", "aligning_torque_Nmm", "toe_deg",
                                 "Steer vs aligning torque"),
}


def axis_label(load_case: str, column: str) -> str:
    """A column's axis label: the load case's input label for its input, else the channel's."""
    lc = LOAD_CASES[load_case]
    return lc.label if column == lc.input else channel(column).label


def kc_charts(sweeps: list[Sweep], out_dir: Path, provenance: dict) -> list[Path]:
    """Every chart of a K&C run whose load case was run, each overlaying all models (PNG and
    SVG); drawn in two forked processes where the platform forks (Linux), about twice as
    fast. Returns the files written, in chart order."""
    jobs = [_steer_vs_travel_args(sweeps, out_dir, provenance)]
    for name, (case, x, y, title) in CHARTS.items():
        chosen = [sw for sw in sweeps if sw.load_case == case]
        if chosen:
            jobs.append((chosen, x, y, axis_label(case, x), axis_label(case, y), title, name,
                         out_dir, provenance, False))
    if len(jobs) > 2 and sys.platform.startswith("linux") and (os.cpu_count() or 1) > 1:
        import multiprocessing

        new_figure()[0].close("all")  # pyplot imported once, before the fork

        with multiprocessing.get_context("fork").Pool(2) as pool:
            done = pool.starmap(_overlay, jobs)
    else:
        done = [_overlay(*job) for job in jobs]
    return [path for paths in done for path in paths]
