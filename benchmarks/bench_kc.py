"""Speed of the virtual K&C rig on the compliant pseudo-McPherson (issue 2).

Times, in one run on this machine: model build, one static solve (design wheel load), and the
parallel-travel sweep (-90..+90 mm at 1 mm after the approach from the design position), set up
two ways:

- ``tuned`` (what ``elastokin kc`` does): Rxyz nodes, bushing laws in C++ (Exudyn's stiffness
  matrix for linear laws, symbolic user functions otherwise), rig paths as symbolic user
  functions, modified Newton, one SolveStatic over all steps, outputs recorded by sensors;
- ``naive`` (the straightforward set-up): Python user functions for bushings and rig paths,
  full Newton, one SolveStatic call per point.

Both give the same curve (checked here). Best of ``--repeat`` runs.

End to end (issue 17), the commands a user runs, as subprocesses: ``elastokin --help``
(``help_s``), ``elastokin kc`` on the case study into a new folder (``kc_cold_s``: no cache)
and again into the same folder (``kc_warm_s``: identification, fit and load cases reused),
``--models initial,identified`` (``kc_no_fit_s``), and the charts of a run (``charts_s``);
the machine's load average beside them.

The stiffness fit (issue 17), alone, in a subprocess each: today's (exact sensitivities,
maximum likelihood) and that of an earlier release (``--baseline-rev``, default the last
commit with finite-difference Jacobians and reweighting passes, exported with ``git
archive``; ``--baseline-rev none`` skips it): wall time ``fit_s``, CPU time of the process
and its workers ``fit_cpu_s``, model runs, and ``model_run_equivalents`` = fit CPU time / CPU
time of one plain run of the test's load cases on the same model (same run, same machine).

The sweep again with the static solver set up as before issue 28 (``ms_per_point_before_
issue28``; the same results). The sweep of an earlier revision and of today's code, each in a
subprocess with the same script (``sweep_revisions``; ``--sweep-baseline-rev``, default the
merge of issue 28, before its speed work; exported with ``git archive``): CPU time per point,
the part of it inside Exudyn's ``SolveStatic`` (C++: Newton iterations, residuals, sensors)
and the rest (Python: inputs, states, the rig's columns), the largest difference of the
spin axes between the revisions, and Exudyn's own statistics of one solve (Newton
iterations per step, its CPU-time shares). ``--quick`` (the tests): the per-point figures and
today's sweep in its subprocess on +-20 mm (no baseline revision).

Prints the figures and writes them to ``benchmarks/results/bench_kc.json``. Targets:
ms_per_point <= 0.3 and at least 5x below ms_per_point_naive (issue 2); kc cold <= 10 s,
warm <= 3 s, help <= 0.5 s, charts <= 1 s for the corner's 8 (issue 17) and <= 1.5 s with the
axle's (issue 18: the case study is an axle, 12 charts), the fit >= 10x fewer model-run
equivalents than the baseline (issue 17).
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import platform
import time
from pathlib import Path

import numpy as np

from elastokin.config.loading import load_suspension
from elastokin.mbs.design import build_model, design_state
from elastokin.mbs.model import EXUDYN_VERSION, ModelOptions
from elastokin.rig.pad import run_pad
from elastokin.rig.paths import travel_path
from elastokin.version import __version__

ROOT = Path(__file__).resolve().parents[1]


def command_s(*args: str) -> float:
    """Wall time of one ``elastokin`` command (a subprocess, as a user runs it)."""
    import subprocess
    import sys

    t0 = time.perf_counter()
    subprocess.run([sys.executable, "-c", "import sys; from elastokin.cli import main; "
                    "sys.exit(main())", *args], check=True, capture_output=True)
    return time.perf_counter() - t0


def end_to_end(config: str) -> dict:
    """The end-to-end figures (see the module docstring)."""
    import os
    import tempfile

    from elastokin.report.axle_charts import axle_chart_inputs
    from elastokin.report.charts import kc_charts
    from elastokin.report.files import read_results

    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "res"
        load = os.getloadavg()[0]
        figures = {"help_s": command_s("--help"),
                   "kc_cold_s": command_s("kc", "--config", config, "--out", str(out),
                                          "--quiet"),
                   "kc_warm_s": command_s("kc", "--config", config, "--out", str(out),
                                          "--quiet"),
                   "kc_no_fit_s": command_s("kc", "--config", config, "--out",
                                            str(Path(tmp) / "nofit"), "--quiet", "--models",
                                            "initial,identified")}
        summary, sweeps = read_results(out)
        prov = {k: summary[k] for k in ("elastokin_version", "exudyn_version", "config_file",
                                        "config_sha256")}
        charts = Path(tmp) / "charts"
        charts.mkdir()
        t0 = time.perf_counter()
        kc_charts(sweeps, charts, prov, summary["errors"], axle=axle_chart_inputs(summary))
        figures["charts_s"] = time.perf_counter() - t0
        figures["fit_model_runs"] = json.loads(
            (out / "stiffness_identification.json").read_text())["evaluations"]
        figures["load_average_1min_before"] = load
    figures["targets"] = {"kc_cold_s_max": 10.0, "kc_warm_s_max": 3.0, "help_s_max": 0.5}
    return figures


#: the last commit whose stiffness fit used finite-difference Jacobians (541 model runs)
BASELINE_REV = "20eb699"
#: the fit of one release, timed in a subprocess (the same script for both: argv config)
FIT_SCRIPT = r"""
import dataclasses, json, resource, sys, time
from elastokin.config.loading import load_suspension
from elastokin.mbs.design import build_model
from elastokin.rig.comparison import rig_for_test
from elastokin.rig.load_cases import run_load_cases
from elastokin.studies import kc_job
s = load_suspension(sys.argv[1])
test, _ = kc_job.test_data(s)
v = kc_job.preloads(kc_job.model_variants(s, kc_job.geometry(s)))["identified"]
rig = rig_for_test(test, v.suspension.rig)
model = build_model(dataclasses.replace(v, suspension=dataclasses.replace(v.suspension,
                                                                          rig=rig)))
