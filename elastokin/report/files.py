"""Result files: ``kc.csv`` (long format), ``summary.json``, the identification and
stiffness-fit files, written configs, and the whole results folder of a K&C run.

Every file carries its provenance: the elastokin and Exudyn versions, the SHA-256 of the config
file and the solver settings. Units are in the column names (mm, N, N*mm, deg).
"""

from __future__ import annotations

import csv
import hashlib
import json
import math
import os
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from elastokin.config.frozen import plain_data
from elastokin.config.loading import relocated_folder
from elastokin.report.loads_csv import write_loads_csv
from elastokin.report.text import identification_table, motion_table
from elastokin.rig.axle_channels import dependent_axle, design_track_mm
from elastokin.rig.channels import sign_conventions
from elastokin.rig.drives import vehicle_load_table
from elastokin.rig.loads import load_summary
from elastokin.rig.sweeps import Sweep
from elastokin.version import __version__, code_sha256, exudyn_version

if TYPE_CHECKING:
    from elastokin.studies.kc_job import KCRun


def config_provenance(s) -> dict:
    """Versions, the config file and its SHA-256, the rig file (None: the config's own rig
    section) and its SHA-256, units: carried by every result file."""
    return {
        "elastokin_version": __version__,
        "elastokin_code_sha256": code_sha256(),  # tells apart code of the same version
        "exudyn_version": exudyn_version(),
        "config_file": str(s.source),
        "config_sha256": s.config_sha256,
        "rig_file": s.rig_source or None,
        "rig_sha256": s.rig_sha256,
        "units": {"length": "mm", "force": "N", "torque": "N*mm", "angle": "deg"},
    }


#: the provenance keys kc.csv's header gives first
CSV_HEADER = ("elastokin_version", "exudyn_version", "config_file", "config_sha256")


def write_kc_csv(path: Path, sweeps: list[Sweep], header: dict, side: str = "left",
                 keys: tuple[str, ...] = CSV_HEADER) -> None:
    """One row per model, load case, wheel side and step; a ``#`` comment header carries
    provenance (``keys`` of ``header``; read with ``pandas.read_csv(path, comment="#")``).
    ``side`` is the config's side: the side of a sweep that names none (test data of a
    corner)."""
    names: list[str] = []
    for sw in sweeps:
        names += [c for c in sw.columns if c not in names and c != "branch"]
    with open(path, "w", newline="") as fh:
        for key in keys:
            fh.write(f"# {key}: {header[key]}\n")
        if header.get("rig_file"):
            fh.write(f"# rig_file: {header['rig_file']}\n")
            fh.write(f"# rig_sha256: {header['rig_sha256']}\n")
        fh.write("# units: mm, N, N*mm, deg (in each column name); empty = not applicable; "
                 "side: the wheel's (vehicle left/right)\n")
        writer = csv.writer(fh, lineterminator="\n")
        writer.writerow(["model", "load_case", "side", "step", "branch", *names])
        for sw in sweeps:
            n = sw.steps
            cols = [[sw.model] * n, [sw.load_case] * n, [sw.side or side] * n, range(1, n + 1),
                    [str(b) for b in sw.columns["branch"]]]
            cols += [_formatted(sw.columns[c]) if c in sw.columns else [""] * n
                     for c in names]
            writer.writerows(zip(*cols))


def _formatted(column) -> list[str]:
    """A column's values as kc.csv writes them: rounded to 10 decimals, NaN empty."""
    if np.asarray(column).dtype.kind in "US":
        return [str(x) for x in column]
    return ["" if math.isnan(x) else repr(round(x, 10))
            for x in np.asarray(column, float).tolist()]


def summary_dict(run: KCRun, files: list[str]) -> dict:
    """``summary.json``: per model its characteristics and solver settings, the errors against
    the test, the static equilibrium, the design preloads, the stiffness fit, provenance."""
    st = run.static
    ref = run.suspension.reference
    bushings = {}
    for name, row in st.bushings.items():
        entry = dict(row)
        r = ref.static_bushings.get(name)
        if r is not None:
            entry["reference"] = r.model_dump(exclude_none=True)
        bushings[name] = entry
    s = run.suspension
    models = run.summaries()  # before the warnings: a figure not determined adds one
    for label, figures in models.items():  # and every element's loads (none: the test)
        figures.update(load_summary(run.models[label].sweeps))
    return {
        **config_provenance(s),
        "config_name": s.name,
        "input_files": input_files(run),
        "test_data_synthetic": s.kc_test is not None and s.kc_test.synthetic is not None,
        "solver": {label: m.solver for label, m in run.models.items()},
        "models": models,
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
        "reused_from_cache": run.reused,
        **({"stiffness_identification": stiffness_summary(run.stiffness)}
           if run.stiffness is not None else {}),
        **({"motion_identification": motion_summary(run.motion)}
           if run.motion is not None else {}),
        **({"axle": axle_data(s)} if s.axle is not None else {}),
        **({"vehicle_loads": vehicle_load_table(s)} if s.rig.vehicle_loads else {}),
        "sign_conventions": sign_conventions(),
        "files": files,
    }


