"""The whole car's charts (matplotlib, lazily imported through the chart canvas): the roll
moments of both axles and their sum against the table's body roll, both axles' steer angles
against it, the roll axis in side view, and the understeer-gradient terms of the suspensions.
Every model of the car overlaid; labels and units from the channel table
(:mod:`elastokin.rig.vehicle_channels`); torques in N*m; the footer names the vehicle file and
both axle configs with their SHA-256.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from elastokin.report.chart_canvas import ChartCanvas, legend_corner, save_chart
from elastokin.rig.channels import display_label
from elastokin.rig.sweeps import Sweep
from elastokin.rig.vehicle_channels import CAR_CHANNELS

#: a car model's line style (by its order in the run, cycled): the compliant model first
MODEL_STYLES = ("-", ":", "--", "-.")
ROLE_COLOURS = {"front": "tab:blue", "rear": "tab:orange", "car": "black"}
#: the car's charts: file stem -> (title, caption)
VEHICLE_CHARTS = {
    "car_roll_moment_vs_body_roll": (
        "Roll moment vs body roll on the table",
        "The table rolls the body, each axle at its load: the roll moment of the front axle, "
        "of the rear axle and their sum (what the table holds) against the body roll, every "
        "car model; the legend gives each axle's roll stiffness (slope against its own roll "
        "angle) and its share, and the total's slope against the table's roll."),
    "car_axle_steer_vs_body_roll": (
        "Axle steer vs body roll on the table",
        "Each axle's steer angle (mean of its wheels', + to the left) against the body roll "
        "(+ left side up, as in a left turn); the legend gives the roll steer and its term "
        "of the understeer gradient (+ understeer)."),
    "car_roll_axis": (
        "Roll axis (side view)",
        "The roll axis through the front and the rear roll centre (kinematic: circles and "
        "solid; force-based: crosses and dashed) with the wheels at their loaded radius and "
        "the CG; the CG's height above the axis is the roll moment's arm. Distances from the "
        "front axle's contact line, heights above the ground, true to scale."),
    "car_understeer_terms": (
        "Understeer gradient terms of the suspensions",
        "The terms of the understeer gradient (deg of road-wheel steer per g, + understeer) "
        "from lateral force compliance steer and from roll steer, per axle and their sum: "
        "the suspensions' part only (the tyres' cornering stiffness, load transfer and "
        "aligning torque are not in it)."),
}


def footer(summary: dict) -> str:
    """The provenance lines of the car's charts: versions and the vehicle file, then both
    axle configs, each with the first 12 hex digits of its SHA-256."""
    a = summary["axles"]
    return (f"elastokin {summary['elastokin_version']}, Exudyn {summary['exudyn_version']}; "
            f"vehicle {summary['vehicle_file']} (sha256 {summary['vehicle_sha256'][:12]})\n"
            f"front {a['front']['config_file']} ({a['front']['config_sha256'][:12]}); rear "
            f"{a['rear']['config_file']} ({a['rear']['config_sha256'][:12]})")


def _label(channel: str) -> str:
    c = CAR_CHANNELS[channel]
    return display_label(c.label, c.unit)


def _num(v, fmt: str, factor: float = 1.0) -> str:
    return "-" if v is None else format(v * factor, fmt)


def _against_roll(ax, summary: dict, sweeps: list[Sweep], curves_of, ylabel: str) -> list:
    """Every car model's curves against the table's body roll: ``curves_of(sweep, figures)``
    gives (role, y, legend) per curve; one line style per model, one colour per role."""
    drawn = []
    for k, sw in enumerate(sweeps):
        x = sw.columns["body_roll_deg"]
        style = MODEL_STYLES[k % len(MODEL_STYLES)]
        for role, y, text in curves_of(sw, summary["models"][sw.model]):
            ax.plot(x, y, color=ROLE_COLOURS[role], linestyle=style, label=text)
            drawn.append((x, y))
    ax.set_xlabel(_label("body_roll_deg"), fontsize=9)
    ax.set_ylabel(ylabel, fontsize=9)
    return drawn


def _moments(sw: Sweep, m: dict) -> list:
    """The roll moments (N*m) of the front and rear axles and the table's total."""
    out = []
    for role in ("front", "rear"):
        stiffness = _num(m[role]["roll_stiffness_Nmm_per_deg"], ".0f", 1e-3)
        share = _num(m["car"][f"roll_stiffness_{role}_percent"], ".1f")
        out.append((role, sw.columns[f"roll_moment_{role}_Nmm"] * 1e-3,
                    f"{sw.model}: {role}, {stiffness} N*m/deg ({share} %)"))
    stiffness = _num(m["car"]["roll_stiffness_table_Nmm_per_deg"], ".0f", 1e-3)
    out.append(("car", sw.columns["roll_moment_total_Nmm"] * 1e-3,
                f"{sw.model}: total, {stiffness} N*m/deg on the table"))
    return out


def _steers(sw: Sweep, m: dict) -> list:
    """Each axle's steer angle, its roll steer and understeer term in the legend."""
    return [(role, sw.columns[f"steer_{role}_deg"],
             f"{sw.model}: {role}, roll steer "
             f"{_num(m[role]['axle_roll_steer_deg_per_deg'], '+.4f')} deg/deg, understeer "
             f"{_num(m[role]['understeer_roll_steer_deg_per_g'], '+.3f')} deg/g")
            for role in ("front", "rear")]


