"""Charts of a DOE study (matplotlib only here, without pyplot): histograms of the
characteristics and a tornado chart of the joints' sensitivity. Labels and units come from the
channel table; counts are whole samples; the lines drawn over a histogram are in its legend;
a sensitivity that the sample count cannot support says so on the chart. Every chart carries
its provenance in a footer."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from elastokin.report.chart_canvas import DPI, provenance_footer, save_chart
from elastokin.report.text import characteristic_label

#: the lines over a histogram: statistic -> (legend label, style)
MARKERS = {"mean": ("mean", {"color": "black", "linestyle": "-", "linewidth": 1.2}),
           "p05": ("5th / 95th percentile", {"color": "black", "linestyle": ":",
                                             "linewidth": 1.2}),
           "p95": (None, {"color": "black", "linestyle": ":", "linewidth": 1.2}),
           "nominal": ("nominal model (no clearance shift)", {"color": "tab:red",
                                                               "linestyle": "-",
                                                               "linewidth": 1.6})}


def new_figure(width_in: float, height_in: float, rows: int = 1, cols: int = 1):
    """A figure on matplotlib's Agg canvas with a constrained layout above the footer:
    (figure, axes array of rows x cols)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width_in, height_in), dpi=DPI, layout="constrained")
    FigureCanvasAgg(fig)
    fig.get_layout_engine().set(rect=(0.0, 0.03, 1.0, 0.97))
    return fig, fig.subplots(rows, cols, squeeze=False)


def save(fig, name: str, out_dir: Path, provenance: dict, svg: bool) -> list[Path]:
    """The chart with its provenance footer as ``name``.png in ``out_dir`` (and .svg)."""
    provenance_footer(fig, provenance)
    return save_chart(fig, out_dir / f"{name}.png", svg)


def histogram(ax, values: np.ndarray, stats: dict, nominal: float | None, name: str,
              fontsize: float = 8) -> None:
    """One characteristic's histogram (whole-sample counts) with its mean, 5th / 95th
    percentiles and the nominal model as labelled lines."""
    from matplotlib.ticker import MaxNLocator

    bins = max(5, min(40, int(round(2 * len(values) ** (1 / 3)))))  # Rice rule, bounded
    ax.hist(values, bins=bins, color="tab:blue", alpha=0.7, edgecolor="white")
    if stats.get("p05") is not None:
        for key in ("mean", "p05", "p95"):
            ax.axvline(stats[key], label=MARKERS[key][0], **MARKERS[key][1])
    if nominal is not None:
        ax.axvline(nominal, label=MARKERS["nominal"][0], **MARKERS["nominal"][1])
    ax.set_xlabel(characteristic_label(name), fontsize=fontsize)
    ax.set_ylabel("samples", fontsize=fontsize)
    ax.tick_params(labelsize=fontsize - 1)
    ax.xaxis.set_major_locator(MaxNLocator(5))
    ax.yaxis.set_major_locator(MaxNLocator(integer=True))  # counts are whole samples
    ax.grid(True, alpha=0.3)


def values_of(records: list[dict], name: str) -> np.ndarray:
    x = [r["characteristics"].get(name) for r in records if r["status"] == "ok"]
    return np.array([v for v in x if v is not None and math.isfinite(v)], float)


def steer_amplitude_histogram(doe: dict, records: list[dict]):
    """Histogram of the steer amplitude over the samples that solved, with the mean, 5th /
    95th percentiles and the nominal model in its legend (the figure)."""
    fig, axes = new_figure(7.0, 5.0)
    ax = axes[0, 0]
    name = "steer_amplitude_deg"
    nominal = (doe.get("nominal") or {}).get(name)
    histogram(ax, values_of(records, name), doe[name], nominal, name, fontsize=9)
    ax.legend(fontsize=8, loc="upper right", framealpha=0.9)
    s = doe[name]
    txt = "" if s["mean"] is None else (f": mean {s['mean']:.3f}, p05 {s['p05']:.3f}, "
                                        f"p95 {s['p95']:.3f} deg")
    ax.set_title(f"Steer amplitude over {s['n']} as-built samples ({doe['method']}, seed "
                 f"{doe['seed']}){txt}", fontsize=9)
    return fig


