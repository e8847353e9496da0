"""Design to targets (issue 28): what the exact design sensitivities save, in one run.

- ``optimize``: the shipped six-point case (configs/targets/double_wishbone_six_points.yaml on
  configs/rigs/travel_only.yaml) solved twice with the same SLSQP formulation: on the exact
  gradients (``elastokin optimize``) and on central finite differences of full model runs
  (2 n + 1 runs per gradient). Each is counted in **model-run equivalents**: its CPU time over
  that of one plain run of the same load cases (same process, same machine). Target: the
  exact gradients at least 10x fewer.
- ``sensitivity``: the hardpoint sensitivity table of both shipped configs (every hardpoint
  coordinate, the table's load cases), in model-run equivalents against the 2 n + 1 runs of
  central differences.
- ``--quick`` (run by the tests): the one-variable tie-rod case and the case study's table on
  +-10 mm of travel, for the same figures in seconds.

Writes ``benchmarks/results/bench_design.json`` (``--out``). CPU time of this process (the
model runs are serial).
"""

from __future__ import annotations

import argparse
import json
import platform
import time
from pathlib import Path

import numpy as np

from elastokin.cli.design import nominal_suspension
from elastokin.formats.targets import load_targets
from elastokin.mbs.model import EXUDYN_VERSION
from elastokin.studies.design_job import optimise, start
from elastokin.studies.design_runs import run_design
from elastokin.studies.design_targets import needs_compliance, target_rig, target_values
from elastokin.studies.sensitivity_table import TABLE_LOAD_CASES, sensitivity_table
from elastokin.version import __version__

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
    rig, label = target_rig(s, targets), targets.spec.model
    best = np.inf
    for _ in range(repeat):
        t = cpu()
        run_design(s, targets.variables, x, (label,), rig, derivatives=False,
                   compliance=needs_compliance(targets))
        best = min(best, cpu() - t)
    return best


def fd_optimise(s, targets) -> dict:
    """The same SLSQP problem as :func:`elastokin.studies.design_job.optimise` with central
    finite differences of full runs for every gradient."""
    from scipy.optimize import minimize

    rig, label = target_rig(s, targets), targets.spec.model
    x0, half = start(s, targets)
    runs = [0]
    cache: dict = {}

    def values(u):
        key = np.asarray(u, float).tobytes()
        if key not in cache:
            runs[0] += 1
            run = run_design(s, targets.variables, x0 + half * u, (label,), rig,
                             derivatives=False, compliance=needs_compliance(targets))
            cache[key] = target_values(run, targets, label, derivatives=False)
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


def optimize_case(config: Path, targets_path: Path, rig: Path) -> dict:
    s = nominal_suspension(config, rig)
    targets = load_targets(targets_path, s)
    x0 = start(s, targets)[0]
    one = plain_run_cpu(s, targets, x0)
    t = cpu()
    exact = optimise(s, targets)
    exact_cpu = cpu() - t
    t = cpu()
    fd = fd_optimise(s, targets)
    fd_cpu = cpu() - t
    out = {
        "config": str(config.relative_to(ROOT)), "targets": str(targets_path),
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
    s = nominal_suspension(config, rig)
    t = cpu()
    tab = sensitivity_table(s)
    table_cpu = cpu() - t
    rig_spec = s.rig.model_copy(update={n: None for n in type(s.rig).model_fields
                                        if n != "parallel_travel" and n not in
                                        TABLE_LOAD_CASES})
    best = np.inf
    for _ in range(2):
        t = cpu()
        run_design(s, [], [], ("initial",), rig_spec, derivatives=False)
        best = min(best, cpu() - t)
    n = len(tab.variables)
    return {"config": str(config.relative_to(ROOT)), "coordinates": n,
            "characteristics": len(tab.characteristics), "cpu_s": table_cpu,
            "plain_run_cpu_s": best, "model_run_equivalents": table_cpu / best,
            "finite_difference_runs": 2 * n + 1,
            "fewer_equivalents": (2 * n + 1) / (table_cpu / best)}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="the small cases (seconds)")
    ap.add_argument("--out", default=str(ROOT / "benchmarks" / "results" / "bench_design.json"))
    args = ap.parse_args()
    dw, case = ROOT / "configs" / "double_wishbone_axle.yaml", \
        ROOT / "configs" / "pseudo_mcpherson.yaml"
    result = {"elastokin_version": __version__, "exudyn_version": EXUDYN_VERSION,
              "machine": {"python": platform.python_version(),
                          "processor": platform.machine()},
              "quick": args.quick}
    if args.quick:
        import tempfile

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
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    Path(args.out).write_text(json.dumps(result, indent=1) + "\n")


if __name__ == "__main__":
    main()
