"""Result files of ``elastokin kc``: ``kc.csv`` (long format) and ``summary.json``.

Every file carries its provenance: the elastokin and Exudyn versions, the SHA-256 of the config
file and the solver settings. Units are in the column names (mm, N, N*mm, deg).
"""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path

import numpy as np

from elastokin.rig.load_cases import Sweep
from elastokin.studies.kc_job import KCRun
from elastokin.version import __version__

SIGN_CONVENTIONS = {
    "frame": "the config frame (see its 'frame' key); wheel-centre coordinates in it",
    "toe_deg": "toe angle, positive toe-in (ISO 8855 / SAE J670); 'steer' in the paper",
    "camber_deg": "camber angle, positive top of the wheel leaning outboard",
    "wheel_travel_mm": "wheel-centre vertical displacement from the design position, + bump",
    "pad_z_mm": "prescribed vertical displacement of the contact patch (rig input), + up",
    "contact_patch_f*_N": "force the rig applies to the tyre at the contact patch, config frame",
    "spring_*_force_N": "coil spring force, positive in compression",
    "bushing_*": "deflection of the part-2 sleeve relative to part 1, bushing frame (z axial, "
                 "x main radial), incl. the preload deflection; rotations Tait-Bryan x-y-z",
    "caster_deg": "steering-axis inclination from the vertical in side view, + top rearward "
                  "(docs/characteristics.md)",
    "kingpin_inclination_deg": "steering-axis inclination from the vertical in front view, "
                               "+ top inboard",
    "scrub_radius_mm": "ground-plane offset of the steering axis from the contact point normal "
                       "to the wheel/ground line, + axis inboard",
    "caster_trail_mm": "ground-plane offset of the steering axis from the contact point along "
                       "the wheel/ground line, + axis ahead",
    "bump_steer_deg_per_m": "least-squares slope of toe vs wheel travel over +-50 mm",
    "steer_amplitude_deg": "max - min toe over the measured stroke",
}


def provenance(run: KCRun, exudyn_version: str) -> dict:
    return config_provenance(run.suspension, exudyn_version)


def config_provenance(s, exudyn_version: str) -> dict:
    """Versions, config file and its SHA-256, units: carried by every result file."""
    return {
        "elastokin_version": __version__,
        "exudyn_version": exudyn_version,
        "config_file": str(s.source),
        "config_sha256": s.sha256,
        "rig_file": s.rig_source or None,  # None: the config's own rig section
        "units": {"length": "mm", "force": "N", "torque": "N*mm", "angle": "deg"},
    }


def write_kc_csv(path: Path, sweeps: list[Sweep], header: dict) -> None:
    """One row per model, load case and step; a ``#`` comment header carries provenance
    (read with ``pandas.read_csv(path, comment="#")``)."""
    names: list[str] = []
    for sw in sweeps:
        names += [c for c in sw.columns if c not in names and c != "branch"]
    with open(path, "w", newline="") as fh:
        for key in ("elastokin_version", "exudyn_version", "config_file", "config_sha256"):
            fh.write(f"# {key}: {header[key]}\n")
        if header.get("rig_file"):
            fh.write(f"# rig_file: {header['rig_file']}\n")
        fh.write("# units: mm, N, N*mm, deg (in each column name); empty = not applicable\n")
        writer = csv.writer(fh, lineterminator="\n")
        writer.writerow(["model", "load_case", "step", "branch", *names])
        for sw in sweeps:
            for i in range(sw.steps):
                row = [sw.model, sw.load_case, i + 1, sw.columns["branch"][i]]
                for c in names:
                    v = sw.columns.get(c)
                    row.append("" if v is None else _fmt(v[i]))
                writer.writerow(row)


def _fmt(x) -> str:
    if isinstance(x, (str, np.str_)):
        return str(x)
    x = float(x)
    return "" if math.isnan(x) else repr(round(x, 10))


def summary_dict(run: KCRun, exudyn_version: str, files: list[str]) -> dict:
    st = run.static
    ref = run.suspension.reference
    bushings = {}
    for name, row in st.bushings.items():
        entry = dict(row)
        r = ref.static_bushings.get(name)
        if r is not None:
            entry["reference"] = r.model_dump(exclude_none=True)
        bushings[name] = entry
    return {
        **provenance(run, exudyn_version),
        "solver": {label: m.solver for label, m in run.models.items()},
        "models": {label: m.summary() for label, m in run.models.items()},
        "errors": run.errors,
        "static": {
            "wheel_load_N": st.wheel_load_N,
            "wheel_centre_mm": st.state.wheel_centre_mm.tolist(),
            "contact_patch_force_N": st.state.pad_force_N.tolist(),
            "spring_force_N": st.state.spring_force_N,
            "wheel_assembly_force_residual_N": st.wheel_assembly_force_residual_N,
            "bushings": bushings,
            "reference_source": ref.source,
        },
        "design": {
            "spring_force_N": run.design.spring_force_N,
            "bushing_preload_N_Nmm": {k: v.tolist() for k, v in
                                      run.design.bushing_preload.items()},
        },
        "reference": {"steer_amplitude_deg": ref.steer_amplitude_deg},
        "warnings": run.warnings,
        **({"stiffness_identification": stiffness_summary(run.stiffness)}
           if run.stiffness is not None else {}),
        "sign_conventions": SIGN_CONVENTIONS,
        "files": files,
    }


