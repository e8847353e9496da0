"""Console tables: what ``elastokin kc``, ``identify`` and ``doe`` print (plain text, units in
the headers). No heavy import (no numpy, no matplotlib): the report's other modules take the
summary's axle figures (:func:`axle_models`) and a characteristic's label from here."""

from __future__ import annotations

import math
from pathlib import Path

from elastokin.rig.channels import AXLE_CHARACTERISTICS, CHARACTERISTICS, display_unit


def fixed(value: float, decimals: int) -> str:
    """``value`` with ``decimals`` decimals, without a sign on a value that rounds to 0."""
    return f"{round(value, decimals) + 0.0:.{decimals}f}"


def kc_table(summary: dict, out_dir: Path) -> str:
    """The K&C run's summary: provenance, static bushing table, characteristics, errors and
    the fitted stiffness (its warnings are printed apart, as ``elastokin: warning:`` lines)."""
    lines = [f"elastokin {summary['elastokin_version']} (exudyn {summary['exudyn_version']}), "
             f"config {summary['config_file']} sha256 {summary['config_sha256'][:12]}"
             + (f", rig {summary['rig_file']}" if summary.get("rig_file") else ""), ""]
    st = summary["static"]
    residual = st["wheel_assembly_force_residual_N"]
    lines.append(f"Static equilibrium under {st['wheel_load_N']:g} N wheel load "
                 f"(force residual on the wheel assembly {residual:.1e} N)")
    w = max([10, *(len(n) + 2 for n in st["bushings"])])
    refs = any(b.get("reference") for b in st["bushings"].values())
    if st["bushings"]:
        lines.append(f"  {'bushing':<{w}}{'radial mm':>11}{'axial mm':>10}{'torsion deg':>13}"
                     + (f"   reference {st['reference_source']}" if refs else ""))
    else:
        lines.append("  no bushing (every joint ideal)")
    for name, b in st["bushings"].items():
        ref = b.get("reference", {})
        ref_txt = ", ".join(f"{k} {v:g}" for k, v in ref.items())
        row = (f"  {name:<{w}}{fixed(b['radial_mm'], 3):>11}{fixed(b['axial_mm'], 3):>10}"
               f"{fixed(b['torsion_deg'], 4):>13}")
        lines.append(row + (f"   {ref_txt}" if ref_txt else ""))
    lines.append("")

    def num(v, fmt):
        return "-" if v is None else format(v, fmt)

    errors = summary.get("errors", {})
    head = f"  {'model':<22}{'steer amplitude deg':>21}{'bump steer deg/m':>18}"
    if errors:
        head += f"{'RMS error: steer/travel deg':>29}{'steer/lateral deg':>19}" \
                f"{'long. disp. mm':>16}"
    lines.append(head)
    for label, m in summary["models"].items():
        row = f"  {label:<22}{num(m['steer_amplitude_deg'], '.4f'):>21}" \
              f"{num(m['bump_steer_deg_per_m'], '.3f'):>18}"
        e = errors.get(label)
        if e:
            row += f"{num(e['steer_vs_travel_rms_deg'], '.4f'):>29}" \
                   f"{num(e['steer_vs_lateral_force_rms_deg'], '.4f'):>19}" \
                   f"{num(e['longitudinal_displacement_rms_mm'], '.3f'):>16}"
        lines.append(row)
    refs = {k: v for k, v in summary["reference"]["steer_amplitude_deg"].items()
            if k in summary["models"]}  # the references of the models run only
    if refs:
        lines.append("  reference steer amplitude (deg): "
                     + ", ".join(f"{k} {v:g}" for k, v in refs.items()))
    lines += axle_lines(summary)
    # summary["warnings"] are not repeated here: `elastokin kc` prints each once on stderr
    fit = summary.get("stiffness_identification")
    if fit:
        lines += ["", "Bushing stiffness fitted to the test (model identified_stiffness; "
                  f"details in {fit['file']}):"]
        for key, v in fit["parameters"].items():
            state = "" if v["determined"] else "  not determined"
            lines.append(f"  {key:<26}{v['value']:>10.4g} {v['unit']:<8} 95 % "
                         f"[{v['ci95'][0]:.4g}, {v['ci95'][1]:.4g}]{state}")
    lines.append("")
    if summary.get("reused_from_cache"):
        lines.append("Reused from the previous results (same config, CMM and test files; --refit "
                     "recomputes): " + ", ".join(summary["reused_from_cache"]))
    lines.append(f"Results in {out_dir}/: " + ", ".join(summary["files"]))
    return "\n".join(lines)


