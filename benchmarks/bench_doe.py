"""Throughput of the DOE path on the compliant pseudo-McPherson (issue 5, part 3).

A "sweep" is what ``elastokin doe --load-cases travel`` does for one sample: clearance shifts
-> as-built model (nominal design preloads computed once, as ``elastokin doe`` does) ->
static state under the design wheel load -> parallel wheel travel, whose measured stroke is
181 points (-90..+90 mm at 1 mm; the approach from the static state to -90 mm is solved in
30 mm steps and not recorded) -> steer amplitude, bump steer, bump camber. Measured, in one run
on this machine, through elastokin's public API only:

- ``in_process``: ``ek.evaluate_sample`` in a loop, no dask (``--workers 1``);
- ``reuse_model``: the nominal model built once and swept again and again (not a DOE: it
  shows what the model build costs per sweep);
- ``dask``: ``ek.run_dask`` (what ``elastokin doe`` runs) on a LocalCluster of 1 and of 2
  single-threaded worker processes, worker profiler off as in ``elastokin doe`` (cluster
  start-up and worker warm-up excluded; ``--batch`` samples per task); best of ``--repeat``
  runs of all the sweeps (every run is recorded), as in bench_kc.

Plus a profile of one sweep by public stage: the as-built model (``ek.as_built_model``:
as-built config and model build), the sweep (``ek.travel_sweep``: the static state, every
solve, every channel) and its summary figures (``ek.summary_figures``). Prints the figures and
writes ``benchmarks/results/bench_doe.json``. Target (issue 5): >= 3000 sweeps per minute on
this 2-core machine (``sweeps_per_minute["2"]``). ``--quick``: 2 sweeps, one run, a one-worker
cluster of threads (bench_common).
"""

from __future__ import annotations

import argparse
import logging
import os
import platform
import sys
import time
from pathlib import Path

import numpy as np

import elastokin as ek

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_common import ROOT, add_output_options, output_path, write_json  # noqa: E402

TARGET = 3000.0


def per_minute(count: int, seconds: float) -> float:
    return 60.0 * count / seconds


def profile(s, design, study, repeat: int) -> dict:
    """Median ms of each public stage of one sweep, over ``repeat`` samples."""
    t = {"as_built_model_ms": [], "travel_sweep_ms": [], "summary_ms": []}
    points = 0
    for k in range(repeat):
        shifts = {n: np.asarray(v) for n, v in study.shifts(k % study.samples).items()}
        t0 = time.perf_counter()
        model = ek.as_built_model(s, shifts, design)
        t1 = time.perf_counter()
        sweep = ek.travel_sweep(model)
        t2 = time.perf_counter()
        ek.summary_figures([sweep], False)
        t3 = time.perf_counter()
        points = sweep.steps
        for key, dt in zip(t, (t1 - t0, t2 - t1, t3 - t2)):
            t[key].append(1e3 * dt)
    out = {k: float(np.median(v)) for k, v in t.items()}
    out["stroke_points"] = points
    out["travel_sweep_ms_per_stroke_point"] = out["travel_sweep_ms"] / points
    return out


def in_process(study, n: int, warm_up: int) -> tuple[float, list[int]]:
    """Sweeps per minute evaluating samples in this process, and the samples that failed."""
    for k in range(warm_up):
        ek.evaluate_sample(study.job, k, study.shifts(k))
    t0 = time.perf_counter()
    failed = []
    for k in range(n):
        if ek.evaluate_sample(study.job, k, study.shifts(k))["status"] != "ok":
            failed.append(k)
    return per_minute(n, time.perf_counter() - t0), failed


def reuse_model(s, design, n: int) -> float:
    model = ek.as_built_model(s, {}, design)  # the nominal model
    ek.travel_sweep(model)
    t0 = time.perf_counter()
    for _ in range(n):
        ek.travel_sweep(model)
    return per_minute(n, time.perf_counter() - t0)