def write_summary(path: Path, summary: dict) -> None:
    path.write_text(json.dumps(summary, indent=2, sort_keys=False) + "\n")


def identification_dict(ident, prov: dict) -> dict:
    """``identification.json``: the contract keys (parts, joints, verification) plus details
    and provenance. Vehicle (config) frame, mm, deg."""
    return {**prov,
            "eps_mm": ident.suspension.measurements.eps_mm,
            **ident.to_json(),
            "conventions": {
                "shift_mm": "identified - initial joint location, config frame, loaded state",
                "initial_mm": "joint centre from the parts measured alone (housing centre of "
                              "a bolted side)",
                "identified_mm": "joint centre from the assembled measurement; for a bushing "
                                 "the inner-sleeve centre B* [26]",
                "deflection_mm_deg": "bushing deflection at static equilibrium, part-2 sleeve "
                                     "relative to part 1, bushing frame (x y z mm, rx ry rz "
                                     "deg)",
                "verification_max_deviation_mm": "largest distance of a joint from its "
                                                 "measured location at the identified model's "
                                                 "static equilibrium under the wheel load",
            }}


def identification_table(ident) -> str:
    """A readable summary of an identification (plain text)."""
    d = ident.to_json()
    out = [f"Geometric identification of {ident.suspension.name}",
           f"  config {ident.suspension.source}; units mm, deg; config frame", "",
           "Part poses from the assembled marks [8-12]",
           f"  {'part':<12}{'residual RMS mm':>16}  dropped mark"]
    marks = ident.suspension.measurements.parts
    for p, v in d["parts"].items():
        dropped = "-" if v["dropped_mark"] is None else marks[p].marks[v["dropped_mark"]]
        out.append(f"  {p:<12}{v['residual_rms_mm']:>16.4f}  {dropped}")
    out += ["", "Joints (loaded state): identified - initial shift, and error against the "
            "synthetic truth when known",
            f"  {'joint':<12}{'kind':<11}{'shift x':>9}{'y':>8}{'z':>8}{'|shift|':>9}"
            f"{'dL_max':>8}{'error':>8}"]
    for n, j in d["joints"].items():
        sx, sy, sz = j["shift_mm"]
        dl = "" if j["max_shift_mm"] is None else f"{j['max_shift_mm']:.2f}"
        err = "" if j["error_vs_truth_mm"] is None else f"{j['error_vs_truth_mm']:.3f}"
        out.append(f"  {n:<12}{j['kind']:<11}{sx:>9.3f}{sy:>8.3f}{sz:>8.3f}"
                   f"{math.hypot(sx, sy, sz):>9.3f}{dl:>8}{err:>8}")
    out += ["", "Bushing deflections at static equilibrium [22-23] (part 2 rel. part 1, "
            "bushing frame)",
            f"  {'bushing':<10}{'radial mm':>10}{'axial mm':>10}{'torsion deg':>12}"
            f"   B* z-x-z Euler deg [20-21]"]
    for n, j in d["joints"].items():
        if j["deflection_mm_deg"] is not None:
            u = j["deflection_mm_deg"]
            e = ", ".join(f"{a:.2f}" for a in j["euler_zxz_deg"])
            out.append(f"  {n:<10}{math.hypot(u[0], u[1]):>10.3f}{u[2]:>10.3f}{u[5]:>12.4f}"
                       f"   ({e})")
    out += ["", f"Verification [7]: at the identified model's static equilibrium the joints "
            f"are within {d['verification_max_deviation_mm']:.2e} mm of their measured "
            "locations"]
    if d["warnings"]:
        out += ["", "Warnings:"] + [f"  - {w}" for w in d["warnings"]]
    return "\n".join(out) + "\n"


def write_identification(folder: Path, ident, prov: dict) -> None:
    (folder / "identification.json").write_text(
        json.dumps(identification_dict(ident, prov), indent=2) + "\n")
    (folder / "identification.txt").write_text(identification_table(ident))


def stiffness_summary(fit) -> dict:
    """The stiffness identification in ``summary.json`` (details in
    ``stiffness_identification.json``)."""
    return {
        "parameters": {f"{p.bushing}.{p.name}": {
            "value": p.value, "unit": p.unit, "ci95": list(p.ci95),
            "determined": p.determined} for p in fit.parameters},
        "condition_number": fit.condition_number,
        "warnings": fit.warnings,
        "file": "stiffness_identification.json",
    }


def write_stiffness_identification(folder: Path, fit, prov: dict) -> list[str]:
    """``stiffness_identification.json`` (with provenance) and ``.txt``; returns the names."""
    (folder / "stiffness_identification.json").write_text(
        json.dumps({**prov, **fit.to_json()}, indent=2) + "\n")
    (folder / "stiffness_identification.txt").write_text(fit.table())
    return ["stiffness_identification.json", "stiffness_identification.txt"]
