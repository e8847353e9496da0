"""Design to targets (issue 28): what the exact design sensitivities save, in one run.

- ``optimize``: the shipped six-point case (configs/targets/double_wishbone_six_points.yaml on
  configs/rigs/travel_only.yaml) solved twice with the same SLSQP formulation: on the exact
  gradients (``ek.run_optimize``, what ``elastokin optimize`` runs: the targets read, the
  optimiser and the verifying plain run) and on central finite differences of full model
  runs (2 n + 1 runs per gradient, each ``ek.evaluate_targets`` without derivatives). Each is
  counted in **model-run equivalents**: its CPU time over that of one plain run of the same
  load cases (same process, same machine). Target: the exact gradients at least 10x fewer.
- ``sensitivity``: the hardpoint sensitivity table of both shipped configs
  (``ek.sensitivity_table``: every hardpoint coordinate, the table's load cases), in
  model-run equivalents against the 2 n + 1 runs of central differences.
- ``--quick`` (run by the tests): the one-variable tie-rod case and the case study's table on
  +-10 mm of travel, for the same figures in seconds (bench_common).

Writes ``benchmarks/results/bench_design.json`` (``--out``), with the machine's load average
before and after. CPU time of this process (the model runs are serial). Through elastokin's
public API only (the runs before issue 24's item 6 timed the optimiser without its verifying
run: one plain run fewer in ``exact``).
"""

from __future__ import annotations

import argparse
import os
import platform
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

import elastokin as ek

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_common import add_output_options, output_path, write_json  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
QUICK_RIG = ("parallel_travel: {rebound_mm: -1, bump_mm: 1, step_mm: 0.25, unloading: false}"
             "\nvertical_force: null\n")
QUICK_TABLE_RIG = ("parallel_travel: {rebound_mm: -10, bump_mm: 10, step_mm: 5, "
                   "unloading: false}\nvertical_force: null\n")
QUICK_TARGETS = """elastokin_targets: 1
model: initial_kinematic
variables:
  - {hardpoint: tierod_inner, axis: z, within_mm: 40}
characteristics:
  bump_steer_at_design_deg_per_m: {target: 0.0, tolerance: 0.001}
"""


def cpu() -> float:
    return time.process_time()


def plain_run_cpu(s, targets, x, repeat: int = 3) -> float:
    """CPU seconds of one plain run (no derivatives) of the targets' model and load cases."""
    best = np.inf
    for _ in range(repeat):
        t = cpu()
        ek.evaluate_targets(s, targets, x, derivatives=False)
        best = min(best, cpu() - t)
    return best


def scales(targets) -> np.ndarray:
    """The variables' scales as ``elastokin optimize`` takes them: half the width of their
    bounds, or 10 of their unit when a bound is open."""
    return np.array([(v.upper - v.lower) / 2 if np.isfinite(v.upper - v.lower) else 10.0
                     for v in targets.variables])


def fd_optimise(s, targets) -> dict:
    """The same SLSQP problem as ``ek.run_optimize`` with central finite differences of full
    runs for every gradient."""
    from scipy.optimize import minimize

    x0, half = np.array([v.value(s.raw) for v in targets.variables]), scales(targets)
    runs = [0]
    cache: dict = {}

    def values(u):
        key = np.asarray(u, float).tobytes()
        if key not in cache:
            runs[0] += 1
            cache[key] = ek.evaluate_targets(s, targets, x0 + half * u, derivatives=False)[1]
        return cache[key]

    def grads(u):
        h = 1e-3  # of each variable's half-width
        cols = [(values(u + h * e), values(u - h * e)) for e in np.eye(u.size)]
        g = np.array([(a.objective - b.objective) / (2 * h) for a, b in cols])
        J = np.array([(a.constraints - b.constraints) / (2 * h) for a, b in cols]).T
        return g, J

    f0 = values(np.zeros(x0.size)).objective or 1.0
    bounds = [((v.lower - x) / h, (v.upper - x) / h)
              for v, x, h in zip(targets.variables, x0, half)]
    cons = [{"type": "ineq", "fun": lambda u: values(u).constraints,
             "jac": lambda u: grads(u)[1]}] if values(np.zeros(x0.size)).labels else []
    res = minimize(lambda u: values(u).objective / f0, np.zeros(x0.size),
                   jac=lambda u: grads(u)[0] / f0, method="SLSQP", bounds=bounds,
                   constraints=cons, options={"maxiter": targets.spec.optimizer.max_iterations,
                                              "ftol": targets.spec.optimizer.tolerance})
    best = values(res.x)
    return {"plain_runs": runs[0], "met": best.met, "values": (x0 + half * res.x).tolist(),
            "message": str(res.message)}


