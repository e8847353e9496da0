"""Joints from motion on the case study (issue 29): how many rig positions, how far apart?

For the as-built suspension of configs/pseudo_mcpherson_motion.yaml (the case study's, same
clearance shifts), solved once at every position any plan uses, each motion plan is measured
again and again by the virtual CMM (the case study's noise: 95 % of points within 0.1 mm)
and its joints located from the motion; per joint the RMS error against the truth, the
spread of the located point against the uncertainty the first draw states (the Monte-Carlo
check), and for comparison the paper's disassembly method on the virtual CMM's files of
several seeds. Plans: a 5 x 5 grid of wheel travel and steering-rack travel (rack = 3/8 of
the travel) scaled from +-10 to +-80 mm; 3 x 3 to 9 x 9 grids at +-80 / +-30 mm; travel
only (no steer). Every plan adds the wheel turned by hand to 90, 180 and 270 deg.

Writes benchmarks/results/motion_positions.json and the chart docs/motion_positions.png.
``--quick``: two plans, few draws, no disassembly comparison (the tests run it), the JSON
and the chart into the temporary folder unless ``--out`` names a folder (bench_common: never
benchmarks/results); ``--replot``: the chart again from the JSON. Takes about 1.5 minutes on
a quiet 2-core machine, 7 at load 7-9 (others' runs beside it). Through elastokin's public
API only (``ek.motion_grid_positions``, ``ek.motion_position_study``,
``ek.disassembly_errors``, ``ek.draw_motion_positions_chart``).
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import tempfile
import time
from pathlib import Path

import numpy as np

import elastokin as ek

ROOT = Path(__file__).resolve().parents[1]
CONFIG = Path("configs") / "pseudo_mcpherson_motion.yaml"  # relative to ROOT
RACK_PER_TRAVEL = 0.375  # +-30 mm of rack at +-80 mm of travel
RESULTS = ROOT / "benchmarks" / "results"
#: where ``--quick`` writes without ``--out`` (bench_common's folder)
QUICK_OUT = Path(tempfile.gettempdir()) / "elastokin-benchmarks"


def plans(quick: bool) -> tuple[dict, list[dict], list[dict]]:
    """The plans, the spread series and the count series."""
    spreads = [80.0] if quick else [10.0, 20.0, 40.0, 60.0, 80.0]
    levels = [3] if quick else [3, 5, 7, 9]
    out, spread, count = {}, [], []
    for t in spreads:
        name = f"grid5_travel{t:g}"
        out[name] = ek.motion_grid_positions(t, RACK_PER_TRAVEL * t, 5)
        spread.append({"plan": name, "travel_mm": t, "rack_mm": RACK_PER_TRAVEL * t,
                       "positions": len(out[name])})
    for n in levels:
        name = f"grid{n}_travel80"
        out[name] = ek.motion_grid_positions(80.0, 30.0, n)
        count.append({"plan": name, "travel_mm": 80.0, "rack_mm": 30.0,
                      "positions": len(out[name])})
    if not quick:
        count.insert(1, spread[-1])  # the 5 x 5 grid at full spread
        out["travel_only"] = ek.motion_grid_positions(80.0, 0.0, 9)
    return out, spread, count


def main(argv: list[str] | None = None) -> dict | None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true",
                    help="two plans, few draws (a smoke run: into the temporary folder "
                         "unless --out says where)")
    ap.add_argument("--draws", type=int, default=None, help="noise draws per plan")
    ap.add_argument("--out", type=Path, default=None,
                    help="folder for the JSON and chart (default: benchmarks/results and docs; "
                         "with --quick the temporary folder)")
    ap.add_argument("--replot", action="store_true",
                    help="only draw the chart again from the results JSON")
    args = ap.parse_args(argv)
    out = args.out.resolve() if args.out else (QUICK_OUT if args.quick else None)
    if args.quick and RESULTS.resolve() in (out, *out.parents):
        raise SystemExit(f"--quick writes no committed result: --out {args.out} is in "
                         "benchmarks/results")
    os.chdir(ROOT)  # the config named as in the repository (the charts' footer)
    if args.replot:
        doc = json.loads((RESULTS / "motion_positions.json").read_text())
        ek.draw_motion_positions_chart(doc, ROOT / "docs", ek.load_suspension(CONFIG))
        return doc
    draws = args.draws or (3 if args.quick else 100)
    s = ek.load_suspension(CONFIG)
    noise = s.motion.synthetic.noise_mm
    load_before = os.getloadavg()[0]
    t0 = time.perf_counter()
    chosen, spread, count = plans(args.quick)
    study = ek.motion_position_study(s, chosen, draws, 29)  # the config's CMM noise
    doc = {"elastokin_version": ek.__version__, "exudyn_version": ek.exudyn_version(),
           "config": str(CONFIG), "quick": args.quick, "noise_mm": noise, "draws": draws,
           "rack_per_travel": RACK_PER_TRAVEL, "plans": study, "spread_series": spread,
           "count_series": count}
    if not args.quick:
        with tempfile.TemporaryDirectory() as tmp:
            errors = ek.disassembly_errors(s, list(range(1, 21)), Path(tmp))
        doc["disassembly"] = {"seeds": 20, "joints": {
            j: {"rms_error_mm": float(np.sqrt(np.mean(np.square(e)))),
                "max_error_mm": float(np.max(e))} for j, e in errors.items()}}
    doc["seconds"] = round(time.perf_counter() - t0, 1)
    doc["load_average"] = [round(load_before, 2), round(os.getloadavg()[0], 2)]
    doc["machine"] = platform.platform()
    for name, p in study.items():
        if "too_small" in p:
            print(f"{name} ({p['positions']} positions): {p['too_small'][:200]}...")
            continue
        errs = ", ".join(f"{j} {v['rms_error_mm']:.3f}" for j, v in p["joints"].items()
                         if v["rms_error_mm"] is not None)
        print(f"{name} ({p['positions']} positions): RMS error mm {errs}")
    results, charts = (out, out) if out is not None else (RESULTS, ROOT / "docs")
    results.mkdir(parents=True, exist_ok=True)
    (results / "motion_positions.json").write_text(json.dumps(doc, indent=1) + "\n")
    ek.draw_motion_positions_chart(doc, charts, s)
    print(f"wrote {results / 'motion_positions.json'} and {charts / 'motion_positions.png'}")
    return doc


if __name__ == "__main__":
    main()
