"""``report.html``: one self-contained page (charts embedded as PNG data, a few lines of inline
script to enlarge them, nothing fetched) that reads like a K&C report: a section per stage of
the run (geometric identification, static state, K&C characteristics with the charts, errors
against the test, stiffness fit), the sign conventions, and the provenance of every number as a
short table (versions, hashes of the config, rig and test files, solver settings once).

Everything comes from ``summary.json``'s content and, with CMM measurements, from
``identification.json``'s (:func:`elastokin.report.files.identification_dict`). Section ids
(:data:`SECTIONS`) are stable: tests and links use them.
"""

from __future__ import annotations

from pathlib import Path

from elastokin.report.axle_charts import AXLE_CHARTS
from elastokin.report.charts import CHARTS, chart_caption
from elastokin.report.html.axle import axle_section
from elastokin.report.html.loads import loads_section
from elastokin.report.html.motion import motion_section
from elastokin.report.html.parts import esc, figure, note, num, page, table
from elastokin.report.load_charts import LOAD_CHART
from elastokin.report.text import fixed
from elastokin.rig.channels import CHANNELS, CHARACTERISTIC_LIST, ERROR_LIST, channel

#: the sections of the report, in order: (id, heading); a section without data is left out
SECTIONS = (
    ("summary", "Summary"),
    ("warnings", "Warnings"),
    ("view", "3D view"),
    ("identification", "Geometric identification"),
    ("motion", "Joints from motion"),
    ("static", "Static state"),
    ("characteristics", "K&C characteristics"),
    ("charts", "Charts"),
    ("axle", "Axle"),
    ("loads", "Loads"),
    ("errors", "Errors against the test"),
    ("stiffness", "Bushing-stiffness identification"),
    ("signs", "Sign conventions"),
    ("provenance", "Provenance"),
)
HEADINGS = dict(SECTIONS)
PAPER = "Meissonnier et al. (2006), Proc. IMechE Part D 220"

#: the channels whose signs the report states (those its tables and charts show)
SIGNED = ("toe_deg", "camber_deg", "wheel_travel_mm", "wheel_centre_longitudinal_mm",
          "wheel_centre_lateral_mm", "vertical_force_N", "lateral_force_N",
          "longitudinal_force_N", "aligning_torque_Nmm", "caster_deg",
          "kingpin_inclination_deg", "scrub_radius_mm", "caster_trail_mm")

# ------------------------------------------------------------------------------ sections
def summary_section(summary: dict) -> list[str]:
    """The run in a few lines: the models, the steer amplitude against the paper's, the Fig. 9
    errors, and what follows."""
    models = list(summary["models"])
    refs = summary.get("reference", {}).get("steer_amplitude_deg", {}) or {}
    errors = summary.get("errors") or {}
    rows = [["steer amplitude over the travel stroke [deg] (Fig. 9a)",
             *(num(summary["models"][m].get("steer_amplitude_deg"), ".3f") for m in models)]]
    if any(m in refs for m in models):
        source = esc(summary["static"].get("reference_source", ""))
        rows.append([f"reference steer amplitude [deg] ({source})",
                     *(num(refs.get(m), "g") for m in models)])
    for e in ERROR_LIST if errors else ():
        rows.append([f"RMS error, {esc(e.label)} [{e.unit}]",
                     *(num((errors.get(m) or {}).get(e.name), e.fmt) for m in models)])
    meaning = [[f"<b>{esc(m)}</b>", esc(model_meaning(m, "identified" in models))]
               for m in models]
    return [table(["model", "what it is"], meaning, text_columns=(1,)),
            note("Units mm, N, deg; torques N&middot;m in the charts (N&middot;mm in the "
                 'files); signs ISO 8855 (<a href="#signs">sign conventions</a>).'),
            table(["", *models], rows)]


def model_meaning(label: str, measured: bool) -> str:
    """What a model of a K&C run is, for the report's reader."""
    known = {
        "test": "the K&C rig test data (the config's kc_test files)",
        "initial": ("joints at the housing centres of the parts measured alone, bushings "
                    "undeflected (the paper's initial model)" if measured
                    else "the config's geometry"),
        "identified": "joints where the assembled measurement puts them, each bushing "
                      "deflected as at the static equilibrium (the paper's identified model)",
        "identified_motion": "joints where the parts' motion over the rig positions locates "
                             "them (no disassembly: SCoRE, SARA), bushings where the config "
                             "puts them",
        "identified_stiffness": "the identified model with its bushing laws fitted to the "
                                "test data",
    }
    if label in known:
        return known[label]
    if label.endswith("_kinematic"):
        return f"{label.removesuffix('_kinematic')} with every bushing replaced by its ideal joint"
    return "the config's geometry (its label)"


