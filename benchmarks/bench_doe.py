"""Throughput of the DOE path on the compliant pseudo-McPherson (issue 5, part 3).

A "sweep" is what ``elastokin doe --load-cases travel`` does for one sample: clearance shifts
-> as-built model (nominal design preloads computed once, see
``elastokin.studies.doe.study_job``) ->
parallel wheel travel, whose measured stroke is 181 points (-90..+90 mm at 1 mm; the approach
from the design position to -90 mm is solved in 30 mm steps and not recorded: 183 solved
points) -> steer amplitude, bump steer, bump camber. Measured, in one run on this machine:

- ``in_process``: ``evaluate_sample`` in a loop, no dask (``--workers 1``);
- ``reuse_model``: the nominal model built once and swept again and again (not a DOE: it
  shows what the model build costs per sweep);
- ``dask``: ``run_dask`` (what ``elastokin doe`` runs) on a LocalCluster of 1 and of 2
  single-threaded worker processes, worker profiler off as in ``elastokin doe`` (cluster
  start-up and worker warm-up excluded; ``--batch`` samples per task); best of ``--repeat``
  runs of all the sweeps (every run is recorded), as in bench_kc.

Plus a profile of one sweep (as-built config, model build, solve, characteristics). Prints the
figures and writes ``benchmarks/results/bench_doe.json``. Target (issue 5): >= 3000 sweeps per
minute on this 2-core machine (``sweeps_per_minute["2"]``).
"""

from __future__ import annotations

import argparse
import json
import logging
import os
import platform
import time
from pathlib import Path

import numpy as np

from elastokin.config.loading import load_suspension
from elastokin.mbs.design import design_state
from elastokin.mbs.model import EXUDYN_VERSION
from elastokin.rig.paths import leg
from elastokin.studies import doe, doe_runner
from elastokin.version import __version__

ROOT = Path(__file__).resolve().parents[1]
TARGET = 3000.0


def per_minute(count: int, seconds: float) -> float:
    return 60.0 * count / seconds


def profile(study: doe.Study, repeat: int) -> dict:
    """Median ms of each stage of one sweep, over ``repeat`` samples."""
    from elastokin.config.variants import DesignState
    from elastokin.mbs.model import ModelOptions, SuspensionModel
    from elastokin.rig.characteristics import characteristics
    from elastokin.rig.pad import run_pad
    from elastokin.synthetic.virtual_cmm import as_built

    s, design = doe._context(study.job)
    spec = s.rig.parallel_travel
    z = np.r_[leg(0.0, spec.rebound_mm, doe.APPROACH_STEP_MM),
              leg(spec.rebound_mm, spec.bump_mm, spec.step_mm)]
    t = {"as_built_ms": [], "model_build_ms": [], "solve_ms": [], "characteristics_ms": []}
    for k in range(repeat):
        shifts = {n: np.asarray(v) for n, v in study.shifts(k % study.samples).items()}
        t0 = time.perf_counter()
        ab = as_built(s, shifts, design)
        t1 = time.perf_counter()
        model = SuspensionModel(ab.suspension, ModelOptions(),
                                DesignState(ab.spring_force_N, ab.bushing_preload))
        t2 = time.perf_counter()
        states = run_pad(model, pad_z_mm=z)
        t3 = time.perf_counter()
        characteristics(states, s)
        t4 = time.perf_counter()
        for key, dt in zip(t, (t1 - t0, t2 - t1, t3 - t2, t4 - t3)):
            t[key].append(1e3 * dt)
    out = {k: float(np.median(v)) for k, v in t.items()}
    out["solved_points"] = int(z.size)
    out["solve_ms_per_point"] = out["solve_ms"] / z.size
    return out


def in_process(study: doe.Study, n: int) -> tuple[float, list[int]]:
    """Sweeps per minute evaluating samples in this process, and the samples that failed."""
    for k in range(3):  # warm-up
        doe.evaluate_sample(study.job, k, study.shifts(k))
    t0 = time.perf_counter()
    failed = []
    for k in range(n):
        if doe.evaluate_sample(study.job, k, study.shifts(k))["status"] != "ok":
            failed.append(k)
    return per_minute(n, time.perf_counter() - t0), failed


def reuse_model(study: doe.Study, n: int) -> float:
    s, design = doe._context(study.job)
    model = doe.as_built_model(s, {}, design)  # the nominal model
    doe.travel_sweep(model)
    t0 = time.perf_counter()
    for _ in range(n):
        doe.travel_sweep(model)
    return per_minute(n, time.perf_counter() - t0)