#: the axle's figures the K&C table shows (summary.json "axle" has them all): key, label, format
#: (of the figure in the unit the report shows: :func:`~elastokin.rig.channels.display_unit`)
AXLE_FIGURES = (
    ("roll_centre_height_mm", "roll centre height, kinematic mm", ".1f"),
    ("roll_centre_height_force_based_mm", "roll centre height, force-based mm", ".1f"),
    ("roll_stiffness_Nmm_per_deg", "roll stiffness N*m/deg", ".1f"),
    ("anti_roll_bar_share", "anti-roll bar share -", ".3f"),
    ("axle_roll_steer_deg_per_deg", "roll steer deg/deg", ".4f"),
    ("roll_camber_left_deg_per_deg", "roll camber (left) deg/deg", ".4f"),
    ("ride_rate_left_N_per_mm", "ride rate (left) N/mm", ".2f"),
    ("steering_ratio_centre", "steering ratio on centre -", ".2f"),
    ("percent_ackermann_lock", "Ackermann at lock %", ".1f"),
    ("percent_anti_dive", "anti-dive %", ".1f"),
    ("percent_anti_squat", "anti-squat %", ".1f"),
)


def axle_models(summary: dict) -> dict[str, dict]:
    """The models with axle figures: label -> ``models.<label>.axle`` (none on a corner)."""
    return {m: v["axle"] for m, v in summary["models"].items() if v.get("axle")}


def axle_lines(summary: dict) -> list[str]:
    """The axle's key figures, one row each, one column per model (none for a corner)."""
    axles = axle_models(summary)
    if not axles:
        return []
    out = ["", "Axle (both wheels; every figure and its definition: summary.json 'axle', "
           "docs/characteristics.md)",
           f"  {'':<36}" + "".join(f"{label:>22}" for label in axles)]
    for key, label, fmt in AXLE_FIGURES:
        values = [a.get(key) for a in axles.values()]
        if all(v is None for v in values):
            continue
        factor = display_unit(AXLE_CHARACTERISTICS[key].unit)[1]
        cells = ["-" if v is None else format(v * factor, fmt) for v in values]
        out.append(f"  {label:<36}" + "".join(f"{c:>22}" for c in cells))
    return out


#: the reference the identification's equation numbers are those of
PAPER = ("Meissonnier et al. (2006), Geometric identification of an elastokinematic model in "
         "a car suspension, Proc. IMechE Part D 220")