def warnings_section(summary: dict) -> list[str]:
    return ["<ul>" + "".join(f"<li>{esc(w)}</li>" for w in summary["warnings"]) + "</ul>"]


def _pose_rows(ident: dict) -> list[list[str]]:
    rows = []
    for part, p in ident["parts"].items():
        dropped = p.get("dropped_mark_label") or ("&ndash;" if p["dropped_mark"] is None
                                                  else str(p["dropped_mark"]))
        marks = "4" if p["dropped_mark"] is None else "3"
        rows.append([esc(part), f"{p['residual_rms_mm']:.4f}", marks,
                     f'<span class="bad">{esc(dropped)}</span>'
                     if p["dropped_mark"] is not None else dropped])
    return rows


def _joint_rows(ident: dict) -> tuple[list[list[str]], list[str]]:
    rows, classes = [], []
    for name, j in ident["joints"].items():
        sx, sy, sz = j["shift_mm"]
        bounded = j.get("max_shift_mm") is not None
        flag = bool(j.get("exceeds_clearance"))
        status = ('<span class="bad">beyond dL<sub>max</sub></span>' if flag
                  else "within" if bounded else "&ndash;")
        rows.append([esc(name), esc(j["kind"]), f"{sx:.3f}", f"{sy:.3f}", f"{sz:.3f}",
                     f"{(sx * sx + sy * sy + sz * sz) ** 0.5:.3f}",
                     num(j.get("clearance_shift_mm") if bounded else None, ".3f"),
                     num(j.get("max_shift_mm"), ".3f"), status,
                     num(j.get("error_vs_truth_mm"), ".3f")])
        classes.append("flag" if flag else "")
    return rows, classes


def identification_section(ident: dict) -> list[str]:
    """Part poses, joint shifts against dL_max, bushing deflections and the verification,
    equation numbers of the paper."""
    out = [note(f"The paper's method ({esc(PAPER)}; &ldquo;eq. (n)&rdquo; is its equation n): "
                "each part measured alone on the CMM, its 4 marks measured again on the "
                "assembled suspension under the wheel load, ordered by their distances "
                "(eqs. (8)&ndash;(10)) and fitted (eqs. (11)&ndash;(12)); every joint in the "
                "vehicle frame (eq. (19)). The <b>initial</b> model puts a bolted joint at its "
                "housing centre, the <b>identified</b> model where the assembly puts it, with "
                "each bushing deflected as at the static equilibrium (eqs. (22)&ndash;(26))."),
           "<h3>Part poses from the assembled marks</h3>",
           table(["part", "pose residual RMS mm", "marks used", "dropped (wrong) mark"],
                 _pose_rows(ident))]
    rows, classes = _joint_rows(ident)
    out += ["<h3>Joints: identified &minus; initial (housing centre)</h3>",
            note("Shift in the vehicle frame at the loaded state. <i>In clearance</i>: the part "
                 "of the shift the assembly clearance bounds (a bushing: normal to its housing "
                 "axis), against dL<sub>max</sub> = hole/2 &minus; bolt + bore/2 (eq. (1)). "
                 "<i>Error</i>: against the synthetic truth, when known."),
            table(["joint", "kind", "shift x mm", "y mm", "z mm", "|shift| mm",
                   "in clearance mm", "dL_max mm", "", "error mm"], rows, classes, (1, 8))]
    rows = []
    for name, j in ident["joints"].items():
        u = j.get("deflection_mm_deg")
        if u is not None:
            rows.append([esc(name), f"{(u[0] ** 2 + u[1] ** 2) ** 0.5:.3f}", f"{u[2]:.3f}",
                         f"{u[5]:.4f}", ", ".join(f"{a:.2f}" for a in j["euler_zxz_deg"])])
    if rows:
        out += ["<h3>Identified bushing deflections at the static equilibrium</h3>",
                note("Part 2 relative to part 1, bushing frame (eqs. (22)&ndash;(23)); "
                     "B*: the inner-sleeve frame (eq. (26)) as z-x-z Euler angles "
                     "(eq. (20))."),
                table(["bushing", "radial mm", "axial mm", "torsion deg",
                       "B* z-x-z Euler deg"], rows)]
    dev = ident.get("verification_max_deviation_mm")
    out += ["<h3>Verification</h3>",
            f"<p>The paper's check (its section 5): at the identified model's static "
            f"equilibrium under the wheel load every joint lies within <b>{num(dev, '.2e')} "
            "mm</b> of its measured location.</p>"]
    return out


