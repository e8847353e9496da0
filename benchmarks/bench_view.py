"""The 3D view's cost (issue 26): the report's size and its load time in Chromium, the
``elastokin view`` page of every config in configs/ (its time and size), and what recording
the parts' poses at every rig step costs the K&C run.

- **report**: ``ek.run_kc`` on the case study (``--quick``: the double wishbone axle on the
  travel-only rig) and ``ek.write_kc_results``, its report.html's size split into plotly.js
  (the page's script that is the plotly.js bundle), the view's data and the rest (charts,
  tables), the time the view adds to writing the results (``view_in_report_s``: the same
  run written with its sweeps' poses dropped, so without a view, alternately, best of
  ``--repeat``), and the page's load time in headless Chromium with the network cut: to the
  page loaded (readable: the view waits until it is scrolled to), then from scrolling to the
  view to the view drawn and ready (plotly.js run, the first frame drawn), medians of
  ``--repeat``, and the CPU time Chromium spent (all its processes, and the page's renderer
  alone: what the time comes to on an idle machine, where the wall time is inflated by
  other work); and the same page with plotly's full bundle in place of the gl3d partial
  bundle the view ships (``full_bundle``), measured in the same run;
- **view**: per config, ``elastokin view`` in a fresh process (start-up, imports and the
  page) and in-process (the command called in this process, its modules imported: the
  draft, the scene and the page), the page's size and load time;
- **poses**: every load case of the rig on the model with every part's pose recorded
  (``ek.ModelOptions(record_loads=False)``) against the same with only the wheels' parts'
  (``ek.ModelOptions(part_poses=False)``, the stiffness fit's set-up: no steering-axis
  columns, no beam nodes), best of ``--repeat``; and the recording itself
  (``parallel_travel``: the steps' poses of one parallel travel stacked into the sweep's
  series, best of ``--repeat``);
- **beam_nodes**: the twist beam's load cases with and without its beam's node poses
  recorded (``ek.ModelOptions(beam_nodes=False)``), alternately, best of ``--repeat``.

Through elastokin's public API and command line only. Runs before issue 24's item 6 timed
``poses`` with only the stacking switched off (``PoseSeries.stack`` replaced by a no-op,
every sensor kept): that can only be done through elastokin's internals; the figure now
includes the sensors and what needs the poses (the steering-axis columns), an upper bound
of the old one.

Prints the figures and writes ``benchmarks/results/bench_view.json`` (``--quick``: the
temporary folder, bench_common), with the machine's load average before and after. Browser
figures are left out (null) when Chromium is not installed. No target is asserted: the
measure.
"""

from __future__ import annotations

import argparse
import contextlib
import io
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
sys.path.insert(0, str(ROOT / "benchmarks"))

import numpy as np  # noqa: E402
from bench_common import (  # noqa: E402
    add_output_options,
    load_cases_by_side,
    output_path,
    without,
    write_json,
)

import elastokin as ek  # noqa: E402

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


#: the page's script that is plotly.js (its bundles begin with their licence comment)
PLOTLY_SCRIPT = re.compile(r"<script[^>]*>(/\*\*\s*\* plotly\.js .*?)</script>", re.S)
#: the view's data
VIEW_DATA = re.compile(r'<script type="application/json" id="ekv-data">(.*?)</script>', re.S)


def page_parts(path: Path) -> dict:
    """Bytes of a page: in all, plotly.js, the view's data, the rest."""
    text = path.read_text(encoding="utf-8")
    library, data = PLOTLY_SCRIPT.search(text), VIEW_DATA.search(text)
    plotly_js = len(library.group(1).encode()) if library else 0
    data_bytes = len(data.group(1).encode()) if data else 0
    total = path.stat().st_size
    return {"bytes": total, "plotly_js_bytes": plotly_js, "view_data_bytes": data_bytes,
            "other_bytes": total - plotly_js - data_bytes}


def view_models(path: Path) -> tuple[list[str], int]:
    """The models of a page's view and its frames (every model's, every load case's)."""
    data = json.loads(VIEW_DATA.search(path.read_text(encoding="utf-8")).group(1))
    frames = sum(len(case["steps"]) for m in data["models"].values()
                 for case in m["data"].values())
    return list(data["order"]), frames