def identification_table(ident) -> str:
    """A readable summary of an identification (plain text); equation numbers are the
    paper's own (:data:`PAPER`)."""
    d = ident.to_json()
    out = [f"Geometric identification of {ident.suspension.name}",
           f"  config {ident.suspension.source}; units mm, deg; config frame",
           "  eq. (n): equation n of the paper, "
           + PAPER.replace(", Geometric", ",\n    Geometric"),
           "", "Part poses from the assembled marks (ordering eqs. (8)-(10), pose fit "
           "eqs. (11)-(12))",
           f"  {'part':<12}{'residual RMS mm':>16}  dropped mark"]
    marks = ident.suspension.measurements.parts
    for p, v in d["parts"].items():
        dropped = "-" if v["dropped_mark"] is None else marks[p].marks[v["dropped_mark"]]
        out.append(f"  {p:<12}{v['residual_rms_mm']:>16.4f}  {dropped}")
    out += ["", "Joints at the loaded state (eq. (19)): shift = identified - initial (housing "
            "centre);",
            "  in clearance = the part of the shift the clearance bounds (bushings: normal to "
            "the housing",
            "  axis), against dL_max (eq. (1)); error = against the synthetic truth when "
            "known",
            f"  {'joint':<12}{'kind':<11}{'shift x':>9}{'y':>8}{'z':>8}{'|shift|':>9}"
            f"{'in clearance':>14}{'dL_max':>8}{'error':>8}"]
    for n, j in d["joints"].items():
        sx, sy, sz = j["shift_mm"]
        dl = "" if j["max_shift_mm"] is None else f"{j['max_shift_mm']:.2f}"
        used = "" if j["max_shift_mm"] is None else f"{j['clearance_shift_mm']:.3f}"
        flag = " !" if j["exceeds_clearance"] else ""
        err = "" if j["error_vs_truth_mm"] is None else f"{j['error_vs_truth_mm']:.3f}"
        out.append(f"  {n:<12}{j['kind']:<11}{sx:>9.3f}{sy:>8.3f}{sz:>8.3f}"
                   f"{math.hypot(sx, sy, sz):>9.3f}{used + flag:>14}{dl:>8}{err:>8}")
    if any(j["exceeds_clearance"] for j in d["joints"].values()):
        out.append("  ! beyond dL_max: see the warnings below")
    out += ["", "Bushing deflections at static equilibrium (eqs. (22)-(23); part 2 rel. part 1, "
            "bushing frame)",
            f"  {'bushing':<10}{'radial mm':>10}{'axial mm':>10}{'torsion deg':>12}"
            f"   B* z-x-z Euler deg (eqs. (20), (26))"]
    for n, j in d["joints"].items():
        if j["deflection_mm_deg"] is not None:
            u = j["deflection_mm_deg"]
            e = ", ".join(f"{a:.2f}" for a in j["euler_zxz_deg"])
            out.append(f"  {n:<10}{math.hypot(u[0], u[1]):>10.3f}{u[2]:>10.3f}{u[5]:>12.4f}"
                       f"   ({e})")
    out += ["", "Verification (the paper's check, its section 5): at the identified model's "
            "static",
            f"  equilibrium the joints are within {d['verification_max_deviation_mm']:.2e} mm "
            "of their measured locations"]
    if d["warnings"]:
        out += ["", "Warnings:"] + [f"  - {w}" for w in d["warnings"]]
    return "\n".join(out) + "\n"


def characteristic_label(name: str) -> str:
    """A characteristic's label and unit from the channel table (units as in summary.json;
    the name itself when the table has none): a DOE table's row, a DOE chart's axis."""
    c = CHARACTERISTICS.get(name)
    return name if c is None else f"{c.label} [{c.unit}]"


def doe_table(doc: dict, out_dir: Path) -> str:
    """A DOE study's characteristics (nominal, mean, std, p05, p95) and sensitivity."""
    s = doc["steer_amplitude_deg"]
    lines = [f"DOE of {doc['config_file']}: {doc['samples']} samples ({doc['method']}, seed "
             f"{doc['seed']}, load cases {doc['load_cases']}), {doc['failed']} failed", ""]
    lines.append(f"  {'characteristic':<48}{'nominal':>10}{'mean':>10}{'std':>10}"
                 f"{'p05':>10}{'p95':>10}")
    nominal = doc.get("nominal") or {}

    def num(x):
        return f"{x:>10.4g}" if x is not None else f"{'-':>10}"

    for name, st in doc["characteristics"].items():
        lines.append(f"  {characteristic_label(name):<48}{num(nominal.get(name))}"
                     f"{num(st['mean'])}{num(st['std'])}{num(st['p05'])}{num(st['p95'])}")
    sens = {k: v for k, v in doc["sensitivity"].items() if v is not None}
    if sens and s["n"]:
        ranked = sorted(sens, key=lambda k: -sens[k])
        what = ("share of the variance" if doc["sensitivity_method"] == "src"
                else "R^2 per joint, not shares: see the warning")
        lines += ["", f"  steer-amplitude sensitivity ({what}): "
                  + ", ".join(f"{k} {sens[k]:.2f}" for k in ranked)]
    lines += ["", f"Results in {out_dir}/: " + ", ".join(doc["files"])]
    return "\n".join(lines)