def shown(path: Path) -> str:
    """A path as the JSON records it: relative to the repository when inside it."""
    return str(path.relative_to(ROOT)) if path.is_relative_to(ROOT) else str(path)


def nominal(config: Path, rig: Path | None):
    """The config's own design on ``rig`` (as ``elastokin optimize`` and ``sensitivity``)."""
    return ek.nominal(ek.load_suspension_with_rig(config, rig))


def optimize_case(config: Path, targets_path: Path, rig: Path) -> dict:
    s = nominal(config, rig)
    targets = ek.load_targets(targets_path, s)
    one = plain_run_cpu(s, targets, None)
    t = cpu()
    exact = ek.run_optimize(s, targets_path)
    exact_cpu = cpu() - t
    t = cpu()
    fd = fd_optimise(s, targets)
    fd_cpu = cpu() - t
    out = {
        "config": shown(config), "targets": shown(targets_path),
        "variables": len(targets.variables), "plain_run_cpu_s": one,
        "exact": {"cpu_s": exact_cpu, "model_runs_with_derivatives": exact.model_runs,
                  "model_run_equivalents": exact_cpu / one, "met": exact.best_values.met,
                  "values": exact.best.values.tolist()},
        "finite_differences": {"cpu_s": fd_cpu, "model_run_equivalents": fd_cpu / one, **fd},
    }
    out["fewer_equivalents"] = out["finite_differences"]["model_run_equivalents"] / \
        out["exact"]["model_run_equivalents"]
    return out


def sensitivity_case(config: Path, rig: Path | None) -> dict:
    s = nominal(config, rig)
    t = cpu()
    tab = ek.sensitivity_table(s)
    table_cpu = cpu() - t
    cases = {sw.load_case for sw in tab.run.models[tab.label].sweeps}  # the table's
    rig_spec = s.rig.model_copy(update={n: None for n in type(s.rig).model_fields
                                        if n not in cases})
    best = np.inf
    for _ in range(2):
        t = cpu()
        ek.run_design(s, [], [], (tab.label,), rig_spec, derivatives=False)
        best = min(best, cpu() - t)
    n = len(tab.variables)
    return {"config": shown(config), "coordinates": n,
            "characteristics": len(tab.characteristics), "load_cases": sorted(cases),
            "cpu_s": table_cpu, "plain_run_cpu_s": best,
            "model_run_equivalents": table_cpu / best, "finite_difference_runs": 2 * n + 1,
            "fewer_equivalents": (2 * n + 1) / (table_cpu / best)}


def main(argv: list[str] | None = None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    add_output_options(ap, "bench_design")
    args = ap.parse_args(argv)
    out = output_path(args, "bench_design")
    dw, case = ROOT / "configs" / "double_wishbone_axle.yaml", \
        ROOT / "configs" / "pseudo_mcpherson.yaml"
    result = {"elastokin_version": ek.__version__, "exudyn_version": ek.exudyn_version(),
              "machine": {"python": platform.python_version(),
                          "processor": platform.machine(), "cpus": os.cpu_count()},
              "quick": args.quick, "load_average_before": os.getloadavg()}
    if args.quick:
        with tempfile.TemporaryDirectory() as tmp:
            rig, targets = Path(tmp) / "rig.yaml", Path(tmp) / "targets.yaml"
            rig.write_text(QUICK_RIG)
            targets.write_text(QUICK_TARGETS)
            result["optimize"] = optimize_case(dw, targets, rig)
            short = Path(tmp) / "short.yaml"
            short.write_text(QUICK_TABLE_RIG)
            result["sensitivity"] = [sensitivity_case(case, short)]
    else:
        result["optimize"] = optimize_case(
            dw, ROOT / "configs" / "targets" / "double_wishbone_six_points.yaml",
            ROOT / "configs" / "rigs" / "travel_only.yaml")
        result["sensitivity"] = [sensitivity_case(c, None) for c in (case, dw)]
    o = result["optimize"]
    print(f"optimize ({o['variables']} variables): exact {o['exact']['model_run_equivalents']:.1f}"
          f" model-run equivalents ({o['exact']['model_runs_with_derivatives']} runs with "
          f"derivatives), finite differences {o['finite_differences']['model_run_equivalents']:.1f}"
          f" ({o['finite_differences']['plain_runs']} plain runs): "
          f"{o['fewer_equivalents']:.1f}x fewer (target >= 10)")
    for t in result["sensitivity"]:
        print(f"sensitivity {t['config']} ({t['coordinates']} coordinates): "
              f"{t['model_run_equivalents']:.1f} model-run equivalents against "
              f"{t['finite_difference_runs']} for central differences: "
              f"{t['fewer_equivalents']:.1f}x fewer")
    result["load_average_after"] = os.getloadavg()
    write_json(out, result)
    print(f"written to {out}")
    return result


if __name__ == "__main__":
    main()