run_load_cases(model, "plain")
t = time.process_time(); run_load_cases(model, "plain"); run_cpu = time.process_time() - t
def cpu():
    a, b = (resource.getrusage(w) for w in (resource.RUSAGE_SELF, resource.RUSAGE_CHILDREN))
    return a.ru_utime + a.ru_stime + b.ru_utime + b.ru_stime
c0, w0 = cpu(), time.perf_counter()
fit = kc_job.fit(s, v, test)
wall, fit_cpu = time.perf_counter() - w0, cpu() - c0
passes = getattr(fit, "passes", len(fit.settings.get("reweighting", [])) + 1)
print(json.dumps({"fit_s": wall, "fit_cpu_s": fit_cpu, "fit_model_runs": fit.evaluations,
                  "passes": passes, "plain_run_cpu_s": run_cpu,
                  "model_run_equivalents": fit_cpu / run_cpu,
                  "values": {p.bushing + "." + p.name: p.value for p in fit.parameters}}))
"""


def fit_figures(root: Path, config: Path) -> dict:
    """The fit of the code in ``root`` on ``config``, in a subprocess (FIT_SCRIPT)."""
    import os
    import subprocess
    import sys

    env = dict(os.environ, PYTHONPATH=str(root))
    out = subprocess.run([sys.executable, "-c", FIT_SCRIPT, str(config)], cwd=root, env=env,
                         check=True, capture_output=True, text=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def fit_comparison(baseline_rev: str | None) -> dict:
    """Today's fit and the baseline release's, in one run (see the module docstring)."""
    import subprocess
    import tempfile

    config = Path("configs") / "pseudo_mcpherson.yaml"
    result = {"today": fit_figures(ROOT, ROOT / config)}
    if baseline_rev:
        with tempfile.TemporaryDirectory() as tmp:
            archive = subprocess.run(["git", "archive", baseline_rev], cwd=ROOT,
                                     check=True, capture_output=True).stdout
            subprocess.run(["tar", "-x", "-C", tmp], input=archive, check=True)
            result["baseline"] = {"rev": baseline_rev,
                                  **fit_figures(Path(tmp), Path(tmp) / config)}
        b, t = result["baseline"], result["today"]
        result["model_run_equivalents_ratio"] = (b["model_run_equivalents"]
                                                 / t["model_run_equivalents"])
        result["fit_s_ratio"] = b["fit_s"] / t["fit_s"]
    return result


#: the merge of issue 28 (design to targets), before its speed work (the sweep's baseline)
SWEEP_BASELINE_REV = "52a3eb2"
#: one revision's sweep of parallel travel, timed in a subprocess (argv: config, repeat,
#: travel half-width in mm or 0 for the config's): CPU time of the whole sweep and of the
#: part inside Exudyn's SolveStatic, best of repeat; then one solve with Exudyn's statistics
#: printed (parsed by the caller). Module-level names both revisions have.
SWEEP_SCRIPT = r"""
import json, sys, time
import numpy as np
import elastokin.mbs.solve as solve
from elastokin.config.loading import load_suspension
from elastokin.mbs.design import build_model, design_state
from elastokin.rig.pad import run_pad
from elastokin.rig.paths import travel_path
s = load_suspension(sys.argv[1])
repeat, half = int(sys.argv[2]), float(sys.argv[3])
tp = s.rig.parallel_travel
z, _ = travel_path(-half if half else tp.rebound_mm, half or tp.bump_mm, tp.step_mm,
                   tp.unloading)
