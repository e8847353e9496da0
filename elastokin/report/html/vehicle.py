"""The whole car's ``report.html``: one self-contained page (charts embedded) that reads like
a full-vehicle K&C report: the car and its axles, the warnings, the car's figures front, rear
and car side by side per car model, the charts, every axle characteristic of both axles side
by side, the definitions and the provenance. Each axle's own report is in its sub-folder
(linked). Everything comes from the car's and the axles' summary.json contents.
"""

from __future__ import annotations

from pathlib import Path

from elastokin.report.html.page import solver_rows
from elastokin.report.html.parts import esc, figure, note, num, page, table
from elastokin.report.vehicle_charts import VEHICLE_CHARTS
from elastokin.report.vehicle_text import car_rows
from elastokin.rig.channels import (
    AXLE_CHARACTERISTIC_LIST,
    CHARACTERISTIC_LIST,
    display_unit,
)
from elastokin.rig.vehicle_channels import (
    AXLE_IN_CAR_LIST,
    CAR_CHANNEL_LIST,
    CAR_CHARACTERISTIC_LIST,
)

ROLES = ("front", "rear")
#: the report's sections: (id, heading)
SECTIONS = (("summary", "The car"), ("warnings", "Warnings"),
            ("car", "The car on the rig"), ("charts", "Charts"),
            ("axles", "The axles side by side"), ("definitions", "Definitions and signs"),
            ("provenance", "Provenance"))


def summary_section(summary: dict) -> list[str]:
    """The vehicle's data, its axles (with links to their reports) and the car's models."""
    v = summary["vehicle"]
    roll = v["body_roll"]
    data = [["wheelbase", f"{v['wheelbase_mm']:g} mm"],
            ["CG height above the ground", f"{v['cg_height_mm']:g} mm"],
            ["mass (front / rear axle)", f"{v['mass_kg']:.1f} kg ({v['axle_mass_kg']['front']:g}"
             f" / {v['axle_mass_kg']['rear']:g} kg, {100 * v['front_mass_fraction']:.1f} % "
             "front)"],
            ["CG behind the front axle", f"{v['cg_behind_front_axle_mm']:.1f} mm"],
            ["front axle's share of braking / of drive",
             f"{v['brake_fraction_front']:g} / {v['drive_fraction_front']:g}"],
            ["body roll on the table", f"0 &rarr; {roll['amplitude_deg']:g} &rarr; "
             f"&minus;{roll['amplitude_deg']:g} &rarr; 0 deg in {roll['step_deg']:g} deg steps, "
             "each axle at its load"]]
    axles = [[role, f"<code>{esc(a['config_file'])}</code>", esc(a["name"]),
              f"{a['track_mm']:.0f}", f"{a['design_wheel_load_N']:g}",
              f'<a href="{esc(a["results"])}/report.html">{esc(a["results"])}/</a>',
              esc(", ".join(a["models"]))] for role, a in summary["axles"].items()]
    pairs = [[f"<b>{esc(label)}</b>", esc(m["front_model"]), esc(m["rear_model"])]
             for label, m in summary["models"].items()]
    return [table(None, data, text_columns=(1,)),
            note("One set of vehicle data for both axles: it replaces each axle config's own "
                 "<code>axle.vehicle</code> (summary.json <code>axles.*.axle_vehicle</code>: "
                 "what each ran with)."),
            "<h3>Axles</h3>",
            table(["axle", "config", "name", "track mm", "design wheel load N", "results",
                   "models"], axles, text_columns=(1, 2, 5, 6)),
            "<h3>Car models</h3>",
            table(["car model", "front axle's model", "rear axle's model"], pairs,
                  text_columns=(1, 2))]


def car_section(summary: dict) -> list[str]:
    """Per car model the car's table: front, rear and car side by side."""
    out = [note("Front and rear side by side, the car's figure where it needs both axles; "
                "definitions in <a href=\"#definitions\">Definitions</a> and "
                "docs/characteristics.md &ldquo;Whole car&rdquo;. A dash: not determined "
                "(e.g. no compliance on a kinematic model).")]
    for label, m in summary["models"].items():
        rows = [[esc(row.label), esc(row.unit), *cells] for row, cells in car_rows(m)]
        out += [f"<h3>Model {esc(label)}</h3>",
                table(["figure", "unit", "front", "rear", "car"], rows, text_columns=(1,))]
    return out


def charts_section(charts: list[Path]) -> list[str]:
    return [figure(p, VEHICLE_CHARTS[p.stem][0], k + 1, VEHICLE_CHARTS[p.stem][1])
            for k, p in enumerate(p for p in charts if p.suffix == ".png")]


def _axle_value(axle_summary: dict, label: str, key: str, wheel: bool):
    m = axle_summary["models"].get(label, {})
    if wheel:  # the left wheel's
        left = m if axle_summary["axle"]["config_side"] == "left" else m.get("left", {})
        return left.get(key)
    return (m.get("axle") or {}).get(key)


