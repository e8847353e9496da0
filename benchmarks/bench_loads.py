"""The cost of recording loads (issue 27): every element's force and moment at every step.

For each suspension, in one run on this machine, the same model built twice (the same design
preloads, ``ek.design_state``): with the loads recorded (``ek.ModelOptions(record_loads=
True)``, what ``elastokin kc`` does) and without; every load case of its rig run on both,
alternately, best of ``--repeat`` (``ek.run_drive_sides`` of every ``ek.drives``: the solves,
every channel of both wheels, and with loads the sensors and their numpy pass). Then what the
loads add to the files (``loads_files_s``): ``ek.write_kc_results`` of a K&C run of the same
rig (``ek.run_kc``, the models with loads) against the same run with the loads dropped from
its sweeps (no loads.csv, no largest-loads chart, no Loads section, no loads in the view),
alternately, best of ``--repeat``. The cost of recording against the whole ``elastokin kc``
run (``kc_s``, the command as a user runs it on the same rig, a subprocess into a new folder:
no cache): ``fraction_of_kc`` = (the extra load-case time times the models that record loads
(``models``; the stiffness fit's own runs do not) + the files') / kc_s, an upper bound (a
kinematic model runs fewer cases); target under 0.10.
Through elastokin's public API only: the split of the files' time into loads.csv, the chart
and the report's section (``loads_csv_s``, ``summary_and_chart_s``, ``report_section_s`` in
runs before issue 24's item 6) could only be timed through the report's internals.

The sweeps with and without loads are checked identical (recording changes no number).
Suspensions: the shipped double wishbone axle (rack, anti-roll bar, stops) with its rig and the
static loads of ``configs/rigs/vehicle_loads.yaml``, and the case study
(configs/pseudo_mcpherson.yaml). ``--quick``: the double wishbone only, a short rig, one
repeat, one model, no kc run (what the tests run: seconds; bench_common).

Prints the figures and writes ``benchmarks/results/bench_loads.json`` (``--out``), with the
machine's load average before and after.
"""

from __future__ import annotations

import argparse
import copy
import json
import os
import platform
import subprocess
import sys
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np

import elastokin as ek

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_common import (  # noqa: E402
    add_output_options,
    load_cases_by_side,
    output_path,
    without,
    write_json,
)

ROOT = Path(__file__).resolve().parents[1]
DW = ROOT / "configs" / "double_wishbone_axle.yaml"
CASE = ROOT / "configs" / "pseudo_mcpherson.yaml"
VEHICLE_RIG = ROOT / "configs" / "rigs" / "vehicle_loads.yaml"
#: the quick mode's rig: a short travel sweep, one force sweep, two vehicle cases
QUICK_RIG = {"parallel_travel": {"rebound_mm": -40, "bump_mm": 40, "step_mm": 10,
                                 "unloading": False},
             "vertical_force": None, "longitudinal_force_patch": None,
             "longitudinal_force_centre": None, "aligning_torque": None,
             "lateral_force": {"amplitude_N": 2000, "step_N": 500}, "opposite_travel": None,
             "single_wheel_travel": None, "roll_vertical_force": None, "steering": None,
             "lateral_force_anti_phase": None,
             "vehicle_loads": {"steps": 4, "cases": {"braking": {"longitudinal_g": -1.0},
                                                     "cornering": {"lateral_g": 0.8}}}}




def suspensions(quick: bool, folder: Path) -> dict:
    """The suspensions timed: name -> (Suspension, the rig file kc runs it with or None)."""
    if quick:
        return {"double_wishbone_axle": (ek.load_suspension(DW, {"rig": QUICK_RIG}), None)}
    rig = {**copy.deepcopy(ek.load_suspension(DW).raw)["rig"],  # plain, editable data
           "vehicle_loads": ek.load_rig(VEHICLE_RIG)["vehicle_loads"]}
    rig_file = folder / "dw_rig.yaml"
    rig_file.write_text(json.dumps(rig))
    return {"double_wishbone_axle": (ek.load_suspension_with_rig(DW, rig_file), rig_file),
            "case_study": (ek.load_suspension(CASE), None)}


def same_sweeps(a: dict, b: dict) -> bool:
    """Whether two runs' sweeps hold the same numbers (loads aside)."""
    for side in a:
        for x, y in zip(a[side], b[side]):
            for name, col in x.columns.items():
                other = y.columns[name]
                if col.dtype.kind in "US":
                    if not np.array_equal(col, other):
                        return False
                elif not np.array_equal(np.asarray(col, float), np.asarray(other, float),
                                        equal_nan=True):
                    return False
    return True