def static_section(summary: dict) -> list[str]:
    """The static equilibrium under the design wheel load: forces, wheel centre, bushing
    deflections against the paper's Table 3."""
    st = summary["static"]
    springs = ", ".join(f"{esc(k)} {v:.1f} N" for k, v in st["spring_force_N"].items())
    x, y, z = st["wheel_centre_mm"]
    fx, fy, fz = st["contact_patch_force_N"]
    out = [table(["quantity", "value"], [
        ["wheel load [N]", f"{st['wheel_load_N']:g}"],
        ["wheel centre x, y, z [mm] (config frame)", f"{x:.3f}, {y:.3f}, {z:.3f}"],
        ["contact-patch force x, y, z [N]", f"{fx:.1f}, {fy:.1f}, {fz:.1f}"],
        ["spring force [N] (+ compression)", springs or "&ndash;"],
        ["force residual on the wheel assembly [N]",
         f"{st['wheel_assembly_force_residual_N']:.1e}"]], text_columns=(1,))]
    refs = any(b.get("reference") for b in st["bushings"].values())
    rows = [[esc(n), fixed(b["radial_mm"], 3), fixed(b["axial_mm"], 3),
             fixed(b["torsion_deg"], 4)]
            + ([esc(", ".join(f"{k} {v:g}" for k, v in b.get("reference", {}).items()))]
               if refs else [])
            for n, b in st["bushings"].items()]
    if rows:
        source = st.get("reference_source") if refs else None
        out += ["<h3>Bushing deflections</h3>",
                note("Part 2 relative to part 1, bushing frame, the design preload included"
                     + (f"; reference: {esc(source)}." if source else ".")),
                table(["bushing", "radial mm", "axial mm", "torsion deg"]
                      + (["reference"] if refs else []), rows,
                      text_columns=(4,) if refs else ())]
    return out


def characteristics_section(summary: dict) -> list[str]:
    models = summary["models"]
    rows = [[f'<span title="{esc(c.definition)}">{esc(c.label)} [{c.unit}]</span>',
             *(num(models[m].get(c.name), c.fmt) for m in models)]
            for c in CHARACTERISTIC_LIST]
    ratios = dict.fromkeys(k for m in models.values() for k in m.get("motion_ratios") or {})
    rows += [[f'<span title="{esc(channel(k).sign)}; at the static state">'
              f"{esc(channel(k).label.split(' [')[0])} [-]</span>",
              *(num((models[m].get("motion_ratios") or {}).get(k), ".4f") for m in models)]
             for k in ratios]
    return [note("Gradients are least-squares slopes over the measured rows of each load case "
                 '(definitions in <a href="#signs">sign conventions</a>); steering-axis '
                 "figures at the static state."), table(["characteristic", *models], rows)]


def charts_section(charts: list[Path], with_test: bool, axle_side: str | None = None
                   ) -> list[str]:
    """The corner's charts (on an axle: the config side's wheel ``axle_side``), each with its
    caption."""
    wheel = (f" On this axle they show the config's ({esc(axle_side)}) wheel; both wheels "
             'and the axle\'s own charts are in the <a href="#axle">Axle</a> section.'
             if axle_side else "")
    out = [note("Click a chart to enlarge it (Escape or a click closes it)." + wheel)]
    for k, path in enumerate(p for p in charts if p.suffix == ".png"):
        spec = CHARTS.get(path.stem)
        out.append(figure(path, spec.title if spec is not None else path.stem, k + 1,
                          chart_caption(spec, with_test) if spec is not None else ""))
    return out