model = build_model(s, design=design_state(s))
call, inside = solve.exudyn_call, [0.0]
def timed(fn, what):
    t = time.process_time()
    try:
        return call(fn, what)
    finally:
        inside[0] += time.process_time() - t
solve.exudyn_call = timed
run_pad(model, pad_z_mm=z)
best = (np.inf, 0.0)
for _ in range(repeat):
    inside[0], t = 0.0, time.process_time()
    states = run_pad(model, pad_z_mm=z)
    best = min(best, (time.process_time() - t, inside[0]))
print(json.dumps({"points": len(z), "ms_per_point": 1e3 * best[0] / len(z),
                  "solve_static_ms_per_point": 1e3 * best[1] / len(z),
                  "spin_axes": [st.spin_axis.tolist() for st in states]}))
import exudyn
settings = solve.simulation_settings
def shown(m, n):
    ss = settings(m, n)
    ss.show.computationTime = ss.show.statistics = True
    ss.staticSolver.verboseMode = 1
    return ss
solve.simulation_settings = shown
solve.exudyn_call = lambda fn, what: fn()  # Exudyn's printout not captured
exudyn.config.printToConsole = True
run_pad(model, pad_z_mm=z)
"""


def exudyn_statistics(text: str) -> dict:
    """Newton iterations per step and Exudyn's CPU-time shares (%) from its printed
    statistics of one solve."""
    import re

    def number(pattern: str) -> float | None:
        m = re.search(pattern, text)
        return float(m.group(1)) if m else None

    steps = number(r"total number of steps:\s*(\d+)")
    iterations = number(r"total number of Newton iterations:\s*(\d+)")
    shares = {m.group(1): float(m.group(2)) for m in
              re.finditer(r"^\s*(\w+)\s*= ([\d.e+-]+)%", text, re.M)}
    return {"steps": steps, "newton_iterations": iterations,
            "newton_iterations_per_step": iterations / steps if steps and iterations else None,
            "jacobians": number(r"total number of Newton Jacobians:\s*(\d+)"),
            "cpu_time_share_percent": shares}


def sweep_figures(root: Path, config: Path, repeat: int, half_mm: float) -> dict:
    """One revision's sweep (SWEEP_SCRIPT) in a subprocess with the code in ``root``."""
    import os
    import subprocess
    import sys

    env = dict(os.environ, PYTHONPATH=str(root))
    out = subprocess.run([sys.executable, "-c", SWEEP_SCRIPT, str(config), str(repeat),
                          str(half_mm)], cwd=root, env=env, check=True, capture_output=True,
                         text=True)
    lines = out.stdout.splitlines()
    first = next(i for i, line in enumerate(lines) if line.startswith("{"))
    figures = json.loads(lines[first])
    figures["python_ms_per_point"] = figures["ms_per_point"] - figures[
        "solve_static_ms_per_point"]
    figures["exudyn"] = exudyn_statistics("\n".join(lines[first + 1:]))
    return figures