def axles_section(summary: dict, axles: dict[str, dict]) -> list[str]:
    """Every characteristic of both axles (the left wheel's for a wheel's), front and rear
    side by side, per car model."""
    out = [note("Each axle's own figures from its summary.json (the axle's, then its left "
                "wheel's); its report has every chart and the right wheel: "
                + ", ".join(f'<a href="{r}/report.html">{r}/report.html</a>' for r in ROLES)
                + ".")]
    items = [(c, False) for c in AXLE_CHARACTERISTIC_LIST] + \
        [(c, True) for c in CHARACTERISTIC_LIST]
    for label, m in summary["models"].items():
        rows = []
        for c, wheel in items:
            values = [_axle_value(axles[role], m[f"{role}_model"], c.name, wheel)
                      for role in ROLES]
            if all(v is None for v in values):
                continue
            unit, factor = display_unit(c.unit)
            rows.append([esc(c.label), esc(unit),
                         *(num(None if v is None else v * factor, c.fmt) for v in values)])
        out += [f"<h3>Model {esc(label)} (front {esc(m['front_model'])}, rear "
                f"{esc(m['rear_model'])})</h3>",
                table(["characteristic", "unit", "front", "rear"], rows, text_columns=(1,))]
    return out


def definitions_section() -> list[str]:
    rows = [[f"<code>{esc(c.name)}</code>", esc(c.unit), esc(c.sign)] for c in CAR_CHANNEL_LIST]
    figs = [[f"<code>car.{esc(c.name)}</code>", esc(c.unit), esc(c.definition)]
            for c in CAR_CHARACTERISTIC_LIST]
    figs += [[f"<code>front/rear.{esc(c.name)}</code>", esc(c.unit), esc(c.definition)]
             for c in AXLE_IN_CAR_LIST]
    return [note("ISO 8855: x forward, y left, z up; steer + to the left, body roll + when "
                 "the left side rises (as in a left turn), pitch + nose down; an understeer "
                 "gradient in deg of road-wheel steer per g of lateral acceleration, + "
                 "understeer (SAE J670). The axles' own figures keep their definitions (each "
                 "axle's report, &ldquo;Sign conventions&rdquo;)."),
            "<h3>car.csv (the table's body roll)</h3>",
            table(["column", "unit", "sign"], rows, text_columns=(2,)),
            "<h3>Figures</h3>",
            table(["summary.json key", "unit", "definition"], figs, text_columns=(2,))]


def provenance_section(summary: dict) -> list[str]:
    rows = [["elastokin", esc(summary["elastokin_version"])],
            ["Exudyn", esc(summary["exudyn_version"])],
            ["units", "mm, N, N&middot;mm, deg, kg (charts: torque in N&middot;m)"],
            ["rig", f"<code>{esc(summary['rig_file'])}</code>" if summary.get("rig_file")
             else "each axle config's <code>rig</code> section, the body roll the vehicle's"]]
    files = [[esc(f["role"]), f"<code>{esc(f['file'])}</code>",
              f"<code>{esc(f['sha256'] or 'missing')}</code>"] for f in summary["input_files"]]
    out = [table(None, rows, text_columns=(1,)), "<h3>Input files</h3>",
           table(["input", "file", "SHA-256"], files, text_columns=(1, 2))]
    for role in ROLES:
        out += [f"<h3>Solver settings, {role} axle</h3>",
                table(["setting", "value"], solver_rows(summary["solver"][role]),
                      text_columns=(1,))]
    return out


def write_vehicle_report(path: Path, summary: dict, charts: list[Path],
                         axles: dict[str, dict]) -> Path:
    """Write the car's ``report.html`` from its summary.json content, its PNG charts and
    each axle's summary.json content (``axles``: by role)."""
    parts = {"summary": summary_section(summary),
             "warnings": ([note("Each once, as in summary.json <code>warnings</code>."),
                           "<ul>" + "".join(f"<li>{esc(w)}</li>" for w in summary["warnings"])
                           + "</ul>"] if summary["warnings"] else None),
             "car": car_section(summary),
             "charts": charts_section(charts) if charts else None,
             "axles": axles_section(summary, axles),
             "definitions": definitions_section(),
             "provenance": provenance_section(summary)}
    intro = [note(f"Vehicle file <code>{esc(summary['vehicle_file'])}</code>; front axle "
                  f"<code>{esc(summary['axles']['front']['config_file'])}</code>, rear axle "
                  f"<code>{esc(summary['axles']['rear']['config_file'])}</code>; elastokin "
                  f"{esc(summary['elastokin_version'])}, Exudyn "
                  f"{esc(summary['exudyn_version'])}.")]
    sections = [(key, heading, parts[key]) for key, heading in SECTIONS
                if parts[key] is not None]
    path.write_text(page(f"Whole-car K&C report: {summary['vehicle_name']}", intro, sections),
                    encoding="utf-8")
    return path