def view_section(fragment: str, factor: float | None) -> list[str]:
    """The interactive 3D view (:mod:`elastokin.report.view3d`) and how to read it."""
    ident = (f" The design position also shows the geometric identification: each part's CMM "
             f"marks (fitted &#9675; and measured &times;, the residual magnified "
             f"&times;{factor:g}) and each joint's shift from its initial to its identified "
             f"location (magnified &times;{factor:g})." if factor else "")
    return [note("Pick a model and a load case; drag the slider or press play. Drag to turn "
                 "the view, scroll to zoom, or pick a view (3D, front, side, top); click a "
                 "legend entry to hide it or to overlay another model's outline. One colour "
                 "per part (its sticks join its points, its hull is shaded); bushings are "
                 "coloured by their deflection (mm, scale at the bottom left) with their "
                 "frames (x red, y green, z blue); stops turn red in contact; the steering "
                 "axes are dashed, the front-view instant centres (+) and the roll centre "
                 "(&#9670;) are joined to the contact patches. The arrows are the load each "
                 "body pickup receives (from the pickup, along the force on the body) and the "
                 "rig's load on each tyre (from the contact patch), at the scale the legend "
                 "states: the values of loads.csv at that step; \"worst case of\" goes to a "
                 "pickup's largest load. A flexible beam is drawn through its nodes as solved, "
                 "with a band from its node line to its shear centre that turns with its "
                 "section (its twist magnified as the legend states). The tyre's width is "
                 "drawn 0.7 times its loaded radius (a config gives none). Works offline "
                 "(plotly.js is in the page; docs/view.md)." + ident), fragment]


def errors_section(summary: dict) -> list[str]:
    errors = summary["errors"]
    labels = list(errors)
    rows = [[f"{esc(e.label)} [{e.unit}]", *(num(errors[m].get(e.name), e.fmt)
                                              for m in labels)] for e in ERROR_LIST]
    return [note("RMS over the test points of the model's change from its static state minus "
                 "the test's, branch by branch (loading and unloading apart), the model "
                 "interpolated at the test inputs. The residual panels of the charts show the "
                 "differences."), table(["RMS error", *labels], rows)]


def stiffness_section(fit: dict) -> list[str]:
    rows = [[esc(k), f"{v['value']:.4g}", esc(v["unit"]),
             f"[{v['ci95'][0]:.4g}, {v['ci95'][1]:.4g}]",
             "yes" if v["determined"] else '<span class="bad">no</span>']
            for k, v in fit["parameters"].items()]
    out = [note("Model <b>identified_stiffness</b>: per fitted bushing F(u) = scale &middot; "
                "f<sub>config</sub>(u) &middot; (1 + cubic &middot; u&sup2;), fitted to the test "
                "data (method, correlations and residuals in "
                f"<code>{esc(fit.get('file', ''))}</code>). Condition number "
                f"{num(fit.get('condition_number'), '.3g')}."),
           table(["parameter", "value", "unit", "95 % interval", "determined"], rows,
                 text_columns=(2,))]
    if fit.get("warnings"):
        out.append("<ul>" + "".join(f"<li>{esc(w)}</li>" for w in fit["warnings"]) + "</ul>")
    return out


def signs_section(summary: dict) -> list[str]:
    signs = summary.get("sign_conventions", {})
    rows = [["frame", esc(signs.get("frame", ""))]]
    rows += [[f"{esc(channel(c).label)}", esc(CHANNELS[c].sign)] for c in SIGNED]
    rows += [["bushing deflection", esc(signs.get("bushing_*", ""))],
             ["spring force", esc(signs.get("spring_*_force_N", ""))]]
    rows += [["loads (loads.csv)", esc(v)] for k, v in signs.items() if "loads.csv" in k]
    definitions = [[f"{esc(c.label)} [{c.unit}]", esc(c.definition)]
                   for c in CHARACTERISTIC_LIST]
    return [note("ISO 8855 / SAE J670 names; per wheel for the wheel angles. Every column of "
                 "kc.csv is listed in summary.json <code>sign_conventions</code>."),
            table(["quantity", "sign"], rows, text_columns=(1,)),
            "<h3>Characteristics</h3>",
            table(["characteristic", "definition"], definitions, text_columns=(1,))]


def solver_rows(solver: dict) -> list[list[str]]:
    """Solver settings once: the settings every model shares, then what differs per model
    (the test's entry is its data source, listed with the inputs)."""
    models = {k: v for k, v in solver.items() if k != "test" and isinstance(v, dict)}
    if not models:
        return []
    keys = list(dict.fromkeys(k for v in models.values() for k in v))
    rows = []
    for k in keys:
        values = {m: v.get(k) for m, v in models.items()}
        if len({repr(x) for x in values.values()}) == 1:
            rows.append([esc(k), esc(next(iter(values.values())))])
        else:
            rows.append([esc(k), esc(", ".join(f"{m}: {x}" for m, x in values.items()))])
    return rows


