"""The 3D view's cost (issue 26): the report's size and its load time in Chromium, the
``elastokin view`` page of every config in configs/ (its time and size), and what recording
the parts' poses at every rig step costs the K&C run.

- **report**: ``elastokin kc`` on the case study (``--quick``: the double wishbone axle on
  the travel-only rig), its report.html's size split into plotly.js, the view's data and the
  rest (charts, tables), the time the view adds to writing the results, and the page's load
  time in headless Chromium with the network cut: to the page loaded (readable: the view
  waits until it is scrolled to), then from scrolling to the view to the view drawn and
  ready (plotly.js run, the first frame drawn), medians of ``--repeat``, and the CPU time
  Chromium spent (all its processes, and the page's renderer alone: what the time comes to
  on an idle machine, where the wall time is inflated by other work); and the same page
  with plotly's full bundle in place of the gl3d partial bundle the view ships
  (``full_bundle``), measured in the same run;
- **view**: per config, ``elastokin view`` in a fresh process (start-up, imports and the
  page) and in-process (the draft, the scene and the page), the page's size and load time;
- **poses**: every load case of the rig on one built model with the poses recorded against
  the same without (``PoseSeries.stack`` replaced by a no-op), best of ``--repeat``;
- **beam_nodes**: the twist beam's load cases with and without its beam's node poses
  recorded (the sensors of ``BeamBody.record_line``), alternately, best of ``--repeat``.

Prints the figures and writes ``benchmarks/results/bench_view.json`` (``--quick``:
``bench_view_quick.json``), with the machine's load average before and after. Browser figures
are left out (null) when Chromium is not installed. No target is asserted: the measure.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import re
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))  # tests/browser.py: headless Chromium over a pipe

import numpy as np  # noqa: E402

from elastokin.version import __version__  # noqa: E402

READY = ("!!document.getElementById('ekv-plot') && "
         "document.getElementById('ekv-plot').getAttribute('data-ready') === '1'")


def load_times(url: str, repeat: int, lazy: bool = False) -> dict | None:
    """Seconds from navigation to the page loaded (its text readable) and to the view drawn
    and ready (a ``lazy`` view, as in the report: from scrolling to it), network cut, and
    the CPU time Chromium spent (medians of ``repeat``); None without Chromium."""
    from tests.browser import Browser, chromium_path

    if chromium_path() is None:
        return None
    runs: dict[str, list] = {"load_s": [], "view_s": [], "cpu_s": [], "renderer_cpu_s": []}
    errors: list[str] = []
    for _ in range(repeat):
        with Browser(1280, 900, offline=True) as b:
            before = chromium_cpu(b.proc.pid)
            runs["load_s"].append(b.open(url))
            start = time.perf_counter()
            if lazy:
                b.run("document.getElementById('ekv-plot').scrollIntoView()")
            b.wait_for(READY, 120.0)
            runs["view_s"].append(time.perf_counter() - start + (0 if lazy else
                                                                 runs["load_s"][-1]))
            after = chromium_cpu(b.proc.pid)
            used = {k: after[k] - before.get(k, 0.0) for k in after}
            runs["cpu_s"].append(sum(used.values()))
            runs["renderer_cpu_s"].append(max(v for k, v in used.items()
                                              if "renderer" in k[1]))
            errors += b.errors
    out = {k: round(statistics.median(v), 3) for k, v in runs.items()}
    return {**out, "lazy": lazy, "runs": repeat, "page_errors": errors}


def chromium_cpu(pid: int) -> dict:
    """CPU seconds (user + system) of every process of a Chromium, by (pid, its type)."""
    import psutil

    main = psutil.Process(pid)
    out = {}
    for p in [main, *main.children(recursive=True)]:
        try:
            kind = next((a for a in p.cmdline() if a.startswith("--type=")), "--type=browser")
            t = p.cpu_times()
            out[(p.pid, kind)] = t.user + t.system
        except psutil.Error:
            continue
    return out


def page_parts(path: Path) -> dict:
    """Bytes of a page: in all, plotly.js, the view's data, the rest."""
    from elastokin.report.view3d import plotly_js as bundle

    text = path.read_text(encoding="utf-8")
    data = re.search(r'<script type="application/json" id="ekv-data">(.*?)</script>', text,
                     re.S)
    plotly_js = len(bundle().encode()) if bundle() in text else 0
    data_bytes = len(data.group(1).encode()) if data else 0
    total = path.stat().st_size
    return {"bytes": total, "plotly_js_bytes": plotly_js, "view_data_bytes": data_bytes,
            "other_bytes": total - plotly_js - data_bytes}


