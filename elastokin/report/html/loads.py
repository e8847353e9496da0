"""The report's "Loads" section: the static-load cases from vehicle accelerations and their
contact-patch forces (summary.json ``vehicle_loads``), the loads the body pickups receive with
the worst case of each marked (``models.<label>.pickups``), the chart of the largest load per
element and every element's peaks (``models.<label>.loads``). Forces N, moments N*m (N*mm in
the files); body (config) frame.
"""

from __future__ import annotations

from pathlib import Path

from elastokin.report.html.parts import esc, figure, note, num, table
from elastokin.report.load_charts import LOAD_CHART, LOAD_CHART_TITLE

#: N*mm -> N*m, as the report shows moments
NM = 1.0e-3


def signed(value: float, fmt: str) -> str:
    """A number in ``fmt``, without the sign of a value that rounds to zero."""
    text = format(value, fmt)
    return text[1:] if text.startswith("-") and not text.strip("-0.") else text


def case_label(case: str) -> str:
    """A load case as the tables show it (a static-load case by its name)."""
    return case.replace("vehicle_loads:", "vehicle: ")


def vehicle_load_rows(cases: dict) -> list[list[str]]:
    """One row per static-load case and wheel: accelerations, the tyre's forces."""
    rows = []
    for case, c in cases.items():
        for side, f in c["contact_patch_force_N"].items():
            centre = c["wheel_centre_force_N"][side]
            rows.append([esc(case_label(case)) if side == "left" else "", esc(side),
                         *(num(c[k], ".2f") if side == "left" else ""
                           for k in ("longitudinal_g", "lateral_g", "bump_g")),
                         *(num(v, ".0f") for v in f),
                         num(centre[0], ".0f") if any(centre) else "&ndash;"])
    return rows


def pickup_rows(pickups: dict) -> list[list[str]]:
    """Each body pickup: where, its worst case (step) and the load there."""
    rows = []
    for name, p in pickups.items():
        w = p["worst"]
        where = [signed(v, ".1f") for v in p["point_mm"]]
        if not w["force_N"] > 0.0:  # a stop never in contact
            rows.append([esc(name), esc(p["kind"]), *where, "no load in any case",
                         *["&ndash;"] * 7])
            continue
        moment = ([signed(v * NM, ".1f") for v in w["moment_vector_Nmm"]] if p["moments"]
                  else ["&ndash;"] * 3)
        rows.append([esc(name), esc(p["kind"]), *where,
                     f"{esc(case_label(w['load_case']))} ({w['step']})",
                     *(signed(v, ".0f") for v in w["force_vector_N"]),
                     f"<b>{w['force_N']:.0f}</b>", *moment])
    return rows


def pickup_case_table(pickups: dict) -> str:
    """Largest force of each pickup in each load case, the worst marked."""
    cases = list(dict.fromkeys(c for p in pickups.values() for c in p["load_cases"]))
    rows = []
    for name, p in pickups.items():
        worst = p["worst"]["load_case"] if p["worst"]["force_N"] > 0.0 else None
        rows.append([esc(name), *(
            (f'<span class="worst">{p["load_cases"][c]:.0f}</span>' if c == worst else
             f"{p['load_cases'][c]:.0f}") if c in p["load_cases"] else "&ndash;"
            for c in cases)])
    return ('<div class="wide">' + table(["pickup", *map(case_label, cases)], rows)
            + "</div>")


def element_rows(loads: dict) -> list[list[str]]:
    """Every element's largest force and moment over the load cases."""
    rows = []
    for name, e in loads.items():
        cases = e["load_cases"]
        cf = max(cases, key=lambda c: cases[c]["force_N"])
        moments = {c: v["moment_Nmm"] for c, v in cases.items() if "moment_Nmm" in v}
        cm = max(moments, key=moments.get) if moments else None
        first, second = e["parts"]
        rows.append([esc(name), esc(e["kind"]), f"{esc(first)} (from {esc(second)})",
                     f"{cases[cf]['force_N']:.0f}", esc(case_label(cf)),
                     num(moments[cm] * NM, ".1f") if cm else "&ndash;",
                     esc(case_label(cm)) if cm else ""])
    return rows


def model_tables(model: str, figures: dict, open_: bool) -> str:
    """The pickups' and the elements' tables of one model, folded unless ``open_``."""
    body = []
    if figures.get("pickups"):
        body += [f"<h4>Body pickups, worst case (model {esc(model)})</h4>",
                 note("The load each ground (body, subframe) pickup receives in the load case "
                      "where its force is largest: force and moment (about the pickup) in "
                      "the body frame; the pickup at its design position."),
                 '<div class="wide">' + table(
                     ["pickup", "kind", "x mm", "y mm", "z mm", "worst case (step)", "Fx N",
                      "Fy N", "Fz N", "|F| N", "Mx N\u00b7m", "My N\u00b7m", "Mz N\u00b7m"],
                     pickup_rows(figures["pickups"]), text_columns=(1, 5)) + "</div>",
                 "<h4>Largest force of each pickup per load case [N]</h4>",
                 note("The worst case of each pickup is marked."),
                 pickup_case_table(figures["pickups"])]
    body += [f"<h4>Every element's largest load (model {esc(model)})</h4>",
             table(["element", "kind", "load on (from)", "|F| max N", "in", "|M| max N\u00b7m",
                    "in"], element_rows(figures["loads"]), text_columns=(1, 2, 4, 6))]
    return (f"<details{' open' if open_ else ''}><summary>Model <b>{esc(model)}</b>"
            "</summary>" + "".join(body) + "</details>")


def loads_section(summary: dict, charts: list[Path], number: int) -> list[str]:
    """The "Loads" section (module docstring); the chart numbered ``number``."""
    out = [note("Every connection, spring, stop, the anti-roll bar and the steering gear "
                "transmit a force and a moment at every step of every load case: "
                "<code>loads.csv</code> (one row per step; force and moment on the element's "
                "first part, in the body frame and in its own), summary.json "
                "<code>models.&lt;model&gt;.loads</code> and <code>.pickups</code>; frames "
                "and signs in docs/characteristics.md (Loads). Forces N, moments N&middot;m "
                "here (N&middot;mm in the files).")]
    cases = summary.get("vehicle_loads")
    if cases:
        out += ["<h3>Static loads from vehicle accelerations</h3>",
                note("ADAMS/Car's static-load analysis: each case's contact-patch forces from "
                     "steady accelerations (g; longitudinal + forward, lateral + to the left, "
                     "bump beyond gravity) and the vehicle data (axle masses, CG height, "
                     "wheelbase, brake and drive split, track), ramped from the design wheel "
                     "load; forces the road applies to each tyre, config frame (method: "
                     "docs/characteristics.md)."),
                table(["case", "wheel", "long. g", "lat. g", "bump g", "Fx N", "Fy N",
                       "Fz N", "Fx at wheel centre N"], vehicle_load_rows(cases),
                      text_columns=(0, 1))]
    chart = next((p for p in charts if p.stem == LOAD_CHART and p.suffix == ".png"), None)
    if chart is not None:
        out.append(figure(chart, LOAD_CHART_TITLE, number,
                          "The largest force magnitude each element transmits in any load "
                          "case, one bar per model, the load case beside it (the contact "
                          "patches, the applied loads, left out)."))
    models = [m for m, f in summary["models"].items() if f.get("loads")]
    out += ["<h3>Body pickups and elements</h3>"]
    out += [model_tables(m, summary["models"][m], k == 0) for k, m in enumerate(models)]
    return out