def _roll_axis(ax, summary: dict) -> list:
    from matplotlib.patches import Circle

    v, axles = summary["vehicle"], summary["axles"]
    L, a, h = v["wheelbase_mm"], v["cg_behind_front_axle_mm"], v["cg_height_mm"]
    for x, role in ((0.0, "front"), (L, "rear")):
        r = axles[role]["loaded_radius_mm"]
        ax.add_patch(Circle((x, r), r, fill=False, color="0.6", linewidth=1.0))
    ax.axhline(0.0, color="0.3", linewidth=1.0)
    for k, (label, m) in enumerate(summary["models"].items()):
        colour = f"C{k}"
        for suffix, marker, style, kind in (("", "o", "-", "kinematic"),
                                            ("_force_based", "x", "--", "force-based")):
            hf, hr = (m[role][f"roll_centre_height{suffix}_mm"] for role in ("front", "rear"))
            if hf is None or hr is None:
                continue
            under = m["car"][f"roll_axis_height_under_cg{suffix}_mm"]
            arm = f", h' {h - under:.0f} mm" if not suffix else ""
            ax.plot([0.0, L], [hf, hr], color=colour, linestyle=style, marker=marker,
                    label=f"{label}, {kind}: {hf:.0f} / {hr:.0f} mm, {under:.0f} mm under "
                          f"the CG{arm}")
            if not suffix:  # the roll moment's arm
                ax.plot([a, a], [under, h], color=colour, linewidth=0.8)
    ax.plot([a], [h], marker="o", markersize=9, markerfacecolor="white", color="black",
            linestyle="none", label=f"CG: {a:.0f} mm behind the front axle, {h:.0f} mm high")
    ax.set_aspect("equal", adjustable="datalim")
    r = max(axles[role]["loaded_radius_mm"] for role in ("front", "rear"))
    ax.set_xlim(-r - 200.0, L + r + 200.0)
    ax.figure.set_size_inches(7.0, 4.0)
    ax.figure.subplots_adjust(bottom=0.2, top=0.91)
    ax.set_xlabel("distance behind the front axle [mm]", fontsize=9)
    ax.set_ylabel("height above the ground [mm]", fontsize=9)
    return []


TERMS = (("front", "understeer_compliance_steer_deg_per_g", "front: compliance steer"),
         ("rear", "understeer_compliance_steer_deg_per_g", "rear: compliance steer"),
         ("front", "understeer_roll_steer_deg_per_g", "front: roll steer"),
         ("rear", "understeer_roll_steer_deg_per_g", "rear: roll steer"),
         ("car", "understeer_suspension_deg_per_g", "sum"))


def _understeer(ax, summary: dict) -> list:
    models = list(summary["models"])
    height = 0.8 / max(len(models), 1)
    rows = np.arange(len(TERMS))
    for k, label in enumerate(models):
        m = summary["models"][label]
        values = [m[where][key] for where, key, _ in TERMS]
        y = rows + (k - 0.5 * (len(models) - 1)) * height
        shown = [(yy, v) for yy, v in zip(y, values) if v is not None]
        if not shown:
            continue
        ax.barh([s[0] for s in shown], [s[1] for s in shown], height=height * 0.9,
                color=f"C{k}", label=label)
        for yy, val in shown:
            ax.annotate(f"{val:+.3f}", (val, yy), xytext=(3 if val >= 0 else -3, 0),
                        textcoords="offset points", fontsize=7, va="center",
                        ha="left" if val >= 0 else "right")
    ax.axvline(0.0, color="black", linewidth=0.8)
    ax.set_yticks(rows, [t[2] for t in TERMS], fontsize=8)
    ax.invert_yaxis()
    ax.figure.subplots_adjust(left=0.25)
    lo, hi = ax.get_xlim()
    pad = 0.15 * (hi - lo)
    ax.set_xlim(lo - pad, hi + pad)
    ax.set_xlabel("understeer gradient term [deg/g] (+ understeer)", fontsize=9)
    return []


def vehicle_charts(summary: dict, sweeps: list[Sweep], out_dir: Path, svg: bool = False
                   ) -> list[Path]:
    """The car's charts (:data:`VEHICLE_CHARTS`) into ``out_dir``: the table's charts when
    there are body-roll sweeps; returns the files written."""
    draw = {"car_roll_moment_vs_body_roll": lambda ax: _against_roll(
                ax, summary, sweeps, _moments, _label("roll_moment_total_Nmm")),
            "car_axle_steer_vs_body_roll": lambda ax: _against_roll(
                ax, summary, sweeps, _steers, "axle steer angle [deg] (+ left)"),
            "car_roll_axis": lambda ax: _roll_axis(ax, summary),
            "car_understeer_terms": lambda ax: _understeer(ax, summary)}
    if not sweeps:
        draw = {k: f for k, f in draw.items() if k.startswith("car_roll_axis")
                or k == "car_understeer_terms"}
    out = []
    for name, fn in draw.items():
        fig, ax, _, foot = ChartCanvas().axes(1)  # a fresh figure: bars and patches differ
        fig.subplots_adjust(bottom=0.13)  # the footer's two lines
        curves = fn(ax)
        ax.set_title(VEHICLE_CHARTS[name][0], fontsize=11, y=1.0, pad=7)
        ax.grid(True, alpha=0.3)
        entries = len(ax.get_legend_handles_labels()[1])
        if entries:
            corner = legend_corner(ax, curves, entries) if curves else "best"
            ax.legend(fontsize=7, loc=corner, framealpha=0.9)
        foot.set_text(footer(summary))
        out += save_chart(fig, out_dir / f"{name}.png", svg)
    return out