def report_figures(quick: bool, repeat: int, folder: Path) -> dict:
    from elastokin.config.loading import load_suspension_with_rig
    from elastokin.report import files
    from elastokin.report.view3d import run_views, view_fragment
    from elastokin.studies.kc_job import run_kc

    if quick:
        config = ROOT / "configs" / "double_wishbone_axle.yaml"
        rig = ROOT / "configs" / "rigs" / "travel_only.yaml"
    else:
        config, rig = ROOT / "configs" / "pseudo_mcpherson.yaml", None
    s = load_suspension_with_rig(config, rig)
    t0 = time.perf_counter()
    run = run_kc(s)
    kc_s = time.perf_counter() - t0
    t0 = time.perf_counter()
    files.write_kc_results(run, folder)
    write_s = time.perf_counter() - t0
    t0 = time.perf_counter()
    views, overlay = run_views(run)
    view_fragment(views, overlay)
    view_s = time.perf_counter() - t0
    frames = sum(f.frames for v in views for f in v.frames)
    out = {"config": str(config.relative_to(ROOT)), "rig": rig and str(rig.relative_to(ROOT)),
           "models": [v.label for v in views], "frames": frames, "kc_run_s": round(kc_s, 3),
           "write_results_s": round(write_s, 3), "view_in_report_s": round(view_s, 3),
           **page_parts(folder / "report.html")}
    out["load"] = load_times((folder / "report.html").resolve().as_uri(), repeat, lazy=True)
    out["full_bundle"] = full_bundle(folder / "report.html", repeat)
    return out


def full_bundle(page: Path, repeat: int) -> dict | None:
    """The same page with plotly's full bundle (the plotly Python package's, 4.8 MB) in place
    of the gl3d partial bundle the view ships: its size and load times, for the comparison
    (None without the plotly package)."""
    try:
        from plotly.offline import get_plotlyjs
    except ImportError:
        return None
    from elastokin.report.view3d import plotly_js

    full = page.with_name("report_full_bundle.html")
    full.write_text(page.read_text(encoding="utf-8").replace(plotly_js(), get_plotlyjs()),
                    encoding="utf-8")
    return {"bytes": full.stat().st_size, "plotly_js_bytes": len(get_plotlyjs().encode()),
            "load": load_times(full.resolve().as_uri(), repeat, lazy=True)}


def view_figures(config: Path, repeat: int, folder: Path, quick: bool) -> dict:
    """``elastokin view`` of one config: in-process, and (not ``quick``) in a fresh process
    and the page's load time."""
    from elastokin.cli.view import design_view
    from elastokin.config.draft import draft_suspension
    from elastokin.report.view3d import write_view_page

    page = folder / f"{config.stem}.view.html"
    t0 = time.perf_counter()
    draft = draft_suspension(config)
    write_view_page(page, draft.name, [design_view(draft)], list(draft.errors), [])
    out = {"in_process_s": round(time.perf_counter() - t0, 3), "errors": len(draft.errors),
           **page_parts(page)}
    if quick:
        return out
    t0 = time.perf_counter()
    done = subprocess.run([sys.executable, "-m", "elastokin.cli.main", "view", str(config),
                           "--out", str(page)], capture_output=True, text=True,
                          env={**os.environ, "PYTHONPATH": str(ROOT)})
    out.update(exit_code=done.returncode, process_s=round(time.perf_counter() - t0, 3),
               load=load_times(page.resolve().as_uri(), repeat))
    return out