def provenance_section(summary: dict) -> list[str]:
    rows = [["elastokin", esc(summary["elastokin_version"])],
            ["Exudyn", esc(summary["exudyn_version"])],
            ["units", "mm, N, N&middot;mm, deg (charts: torque in N&middot;m)"]]
    files = summary.get("input_files") or [
        {"role": "config", "file": summary["config_file"], "sha256": summary["config_sha256"]}]
    if not summary.get("rig_file"):
        rows.append(["rig", "the config's <code>rig</code> section"])
    file_rows = [[esc(f["role"]), f"<code>{esc(f['file'])}</code>",
                  f"<code>{esc(f['sha256'] or 'missing')}</code>"] for f in files]
    return [table(None, rows, text_columns=(1,)),
            "<h3>Input files</h3>",
            table(["input", "file", "SHA-256"], file_rows, text_columns=(1, 2)),
            "<h3>Solver settings</h3>",
            table(["setting", "value"], solver_rows(summary.get("solver", {})),
                  text_columns=(1,)),
            note("The same in summary.json (<code>solver</code>, <code>input_files</code>); "
                 "versions and hashes also in the header of kc.csv and in every chart's "
                 "footer.")]


# ------------------------------------------------------------------------------ the page
def report_sections(summary: dict, charts: list[Path], identification: dict | None = None,
                    motion: dict | None = None,
                    view: tuple[str, float | None] | None = None
                    ) -> list[tuple[str, list[str]]]:
    """(section id, body) of every section that has data, in :data:`SECTIONS` order."""
    with_test = "test" in summary["models"]
    axle_charts = [p for p in charts if p.stem in AXLE_CHARTS]
    load_charts = [p for p in charts if p.stem == LOAD_CHART]
    charts = [p for p in charts if p.stem not in AXLE_CHARTS and p.stem != LOAD_CHART]
    first = 1 + sum(p.suffix == ".png" for p in charts)
    after_axle = first + sum(p.suffix == ".png" for p in axle_charts)
    loads = any(m.get("loads") for m in summary["models"].values())
    parts = {"summary": summary_section(summary),
             "warnings": warnings_section(summary) if summary.get("warnings") else None,
             "view": view_section(*view) if view else None,
             "identification": (identification_section(identification)
                                if identification else None),
             "motion": motion_section(motion) if motion else None,
             "static": static_section(summary),
             "characteristics": characteristics_section(summary),
             "charts": (charts_section(charts, with_test,
                                       (summary.get("axle") or {}).get("config_side"))
                        if charts else None),
             "axle": (axle_section(summary, axle_charts, first) if summary.get("axle")
                      else None),
             "loads": loads_section(summary, load_charts, after_axle) if loads else None,
             "errors": errors_section(summary) if summary.get("errors") else None,
             "stiffness": (stiffness_section(summary["stiffness_identification"])
                           if summary.get("stiffness_identification") else None),
             "signs": signs_section(summary),
             "provenance": provenance_section(summary)}
    return [(key, parts[key]) for key, _ in SECTIONS if parts[key] is not None]


def write_report(path: Path, summary: dict, charts: list[Path],
                 identification: dict | None = None, motion: dict | None = None,
                 view: tuple[str, float | None] | None = None) -> Path:
    """Write ``report.html`` from ``summary.json``'s content, the PNG charts, (with
    measurements) ``identification.json``'s and (with a motion plan)
    ``motion_identification.json``'s content, and the 3D view (its HTML fragment and the
    identification's magnification, :func:`view_section`)."""
    sections = report_sections(summary, charts, identification, motion, view)
    title = f"K&C report: {summary.get('config_name') or summary['config_file']}"
    intro = [note(f"Config <code>{esc(summary['config_file'])}</code>"
                  + (f", rig file <code>{esc(summary['rig_file'])}</code>"
                     if summary.get("rig_file") else "")
                  + f"; elastokin {esc(summary['elastokin_version'])}, Exudyn "
                  f"{esc(summary['exudyn_version'])}.")]
    if summary.get("test_data_synthetic"):
        intro.append('<p class="synthetic"><b>The test data are synthetic</b>: the K&amp;C '
                     "test files (and the CMM files) of this case study were made by <code>"
                     "elastokin synthesize</code> from the config; the paper's measurements "
                     "are not public (README, &ldquo;Case study data&rdquo;).</p>")
    path.write_text(page(title, intro, [(key, HEADINGS[key], parts)
                                        for key, parts in sections]), encoding="utf-8")
    return path
