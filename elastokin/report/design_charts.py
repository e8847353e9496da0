"""Charts of a design study (matplotlib only here, without pyplot): each target curve with
the start and the optimised model against the target points and their band, the target
characteristics before and after against what is asked, the optimiser's history, and the
hardpoint sensitivity table's largest effects. Labels and units from the channel table;
every chart carries its provenance in a footer."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from elastokin.formats.targets import characteristic_unit
from elastokin.report.doe_charts import new_figure, save
from elastokin.rig.channels import channel

START = {"color": "tab:blue", "linestyle": "--", "linewidth": 1.4}
BEST = {"color": "tab:red", "linestyle": "-", "linewidth": 1.8}


def _label(name: str) -> str:
    c = channel(name)
    return name if c is None else c.label


def curve_chart(name: str, spec, start_xy, best_xy, out_dir: Path, provenance: dict,
                svg: bool) -> list[Path]:
    """One target curve: the model's curve at the start and optimised (on the target's x
    range), the target points and their tolerance band."""
    fig, axes = new_figure(7.0, 4.6)
    ax = axes[0, 0]
    at = np.asarray(spec.points[spec.x], float)
    want = np.asarray(spec.points[spec.y], float)
    tol = spec.tolerance
    ax.plot(*start_xy, label="start (the config)", **START)
    ax.plot(*best_xy, label="optimised", **BEST)
    if tol:
        ax.fill_between(at, want - tol, want + tol, color="0.85",
                        label=f"target band +- {tol:g}")
    ax.plot(at, want, "o", color="black", markersize=4, label="target")
    ax.set_xlabel(_label(spec.x))
    ax.set_ylabel(_label(spec.y) + (" (change from x = 0)" if spec.relative else ""))
    ax.set_title(f"Target curve '{name}' ({spec.load_case})", fontsize=10)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    return save(fig, f"target_curve_{name}", out_dir, provenance, svg)


def characteristics_chart(rows_start, rows_best, asked: dict, out_dir: Path,
                          provenance: dict, svg: bool) -> list[Path]:
    """Every target characteristic, one row each: start and optimised value against the
    target (a point with its tolerance) or range."""
    names = list(asked)
    fig, axes = new_figure(7.0, 0.9 + 0.75 * len(names), rows=len(names))
    for ax, name in zip(axes[:, 0], names):
        t = asked[name]
        if t.range is not None:
            ax.axvspan(*t.range, color="0.85", label="range")
        else:
            if t.tolerance:
                ax.axvspan(t.target - t.tolerance, t.target + t.tolerance, color="0.85",
                           label="tolerance")
            ax.axvline(t.target, color="black", linewidth=1.0, label="target")
        ax.plot([rows_start[name]], [0], "o", color=START["color"], label="start")
        ax.plot([rows_best[name]], [0], "s", color=BEST["color"], label="optimised")
        ax.set_yticks([])
        ax.set_ylabel(name, rotation=0, ha="right", va="center", fontsize=8)
        ax.tick_params(labelsize=8)
        ax.grid(True, axis="x", alpha=0.3)
    axes[0, 0].legend(fontsize=7, ncols=5, loc="lower left", bbox_to_anchor=(0.0, 1.02))
    return save(fig, "target_characteristics", out_dir, provenance, svg)


def history_chart(history, out_dir: Path, provenance: dict, svg: bool) -> list[Path]:
    """The optimiser's model runs: objective (relative to the start) and the largest
    constraint violation."""
    fig, axes = new_figure(7.0, 4.0)
    ax = axes[0, 0]
    runs = [h.run for h in history]
    f0 = history[0].objective or 1.0
    ax.semilogy(runs, [max(h.objective / f0, 1e-16) for h in history], "o-",
                label="objective / start")
    ax.semilogy(runs, [max(h.violation, 1e-16) for h in history], "s--",
                label="largest constraint violation (none: drawn at 1e-16)")
    ax.set_xlabel("model run (with derivatives)")
    ax.set_ylabel("[-] (log)")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    ax.set_title("Optimiser history", fontsize=10)
    return save(fig, "optimiser_history", out_dir, provenance, svg)


def effects_chart(table, out_dir: Path, provenance: dict, svg: bool,
                  top: int = 8) -> list[Path]:
    """The largest effects per mm of the hardpoint coordinates on the first six
    characteristics of a sensitivity table, one panel each."""
    names = table.characteristics[:6]
    rows = (len(names) + 1) // 2
    fig, axes = new_figure(7.5, 2.6 * rows, rows=rows, cols=2)
    for ax, name in zip(axes.ravel(), names):
        ranked = table.ranked(name)[:top][::-1]
        ax.barh([v.name for v, _ in ranked], [e for _, e in ranked],
                color=["tab:red" if e > 0 else "tab:blue" for _, e in ranked])
        unit = characteristic_unit(name)
        ax.set_title(f"{name} per mm", fontsize=8)
        ax.tick_params(labelsize=7)
        ax.axvline(0.0, color="black", linewidth=0.8)
        ax.grid(True, axis="x", alpha=0.3)
        ax.set_xlabel(f"effect [{unit} / mm]", fontsize=7)
    for ax in axes.ravel()[len(names):]:
        ax.set_visible(False)
    return save(fig, "hardpoint_effects", out_dir, provenance, svg)