def sweep_revisions(config: Path, baseline_rev: str | None, repeat: int,
                    half_mm: float) -> dict:
    """Today's sweep and the baseline revision's, alternately in subprocesses (module
    docstring), with their ratio and the largest spin-axis difference."""
    import subprocess
    import tempfile

    rel = config.resolve().relative_to(ROOT)
    with tempfile.TemporaryDirectory() as tmp:
        roots = {"today": ROOT}
        if baseline_rev:
            archive = subprocess.run(["git", "archive", baseline_rev], cwd=ROOT,
                                     check=True, capture_output=True).stdout
            subprocess.run(["tar", "-x", "-C", tmp], input=archive, check=True)
            roots["baseline"] = Path(tmp)
        runs = {name: sweep_figures(root, root / rel, repeat, half_mm)
                for name, root in roots.items()}
    result = {name: {k: v for k, v in r.items() if k != "spin_axes"}
              for name, r in runs.items()}
    if baseline_rev:
        result["baseline"]["rev"] = baseline_rev
        result["ms_per_point_ratio"] = (runs["baseline"]["ms_per_point"]
                                        / runs["today"]["ms_per_point"])
        result["max_spin_axis_difference"] = float(np.max(np.abs(
            np.array(runs["baseline"]["spin_axes"]) - np.array(runs["today"]["spin_axes"]))))
    return result


def sweep_before_issue28(model, z):
    """The sweep with the static solver set up as before issue 28 (the discontinuous
    iteration's five passes)."""
    import elastokin.mbs.solve as solve

    now = solve.simulation_settings

    def before(m, steps):
        ss = now(m, steps)
        ss.staticSolver.discontinuous.maxIterations = 5
        return ss

    solve.simulation_settings = before
    try:
        return run_pad(model, pad_z_mm=z)
    finally:
        solve.simulation_settings = now


