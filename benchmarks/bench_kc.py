"""Speed of the virtual K&C rig on the compliant pseudo-McPherson (issue 2).

Times, in one run on this machine: model build, one static solve (design wheel load), and the
parallel-travel sweep (-90..+90 mm at 1 mm after the approach from the design position), set up
two ways:

- ``tuned`` (what ``elastokin kc`` does): Rxyz nodes, bushing laws in C++ (Exudyn's stiffness
  matrix for linear laws, symbolic user functions otherwise), rig paths as symbolic user
  functions, modified Newton, one SolveStatic over all steps, outputs recorded by sensors;
- ``naive`` (the straightforward set-up): Python user functions for bushings and rig paths,
  full Newton, one SolveStatic call per point.

Both give the same curve (checked here); the tuned sweep again with the static solver set up
as before issue 28 (``ms_per_point_before_issue28``: Exudyn's five passes of the discontinuous
iteration, ``ModelOptions(discontinuous_iterations=5)``; the same results). Best of
``--repeat`` runs.

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

The sweep of an earlier revision and of today's code, each in a subprocess with the same
script (``sweep_revisions``; ``--sweep-baseline-rev``, default the merge of issue 28, before
its speed work; exported with ``git archive``): CPU time per point, the part of it inside
Exudyn's ``SolveStatic`` (C++: Newton iterations, residuals, sensors) and the rest (Python:
inputs, states, the rig's columns), the largest difference of the spin axes between the
revisions (not zero against a revision before issue 24: the pad holds the tyre's lowest
point), and Exudyn's own statistics of one solve (Newton iterations per step, its CPU-time
shares).

Prints the figures and writes them to ``benchmarks/results/bench_kc.json``. ``--quick``
(bench_common): parallel travel only (configs/rigs/travel_only.yaml), one run (the naive
set-up over 5 points), today's sweep in its subprocess on +-20 mm (no baseline revision),
``--help`` and one ``elastokin kc`` of the double wishbone axle at that rig, its charts; the
fit's names checked, the fit not run. Targets:
ms_per_point <= 0.3 and at least 5x below ms_per_point_naive (issue 2); kc cold <= 10 s,
warm <= 3 s, help <= 0.5 s, charts <= 1 s for the corner's 8 (issue 17) and <= 1.5 s with the
axle's (issue 18: the case study is an axle, 12 charts), the fit >= 10x fewer model-run
equivalents than the baseline (issue 17).
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import os
import platform
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

import elastokin as ek

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_common import add_output_options, output_path, write_json  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
#: the quick mode's rig (bench_common): parallel travel only, +-50 mm in 2 mm steps, and its
#: end-to-end run: the double wishbone axle (no identification, no fit), one model
QUICK_RIG = ROOT / "configs" / "rigs" / "travel_only.yaml"
QUICK_KC = ("--config", str(ROOT / "configs" / "double_wishbone_axle.yaml"), "--rig",
            str(QUICK_RIG), "--models", "initial")


def command_s(*args: str) -> float:
    """Wall time of one ``elastokin`` command (a subprocess, as a user runs it)."""
    t0 = time.perf_counter()
    subprocess.run([sys.executable, "-c", "import sys; from elastokin.cli import main; "
                    "sys.exit(main())", *args], check=True, capture_output=True)
    return time.perf_counter() - t0


def end_to_end(config: str, quick: bool) -> dict:
    """The end-to-end figures (see the module docstring; quick: --help and one run of
    :data:`QUICK_KC`, its charts)."""
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "res"
        figures = {"load_average_1min_before": os.getloadavg()[0],
                   "help_s": command_s("--help")}
        if quick:
            figures["kc_cold_s"] = command_s("kc", *QUICK_KC, "--out", str(out), "--quiet")
        else:
            kc = ("kc", "--config", config, "--quiet")
            figures["kc_cold_s"] = command_s(*kc, "--out", str(out))
            figures["kc_warm_s"] = command_s(*kc, "--out", str(out))
            figures["kc_no_fit_s"] = command_s(*kc, "--out", str(Path(tmp) / "nofit"),
                                               "--models", "initial,identified")
        summary, sweeps = ek.read_results(out)
        charts = Path(tmp) / "charts"
        charts.mkdir()
        t0 = time.perf_counter()
        ek.draw_kc_charts(summary, sweeps, charts)
        figures["charts_s"] = time.perf_counter() - t0
        fit = out / "stiffness_identification.json"
        figures["fit_model_runs"] = (json.loads(fit.read_text())["evaluations"]
                                     if fit.exists() else None)
    figures["targets"] = {"kc_cold_s_max": 10.0, "kc_warm_s_max": 3.0, "help_s_max": 0.5}
    return figures


#: the last commit whose stiffness fit used finite-difference Jacobians (541 model runs)
BASELINE_REV = "20eb699"
#: the fit of one release, timed in a subprocess (the same script for both: argv config).
#: It runs on the baseline release too, which predates today's ``elastokin`` API: it uses
#: the module-level public functions both releases have.
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


def fit_script_names() -> dict:
    """The quick mode's check of FIT_SCRIPT: the names it imports exist (the fit itself takes
    seconds), by import in this process."""
    import importlib

    def exists(module: str, name: str) -> bool:
        if hasattr(importlib.import_module(module), name):
            return True
        try:  # a submodule
            return importlib.import_module(f"{module}.{name}") is not None
        except ImportError:
            return False

    checked = {}
    for line in FIT_SCRIPT.splitlines():
        words = line.split()
        if line.startswith("from elastokin"):
            for name in " ".join(words[3:]).split(","):
                checked[f"{words[1]}.{name.strip()}"] = exists(words[1], name.strip())
    missing = [k for k, ok in checked.items() if not ok]
    if missing:
        raise SystemExit(f"bench_kc: FIT_SCRIPT imports names that do not exist: {missing}")
    return {"skipped": "quick mode: the fit's names checked, the fit not run",
            "names": sorted(checked)}


def fit_figures(root: Path, config: Path) -> dict:
    """The fit of the code in ``root`` on ``config``, in a subprocess (FIT_SCRIPT)."""
    env = dict(os.environ, PYTHONPATH=str(root))
    out = subprocess.run([sys.executable, "-c", FIT_SCRIPT, str(config)], cwd=root, env=env,
                         check=True, capture_output=True, text=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def fit_comparison(baseline_rev: str | None) -> dict:
    """Today's fit and the baseline release's, in one run (see the module docstring)."""
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


def best_of(fn, repeat: int) -> tuple[float, object]:
    best, out = float("inf"), None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return best, out


def solver_figures(s, design, repeat: int, naive_points: int | None = None) -> dict:
    """Model build, one static solve and the parallel-travel sweep, tuned and naive (see the
    module docstring; the naive one over the first ``naive_points`` points: all by default),
    best of ``repeat``."""
    z = ek.parallel_travel_drive(s).inputs  # from the design position, the stroke, the return
    n, n_naive = len(z), len(z) if naive_points is None else naive_points
    t_build, model = best_of(lambda: ek.build_model(s, ek.ModelOptions(), design), repeat)
    t_static, _ = best_of(lambda: ek.run_pad(model, pad_loads=[s.up * s.design.wheel_load_N]),
                          repeat)
    t_sweep, tuned = best_of(lambda: ek.run_pad(model, pad_z_mm=z), repeat)
    naive_s = dataclasses.replace(s, solver=s.solver.model_copy(
        update={"modified_newton": False}))
    naive_model = ek.build_model(naive_s, ek.ModelOptions(user_functions="python"), design)
    t_naive, naive = best_of(lambda: ek.run_pad(naive_model, pad_z_mm=z[:n_naive],
                                                solve_per_step=True), repeat)
    spin = np.array([st.spin_axis for st in tuned[:n_naive]])
    spin_naive = np.array([st.spin_axis for st in naive])
    # the static solver set up as before issue 28: Exudyn's five passes of the discontinuous
    # iteration (the same results, bit for bit)
    before_model = ek.build_model(s, ek.ModelOptions(discontinuous_iterations=5), design)
    t_before, before = best_of(lambda: ek.run_pad(before_model, pad_z_mm=z), repeat)
    spin_all = np.array([st.spin_axis for st in tuned])
    before_diff = float(np.max(np.abs(spin_all - np.array([st.spin_axis for st in before]))))
    out = {"points": n, "repeat": repeat, "build_ms": 1e3 * t_build,
           "static_solve_ms": 1e3 * t_static, "sweep_ms": 1e3 * t_sweep,
           "ms_per_point": 1e3 * t_sweep / n, "naive_points": n_naive,
           "naive_sweep_ms": 1e3 * t_naive, "ms_per_point_naive": 1e3 * t_naive / n_naive,
           "speedup": (t_naive / n_naive) / (t_sweep / n),
           "ms_per_point_before_issue28": 1e3 * t_before / n,
           "max_spin_axis_difference_before_issue28": before_diff,
           "max_spin_axis_difference_tuned_vs_naive": float(np.max(np.abs(spin - spin_naive))),
           "solver": model.solver_settings(),
           "targets": {"ms_per_point_max": 0.3, "speedup_min": 5.0}}
    out["meets_targets"] = bool(out["ms_per_point"] <= 0.3 and out["speedup"] >= 5.0)
    return out


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--config", default=str(ROOT / "configs" / "pseudo_mcpherson.yaml"))
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--baseline-rev", default=BASELINE_REV,
                    help="git revision whose stiffness fit is the baseline ('none': skip)")
    ap.add_argument("--sweep-baseline-rev", default=SWEEP_BASELINE_REV,
                    help="git revision whose sweep is timed beside today's ('none': skip)")
    add_output_options(ap, "bench_kc")
    args = ap.parse_args(argv)
    out = output_path(args, "bench_kc")

    s = ek.load_suspension_with_rig(args.config, QUICK_RIG if args.quick else None)
    result = {"elastokin_version": ek.__version__, "exudyn_version": ek.exudyn_version(),
              "config_sha256": s.sha256, "quick": args.quick,
              "machine": {"python": platform.python_version(),
                          "processor": platform.machine()},
              **solver_figures(s, ek.design_state(s), 1 if args.quick else args.repeat,
                               5 if args.quick else None)}
    result["sweep_revisions"] = sweep_revisions(
        Path(args.config), None if args.quick or args.sweep_baseline_rev == "none" else
        args.sweep_baseline_rev, 1 if args.quick else args.repeat, 20.0 if args.quick else 0.0)
    result["end_to_end"] = end_to_end(args.config, args.quick)
    if args.quick:
        result["stiffness_fit"] = fit_script_names()
    else:
        result["stiffness_fit"] = fit_comparison(None if args.baseline_rev == "none"
                                                 else args.baseline_rev)
    write_json(out, result)
    report(result, out)


def report(r: dict, out: Path) -> None:
    n = r["points"]
    print(f"model build        {r['build_ms']:8.2f} ms")
    print(f"static solve       {r['static_solve_ms']:8.2f} ms")
    print(f"sweep ({n} points) {r['sweep_ms']:8.2f} ms  -> {r['ms_per_point']:.3f} "
          "ms/point (target <= 0.3)")
    print(f"naive ({r['naive_points']} points) {r['naive_sweep_ms']:8.2f} ms  -> "
          f"{r['ms_per_point_naive']:.3f} ms/point; speed-up {r['speedup']:.1f}x (target >= 5)")
    print("tuned vs naive: max spin-axis difference "
          f"{r['max_spin_axis_difference_tuned_vs_naive']:.2e}")
    print(f"before issue 28    {r['ms_per_point_before_issue28']:.3f} ms/point (the same "
          f"results: max spin-axis difference {r['max_spin_axis_difference_before_issue28']:.1e})")
    sw = r["sweep_revisions"]
    for name in ("baseline", "today"):
        if name in sw:
            v = sw[name]
            print(f"sweep, {name:<8} {v.get('rev', 'this code'):>9}: {v['ms_per_point']:.3f} "
                  f"ms/point CPU ({v['solve_static_ms_per_point']:.3f} in Exudyn's "
                  f"SolveStatic, {v['python_ms_per_point']:.3f} Python; "
                  f"{v['exudyn']['newton_iterations_per_step'] or float('nan'):.1f} Newton "
                  "iterations a step)")
    if "ms_per_point_ratio" in sw:
        print(f"sweep: {sw['ms_per_point_ratio']:.2f}x faster than {sw['baseline']['rev']}, max "
              f"spin-axis difference {sw['max_spin_axis_difference']:.1e}")
    e = r["end_to_end"]
    print(f"elastokin --help    {e['help_s']:8.2f} s (target <= 0.5)")
    print(f"kc cold             {e['kc_cold_s']:8.2f} s (target <= 10; stiffness fit "
          f"{e['fit_model_runs']} model runs)")
    if "kc_warm_s" in e:
        print(f"kc warm (cache)     {e['kc_warm_s']:8.2f} s (target <= 3)")
        print(f"kc --models initial,identified {e['kc_no_fit_s']:8.2f} s")
    print(f"charts              {e['charts_s']:8.2f} s (target <= 1)")
    f = r["stiffness_fit"]
    for name, v in (("fit (today)", f.get("today")), ("fit (baseline)", f.get("baseline"))):
        if v:
            print(f"{name:<19} {v['fit_s']:8.2f} s wall, {v['fit_cpu_s']:.2f} s CPU, "
                  f"{v['fit_model_runs']} model runs, {v['passes']} passes, "
                  f"{v['model_run_equivalents']:.1f} model-run equivalents")
    if "model_run_equivalents_ratio" in f:
        print(f"fit: {f['model_run_equivalents_ratio']:.1f}x fewer model-run equivalents "
              f"than {f['baseline']['rev']} (target >= 10), {f['fit_s_ratio']:.1f}x faster")
    print(f"load average {e['load_average_1min_before']:.2f} before the commands; "
          f"written to {out}")


if __name__ == "__main__":
    main()