def on_dask(study, workers: int, batch: int, repeat: int, processes: bool) -> list[float]:
    """Sweeps per minute of ``repeat`` timed runs of the whole study on one LocalCluster."""
    import dask
    from distributed import Client, LocalCluster

    with dask.config.set({"distributed.worker.profile.enabled": False}):  # as elastokin doe
        cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=processes,
                               dashboard_address=None, silence_logs=logging.ERROR)
    items = [(k, study.shifts(k)) for k in range(study.samples)]
    rates = []
    with cluster, Client(cluster) as client:
        ek.run_dask(client, study.job, items[:4 * workers], lambda rec: None, 1)  # warm-up
        for _ in range(repeat):
            done = []
            t0 = time.perf_counter()
            ek.run_dask(client, study.job, items, done.append, batch)
            rates.append(per_minute(study.samples, time.perf_counter() - t0))
            assert len(done) == study.samples
    return rates


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--config", default=str(ROOT / "configs" / "pseudo_mcpherson.yaml"))
    ap.add_argument("--sweeps", type=int, default=400, help="sweeps per measurement")
    ap.add_argument("--batch", type=int, default=4, help="samples per dask task")
    ap.add_argument("--repeat", type=int, default=3,
                    help="timed runs per dask set-up (the best is reported)")
    add_output_options(ap, "bench_doe")
    args = ap.parse_args(argv)
    out = output_path(args, "bench_doe")
    load_before = os.getloadavg()[0]
    if args.quick:
        args.sweeps, args.batch, args.repeat = 2, 1, 1

    s = ek.load_suspension(args.config)
    design = ek.design_state(s)
    study = ek.make_study(s, args.sweeps, "lhs", 0, "travel", design)
    spec = s.rig.parallel_travel

    prof = profile(s, design, study, 2 if args.quick else 30)
    serial, failed = in_process(study, args.sweeps, 0 if args.quick else 3)
    reuse = reuse_model(s, design, args.sweeps)
    worker_counts = (1,) if args.quick else (1, 2)
    runs = {str(w): on_dask(study, w, args.batch, args.repeat, not args.quick)
            for w in worker_counts}
    dask = {w: max(r) for w, r in runs.items()}
    dask_batch1 = None if args.quick else max(on_dask(study, 2, 1, args.repeat, True))

    result = {
        "elastokin_version": ek.__version__,
        "exudyn_version": ek.exudyn_version(),
        "config_file": os.path.relpath(args.config, ROOT),
        "config_sha256": s.sha256,
        "quick": args.quick,
        "machine": {"python": platform.python_version(), "processor": platform.machine(),
                    "cores": os.cpu_count()},
        "load_average_1min_before": load_before,
        "sweep": {"load_case": "parallel_travel (elastokin doe --load-cases travel)",
                  "stroke_points": prof["stroke_points"],
                  "stroke_mm": [spec.rebound_mm, spec.bump_mm], "step_mm": spec.step_mm,
                  "per_sweep": "clearance shifts -> as-built model build -> static state -> "
                               "travel sweep -> steer amplitude, bump steer, bump camber"},
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
        "speedup_2_vs_1_worker": dask["2"] / dask["1"] if "2" in dask else None,
        "profile_one_sweep_ms": prof,
        "solver": ek.as_built_model(s, {}, design).solver_settings(),
        "target_sweeps_per_minute_2_workers": TARGET,
        "meets_target": bool(dask.get("2", 0.0) >= TARGET),
    }
    result["load_average_1min_after"] = os.getloadavg()[0]
    write_json(out, result)
    report(result, out)


def report(r: dict, out: Path) -> None:
    p = r["profile_one_sweep_ms"]
    print(f"one sweep ({p['stroke_points']} stroke points): as-built model "
          f"{p['as_built_model_ms']:.2f} ms, travel sweep {p['travel_sweep_ms']:.2f} ms "
          f"({p['travel_sweep_ms_per_stroke_point']:.3f} ms/point), summary "
          f"{p['summary_ms']:.2f} ms")
    print(f"in process (no dask)         {r['sweeps_per_minute_in_process']:8.0f} sweeps/min "
          f"({r['failed_sweeps']['count']} of {r['sweeps_per_measurement']} samples failed to "
          "solve)")
    print(f"one model reused             {r['sweeps_per_minute_reusing_one_model']:8.0f} "
          "sweeps/min")
    for w, v in r["sweeps_per_minute"].items():
        print(f"dask LocalCluster, {w} worker{'s' if w != '1' else ' '}  {v:8.0f} sweeps/min "
              f"(batch {r['sweeps_per_minute_dask_batch']})")
    if r["sweeps_per_minute_2_workers_batch_1"] is not None:
        print(f"dask LocalCluster, 2 workers  {r['sweeps_per_minute_2_workers_batch_1']:8.0f} "
              "sweeps/min (batch 1)")
    print("all runs: " + "; ".join(f"{w} worker(s) " + ", ".join(f"{v:.0f}" for v in runs)
                                   for w, runs in r["sweeps_per_minute_all_runs"].items()))
    if r["speedup_2_vs_1_worker"] is not None:
        print(f"2 vs 1 worker: {r['speedup_2_vs_1_worker']:.2f}x; target >= "
              f"{TARGET:.0f} sweeps/min with 2 workers: "
              f"{'met' if r['meets_target'] else 'NOT met'}")
    print(f"load average {r['load_average_1min_before']:.2f} before, "
          f"{r['load_average_1min_after']:.2f} after; written to {out}")


if __name__ == "__main__":
    main()
