"""The cost of recording loads (issue 27): every element's force and moment at every step.

For each suspension, in one run on this machine, the same model built twice (the same design
preloads): with the loads recorded (``ModelOptions.record_loads``, what ``elastokin kc``
does) and without; every load case of its rig run on both, alternately, best of ``--repeat``
(:func:`elastokin.rig.load_cases.run_load_cases_sides`: the solves, every channel of both
wheels, and with loads the sensors and their numpy pass). Then what the loads add to the
files: loads.csv, the largest-loads chart and the report's Loads section, timed on the
recorded run. The cost of recording against the whole ``elastokin kc`` run (``kc_s``, the
command as a user runs it on the same rig, a subprocess into a new folder: no cache):
``fraction_of_kc`` = (the extra load-case time times the models that record loads + the
files') / kc_s, an upper bound (a kinematic model runs fewer cases); target under 0.10.

The sweeps with and without loads are checked identical (recording changes no number).
Suspensions: the shipped double wishbone axle (rack, anti-roll bar, stops) with its rig and the
static loads of ``configs/rigs/vehicle_loads.yaml``, and the case study
(configs/pseudo_mcpherson.yaml). ``--quick``: the double wishbone only, a short rig, one
repeat, no kc run (what the tests run: seconds).

Prints the figures and writes ``benchmarks/results/bench_loads.json`` (``--out``), with the
machine's load average before and after.
"""

from __future__ import annotations

import argparse
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

from elastokin.config.loading import load_suspension, read_yaml, suspension_from_dict
from elastokin.mbs.design import build_model, design_state
from elastokin.mbs.model import EXUDYN_VERSION, ModelOptions
from elastokin.rig.load_cases import run_load_cases_sides
from elastokin.version import __version__

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


#: the models of each kc run that record loads (the stiffness fit's own runs do not)
MODELS = {"double_wishbone_axle": 2, "case_study": 3}


def suspensions(quick: bool, folder: Path) -> dict:
    """The suspensions timed: name -> (Suspension, the rig file kc runs it with or None)."""
    dw = read_yaml(DW)[0]
    if quick:
        return {"double_wishbone_axle": (suspension_from_dict({**dw, "rig": QUICK_RIG},
                                                              str(DW)), None)}
    rig = {**dw["rig"], "vehicle_loads": read_yaml(VEHICLE_RIG)[0]["vehicle_loads"]}
    rig_file = folder / "dw_rig.yaml"
    rig_file.write_text(json.dumps(rig))
    return {"double_wishbone_axle": (suspension_from_dict({**dw, "rig": rig}, str(DW)),
                                     rig_file),
            "case_study": (load_suspension(CASE), None)}


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
    design = design_state(s)
    models = {rec: build_model(s, ModelOptions(record_loads=rec), design)
              for rec in (False, True)}
    runs = {rec: run_load_cases_sides(m, "bench") for rec, m in models.items()}  # warm up
    best = {False: float("inf"), True: float("inf")}
    for _ in range(repeat):
        for rec, model in models.items():
            t0 = time.perf_counter()
            runs[rec] = run_load_cases_sides(model, "bench")
            best[rec] = min(best[rec], time.perf_counter() - t0)
    steps = sum(sw.steps for sw in runs[True][s.side])
    return {"steps": steps, "without_loads_s": best[False], "with_loads_s": best[True],
            "extra_s": best[True] - best[False],
            "extra_fraction": (best[True] - best[False]) / best[False],
            "identical_numbers": same_sweeps(runs[False], runs[True]),
            "elements": len(runs[True][s.side][0].loads.items)}, runs[True]


def file_times(s, runs: dict, folder: Path) -> dict:
    """loads.csv, the largest-loads chart and the Loads section from one model's run."""
    from elastokin.report.chart_canvas import ChartCanvas, save_chart
    from elastokin.report.files import config_provenance
    from elastokin.report.html_loads import loads_section
    from elastokin.report.load_charts import draw_load_chart, load_chart_data
    from elastokin.report.loads_csv import write_loads_csv
    from elastokin.rig.loads import load_summary
    from elastokin.studies.kc_job import ModelResult

    result = ModelResult("initial", False, runs[s.side], {})
    prov = config_provenance(s)
    canvas = ChartCanvas()
    canvas.axes("bars")  # matplotlib imported and the figure made, as in a kc run's charts
    t0 = time.perf_counter()
    write_loads_csv(folder / "loads.csv", {"initial": result}, prov)
    t1 = time.perf_counter()
    summary = {"models": {"initial": load_summary(result.sweeps)}}
    data = load_chart_data(summary)
    save_chart(draw_load_chart(canvas, data, prov), folder / "largest_loads.png")
    t2 = time.perf_counter()
    loads_section(summary, [folder / "largest_loads.png"], 1)
    t3 = time.perf_counter()
    return {"loads_csv_s": t1 - t0, "loads_csv_bytes": (folder / "loads.csv").stat().st_size,
            "summary_and_chart_s": t2 - t1, "report_section_s": t3 - t2}


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
    figures = {}
    with warnings.catch_warnings(), tempfile.TemporaryDirectory() as tmp:
        warnings.simplefilter("ignore")  # e.g. an undefined steering axis at a step
        for name, (s, rig) in suspensions(quick, Path(tmp)).items():
            times, recorded = load_case_times(s, 1 if quick else repeat)
            files = file_times(s, recorded, Path(tmp))
            entry = {**times, **files}
            if not quick:
                entry["kc_s"] = kc_seconds(Path(s.source), rig, Path(tmp) / name)
                entry["fraction_of_kc"] = (MODELS[name] * max(times["extra_s"], 0.0)
                                           + files["loads_csv_s"]
                                           + files["summary_and_chart_s"]) / entry["kc_s"]
            figures[name] = entry
    return {"elastokin_version": __version__, "exudyn_version": EXUDYN_VERSION,
            "machine": {"python": platform.python_version(), "processor": platform.machine(),
                        "cpus": os.cpu_count()},
            "quick": quick, "repeat": 1 if quick else repeat, "target_fraction_of_kc": 0.10,
            "load_average_before": load_before, "load_average_after": os.getloadavg(),
            "suspensions": figures}


def main(argv: list[str] | None = None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--quick", action="store_true", help="one short case, no kc run")
    ap.add_argument("--out", default=str(ROOT / "benchmarks" / "results" / "bench_loads.json"))
    args = ap.parse_args(argv)
    result = run(args.quick, args.repeat)
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    Path(args.out).write_text(json.dumps(result, indent=2) + "\n")
    for name, f in result["suspensions"].items():
        kc = (f" of kc {f['kc_s']:.2f} s: {100 * f['fraction_of_kc']:.1f} %"
              if "kc_s" in f else "")
        print(f"{name}: {f['steps']} steps, {f['elements']} elements; load cases "
              f"{f['without_loads_s']:.3f} s -> {f['with_loads_s']:.3f} s "
              f"(+{100 * f['extra_fraction']:.1f} %), loads.csv {f['loads_csv_s']:.3f} s, "
              f"chart {f['summary_and_chart_s']:.3f} s{kc}; identical numbers: "
              f"{f['identical_numbers']}")
    print(f"written to {args.out}")
    return result


if __name__ == "__main__":
    main()
