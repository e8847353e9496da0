"""Charts (matplotlib only here). Every chart carries its provenance in a footer."""

from __future__ import annotations

from pathlib import Path

from elastokin.rig.load_cases import Sweep, steer_amplitude_deg

STYLE = {
    "test": {"color": "black", "linestyle": "-", "linewidth": 2.0},
    "initial": {"color": "tab:blue", "linestyle": "-"},
    "identified": {"color": "tab:red", "linestyle": "-"},
    "initial_kinematic": {"color": "tab:blue", "linestyle": ":"},
    "identified_stiffness": {"color": "tab:green", "linestyle": "--"},
}


def _figure():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7.0, 5.0), layout="constrained")
    fig.get_layout_engine().set(rect=(0.0, 0.03, 1.0, 0.97))  # room for the footer
    return plt, fig, ax


def _footer(fig, provenance: dict) -> None:
    fig.text(0.01, 0.005, f"elastokin {provenance['elastokin_version']}, exudyn "
             f"{provenance['exudyn_version']}, config {provenance['config_file']} sha256 "
             f"{provenance['config_sha256'][:12]}", fontsize=6, color="0.4",
             ha="left", va="bottom")


def _overlay(sweeps: list[Sweep], x: str, y: str, xlabel: str, ylabel: str, title: str,
             name: str, out_dir: Path, provenance: dict, legend=None,
             stroke_only: bool = False) -> list[Path]:
    plt, fig, ax = _figure()
    for sw in sweeps:
        style = STYLE.get(sw.model, {})
        xs = sw.stroke(x) if stroke_only else sw.columns[x]
        ys = sw.stroke(y) if stroke_only else sw.columns[y]
        ax.plot(xs, ys, **style, label=legend(sw) if legend else sw.model)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title)
    ax.grid(True, alpha=0.3)
    ax.legend()
    _footer(fig, provenance)
    paths = [out_dir / f"{name}.png", out_dir / f"{name}.svg"]
    fig.savefig(paths[0], dpi=150)
    fig.savefig(paths[1], metadata={"Date": None})
    plt.close(fig)
    return paths


def steer_vs_travel(sweeps: list[Sweep], out_dir: Path, provenance: dict) -> list[Path]:
    """Toe (steer) vs wheel travel, one line per model (measured stroke only), as PNG and SVG
    (the paper's Fig. 9a). Returns the files written."""
    return _overlay([sw for sw in sweeps if sw.load_case == "parallel_travel"],
                    "wheel_travel_mm", "toe_deg", "wheel travel [mm] (+ bump)",
                    "toe [deg] (+ toe-in)", "Steer vs parallel wheel travel",
                    "steer_vs_travel", out_dir, provenance, stroke_only=True,
                    legend=lambda sw: f"{sw.model} (amplitude {steer_amplitude_deg(sw):.3f} deg)")


#: the charts of every K&C run: file name -> (load case, x, y, x label, y label, title)
CHARTS = {
    "steer_vs_lateral_force": (
        "lateral_force", "lateral_force_N", "toe_deg",
        "lateral force at the contact patch [N] (+ to the vehicle's left)",
        "toe [deg] (+ toe-in)", "Steer vs lateral force (Fig. 9b)"),
    "longitudinal_displacement_vs_force": (
        "longitudinal_force_patch", "longitudinal_force_N", "wheel_centre_longitudinal_mm",
        "longitudinal force at the contact patch [N] (+ forward; braking -)",
        "wheel-centre longitudinal displacement [mm] (+ forward)",
        "Longitudinal displacement vs force (Fig. 9c)"),
    "camber_vs_travel": (
        "parallel_travel", "wheel_travel_mm", "camber_deg", "wheel travel [mm] (+ bump)",
        "camber [deg] (+ top outboard)", "Camber vs parallel wheel travel"),
    "track_vs_travel": (
        "parallel_travel", "wheel_travel_mm", "wheel_centre_lateral_mm",
        "wheel travel [mm] (+ bump)", "wheel-centre lateral displacement [mm] (+ left)",
        "Wheel-centre lateral displacement vs travel"),
    "vertical_force_vs_travel": (
        "vertical_force", "wheel_travel_mm", "vertical_force_N", "wheel travel [mm] (+ bump)",
        "vertical force at the contact patch [N]", "Vertical force vs wheel travel"),
    "steer_vs_traction_force": (
        "longitudinal_force_centre", "longitudinal_force_N", "toe_deg",
        "longitudinal force at the wheel centre [N] (+ forward: traction)",
        "toe [deg] (+ toe-in)", "Steer vs traction force"),
    "steer_vs_aligning_torque": (
        "aligning_torque", "aligning_torque_Nmm", "toe_deg",
        "aligning torque [N*mm] (+ about the vertical axis, up)", "toe [deg] (+ toe-in)",
        "Steer vs aligning torque"),
}


def kc_charts(sweeps: list[Sweep], out_dir: Path, provenance: dict) -> list[Path]:
    """Every chart of a K&C run whose load case was run, each overlaying all models."""
    paths = steer_vs_travel(sweeps, out_dir, provenance)
    for name, (case, x, y, xl, yl, title) in CHARTS.items():
        chosen = [sw for sw in sweeps if sw.load_case == case]
        if chosen:
            paths += _overlay(chosen, x, y, xl, yl, title, name, out_dir, provenance)
    return paths