def report_figures(quick: bool, repeat: int, folder: Path) -> dict:
    if quick:
        config = ROOT / "configs" / "double_wishbone_axle.yaml"
        rig = ROOT / "configs" / "rigs" / "travel_only.yaml"
    else:
        config, rig = ROOT / "configs" / "pseudo_mcpherson.yaml", None
    s = ek.load_suspension_with_rig(config, rig)
    t0 = time.perf_counter()
    run = ek.run_kc(s)
    kc_s = time.perf_counter() - t0
    runs = {"with_view": (run, folder), "without_view": (without(run, "poses"),
                                                         folder.with_name("no_view"))}
    for _, out in runs.values():
        out.mkdir(parents=True)
    ek.write_kc_results(run, folder)  # warm up: every module the files need imported
    best = {k: float("inf") for k in runs}
    for _ in range(repeat):
        for k, (r, out) in runs.items():
            t0 = time.perf_counter()
            ek.write_kc_results(r, out)
            best[k] = min(best[k], time.perf_counter() - t0)
    models, frames = view_models(folder / "report.html")
    out = {"config": str(config.relative_to(ROOT)), "rig": rig and str(rig.relative_to(ROOT)),
           "models": models, "frames": frames, "kc_run_s": round(kc_s, 3),
           "write_results_s": round(best["with_view"], 3),
           "view_in_report_s": round(best["with_view"] - best["without_view"], 3),
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
    text = page.read_text(encoding="utf-8")
    shipped = PLOTLY_SCRIPT.search(text).group(1)
    full = page.with_name("report_full_bundle.html")
    full.write_text(text.replace(shipped, get_plotlyjs()), encoding="utf-8")
    return {"bytes": full.stat().st_size, "plotly_js_bytes": len(get_plotlyjs().encode()),
            "load": load_times(full.resolve().as_uri(), repeat, lazy=True)}


def view_command(config: Path, page: Path) -> tuple[int, str]:
    """``elastokin view CONFIG --out PAGE`` called in this process: exit code, its errors."""
    from elastokin.cli import main

    err = io.StringIO()
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(err):
        try:
            main.main(["view", str(config), "--out", str(page)], standalone_mode=False)
            code = 0
        except SystemExit as exc:
            code = exc.code or 0
    return code, err.getvalue()


def view_figures(config: Path, repeat: int, folder: Path, quick: bool) -> dict:
    """``elastokin view`` of one config: in-process, and (not ``quick``) in a fresh process
    and the page's load time."""
    page = folder / f"{config.stem}.view.html"
    view_command(config, page)  # warm up: the command's modules imported
    t0 = time.perf_counter()
    code, err = view_command(config, page)
    listed = re.search(r"(\d+) errors? in the config", err)
    out = {"in_process_s": round(time.perf_counter() - t0, 3),
           "errors": int(listed.group(1)) if listed else 0, **page_parts(page)}
    if code and not listed:
        raise SystemExit(f"elastokin view {config} failed: {err}")
    if quick:
        return out
    t0 = time.perf_counter()
    done = subprocess.run([sys.executable, "-c", "import sys; from elastokin.cli import main; "
                           "sys.exit(main())", "view", str(config), "--out", str(page)],
                          capture_output=True, text=True,
                          env={**os.environ, "PYTHONPATH": str(ROOT)})
    out.update(exit_code=done.returncode, process_s=round(time.perf_counter() - t0, 3),
               load=load_times(page.resolve().as_uri(), repeat))
    return out


def best_times(models: dict, repeat: int) -> tuple[dict, dict]:
    """Every load case on each model (name -> model), alternately, best of ``repeat``: the
    times and the last sweeps by name."""
    best = {k: float("inf") for k in models}
    sweeps = {}
    for _ in range(repeat):
        for k, model in models.items():
            t0 = time.perf_counter()
            sweeps[k] = load_cases_by_side(model, "bench")
            best[k] = min(best[k], time.perf_counter() - t0)
    return best, sweeps


def stack_cost(model, repeat: int) -> dict:
    """The recording itself: the poses of every step of the model's parallel travel (as the
    rig records them) stacked into the sweep's series, best of ``repeat``."""
    series = ek.parallel_travel(model, "bench").poses
    poses = [series.at(i) for i in range(series.steps)]
    t = float("inf")
    for _ in range(max(repeat, 3)):
        t0 = time.perf_counter()
        type(series).stack(poses)
        t = min(t, time.perf_counter() - t0)
    return {"steps": len(poses), "parts": len(poses[0].rotation), "stack_ms": round(1e3 * t, 3)}


def pose_cost(quick: bool, repeat: int) -> dict:
    """Every load case on the model with every part's pose recorded and on the same with only
    the wheels' (best of ``repeat``, alternately; loads off in both: they need the poses)
    and the recording itself (:func:`stack_cost`)."""
    config = ROOT / "configs" / ("double_wishbone_axle.yaml" if quick else
                                 "pseudo_mcpherson.yaml")
    s = ek.load_suspension_with_rig(config, ROOT / "configs" / "rigs" / "travel_only.yaml"
                                    if quick else None)
    design = ek.design_state(s)
    models = {"with_poses": ek.build_model(s, ek.ModelOptions(record_loads=False), design),
              "without_poses": ek.build_model(s, ek.ModelOptions(part_poses=False), design)}
    best_times(models, 1)  # warm up
    best, sweeps = best_times(models, repeat)
    a, b = (sweeps[k][s.side] for k in models)
    return {"config": str(config.relative_to(ROOT)), "with_poses_s": round(best["with_poses"], 4),
            "without_poses_s": round(best["without_poses"], 4),
            "ratio": round(best["with_poses"] / best["without_poses"], 4),
            "columns_without_poses": sorted({c for x, y in zip(a, b) for c in x.columns
                                             if c not in y.columns}),
            "identical_common_columns": same_columns(a, b, common=True),
            "parallel_travel": stack_cost(models["with_poses"], repeat)}


def _same(u, v) -> bool:
    u, v = np.asarray(u), np.asarray(v)
    return np.array_equal(u, v, equal_nan=u.dtype.kind == "f")


def same_columns(a: list, b: list, common: bool = False) -> bool:
    """Whether two runs' sweeps hold the same columns and numbers (``common``: the columns
    both have)."""
    def names(x, y):
        return set(x.columns) & set(y.columns) if common else set(x.columns)

    return all((common or set(x.columns) == set(y.columns))
               and all(_same(x.columns[c], y.columns[c]) for c in names(x, y))
               for x, y in zip(a, b))


def beam_node_cost(quick: bool, repeat: int) -> dict:
    """The twist beam's load cases (``quick``: a short parallel travel only) on a model that
    records its beam's node poses against the same model without
    (``ModelOptions(beam_nodes=False)``), alternately, best of ``repeat``; every column
    checked identical."""
    config = ROOT / "configs" / "twist_beam_axle.yaml"
    rig = {"rig": {**{k: None for k in ("vertical_force", "lateral_force",
                                        "longitudinal_force_patch", "aligning_torque",
                                        "longitudinal_force_centre", "roll_vertical_force",
                                        "single_wheel_travel", "steering")},
                   "parallel_travel": {"rebound_mm": -10, "bump_mm": 10, "step_mm": 10}}}
    s = ek.load_suspension(config, rig if quick else None)
    design = ek.design_state(s)
    models = {"with_nodes": ek.build_model(s, design=design),
              "without_nodes": ek.build_model(s, ek.ModelOptions(beam_nodes=False), design)}
    best, sweeps = best_times(models, max(repeat, 2))
    a, b = (sweeps[k][s.side] for k in models)
    steps = sum(sw.steps for sw in a)
    nodes = [sum(x.shape[1] for x in sw[0].poses.node_mm.values()) for sw in (a, b)]
    return {"config": str(config.relative_to(ROOT)), "quick": quick, "steps": steps,
            "nodes_recorded": nodes[0], "nodes_recorded_without": nodes[1],
            "with_nodes_s": round(best["with_nodes"], 4),
            "without_nodes_s": round(best["without_nodes"], 4),
            "ratio": round(best["with_nodes"] / best["without_nodes"], 4),
            "identical_columns": same_columns(a, b)}


def main(argv: list[str] | None = None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    add_output_options(ap, "bench_view")
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args(argv)
    out = output_path(args, "bench_view")
    repeat = 1 if args.quick else args.repeat
    load_before = os.getloadavg()
    configs = [c for c in sorted((ROOT / "configs").glob("*.yaml"))  # suspensions only
               if not ek.is_vehicle_file(c)][:1 if args.quick else None]
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        result = {"benchmark": "bench_view", "quick": args.quick, "elastokin": ek.__version__,
                  "elastokin_version": ek.__version__, "exudyn_version": ek.exudyn_version(),
                  "python": platform.python_version(), "machine": platform.machine(),
                  "cpus": os.cpu_count(), "load_average_before": load_before,
                  "report": report_figures(args.quick, repeat, folder / "res"),
                  "view": {c.stem: view_figures(c, repeat, folder, args.quick)
                           for c in configs},
                  "poses": pose_cost(args.quick, repeat),
                  "beam_nodes": beam_node_cost(args.quick, repeat)}
    result["load_average_after"] = os.getloadavg()
    write_json(out, result)
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
          f"{p['without_poses_s']:.3f} s with the wheels' only (x{p['ratio']:.3f}); stacking "
          f"{p['parallel_travel']}")
    n = result["beam_nodes"]
    print(f"beam nodes recorded ({n['config']}, {n['nodes_recorded']} nodes, {n['steps']} "
          f"steps): {n['with_nodes_s']:.3f} s against {n['without_nodes_s']:.3f} s without "
          f"(x{n['ratio']:.3f}); identical columns: {n['identical_columns']}")
    print(f"wrote {out}")
    return result


if __name__ == "__main__":
    main()