def axle_data(s) -> dict:
    """summary.json ``axle``: the axle's make-up and vehicle data (the figures are per model,
    ``models.<label>.axle``): its sides (the config's first), the design track at the contact
    points [mm], shared parts, whether the wheels are dependent (a solid axle: the
    kinematic roll centre is then the instant centre of the axle's roll motion), steering and
    anti-roll bar present, and the config's ``axle.vehicle`` (None without)."""
    v = s.axle.vehicle
    return {"sides": list(s.axle.sides), "config_side": s.side,
            "track_mm": design_track_mm(s),
            "shared_parts": list(s.axle.shared),
            "dependent": dependent_axle(s),
            "steering": s.axle.steering is not None,
            "anti_roll_bar": s.axle.anti_roll_bar is not None,
            "vehicle": v.model_dump() if v is not None else None,
            "wheelbase_mm": v.wheelbase_mm if v is not None else None}


def _sha256(path: str) -> str | None:
    try:
        return hashlib.sha256(Path(path).read_bytes()).hexdigest()
    except OSError:
        return None


def input_files(run: KCRun) -> list[dict]:
    """Every file the run read, with its role and SHA-256 (None: no longer readable): the
    config, the rig file, the K&C test files and the CMM files."""
    s = run.suspension
    out = [{"role": "config", "file": str(s.source), "sha256": s.config_sha256}]
    if s.rig_source:
        out.append({"role": "rig file", "file": s.rig_source, "sha256": s.rig_sha256})
    test = run.models.get("test")
    for f in (test.solver.get("files", []) if test is not None else []):
        out.append({"role": "K&C test", "file": str(f), "sha256": _sha256(f)})
    if run.identification is not None:
        for part, f in run.identification.sources.items():
            role = "CMM, assembled marks" if part == "assembly" else f"CMM, part {part}"
            out.append({"role": role, "file": str(f), "sha256": _sha256(f)})
    if run.motion is not None:
        for position, f in run.motion.sources.items():
            role = ("CMM, ground marks" if position == "ground"
                    else f"CMM, motion position {position}")
            out.append({"role": role, "file": str(f), "sha256": _sha256(f)})
    return out


def write_summary(path: Path, summary: dict) -> None:
    path.write_text(json.dumps(summary, indent=2, sort_keys=False) + "\n")


def identification_dict(ident, prov: dict) -> dict:
    """``identification.json``: the contract keys (parts, joints, verification) plus details
    and provenance. Vehicle (config) frame, mm, deg."""
    body = ident.to_json()
    marks = ident.suspension.measurements.parts
    for part, p in body["parts"].items():
        k = p["dropped_mark"]
        p["dropped_mark_label"] = None if k is None else marks[part].marks[k]
    return {**prov,
            "eps_mm": ident.suspension.measurements.eps_mm,
            **body,
            "conventions": {
                "shift_mm": "identified - initial joint location, config frame, loaded state",
                "initial_mm": "joint centre from the parts measured alone (housing centre of "
                              "a bolted side)",
                "identified_mm": "joint centre from the assembled measurement; for a bushing "
                                 "the inner-sleeve centre B* (eq. (26))",
                "clearance_shift_mm": "the part of the shift a clearance bounds (a bushing: "
                                      "normal to its housing axis), against max_shift_mm = "
                                      "dL_max (eq. (1); null: no clearance given); "
                                      "exceeds_clearance flags it (and a warning)",
                "equations": "eq. (n): equation n of Meissonnier et al. (2006), Proc. IMechE "
                             "Part D 220",
                "deflection_mm_deg": "bushing deflection at static equilibrium, part-2 sleeve "
                                     "relative to part 1, bushing frame (x y z mm, rx ry rz "
                                     "deg)",
                "verification_max_deviation_mm": "largest distance of a joint from its "
                                                 "measured location at the identified model's "
                                                 "static equilibrium under the wheel load",
            }}


