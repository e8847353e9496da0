"""Charts (matplotlib only here). Every chart carries its provenance in a footer."""

from __future__ import annotations

from pathlib import Path

from .kc import Sweep, steer_amplitude_deg

STYLE = {
    "test": {"color": "black", "linestyle": "-", "linewidth": 2.0},
    "initial": {"color": "tab:blue", "linestyle": "-"},
    "identified": {"color": "tab:red", "linestyle": "-"},
    "initial_kinematic": {"color": "tab:blue", "linestyle": ":"},
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


def steer_vs_travel(sweeps: list[Sweep], out_dir: Path, provenance: dict) -> list[Path]:
    """Toe (steer) vs wheel travel, one line per model (measured stroke only), as PNG and SVG.
    Returns the files written."""
    plt, fig, ax = _figure()
    for sw in sweeps:
        style = STYLE.get(sw.model, {})
        ax.plot(sw.stroke("wheel_travel_mm"), sw.stroke("toe_deg"), **style,
                label=f"{sw.model} (amplitude {steer_amplitude_deg(sw):.3f} deg)")
    ax.set_xlabel("wheel travel [mm] (+ bump)")
    ax.set_ylabel("toe [deg] (+ toe-in)")
    ax.set_title("Steer vs parallel wheel travel")
    ax.grid(True, alpha=0.3)
    ax.legend()
    _footer(fig, provenance)
    paths = [out_dir / "steer_vs_travel.png", out_dir / "steer_vs_travel.svg"]
    fig.savefig(paths[0], dpi=150)
    fig.savefig(paths[1], metadata={"Date": None})
    plt.close(fig)
    return paths