def load_case_times(s, repeat: int) -> dict:
    """Every load case run with and without loads, alternately: best times and checks."""
    design = ek.design_state(s)
    models = {rec: ek.build_model(s, ek.ModelOptions(record_loads=rec), design)
              for rec in (False, True)}
    runs = {rec: load_cases_by_side(m, "bench") for rec, m in models.items()}  # warm up
    best = {False: float("inf"), True: float("inf")}
    for _ in range(repeat):
        for rec, model in models.items():
            t0 = time.perf_counter()
            runs[rec] = load_cases_by_side(model, "bench")
            best[rec] = min(best[rec], time.perf_counter() - t0)
    steps = sum(sw.steps for sw in runs[True][s.side])
    return {"steps": steps, "without_loads_s": best[False], "with_loads_s": best[True],
            "extra_s": best[True] - best[False],
            "extra_fraction": (best[True] - best[False]) / best[False],
            "identical_numbers": same_sweeps(runs[False], runs[True]),
            "elements": len(runs[True][s.side][0].loads.items)}


def file_times(s, repeat: int, folder: Path, quick: bool = False) -> dict:
    """``ek.write_kc_results`` of the K&C run of ``s`` with its loads and with them dropped,
    alternately, best of ``repeat``: what the loads add to the files (loads.csv, the
    largest-loads chart, the report's Loads section and the view's loads). ``quick``: one
    model, no warm-up write."""
    run = ek.run_kc(s, models=["initial"] if quick else None)
    runs = {True: run, False: without(run, "loads")}
    best = {True: float("inf"), False: float("inf")}
    for name in ("with_loads", "without_loads"):
        (folder / name).mkdir(parents=True)
    if not quick:
        ek.write_kc_results(runs[True], folder / "with_loads")  # warm up: imports, fonts
    for _ in range(repeat):
        for loads, r in runs.items():
            out = folder / ("with_loads" if loads else "without_loads")
            t0 = time.perf_counter()
            ek.write_kc_results(r, out)
            best[loads] = min(best[loads], time.perf_counter() - t0)
    written = folder / "with_loads"
    recorded = [m for m in run.models.values() if m.sweeps and m.sweeps[0].loads is not None]
    return {"models": len(recorded), "write_results_s": best[True],
            "write_results_without_loads_s": best[False],
            "loads_files_s": best[True] - best[False],
            "loads_csv_bytes": (written / "loads.csv").stat().st_size,
            "load_chart_bytes": (written / "largest_loads.png").stat().st_size,
            "report_bytes": (written / "report.html").stat().st_size,
            "report_without_loads_bytes": (folder / "without_loads" / "report.html").stat()
            .st_size}


def kc_seconds(config: Path, rig: Path | None, folder: Path) -> float:
    """Wall time of ``elastokin kc`` into a new folder (a subprocess, no cache)."""
    args = [sys.executable, "-c", "import sys; from elastokin.cli import main; sys.exit(main())",
            "kc", "--config", str(config), "--out", str(folder), "--quiet"] + (
                ["--rig", str(rig)] if rig else [])
    t0 = time.perf_counter()
    subprocess.run(args, check=True, capture_output=True)
    return time.perf_counter() - t0


def run(quick: bool = False, repeat: int = 3) -> dict:
    """Every figure of the benchmark (module docstring)."""
    load_before = os.getloadavg()
    repeat = 1 if quick else repeat
    figures = {}
    with warnings.catch_warnings(), tempfile.TemporaryDirectory() as tmp:
        warnings.simplefilter("ignore")  # e.g. an undefined steering axis at a step
        for name, (s, rig) in suspensions(quick, Path(tmp)).items():
            entry = {**load_case_times(s, repeat), **file_times(s, repeat, Path(tmp) / name,
                                                                    quick)}
            if not quick:
                entry["kc_s"] = kc_seconds(Path(s.source), rig, Path(tmp) / name / "kc")
                entry["fraction_of_kc"] = (entry["models"] * max(entry["extra_s"], 0.0)
                                           + max(entry["loads_files_s"], 0.0)) / entry["kc_s"]
            figures[name] = entry
    return {"elastokin_version": ek.__version__, "exudyn_version": ek.exudyn_version(),
            "machine": {"python": platform.python_version(), "processor": platform.machine(),
                        "cpus": os.cpu_count()},
            "quick": quick, "repeat": repeat, "target_fraction_of_kc": 0.10,
            "load_average_before": load_before, "load_average_after": os.getloadavg(),
            "suspensions": figures}


def main(argv: list[str] | None = None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    add_output_options(ap, "bench_loads")
    args = ap.parse_args(argv)
    out = output_path(args, "bench_loads")
    result = run(args.quick, args.repeat)
    write_json(out, result)
    for name, f in result["suspensions"].items():
        kc = (f" of kc {f['kc_s']:.2f} s: {100 * f['fraction_of_kc']:.1f} %"
              if "kc_s" in f else "")
        print(f"{name}: {f['steps']} steps, {f['elements']} elements; load cases "
              f"{f['without_loads_s']:.3f} s -> {f['with_loads_s']:.3f} s "
              f"(+{100 * f['extra_fraction']:.1f} %); the files of {f['models']} models "
              f"{f['write_results_without_loads_s']:.3f} s -> {f['write_results_s']:.3f} s "
              f"(loads.csv {f['loads_csv_bytes'] / 1e6:.1f} MB){kc}; identical numbers: "
              f"{f['identical_numbers']}")
    print(f"written to {out}")
    return result


if __name__ == "__main__":
    main()