def characteristics_histograms(doe: dict, records: list[dict]):
    """One histogram per characteristic on a grid, one legend for the lines of all in the
    grid's first free cell (the figure)."""
    names = list(doe["characteristics"])
    cols = 3
    rows = math.ceil((len(names) + 1) / cols)  # a free cell for the legend
    fig, axes = new_figure(11.0, 2.6 * rows + 1.0, rows, cols)
    nominal = doe.get("nominal") or {}
    for ax, name in zip(axes.flat, names):
        histogram(ax, values_of(records, name), doe["characteristics"][name],
                  nominal.get(name), name)
    handles, labels = axes.flat[0].get_legend_handles_labels()
    free = list(axes.flat)[len(names):]
    free[0].axis("off")
    free[0].legend(handles, labels, loc="center", fontsize=9, title="lines on every histogram",
                   title_fontsize=9)
    for ax in free[1:]:
        ax.set_visible(False)
    fig.suptitle(f"K&C characteristics over {doe['completed'] - doe['failed']} as-built "
                 f"samples ({doe['method']}, seed {doe['seed']})", fontsize=10)
    return fig


def tornado_text(doe: dict) -> tuple[str, str]:
    """The tornado's x label and title for the sensitivity method used."""
    sens = {k: v for k, v in doe["sensitivity"].items() if v is not None}
    r2 = doe.get("sensitivity_r2")
    total = sum(sens.values())
    if doe.get("sensitivity_method") == "src":
        return ("share of the steer-amplitude variance (sum of the joint's squared SRCs)",
                f"Joint sensitivity: shares sum to {total:.2f} (R$^2$ {r2:.2f} of the "
                f"linear fit), {doe['completed'] - doe['failed']} samples")
    return ("R$^2$ of a regression on the joint's own shift components (not shares)",
            f"Joint sensitivity per joint: figures sum to {total:.2f}, "
            f"{doe['completed'] - doe['failed']} samples")


def sensitivity_tornado(doe: dict):
    """Tornado chart of the steer amplitude's sensitivity: each joint's figure, largest on
    top, beside it the signed SRC of every shift component when the multiple regression was
    possible; the study's sensitivity warning (too few samples) on the chart (the figure)."""
    sens = {k: v for k, v in doe["sensitivity"].items() if v is not None}
    src = doe["src_components"].get("steer_amplitude_deg")
    ncols = 2 if src is not None else 1
    warning = next(iter(doe.get("warnings") or []), None)
    fig, axes = new_figure(11.0 if ncols == 2 else 7.0, 5.6 if warning else 5.0, 1, ncols)
    ax = axes[0, 0]
    order = sorted(sens, key=lambda k: sens[k])
    ax.barh(order, [sens[k] for k in order], color="tab:gray" if warning else "tab:blue")
    xlabel, title = tornado_text(doe)
    ax.set_xlabel(xlabel, fontsize=9)
    ax.set_title(title, fontsize=9)
    ax.grid(True, axis="x", alpha=0.3)
    if src is not None:
        ax2 = axes[0, 1]
        inputs = doe["src_components"]["inputs"]
        idx = sorted(range(len(src)), key=lambda i: abs(src[i]))
        colors = ["tab:red" if src[i] > 0 else "tab:blue" for i in idx]
        ax2.barh([inputs[i] for i in idx], [src[i] for i in idx], color=colors)
        ax2.axvline(0.0, color="black", linewidth=0.8)
        ax2.set_xlabel("standardised regression coefficient (+ raises the steer amplitude)",
                       fontsize=9)
        ax2.set_title("Shift components (joint frame x, y, z)", fontsize=9)
        ax2.grid(True, axis="x", alpha=0.3)
    if warning:
        import textwrap

        fig.suptitle("\n".join(textwrap.wrap("Warning: " + warning, 130 if ncols == 2
                                             else 85)), fontsize=8, color="tab:red")
    return fig


def doe_charts(doe: dict, records: list[dict], out_dir: Path, provenance: dict,
               svg: bool = False) -> list[Path]:
    """Every chart of a DOE study that has data: steer-amplitude histogram, histograms of all
    characteristics, sensitivity tornado (PNG; with ``svg`` also SVG)."""
    if doe["steer_amplitude_deg"]["n"] == 0:
        return []
    paths = save(steer_amplitude_histogram(doe, records), "doe_steer_amplitude", out_dir,
                 provenance, svg)
    paths += save(characteristics_histograms(doe, records), "doe_characteristics", out_dir,
                  provenance, svg)
    if any(v is not None for v in doe["sensitivity"].values()):
        paths += save(sensitivity_tornado(doe), "doe_sensitivity_tornado", out_dir,
                      provenance, svg)
    return paths