def stack_cost(model, repeat: int) -> dict:
    """The recording itself: :meth:`PoseSeries.stack` of every step of the model's parallel
    travel (the steps' poses as the rig records them), best of ``repeat``."""
    from elastokin.physics.states import PoseSeries
    from elastokin.rig.drives import parallel_travel_drive
    from elastokin.rig.pad import run_rig

    s = model.suspension
    drive = parallel_travel_drive(s)
    steps = run_rig(model, drive.wheels, drive.rack_travel_mm, drive.heave_load_N)
    poses = [st[s.side].poses for st in steps]
    t = float("inf")
    for _ in range(max(repeat, 3)):
        t0 = time.perf_counter()
        PoseSeries.stack(poses)
        t = min(t, time.perf_counter() - t0)
    return {"steps": len(poses), "parts": len(poses[0].rotation), "stack_ms": round(1e3 * t, 3)}


def pose_cost(quick: bool, repeat: int) -> dict:
    """Every load case on one model with and without recording the poses (best of
    ``repeat``; the solver's spread between runs is larger than the difference) and the
    recording itself (:func:`stack_cost`)."""
    from elastokin.config.loading import load_suspension_with_rig
    from elastokin.mbs.design import build_model
    from elastokin.physics.states import PoseSeries
    from elastokin.rig.load_cases import run_load_cases_sides

    config = ROOT / "configs" / ("double_wishbone_axle.yaml" if quick else
                                 "pseudo_mcpherson.yaml")
    s = load_suspension_with_rig(config, ROOT / "configs" / "rigs" / "travel_only.yaml"
                                 if quick else None)
    model = build_model(s)
    run_load_cases_sides(model, "warm-up")
    stack = PoseSeries.stack

    def best() -> float:
        t = float("inf")
        for _ in range(repeat):
            t0 = time.perf_counter()
            run_load_cases_sides(model, "bench")
            t = min(t, time.perf_counter() - t0)
        return t

    with_poses = best()
    PoseSeries.stack = classmethod(lambda cls, poses: None)
    try:
        without = best()
    finally:
        PoseSeries.stack = stack
    return {"config": str(config.relative_to(ROOT)), "with_poses_s": round(with_poses, 4),
            "without_poses_s": round(without, 4), "ratio": round(with_poses / without, 4),
            "parallel_travel": stack_cost(model, repeat)}


def _same(u, v) -> bool:
    u, v = np.asarray(u), np.asarray(v)
    return np.array_equal(u, v, equal_nan=u.dtype.kind == "f")


def beam_node_cost(quick: bool, repeat: int) -> dict:
    """The twist beam's load cases (``quick``: its opposite travel only) on a model that
    records its beam's node poses against the same model without (``BeamBody.record_line``
    recording nothing), alternately, best of ``repeat``; every column checked identical."""
    from elastokin.config.loading import read_yaml, suspension_from_dict
    from elastokin.mbs import beams
    from elastokin.mbs.design import build_model
    from elastokin.rig.load_cases import run_load_cases_sides

    config = ROOT / "configs" / "twist_beam_axle.yaml"
    data = read_yaml(config)[0]
    if quick:
        data["rig"] = {**{k: None for k in ("vertical_force", "lateral_force",
                                            "longitudinal_force_patch", "aligning_torque",
                                            "longitudinal_force_centre", "roll_vertical_force",
                                            "single_wheel_travel", "steering")},
                       "parallel_travel": {"rebound_mm": -10, "bump_mm": 10, "step_mm": 10}}
    s = suspension_from_dict(data, str(config))
    record = beams.BeamBody.record_line
    models = {"with_nodes": build_model(s)}
    beams.BeamBody.record_line = lambda self, sensors: []
    try:
        models["without_nodes"] = build_model(s)
    finally:
        beams.BeamBody.record_line = record
    best = {k: float("inf") for k in models}
    sweeps = {}
    for _ in range(max(repeat, 2)):
        for k, model in models.items():
            t0 = time.perf_counter()
            sweeps[k] = run_load_cases_sides(model, "bench")
            best[k] = min(best[k], time.perf_counter() - t0)
    a, b = (sweeps[k][s.side] for k in models)
    same = all(set(x.columns) == set(y.columns) and all(
        _same(x.columns[c], y.columns[c]) for c in x.columns) for x, y in zip(a, b))
    steps = sum(sw.steps for sw in a)
    nodes = sum(len(v) for v in models["with_nodes"].node_lines.values())
    return {"config": str(config.relative_to(ROOT)), "quick": quick, "steps": steps,
            "nodes_recorded": nodes, "with_nodes_s": round(best["with_nodes"], 4),
            "without_nodes_s": round(best["without_nodes"], 4),
            "ratio": round(best["with_nodes"] / best["without_nodes"], 4),
            "identical_columns": bool(same)}