def write_identification(folder: Path, ident, prov: dict) -> dict:
    """identification.json and .txt; returns the JSON's content."""
    doc = identification_dict(ident, prov)
    (folder / "identification.json").write_text(json.dumps(doc, indent=2) + "\n")
    (folder / "identification.txt").write_text(identification_table(ident))
    return doc


def motion_dict(motion, prov: dict, ident: dict | None = None) -> dict:
    """``motion_identification.json``: the joints located from the motion (with provenance)
    and, when the run also identified the geometry from the parts measured alone
    (``ident``, ``identification.json``'s content), that method's error against the truth
    beside each joint's. Vehicle (config) frame at the design position, mm, deg."""
    body = motion.to_json()
    for name, j in body["joints"].items():
        other = (ident or {}).get("joints", {}).get(name)
        j["disassembly_error_vs_truth_mm"] = None if other is None else \
            other.get("error_vs_truth_mm")
    return {**prov, **body, "conventions": {
        "located_mm": "joint centre from the parts' motion at the design position (an axis "
                      "joint: the axis point nearest the config's hardpoint; null: only the "
                      "axis is located, e.g. a bushing)",
        "uncertainty_mm": "1-sigma 3-D RMS from the CMM noise (noise_sigma_mm, first-order "
                          "propagation); worst_std_mm along the worst direction",
        "residual_rms_mm": "RMS distance between the two bodies' points over the positions",
        "error_vs_truth_mm": "against the synthetic truth; an axis joint's across the true "
                             "axis",
        "methods": "SCoRE: Ehrig et al. 2006, J. Biomech. 39:2798; SARA: Ehrig et al. 2007, "
                   "J. Biomech. 40:2150"}}


def motion_summary(motion) -> dict:
    """The joints from motion in ``summary.json`` (details in motion_identification.json)."""
    return {"file": "motion_identification.json",
            "noise_sigma_mm": motion.noise_sigma_mm,
            "joints": {n: {"located_mm": None if not j.plan.locates_point
                           else [float(x) for x in j.point_mm],
                           "uncertainty_mm": j.uncertainty_mm if j.plan.locates_point
                           else None,
                           "axis_uncertainty_deg": j.axis_uncertainty_deg,
                           "error_vs_truth_mm": j.error_vs_truth_mm,
                           "axis_error_deg": j.axis_error_deg}
                       for n, j in motion.joints.items()}}


def write_motion_identification(folder: Path, motion, prov: dict, ident: dict | None = None
                                ) -> dict:
    """motion_identification.json and .txt; returns the JSON's content."""
    doc = motion_dict(motion, prov, ident)
    (folder / "motion_identification.json").write_text(json.dumps(doc, indent=2) + "\n")
    (folder / "motion_identification.txt").write_text(motion_table(doc))
    return doc


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


def write_config(path: Path, config: dict, header: str) -> None:
    """A config dict as YAML, with a comment header (units, provenance)."""
    import yaml

    text = yaml.safe_dump(plain_data(config), sort_keys=False, default_flow_style=None,
                          width=100)
    lines = "".join(f"# {ln}\n" for ln in header.splitlines())
    Path(path).write_text(lines + text)


