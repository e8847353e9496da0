"""Charts of a DOE study (matplotlib only here): histograms of the characteristics and a
tornado chart of the joints' sensitivity. Every chart carries its provenance in a footer."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from elastokin.report.charts import provenance_footer
from elastokin.rig.channels import CHARACTERISTICS


def label(name: str) -> str:
    """Axis label of a characteristic (units and signs as in summary.json)."""
    c = CHARACTERISTICS.get(name)
    return name if c is None else f"{c.label} [{c.unit}]"


def _plt():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _save(plt, fig, name: str, out_dir: Path, provenance: dict) -> list[Path]:
    provenance_footer(fig, provenance)
    paths = [out_dir / f"{name}.png", out_dir / f"{name}.svg"]
    fig.savefig(paths[0], dpi=150)
    with plt.rc_context({"svg.hashsalt": "elastokin"}):  # reproducible SVG ids
        fig.savefig(paths[1], metadata={"Date": None})
    plt.close(fig)
    return paths


def _histogram(ax, values: np.ndarray, stats: dict, nominal: float | None, label: str) -> None:
    bins = max(5, min(40, int(round(2 * len(values) ** (1 / 3)))))  # Rice rule, bounded
    from matplotlib.ticker import MaxNLocator

    ax.hist(values, bins=bins, color="tab:blue", alpha=0.7, edgecolor="white")
    if stats.get("p05") is not None:
        for key, style in (("p05", ":"), ("mean", "-"), ("p95", ":")):
            ax.axvline(stats[key], color="black", linestyle=style, linewidth=1.0)
    if nominal is not None:
        ax.axvline(nominal, color="tab:red", linewidth=1.5)
    ax.set_xlabel(label, fontsize=8)
    ax.set_ylabel("samples", fontsize=8)
    ax.tick_params(labelsize=7)
    ax.xaxis.set_major_locator(MaxNLocator(5))
    ax.grid(True, alpha=0.3)


def _values(records: list[dict], name: str) -> np.ndarray:
    x = [r["characteristics"].get(name) for r in records if r["status"] == "ok"]
    return np.array([v for v in x if v is not None and math.isfinite(v)], float)


def steer_amplitude_histogram(doe: dict, records: list[dict], out_dir: Path,
                              provenance: dict) -> list[Path]:
    """Histogram of the steer amplitude over the samples that solved, with the mean (solid),
    5th / 95th percentiles (dotted) and the nominal model (red)."""
    plt = _plt()
    fig, ax = plt.subplots(figsize=(7.0, 5.0), layout="constrained")
    fig.get_layout_engine().set(rect=(0.0, 0.03, 1.0, 0.97))
    name = "steer_amplitude_deg"
    nominal = (doe.get("nominal") or {}).get(name)
    _histogram(ax, _values(records, name), doe["steer_amplitude_deg"], nominal, label(name))
    s = doe["steer_amplitude_deg"]
    txt = "" if s["mean"] is None else (f": mean {s['mean']:.3f}, p05 {s['p05']:.3f}, "
                                        f"p95 {s['p95']:.3f} deg")
    ax.set_title(f"Steer amplitude over {s['n']} as-built samples ({doe['method']}, seed "
                 f"{doe['seed']}){txt}\nred: nominal model", fontsize=9)
    return _save(plt, fig, "doe_steer_amplitude", out_dir, provenance)


def characteristics_histograms(doe: dict, records: list[dict], out_dir: Path,
                               provenance: dict) -> list[Path]:
    """One histogram per characteristic on a grid (mean solid, p05 / p95 dotted, nominal
    red)."""
    plt = _plt()
    names = list(doe["characteristics"])
    cols = 3
    rows = max(1, math.ceil(len(names) / cols))
    fig, axes = plt.subplots(rows, cols, figsize=(11.0, 2.6 * rows + 0.6), layout="constrained",
                             squeeze=False)
    fig.get_layout_engine().set(rect=(0.0, 0.03, 1.0, 0.97))
    nominal = doe.get("nominal") or {}
    for ax, name in zip(axes.flat, names):
        _histogram(ax, _values(records, name), doe["characteristics"][name], nominal.get(name),
                   label(name))
    for ax in list(axes.flat)[len(names):]:
        ax.set_visible(False)
    fig.suptitle(f"K&C characteristics over {doe['completed'] - doe['failed']} as-built "
                 f"samples (mean solid, p05/p95 dotted, nominal red)", fontsize=10)
    return _save(plt, fig, "doe_characteristics", out_dir, provenance)


def sensitivity_tornado(doe: dict, out_dir: Path, provenance: dict) -> list[Path]:
    """Tornado chart of the steer amplitude's sensitivity: each joint's share of the variance
    (sum of its squared SRCs), largest on top; beside it the signed SRC of every shift
    component when the multiple regression was possible."""
    plt = _plt()
    sens = {k: v for k, v in doe["sensitivity"].items() if v is not None}
    src = doe["src_components"].get("steer_amplitude_deg")
    ncols = 2 if src is not None else 1
    fig, axes = plt.subplots(1, ncols, figsize=(11.0 if ncols == 2 else 7.0, 5.0),
                             layout="constrained", squeeze=False)
    fig.get_layout_engine().set(rect=(0.0, 0.03, 1.0, 0.97))
    ax = axes[0, 0]
    order = sorted(sens, key=lambda k: sens[k])
    ax.barh(order, [sens[k] for k in order], color="tab:blue")
    ax.set_xlabel("share of steer-amplitude variance (sum of squared SRCs)")
    r2 = doe.get("sensitivity_r2")
    ax.set_title(f"Joint sensitivity ({doe.get('sensitivity_method')}"
                 + (f", R^2 {r2:.2f})" if r2 is not None else ")"), fontsize=9)
    ax.grid(True, axis="x", alpha=0.3)
    if src is not None:
        ax2 = axes[0, 1]
        inputs = doe["src_components"]["inputs"]
        idx = sorted(range(len(src)), key=lambda i: abs(src[i]))
        colors = ["tab:red" if src[i] > 0 else "tab:blue" for i in idx]
        ax2.barh([inputs[i] for i in idx], [src[i] for i in idx], color=colors)
        ax2.axvline(0.0, color="black", linewidth=0.8)
        ax2.set_xlabel("standardised regression coefficient (+ raises the steer amplitude)")
        ax2.set_title("Shift components (joint frame x, y, z)", fontsize=9)
        ax2.grid(True, axis="x", alpha=0.3)
    return _save(plt, fig, "doe_sensitivity_tornado", out_dir, provenance)


def doe_charts(doe: dict, records: list[dict], out_dir: Path, provenance: dict) -> list[Path]:
    """Every chart of a DOE study that has data: steer-amplitude histogram, histograms of all
    characteristics, sensitivity tornado."""
    if doe["steer_amplitude_deg"]["n"] == 0:
        return []
    paths = steer_amplitude_histogram(doe, records, out_dir, provenance)
    paths += characteristics_histograms(doe, records, out_dir, provenance)
    if any(v is not None for v in doe["sensitivity"].values()):
        paths += sensitivity_tornado(doe, out_dir, provenance)
    return paths