def main() -> None:
    from elastokin.config.vehicle import is_vehicle_file

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true",
                    help="the report of the double wishbone axle on the travel-only rig, one "
                         "config's view in process")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--out", default=None)
    args = ap.parse_args()
    name = "bench_view_quick.json" if args.quick else "bench_view.json"
    out = Path(args.out or ROOT / "benchmarks" / "results" / name)
    repeat = 1 if args.quick else args.repeat
    load_before = os.getloadavg()
    configs = [c for c in sorted((ROOT / "configs").glob("*.yaml"))  # suspensions only
               if not is_vehicle_file(c)][:1 if args.quick else None]
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        (folder / "res").mkdir()
        result = {"benchmark": "bench_view", "quick": args.quick, "elastokin": __version__,
                  "python": platform.python_version(), "machine": platform.machine(),
                  "cpus": os.cpu_count(), "load_average_before": load_before,
                  "report": report_figures(args.quick, repeat, folder / "res"),
                  "view": {c.stem: view_figures(c, repeat, folder, args.quick)
                           for c in configs},
                  "poses": pose_cost(args.quick, repeat),
                  "beam_nodes": beam_node_cost(args.quick, repeat)}
    result["load_average_after"] = os.getloadavg()
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps(result, indent=2) + "\n")
    r = result["report"]
    print(f"load average before {load_before[0]:.2f}, after {result['load_average_after'][0]:.2f}")
    print(f"report ({r['config']}): {r['bytes'] / 1e6:.2f} MB (plotly.js "
          f"{r['plotly_js_bytes'] / 1e6:.2f}, view data {r['view_data_bytes'] / 1e6:.2f}, rest "
          f"{r['other_bytes'] / 1e6:.2f}); {r['frames']} frames; view adds "
          f"{r['view_in_report_s']:.2f} s to writing the results ({r['write_results_s']:.2f} s)"
          f"; load {r['load']}")
    if r["full_bundle"]:
        print(f"the same with plotly's full bundle: {r['full_bundle']['bytes'] / 1e6:.2f} MB; "
              f"load {r['full_bundle']['load']}")
    for c, v in result["view"].items():
        print(f"view {c}: process {v.get('process_s')} s, in process {v['in_process_s']:.2f} s,"
              f" {v['bytes'] / 1e6:.2f} MB, load {v.get('load')}")
    p = result["poses"]
    print(f"poses recorded ({p['config']}): {p['with_poses_s']:.3f} s against "
          f"{p['without_poses_s']:.3f} s without (x{p['ratio']:.3f}); stacking "
          f"{p['parallel_travel']}")
    n = result["beam_nodes"]
    print(f"beam nodes recorded ({n['config']}, {n['nodes_recorded']} nodes, {n['steps']} "
          f"steps): {n['with_nodes_s']:.3f} s against {n['without_nodes_s']:.3f} s without "
          f"(x{n['ratio']:.3f}); identical columns: {n['identical_columns']}")
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