def write_kc_results(run: KCRun, folder: Path, svg: bool = False) -> dict:
    """Every file of a K&C run into ``folder``: kc.csv, identification and stiffness-fit files
    (when there are), the charts (PNG; with ``svg`` also SVG), summary.json, report.html and,
    when loads were recorded, loads.csv and the largest loads' chart (listed last).
    Returns the summary."""
    from elastokin.report.axle_charts import axle_chart_inputs
    from elastokin.report.charts import kc_charts
    from elastokin.report.html.page import write_report
    from elastokin.report.load_charts import LOAD_CHART, load_chart_data
    from elastokin.report.view3d import run_views, view_fragment

    prov = config_provenance(run.suspension)
    sweeps = [sw for m in run.models.values()
              for sw in [*m.sweeps, *(o for side in m.other_sides.values() for o in side)]]
    write_kc_csv(folder / "kc.csv", sweeps, prov, run.suspension.side)
    files = ["kc.csv", "summary.json"]
    ident = None
    if run.identification is not None:
        ident = write_identification(folder, run.identification, prov)
        files += ["identification.json", "identification.txt"]
    motion = None
    if run.motion is not None:
        motion = write_motion_identification(folder, run.motion, prov, ident)
        files += ["motion_identification.json", "motion_identification.txt"]
    if run.stiffness is not None:
        files += write_stiffness_identification(folder, run.stiffness, prov)
    summary = summary_dict(run, list(files))  # the axle charts' legends need its figures
    later = {}  # loads.csv and the 3D views: made while the other process draws charts
    charts = kc_charts(sweeps, folder, prov, run.errors, svg, axle_chart_inputs(summary),
                       load_chart_data(summary), lambda: later.update(
                           loads=write_loads_csv(folder / "loads.csv", run.models, prov),
                           views=run_views(run)))
    loads = ["loads.csv"] if later["loads"] else []
    load_chart = [p.name for p in charts if p.stem == LOAD_CHART]
    files += [p.name for p in charts if p.stem != LOAD_CHART] + ["report.html"]
    files += loads + load_chart
    summary["files"] = files
    write_summary(folder / "summary.json", summary)
    views, overlay = later["views"]
    view = (view_fragment(views, overlay, lazy=True), overlay.factor if overlay else None) \
        if views else None
    write_report(folder / "report.html", summary, charts, ident, motion, view)
    return summary


def written_config(config: dict, suspension, label: str, folder: Path,
                   fit_again: bool = True) -> dict:
    """A config that ``elastokin identify`` writes into ``folder``: the model's ``label``
    (what ``elastokin kc`` calls the model), the references, and the config's ``kc_test``
    section with its folder as seen from ``folder`` (so that ``elastokin kc`` on it overlays
    the test, as on the config: :func:`~elastokin.config.loading.relocated_folder`).
    ``fit_again`` False: the stiffness fit is switched off (the initial model's config: the
    fit belongs to the identified model; the fitted model's config: its laws are fitted)."""
    out = {"elastokin": config["elastokin"], "name": config["name"], "label": label,
           **{k: v for k, v in config.items() if k not in ("elastokin", "name", "label")}}
    kc_test = suspension.raw.get("kc_test")
    if kc_test is not None:
        kc_test = plain_data(kc_test)
        kc_test["folder"] = relocated_folder(kc_test.get("folder", "."),
                                             Path(suspension.source).parent, folder)
        if not fit_again:
            kc_test.setdefault("stiffness_identification", {})["enabled"] = False
        out["kc_test"] = kc_test
    return out


def _header(s, config_path: Path) -> str:
    prov = config_provenance(s)
    return (f"elastokin {prov['elastokin_version']} (exudyn {prov['exudyn_version']}): "
            f"{{what}} of {config_path} (sha256 {prov['config_sha256'][:12]}).\nUnits: "
            "lengths mm, forces N, torques N*mm, angles deg; config frame.")


def _stiffness_files(folder: Path, start_config: dict, s, fit, where: Path,
                     header: str) -> list[str]:
    """identified_stiffness.yaml (the start model with the fitted laws) and the fit's
    files."""
    from elastokin.identification.stiffness_results import stiffness_config

    write_config(folder / "identified_stiffness.yaml",
                 written_config(stiffness_config(start_config, fit), s,
                                "identified_stiffness", where, fit_again=False),
                 header.format(what="identified model with the bushing laws fitted to the "
                               "K&C test data"))
    return ["identified_stiffness.yaml",
            *write_stiffness_identification(folder, fit, config_provenance(s))]


def write_identification_results(folder: Path, ident, fit, config_path: Path,
                                 final_folder: Path | None = None) -> list[str]:
    """``elastokin identify``'s files: identified.yaml and initial.yaml (configs that
    ``elastokin kc`` loads: :func:`written_config`), identification.json / .txt and, with a
    stiffness ``fit``, identified_stiffness.yaml and stiffness_identification.json / .txt.
    ``final_folder``: where the files end up (the configs' paths are relative to it; default
    ``folder``). Returns the names."""
    s = ident.suspension
    where = final_folder or folder
    header = _header(s, config_path)
    write_config(folder / "identified.yaml",
                 written_config(ident.identified_config, s, "identified", where),
                 header.format(what="identified model (joints from the assembled "
                               "measurement, bushing deflections at equilibrium)"))
    write_config(folder / "initial.yaml", written_config(ident.initial_config, s, "initial",
                                                         where, fit_again=False),
                 header.format(what="initial model (joints from the parts measured alone, "
                               "undeflected bushings)"))
    write_identification(folder, ident, config_provenance(s))
    files = ["identified.yaml", "initial.yaml", "identification.json", "identification.txt"]
    if fit is not None:
        files += _stiffness_files(folder, ident.identified_config, s, fit, where, header)
    return files


