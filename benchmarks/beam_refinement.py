"""Mesh refinement study of the twist-beam axle's cross beam (docs/beams.md).

The shipped twist beam (configs/twist_beam_axle.yaml) run by ``elastokin kc`` (model
``initial``: the bushings, the config's rig) with 1, 2, 4, 8, 16 and 32 beam elements per
segment (each half of the beam is one segment): its characteristics against the converged
value, the Richardson extrapolation of the two finest meshes (the elements converge as the
square of their length: ``(4 f_32 - f_16) / 3``), and the cost of the run per rig step. The
figures: roll stiffness, roll steer and roll camber (roll test), the force-based roll centre
(12x12 compliance), the wheel rate and bump steer (parallel travel), the lateral-force toe and
camber compliance in phase and the braking-force toe compliance (compliance matrix).

Writes ``benchmarks/results/beam_refinement.json`` and the chart
``docs/images/twist_beam_refinement.png`` (relative error against elements per segment,
log-log, with the cost per step), and prints the table of docs/beams.md. ``--quick``: 1 and 2
elements per segment on a rig of few steps, nothing written but the JSON (bench_common: into
the temporary folder unless ``--out``). Through elastokin's public API only (``ek.run_kc``).
"""

from __future__ import annotations

import argparse
import copy
import json
import os
import sys
import time
import warnings
from pathlib import Path

import numpy as np

import elastokin as ek

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_common import RESULTS, add_output_options, output_path, write_json  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
CONFIG = ROOT / "configs" / "twist_beam_axle.yaml"
MESHES = (1, 2, 4, 8, 16, 32)
#: (key, where in the summary, label for the table and the chart, unit)
FIGURES = (
    ("roll_stiffness_Nmm_per_deg", "axle", "roll stiffness", "N*mm/deg"),
    ("axle_roll_steer_deg_per_deg", "axle", "roll steer (axle)", "deg/deg"),
    ("roll_camber_left_deg_per_deg", "axle", "roll camber", "deg/deg"),
    ("roll_centre_height_force_based_mm", "axle", "roll centre (force-based)", "mm"),
    ("wheel_rate_N_per_mm", "wheel", "wheel rate", "N/mm"),
    ("bump_steer_deg_per_m", "wheel", "bump steer", "deg/m"),
    ("lateral_force_toe_in_phase_left_deg_per_kN", "named",
     "lateral force toe compliance", "deg/kN"),
    ("lateral_force_camber_in_phase_left_deg_per_kN", "named",
     "lateral force camber compliance", "deg/kN"),
    ("longitudinal_force_toe_in_phase_left_deg_per_kN", "named",
     "braking force toe compliance", "deg/kN"),
)
#: relative errors below this are drawn at it (a figure the beam does not change)
FLOOR = 1e-9
QUICK_RIG = {"parallel_travel": {"rebound_mm": -20, "bump_mm": 20, "step_mm": 10},
             "vertical_force": None, "lateral_force": None, "longitudinal_force_patch": None,
             "longitudinal_force_centre": None, "aligning_torque": None,
             "single_wheel_travel": None, "lateral_force_anti_phase": None,
             "opposite_travel": {"rebound_mm": -10, "bump_mm": 10, "step_mm": 5},
             "roll_vertical_force": {"amplitude_deg": 1.0, "step_deg": 0.5}}


def figures(summary: dict) -> dict[str, float | None]:
    axle = summary["axle"]
    where = {"axle": axle, "wheel": summary, "named": axle.get("named_compliances") or {}}
    return {key: where[place].get(key) for key, place, *_ in FIGURES}


def run(elements: int, quick: bool) -> dict:
    """The characteristics and the cost of one mesh."""
    data = copy.deepcopy(ek.load_suspension(CONFIG).raw)  # the config as editable data
    data["parts"]["cross_beam"]["beam"]["elements_per_segment"] = elements
    if quick:
        data["rig"] = QUICK_RIG
    s = ek.suspension_from_dict(data, str(CONFIG.relative_to(ROOT)))
    t0 = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # a rear axle: no steering axis
        result = ek.run_kc(s, models=["initial"])
    seconds = time.perf_counter() - t0
    model = result.models["initial"]
    steps = sum(sw.steps for sw in model.sweeps)
    return {"elements_per_segment": elements, "figures": figures(model.summary()),
            "run_s": seconds, "rig_steps": steps, "ms_per_step": 1e3 * seconds / steps}


def converged(rows: list[dict]) -> dict[str, float]:
    """The Richardson extrapolation of the two finest meshes (h^2 convergence)."""
    coarse, fine = rows[-2]["figures"], rows[-1]["figures"]
    return {k: (4.0 * fine[k] - coarse[k]) / 3.0 for k in fine
            if fine[k] is not None and coarse[k] is not None}