def motion_table(doc: dict) -> str:
    """A readable summary of the joints located from the motion (``motion_identification.
    json``'s content): per joint its method, location, uncertainty (1 sigma from the CMM
    noise), fit residual and, on synthetic data, its error against the truth and the
    disassembly method's."""
    positions = doc["positions"]
    out = [f"Joints from motion ({len(positions)} rig positions, design position "
           f"'{doc['design_position']}'); units mm, deg; config frame at the design position",
           f"  CMM noise from the pose fits: sigma {doc['noise_sigma_mm']:.4f} mm per "
           f"coordinate ({doc['noise_dof']} degrees of freedom)",
           "  uncertainty: 1-sigma 3-D RMS of the point (worst direction), from that noise; "
           "residual: how far",
           "  the two bodies' points part over the positions; error: against the synthetic "
           "truth (an axis",
           "  joint's across the true axis), beside the disassembly method's (the paper's) "
           "when both ran",
           f"  {'joint':<12}{'method':<20}{'x':>9}{'y':>9}{'z':>9}{'uncert.':>9}{'(worst)':>8}"
           f"{'residual':>9}{'error':>8}{'disass.':>8}{'axis deg':>9}{'err deg':>8}"]

    def f(v, fmt):
        return "" if v is None else format(v, fmt)

    for name, j in doc["joints"].items():
        x = j["located_mm"] or [math.nan] * 3
        cells = "" if j["located_mm"] is None else f"{x[0]:>9.2f}{x[1]:>9.2f}{x[2]:>9.2f}"
        out.append(f"  {name:<12}{j['method']:<20}{cells:>27}{f(j['uncertainty_mm'], '.3f'):>9}"
                   f"{f(j['worst_std_mm'], '.3f'):>8}{f(j['residual_rms_mm'], '.3f'):>9}"
                   f"{f(j['error_vs_truth_mm'], '.3f'):>8}"
                   f"{f(j.get('disassembly_error_vs_truth_mm'), '.3f'):>8}"
                   f"{f(j['axis_uncertainty_deg'], '.3f'):>9}{f(j['axis_error_deg'], '.3f'):>8}")
    if doc["dropped_marks"]:
        out += ["", "Wrong marks dropped (poses fitted to the other three):"]
        out += [f"  {d['body']} at position '{d['position']}': mark '{d['mark']}'"
                for d in doc["dropped_marks"]]
    if doc["warnings"]:
        out += ["", "Warnings:"] + [f"  - {w}" for w in doc["warnings"]]
    return "\n".join(out) + "\n"


def design_table(result) -> str:
    """A design study's outcome: each variable's move, each target before and after, and
    what binds when the targets cannot all be met."""
    lines = [("Every target met" if result.met else
              "The targets cannot all be met: the best point found is written")
             + f" (model {result.label}, {result.model_runs} model runs with derivatives, "
             f"{result.seconds:.1f} s; optimiser: {result.message})", "",
             f"  {'variable':<36}{'start':>12}{'optimised':>12}{'moved':>10}  unit"]
    for v, a, b in zip(result.variables, result.start.values, result.best.values):
        lines.append(f"  {v.name:<36}{a:>12.4f}{b:>12.4f}{b - a:>+10.4f}  {v.unit}")
    lines += ["", f"  {'target':<36}{'start':>12}{'optimised':>12}  asked"]
    for a, b in zip(result.start_values.rows, result.best_values.rows):
        mark = "" if b.met else f"  MISSED by {b.miss:.3g}"
        lines.append(f"  {a.name:<36}{a.value:>12.5g}{b.value:>12.5g}  {b.asked} "
                     f"{b.unit}{mark}")
    if result.binding:
        lines += ["", "What binds:"] + [f"  - {b}" for b in result.binding]
    return "\n".join(lines)


def sensitivity_text(tab, top: int = 5) -> str:
    """The largest effects per mm of a hardpoint sensitivity table, per characteristic."""
    lines = [f"Hardpoint sensitivity, model {tab.label}: {len(tab.variables)} coordinates, "
             f"{len(tab.characteristics)} characteristics ({tab.seconds:.1f} s); the {top} "
             "largest effects per mm:"]
    for j, name in enumerate(tab.characteristics):
        ranked = ", ".join(f"{v.name} {e:+.3g}" for v, e in tab.ranked(name)[:top])
        lines.append(f"  {name} ({tab.values[j]:.4g}): {ranked}")
    return "\n".join(lines)