def write_motion_results(folder: Path, motion, fit, config_path: Path,
                         final_folder: Path | None = None, ident: dict | None = None
                         ) -> list[str]:
    """``elastokin identify``'s files of the joints from motion: identified_motion.yaml (a
    config ``elastokin kc`` loads, model ``identified_motion``; the stiffness fit switched on
    in it when no part measurements were identified, ``ident`` None) and
    motion_identification.json / .txt; with a stiffness ``fit`` started from it,
    identified_stiffness.yaml and the fit's files. Returns the names."""
    s = motion.suspension
    where = final_folder or folder
    header = _header(s, config_path)
    write_config(folder / "identified_motion.yaml",
                 written_config(motion.config, s, "identified_motion", where,
                                fit_again=ident is None),
                 header.format(what="model identified from the parts' motion (joints from "
                               "the marks at several rig positions, no disassembly)"))
    write_motion_identification(folder, motion, config_provenance(s), ident)
    files = ["identified_motion.yaml", "motion_identification.json",
             "motion_identification.txt"]
    if fit is not None:
        files += _stiffness_files(folder, motion.config, s, fit, where, header)
    return files


def read_kc_csv(path: str | Path) -> list[Sweep]:
    """The sweeps of a ``kc.csv`` (as :func:`write_kc_csv` wrote them): one per model, load
    case and wheel side, in file order, numeric columns as float arrays (NaN where empty).
    Files without a ``side`` column (elastokin before the axle) give sweeps of side ""."""
    path = Path(path)
    lines = [ln for ln in path.read_text().splitlines() if ln and not ln.startswith("#")]
    rows = list(csv.reader(lines))
    header, body = rows[0], rows[1:]
    sided = len(header) > 2 and header[2] == "side"
    first = 5 if sided else 4
    groups: dict[tuple[str, str, str], list[list[str]]] = {}
    for r in body:
        groups.setdefault((r[0], r[1], r[2] if sided else ""), []).append(r)
    sweeps = []
    for (model, case, side), rs in groups.items():
        cols: dict[str, np.ndarray] = {"branch": np.array([r[first - 1] for r in rs])}
        for k, name in enumerate(header[first:], start=first):
            values = [r[k] for r in rs]
            if all(v == "" for v in values):
                continue
            cols[name] = np.array([float(v) if v != "" else np.nan for v in values])
        sweeps.append(Sweep(model, case, cols, side=side))
    return sweeps


def read_results(folder: str | Path) -> tuple[dict, list[Sweep]]:
    """An ``elastokin kc`` results folder: summary.json and the sweeps of kc.csv."""
    folder = Path(folder)
    return json.loads((folder / "summary.json").read_text()), read_kc_csv(folder / "kc.csv")


def write_json(path: Path, doc: dict) -> None:
    """Write JSON atomically (temporary file, then rename)."""
    tmp = path.with_name(f".{path.name}.tmp")
    tmp.write_text(json.dumps(doc, indent=2) + "\n")
    os.replace(tmp, path)


def write_doe_results(out_dir: Path, study, records: list[dict], nominal: dict,
                      solver: dict, run: dict, svg: bool = False) -> dict:
    """A DOE study's doe.json (statistics, sensitivity, warnings, failures, definitions,
    provenance), doe_run.json (where and how long it ran: ``run``) and charts (PNG; with
    ``svg`` also SVG). Returns doe.json's content."""
    from elastokin.report.doe_charts import doe_charts
    from elastokin.studies.doe_runner import STORE
    from elastokin.studies.doe_statistics import DEFINITIONS, aggregate

    body = aggregate(study, records, nominal)
    prov = config_provenance(study.suspension)
    files = [p.name for p in doe_charts(body, records, out_dir, prov, svg)]
    doc = {**prov, "solver": solver, **body,
           "files": ["doe.json", STORE, "doe_run.json", *files], "definitions": DEFINITIONS}
    write_json(out_dir / "doe.json", doc)
    write_json(out_dir / "doe_run.json", {**prov, **run})
    return doc