def chart(rows: list[dict], reference: dict[str, float], shipped: int, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    n = np.array([r["elements_per_segment"] for r in rows[:-1]])
    fig, (ax, cost) = plt.subplots(1, 2, figsize=(10, 5.6), width_ratios=(2, 1))
    for key, _, label, _ in FIGURES:
        if key not in reference:
            continue
        err = np.array([abs(r["figures"][key] / reference[key] - 1.0) for r in rows[:-1]])
        ax.loglog(n, np.maximum(err, FLOOR), marker="o", label=label)
    ax.loglog(n, 0.1 / n**2, "k--", linewidth=0.8, label="slope -2 (element length squared)")
    for y, style in ((1e-2, "-"), (1e-3, ":")):
        ax.axhline(y, color="grey", linewidth=0.6, linestyle=style)
    ax.axvline(shipped, color="black", linewidth=1.0, alpha=0.5)
    ax.text(shipped * 1.05, 0.3, f"shipped: {shipped}", fontsize=8)
    ax.set_xticks(n, [str(v) for v in n])
    ax.set_ylim(FLOOR / 2, 1.0)
    ax.set_xlabel("beam elements per segment (half beam)")
    ax.set_ylabel(f"|relative error| against the converged value (floor {FLOOR:g})")
    ax.set_title("Twist beam: characteristics against the mesh")
    ax.grid(True, which="major", alpha=0.3)
    m = np.array([r["elements_per_segment"] for r in rows])
    cost.plot(m, [r["ms_per_step"] for r in rows], marker="o", color="tab:red")
    cost.axvline(shipped, color="black", linewidth=1.0, alpha=0.5)
    cost.set_xscale("log", base=2)
    cost.set_yscale("log")
    cost.set_xticks(m, [str(v) for v in m])
    cost.set_xlabel("beam elements per segment")
    cost.set_ylabel("ms per rig step (the whole run: both wheels, every channel)")
    cost.set_title("Cost of the K&C run")
    cost.grid(True, alpha=0.3)
    fig.legend(*ax.get_legend_handles_labels(), loc="lower center", ncol=3, fontsize=8,
               frameon=False, bbox_to_anchor=(0.5, 0.04))
    fig.text(0.01, 0.01, f"elastokin {ek.__version__}; configs/twist_beam_axle.yaml; model "
             "initial; converged value: Richardson extrapolation of 16 and 32 (h^2)",
             fontsize=7, color="#555555")
    fig.tight_layout(rect=(0, 0.2, 1, 1))
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=130)
    plt.close(fig)


def table(rows: list[dict], reference: dict[str, float]) -> str:
    """The docs' markdown table: each figure's relative error per mesh, in %."""
    head = "| figure | converged | " + " | ".join(
        f"{r['elements_per_segment']}" for r in rows) + " |"
    lines = [head, "|---|---|" + "---|" * len(rows)]
    for key, _, label, unit in FIGURES:
        if key not in reference:  # a load case the rig left out
            continue
        errs = " | ".join(f"{100.0 * (r['figures'][key] / reference[key] - 1.0):+.3f}"
                          for r in rows)
        lines.append(f"| {label} [{unit}] | {reference[key]:.5g} | {errs} |")
    lines.append("| ms per rig step | | " + " | ".join(f"{r['ms_per_step']:.2f}"
                                                      for r in rows) + " |")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    add_output_options(ap, "beam_refinement")
    ap.add_argument("--chart", default=str(ROOT / "docs" / "images"
                                           / "twist_beam_refinement.png"))
    ap.add_argument("--replot", action="store_true",
                    help="draw the chart and print the table of the JSON at --out (default "
                         "the committed results), no runs")
    args = ap.parse_args(argv)
    if args.replot:
        result = json.loads(Path(args.out or RESULTS / "beam_refinement.json").read_text())
        rows, reference = result["meshes"], result["converged"]
    else:
        out = output_path(args, "beam_refinement")
        meshes = (1, 2) if args.quick else MESHES
        load_before = os.getloadavg()
        rows = [run(n, args.quick) for n in meshes]
        reference = converged(rows)
        result = {"elastokin_version": ek.__version__, "exudyn_version": ek.exudyn_version(),
                  "config": str(CONFIG.relative_to(ROOT)), "quick": args.quick,
                  "load_average_before": load_before, "load_average_after": os.getloadavg(),
                  "converged": reference, "meshes": rows}
        write_json(out, result)
    print(table(rows, reference))
    if not args.quick:
        shipped = ek.load_suspension(CONFIG).raw["parts"]["cross_beam"]["beam"][
            "elements_per_segment"]
        chart(rows, reference, shipped, Path(args.chart))
        print(f"chart: {args.chart}")
    if not args.replot:
        print(f"written to {out}")
    return result


if __name__ == "__main__":
    main()