def on_dask(study: doe.Study, workers: int, batch: int, repeat: int) -> list[float]:
    """Sweeps per minute of ``repeat`` timed runs of the whole study on one LocalCluster."""
    import dask
    from distributed import Client, LocalCluster

    with dask.config.set({"distributed.worker.profile.enabled": False}):  # as elastokin doe
        cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                               dashboard_address=None, silence_logs=logging.ERROR)
    items = [(k, study.shifts(k)) for k in range(study.samples)]
    rates = []
    with cluster, Client(cluster) as client:
        doe_runner.run_dask(client, study.job, items[:4 * workers], lambda rec: None, 1)  # warm-up
        for _ in range(repeat):
            done = []
            t0 = time.perf_counter()
            doe_runner.run_dask(client, study.job, items, done.append, batch)
            rates.append(per_minute(study.samples, time.perf_counter() - t0))
            assert len(done) == study.samples
    return rates


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--config", default=str(ROOT / "configs" / "pseudo_mcpherson.yaml"))
    ap.add_argument("--sweeps", type=int, default=400, help="sweeps per measurement")
    ap.add_argument("--batch", type=int, default=4, help="samples per dask task")
    ap.add_argument("--repeat", type=int, default=3,
                    help="timed runs per dask set-up (the best is reported)")
    ap.add_argument("--out", default=str(ROOT / "benchmarks" / "results" / "bench_doe.json"))
    args = ap.parse_args()

    s = load_suspension(args.config)
    study = doe.make_study(s, args.sweeps, "lhs", 0, "travel", design_state(s))
    spec = s.rig.parallel_travel
    stroke = leg(spec.rebound_mm, spec.bump_mm, spec.step_mm).size + 1

    prof = profile(study, 30)
    serial, failed = in_process(study, args.sweeps)
    reuse = reuse_model(study, args.sweeps)
    runs = {str(w): on_dask(study, w, args.batch, args.repeat) for w in (1, 2)}
    dask = {w: max(r) for w, r in runs.items()}
    dask_batch1 = max(on_dask(study, 2, 1, args.repeat))

    result = {
        "elastokin_version": __version__,
        "exudyn_version": EXUDYN_VERSION,
        "config_file": os.path.relpath(args.config, ROOT),
        "config_sha256": s.sha256,
        "machine": {"python": platform.python_version(), "processor": platform.machine(),
                    "cores": os.cpu_count()},
        "sweep": {"load_case": "parallel_travel (elastokin doe --load-cases travel)",
                  "stroke_points": stroke, "solved_points": prof["solved_points"],
                  "stroke_mm": [spec.rebound_mm, spec.bump_mm], "step_mm": spec.step_mm,
                  "approach_step_mm": doe.APPROACH_STEP_MM,
                  "per_sweep": "clearance shifts -> as-built model build -> travel sweep -> "
                               "steer amplitude, bump steer, bump camber"},
        "sweeps_per_measurement": args.sweeps,
        "failed_sweeps": {"count": len(failed), "samples": failed,
                          "note": "as-built samples whose static solve did not converge "
                                  "(counted in the throughput: the DOE attempts them too)"},
        "sweeps_per_minute": dask,
        "sweeps_per_minute_all_runs": runs,
        "repeat": args.repeat,
        "sweeps_per_minute_dask_batch": args.batch,
        "sweeps_per_minute_2_workers_batch_1": dask_batch1,
        "sweeps_per_minute_in_process": serial,
        "sweeps_per_minute_reusing_one_model": reuse,
        "speedup_2_vs_1_worker": dask["2"] / dask["1"],
        "profile_one_sweep_ms": prof,
        "solver": doe.solver_settings(study),
        "target_sweeps_per_minute_2_workers": TARGET,
        "meets_target": bool(dask["2"] >= TARGET),
    }
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    Path(args.out).write_text(json.dumps(result, indent=2) + "\n")
    p = prof
    print(f"one sweep ({stroke} stroke points, {p['solved_points']} solved): as-built "
          f"{p['as_built_ms']:.2f} ms, model build {p['model_build_ms']:.2f} ms, solve "
          f"{p['solve_ms']:.2f} ms ({p['solve_ms_per_point']:.3f} ms/point), characteristics "
          f"{p['characteristics_ms']:.2f} ms")
    print(f"in process (no dask)         {serial:8.0f} sweeps/min ({len(failed)} of "
          f"{args.sweeps} samples failed to solve)")
    print(f"one model reused             {reuse:8.0f} sweeps/min")
    for w, v in dask.items():
        print(f"dask LocalCluster, {w} worker{'s' if w != '1' else ' '}  {v:8.0f} sweeps/min "
              f"(batch {args.batch})")
    print(f"dask LocalCluster, 2 workers  {dask_batch1:8.0f} sweeps/min (batch 1)")
    print("all runs: " + "; ".join(f"{w} worker(s) " + ", ".join(f"{v:.0f}" for v in r)
                                   for w, r in runs.items()))
    print(f"2 vs 1 worker: {result['speedup_2_vs_1_worker']:.2f}x; target >= {TARGET:.0f} "
          f"sweeps/min with 2 workers: {'met' if result['meets_target'] else 'NOT met'}")
    print(f"written to {args.out}")


if __name__ == "__main__":
    main()