def best_of(fn, repeat: int) -> tuple[float, object]:
    best, out = float("inf"), None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return best, out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--config", default=str(ROOT / "configs" / "pseudo_mcpherson.yaml"))
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--out", default=str(ROOT / "benchmarks" / "results" / "bench_kc.json"))
    ap.add_argument("--baseline-rev", default=BASELINE_REV,
                    help="git revision whose stiffness fit is the baseline ('none': skip)")
    ap.add_argument("--sweep-baseline-rev", default=SWEEP_BASELINE_REV,
                    help="git revision whose sweep is timed beside today's ('none': skip)")
    ap.add_argument("--quick", action="store_true",
                    help="the per-point figures only, one repeat (seconds; the tests run it)")
    args = ap.parse_args()
    if args.quick:
        args.repeat = min(args.repeat, 2)

    s = load_suspension(args.config)
    design = design_state(s)
    tp = s.rig.parallel_travel
    z, _ = travel_path(tp.rebound_mm, tp.bump_mm, tp.step_mm, tp.unloading)
    n = len(z)

    t_build, model = best_of(lambda: build_model(s, ModelOptions(), design), args.repeat)
    t_static, _ = best_of(lambda: run_pad(model, pad_loads=[s.up * s.design.wheel_load_N]),
                          args.repeat)
    t_sweep, tuned = best_of(lambda: run_pad(model, pad_z_mm=z), args.repeat)
    t_before, before = best_of(lambda: sweep_before_issue28(model, z), args.repeat)
    before_diff = float(np.max(np.abs(np.array([st.spin_axis for st in tuned])
                                      - np.array([st.spin_axis for st in before]))))

    naive_s = dataclasses.replace(s, solver=s.solver.model_copy(
        update={"modified_newton": False}))
    naive_model = build_model(naive_s, ModelOptions(user_functions="python"), design)
    naive_z = z[:20] if args.quick else z  # quick: the naive way's first 20 points
    t_naive, naive = best_of(lambda: run_pad(naive_model, pad_z_mm=naive_z,
                                             solve_per_step=True), args.repeat)
    t_naive *= len(z) / len(naive_z)
    toe = np.array([st.spin_axis for st in tuned])[:len(naive)]
    toe_naive = np.array([st.spin_axis for st in naive])
    max_diff = float(np.max(np.abs(toe - toe_naive)))

    result = {
        "elastokin_version": __version__,
        "exudyn_version": EXUDYN_VERSION,
        "config_sha256": s.sha256,
        "machine": {"python": platform.python_version(), "processor": platform.machine()},
        "points": n,
        "repeat": args.repeat,
        "build_ms": 1e3 * t_build,
        "static_solve_ms": 1e3 * t_static,
        "sweep_ms": 1e3 * t_sweep,
        "ms_per_point": 1e3 * t_sweep / n,
        "ms_per_point_naive": 1e3 * t_naive / n,
        "ms_per_point_before_issue28": 1e3 * t_before / n,
        "max_spin_axis_difference_before_issue28": before_diff,
        "speedup": t_naive / t_sweep,
        "max_spin_axis_difference_tuned_vs_naive": max_diff,
        "solver": model.solver_settings(),
        "targets": {"ms_per_point_max": 0.3, "speedup_min": 5.0},
    }
    result["meets_targets"] = bool(result["ms_per_point"] <= 0.3 and result["speedup"] >= 5.0)
    result["quick"] = args.quick
    result["sweep_revisions"] = sweep_revisions(
        Path(args.config), None if args.quick or args.sweep_baseline_rev == "none" else
        args.sweep_baseline_rev, args.repeat, 20.0 if args.quick else 0.0)
    if not args.quick:
        result["end_to_end"] = end_to_end(args.config)
        result["stiffness_fit"] = fit_comparison(None if args.baseline_rev == "none"
                                                 else args.baseline_rev)
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    Path(args.out).write_text(json.dumps(result, indent=2) + "\n")
    print(f"model build        {result['build_ms']:8.2f} ms")
    print(f"static solve       {result['static_solve_ms']:8.2f} ms")
    print(f"sweep ({n} points) {result['sweep_ms']:8.2f} ms  -> {result['ms_per_point']:.3f} "
          "ms/point (target <= 0.3)")
    print(f"naive sweep        {1e3 * t_naive:8.2f} ms  -> {result['ms_per_point_naive']:.3f} "
          f"ms/point; speed-up {result['speedup']:.1f}x (target >= 5)")
    print(f"tuned vs naive: max spin-axis difference {max_diff:.2e}")
    print(f"before issue 28    {1e3 * t_before:8.2f} ms  -> "
          f"{result['ms_per_point_before_issue28']:.3f} ms/point (the same results: max "
          f"spin-axis difference {before_diff:.1e})")
    sw = result["sweep_revisions"]
    for name in ("baseline", "today"):
        if name in sw:
            r = sw[name]
            print(f"sweep, {name:<8} {r.get('rev', 'this code'):>9}: {r['ms_per_point']:.3f} "
                  f"ms/point CPU ({r['solve_static_ms_per_point']:.3f} in Exudyn's "
                  f"SolveStatic, {r['python_ms_per_point']:.3f} Python; "
                  f"{r['exudyn']['newton_iterations_per_step'] or float('nan'):.1f} Newton "
                  "iterations a step)")
    if "ms_per_point_ratio" in sw:
        print(f"sweep: {sw['ms_per_point_ratio']:.2f}x faster than {sw['baseline']['rev']}, max "
              f"spin-axis difference {sw['max_spin_axis_difference']:.1e}")
    if args.quick:
        print(f"written to {args.out}")
        return
    e = result["end_to_end"]
    print(f"elastokin --help    {e['help_s']:8.2f} s (target <= 0.5)")
    print(f"kc cold             {e['kc_cold_s']:8.2f} s (target <= 10; stiffness fit "
          f"{e['fit_model_runs']} model runs)")
    print(f"kc warm (cache)     {e['kc_warm_s']:8.2f} s (target <= 3)")
    print(f"kc --models initial,identified {e['kc_no_fit_s']:8.2f} s")
    print(f"charts              {e['charts_s']:8.2f} s (target <= 1)")
    f = result["stiffness_fit"]
    for name, v in (("fit (today)", f["today"]), ("fit (baseline)", f.get("baseline"))):
        if v:
            print(f"{name:<19} {v['fit_s']:8.2f} s wall, {v['fit_cpu_s']:.2f} s CPU, "
                  f"{v['fit_model_runs']} model runs, {v['passes']} passes, "
                  f"{v['model_run_equivalents']:.1f} model-run equivalents")
    if "model_run_equivalents_ratio" in f:
        print(f"fit: {f['model_run_equivalents_ratio']:.1f}x fewer model-run equivalents "
              f"than {f['baseline']['rev']} (target >= 10), {f['fit_s_ratio']:.1f}x faster")
    print(f"written to {args.out}")


if __name__ == "__main__":
    main()
