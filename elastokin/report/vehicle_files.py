"""The whole car's results folder (``elastokin kc --vehicle``): ``summary.json`` of the car
(its figures per car model, the vehicle's data, provenance of both axles), ``car.csv`` (the
table's body roll), the car's charts and ``report.html``; each axle's own results (kc.csv,
summary.json, charts, report.html) in the sub-folders ``front/`` and ``rear/``
(:func:`elastokin.report.files.write_kc_results`).

Units mm, N, N*mm, deg, kg; signs ISO 8855 (docs/characteristics.md "Whole car").
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import TYPE_CHECKING

from elastokin.config.vehicle import ROLES
from elastokin.report.files import (
    input_files,
    read_kc_csv,
    read_results,
    write_kc_csv,
    write_kc_results,
    write_summary,
)
from elastokin.rig.axle_channels import design_track_mm
from elastokin.rig.sweeps import Sweep
from elastokin.rig.vehicle_channels import (
    AXLE_IN_CAR_LIST,
    CAR_CHANNEL_LIST,
    CAR_CHARACTERISTIC_LIST,
)
from elastokin.version import __version__, exudyn_version

if TYPE_CHECKING:
    from elastokin.studies.vehicle_job import VehicleRun

#: car.csv's provenance header
CAR_CSV_HEADER = ("elastokin_version", "exudyn_version", "vehicle_file", "vehicle_sha256",
                  "front_config_file", "front_config_sha256", "rear_config_file",
                  "rear_config_sha256")


def vehicle_provenance(run: VehicleRun) -> dict:
    """Versions, the vehicle file and both axle configs with their SHA-256 (each file's
    bytes), the rig file both axles ran (None: their own ``rig`` sections), units."""
    v = run.vehicle
    out = {"elastokin_version": __version__, "exudyn_version": exudyn_version(),
           "vehicle_file": v.source, "vehicle_sha256": v.sha256,
           "rig_file": v.rig_source or None, "rig_sha256": v.rig_sha256}
    for role in ROLES:
        s = v.axle(role)
        out[f"{role}_config_file"] = s.source
        out[f"{role}_config_sha256"] = s.config_sha256
    out["units"] = {"length": "mm", "force": "N", "torque": "N*mm", "angle": "deg",
                    "mass": "kg", "understeer gradient": "deg of road-wheel steer per g"}
    return out


def axle_entry(run: VehicleRun, role: str) -> dict:
    """summary.json ``axles.<role>``: the axle's config, name, results folder, track, design
    load, the vehicle data it ran with and its models."""
    s = run.vehicle.axle(role)
    return {"config_file": s.source, "config_sha256": s.config_sha256, "name": s.name,
            "results": role, "track_mm": design_track_mm(s),
            "loaded_radius_mm": s.wheel.loaded_radius_mm,
            "design_wheel_load_N": s.design.wheel_load_N,
            "axle_vehicle": s.axle.vehicle.model_dump(),
            "models": [m for m in run.axles[role].models if m != "test"]}


def vehicle_summary_dict(run: VehicleRun, files: list[str]) -> dict:
    """The car's ``summary.json``: provenance, the vehicle's data, the axles, every car
    model's figures (``models.<label>``: ``front_model``, ``rear_model``, ``front``,
    ``rear``, ``car``), the solver settings of every axle model, every input file, the
    warnings and the definitions."""
    v = run.vehicle
    inputs = [{"role": "vehicle file", "file": v.source, "sha256": v.sha256}]
    for role in ROLES:
        inputs += [{**f, "role": f"{role} axle: {f['role']}"}
                   for f in input_files(run.axles[role])]
    warnings = list(run.warnings)  # the car's, and every Python warning of the run
    for role in ROLES:  # an axle's own notes (e.g. on its test data) that were no warning
        warnings += [f"{role} axle: {w}" for w in run.axles[role].warnings
                     if w not in run.warnings]
    return {**vehicle_provenance(run), "vehicle_name": v.name,
            "vehicle": {**v.data.as_dict(), "body_roll": v.body_roll.model_dump()},
            "axles": {role: axle_entry(run, role) for role in ROLES},
            "input_files": inputs,
            "solver": {role: {label: m.solver for label, m in run.axles[role].models.items()
                              if label != "test"} for role in ROLES},
            "models": run.figures,
            "warnings": list(dict.fromkeys(warnings)),
            "sign_conventions": {
                **{c.name: c.sign for c in CAR_CHANNEL_LIST},
                **{f"car.{c.name}": c.definition for c in CAR_CHARACTERISTIC_LIST},
                **{f"front/rear.{c.name}": c.definition for c in AXLE_IN_CAR_LIST},
                "front/rear.*": "the axle's own figure: its summary.json "
                                "models.<label>.axle (the left wheel's for bump steer and "
                                "bump camber)"},
            "files": files}


def write_vehicle_results(run: VehicleRun, folder: Path, svg: bool = False) -> dict:
    """Every file of the car into ``folder``: each axle's results in ``front/`` and
    ``rear/``, car.csv, the car's charts (PNG; with ``svg`` also SVG), summary.json and
    report.html. Returns the car's summary."""
    from elastokin.report.html.vehicle import write_vehicle_report
    from elastokin.report.vehicle_charts import vehicle_charts

    axles = {}
    for role in ROLES:
        (folder / role).mkdir(parents=True, exist_ok=True)  # its cache may be there
        axles[role] = write_kc_results(run.axles[role], folder / role, svg)
    prov = vehicle_provenance(run)
    write_kc_csv(folder / "car.csv", list(run.roll.values()), prov, "car", CAR_CSV_HEADER)
    files = ["summary.json", "car.csv"]
    summary = vehicle_summary_dict(run, files)
    charts = vehicle_charts(summary, list(run.roll.values()), folder, svg)
    files += [p.name for p in charts] + ["report.html"]
    files += [f"{role}/" for role in ROLES]
    summary["files"] = files
    write_summary(folder / "summary.json", summary)
    write_vehicle_report(folder / "report.html", summary, charts, axles)
    return summary


def read_vehicle_results(folder: str | Path
                         ) -> tuple[dict, list[Sweep], dict[str, tuple[dict, list[Sweep]]]]:
    """An ``elastokin kc --vehicle`` results folder: the car's summary.json, the sweeps of
    car.csv, and each axle's (summary, sweeps) by role (:func:`read_results`) from the
    sub-folders ``front/`` and ``rear/`` (by those fixed names: a folder may come from
    anyone, and nothing in it decides where elastokin reads)."""
    folder = Path(folder)
    summary = json.loads((folder / "summary.json").read_text())
    return (summary, read_kc_csv(folder / "car.csv"),
            {role: read_results(folder / role) for role in ROLES})

