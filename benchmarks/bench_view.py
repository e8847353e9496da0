"""The 3D view's cost (issue 26): the report's size and its load time in Chromium, the
``elastokin view`` page of every config in configs/ (its time and size), and what recording
the parts' poses at every rig step costs the K&C run.

- **report**: ``elastokin kc`` on the case study (``--quick``: the double wishbone axle on
  the travel-only rig), its report.html's size split into plotly.js, the view's data and the
  rest (charts, tables), the time the view adds to writing the results, and the page's load
  time in headless Chromium with the network cut (navigation start to the view drawn and
  ready: plotly.js parsed, the first frame drawn; median of ``--repeat``);
- **view**: per config, ``elastokin view`` in a fresh process (start-up, imports and the
  page) and in-process (the draft, the scene and the page), the page's size and load time;
- **poses**: every load case of the rig on one built model with the poses recorded against
  the same without (``PoseSeries.stack`` replaced by a no-op), best of ``--repeat``.

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

from elastokin.version import __version__  # noqa: E402

READY = ("!!document.getElementById('ekv-plot') && "
         "document.getElementById('ekv-plot').getAttribute('data-ready') === '1'")


def load_times(url: str, repeat: int) -> dict | None:
    """Median and best seconds from navigation to the view ready, network cut; None without
    Chromium."""
    from tests.browser import Browser, chromium_path

    if chromium_path() is None:
        return None
    times, errors = [], []
    for _ in range(repeat):
        with Browser(1280, 900, offline=True) as b:
            start = time.perf_counter()
            b.page("Page.navigate", url=url)
            b.wait_for(READY, 120.0)
            times.append(time.perf_counter() - start)
            errors += b.errors
    return {"median_s": round(statistics.median(times), 3), "best_s": round(min(times), 3),
            "runs": len(times), "page_errors": errors}


def page_parts(path: Path) -> dict:
    """Bytes of a page: in all, plotly.js, the view's data, the rest."""
    text = path.read_text(encoding="utf-8")
    data = re.search(r'<script type="application/json" id="ekv-data">(.*?)</script>', text,
                     re.S)
    from plotly.offline import get_plotlyjs

    plotly_js = len(get_plotlyjs().encode()) if "Plotly" in text else 0
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
    out["load"] = load_times((folder / "report.html").resolve().as_uri(), repeat)
    return out


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


def pose_cost(quick: bool, repeat: int) -> dict:
    """Every load case on one model with and without recording the poses (best of
    ``repeat``)."""
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
            "without_poses_s": round(without, 4), "ratio": round(with_poses / without, 4)}


def main() -> None:
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
    configs = sorted((ROOT / "configs").glob("*.yaml"))[:1 if args.quick else None]
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        (folder / "res").mkdir()
        result = {"benchmark": "bench_view", "quick": args.quick, "elastokin": __version__,
                  "python": platform.python_version(), "machine": platform.machine(),
                  "cpus": os.cpu_count(), "load_average_before": load_before,
                  "report": report_figures(args.quick, repeat, folder / "res"),
                  "view": {c.stem: view_figures(c, repeat, folder, args.quick)
                           for c in configs},
                  "poses": pose_cost(args.quick, repeat)}
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
    for c, v in result["view"].items():
        print(f"view {c}: process {v.get('process_s')} s, in process {v['in_process_s']:.2f} s,"
              f" {v['bytes'] / 1e6:.2f} MB, load {v.get('load')}")
    p = result["poses"]
    print(f"poses recorded ({p['config']}): {p['with_poses_s']:.3f} s against "
          f"{p['without_poses_s']:.3f} s without (x{p['ratio']:.3f})")
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
