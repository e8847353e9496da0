"""The report's "Axle" section (a run whose config has an ``axle:``): the axle's make-up and
vehicle data (summary.json ``axle``), the axle's characteristics one column per model
(``models.<label>.axle``: every figure but the 12x12 matrix, the named compliances apart),
the per-wheel characteristics left and right (``models.<label>`` is the config side's wheel,
``models.<label>.<other side>`` the other's) and the axle's charts with their captions.
"""

from __future__ import annotations

import re
from pathlib import Path

from elastokin.report.axle_charts import AXLE_CHARTS, axle_chart_caption
from elastokin.report.html.parts import esc, figure, note, num, table
from elastokin.report.text import axle_models
from elastokin.rig.channels import AXLE_CHARACTERISTICS, CHARACTERISTIC_LIST, display_unit

#: the named compliances' parts (elastokin.physics.axle_compliance.named_compliances)
_NAMED = re.compile(r"(lateral_force|longitudinal_force|traction_force|aligning_torque)_"
                    r"(toe|camber|wheel_centre_x|wheel_centre_y)_(in_phase|anti_phase|single)_"
                    r"(left|right)_(\w+)_per_(\w+)")
LOAD_WORDS = {"lateral_force": "lateral force (+ left, at the contact point)",
              "longitudinal_force": "longitudinal force (+ forward, at the contact point)",
              "traction_force": "traction force (+ forward, at the wheel centre)",
              "aligning_torque": "aligning torque (+ about up)"}
RESPONSE_WORDS = {"toe": "toe (toe-in +)", "camber": "camber (top outboard +)",
                  "wheel_centre_x": "wheel-centre x (forward +)",
                  "wheel_centre_y": "wheel-centre y (left +)"}
PHASE_WORDS = {"in_phase": "in phase", "anti_phase": "anti-phase (+ on the left wheel)",
               "single": "this wheel alone"}


def figure_cell(value, unit: str, fmt: str) -> str:
    """A figure of summary.json's ``unit`` in the unit the report shows
    (:func:`~elastokin.rig.channels.display_unit`); a dash for none."""
    text = num(None if value is None else value * display_unit(unit)[1], fmt)
    # a value that rounds to zero is shown without a sign (a centred roll centre: -6e-11 mm)
    return text.removeprefix("-") if text.startswith("-") and not text.strip("-0.") else text


def make_up_rows(axle: dict) -> list[list[str]]:
    """The axle's make-up and vehicle data (summary.json ``axle``)."""
    v = axle.get("vehicle") or {}
    rows = [["wheels", esc(", ".join(axle["sides"]) + f" (config side {axle['config_side']}; "
                           "the other made by mirroring or from axle.other_side)")],
            ["track at the contact points, design [mm]", num(axle.get("track_mm"), ".1f")],
            ["parts declared once (shared)", esc(", ".join(axle.get("shared_parts") or [])
                                                 or "none")],
            ["wheel motion", "dependent (they move together: the kinematic roll centre is the "
             "instant centre of the axle's roll motion)" if axle.get("dependent")
             else "independent"],
            ["steering rack", "yes" if axle.get("steering") else "no (steering locked)"],
            ["anti-roll bar", "yes" if axle.get("anti_roll_bar") else "no"]]
    if not v:
        rows.append(["vehicle data", "none (axle.vehicle): no anti-dive / anti-lift, percent "
                     "Ackermann, turn diameter"])
        return rows
    rows += [["axle position", esc(v["position"])],
             ["wheelbase [mm]", num(v["wheelbase_mm"], ".0f")],
             ["centre-of-gravity height [mm]", num(v["cg_height_mm"], ".1f")],
             ["this axle's share of braking / drive [-]",
              f"{num(v['brake_fraction'], '.2f')} / {num(v['drive_fraction'], '.2f')}"],
             ["brakes", esc(v["brakes"])], ["drive", esc(v.get("drive", "outboard"))]]
    if v.get("live_axle_ratio") is not None:
        rows.append(["live axle: final drive ratio [-]", num(v["live_axle_ratio"], ".4g")
                     + " (the pinion torque enters anti-squat and traction anti-lift)"])
    masses = v.get("axle_mass_kg")
    if masses:
        rows.append(["masses the axles carry at rest, front / rear [kg] (static loads)",
                     f"{num(masses['front'], '.1f')} / {num(masses['rear'], '.1f')}"])
    return rows


def characteristic_rows(axles: dict[str, dict]) -> list[list[str]]:
    """Every axle figure that is a number (or none), in the channel table's order, then any
    other: label [unit] (its definition on hover), one cell per model."""
    keys = list(AXLE_CHARACTERISTICS)
    keys += [k for a in axles.values() for k in a if k not in keys
             and not isinstance(a[k], (dict, list))]
    rows = []
    for key in dict.fromkeys(keys):
        c = AXLE_CHARACTERISTICS.get(key)
        label, unit, fmt, definition = ((c.label, c.unit, c.fmt, c.definition) if c
                                        else (key, "", ".4g", ""))
        rows.append([f'<span title="{esc(definition)}">{esc(label)} '
                     f'[{esc(display_unit(unit)[0])}]</span>',
                     *(figure_cell(a.get(key), unit, fmt) for a in axles.values())])
    return rows


def named_compliance_rows(axles: dict[str, dict]) -> tuple[list[str], list[list[str]]]:
    """(header, rows) of the named compliances: a row per load, response and phase, a left
    and a right column per model."""
    axles = {m: a for m, a in axles.items() if a.get("named_compliances")}
    header = ["load, response, phase", *(f"{m} {side}" for m in axles
                                        for side in ("left", "right"))]
    rows: dict[tuple, dict] = {}
    for m, a in axles.items():
        for name, value in (a.get("named_compliances") or {}).items():
            match = _NAMED.fullmatch(name)
            if match is None:
                continue
            load, response, phase, side, top, bottom = match.groups()
            key = (load, response, phase, f"{top}/{bottom}")
            rows.setdefault(key, {})[(m, side)] = value
    out = []
    for (load, response, phase, unit), values in rows.items():
        out.append([f"{esc(LOAD_WORDS[load])} &rarr; {esc(RESPONSE_WORDS[response])}, "
                    f"{esc(PHASE_WORDS[phase])} [{esc(unit)}]",
                    *(num(values.get((m, side)), ".4f") for m in axles
                      for side in ("left", "right"))])
    return header, out


def per_wheel_rows(summary: dict) -> tuple[list[str], list[list[str]]]:
    """(header, rows): every per-wheel characteristic, a left and a right column per model
    (a dash where a model has no such wheel, e.g. a corner's test data)."""
    config_side = summary["axle"]["config_side"]
    models = summary["models"]
    header = ["characteristic", *(f"{m} {side}" for m in models for side in ("left", "right"))]

    def wheel(m: str, side: str) -> dict:
        return models[m] if side == config_side else (models[m].get(side) or {})

    rows = [[f'<span title="{esc(c.definition)}">{esc(c.label)} [{c.unit}]</span>',
             *(num(wheel(m, side).get(c.name), c.fmt) for m in models
               for side in ("left", "right"))] for c in CHARACTERISTIC_LIST]
    return header, rows


def axle_section(summary: dict, charts: list[Path], first_number: int) -> list[str]:
    """The "Axle" section: make-up, characteristics, named compliances, left and right
    figures, the axle's charts numbered from ``first_number``."""
    axles = axle_models(summary)
    out = [note("Both wheels of the axle on the rig (ADAMS/Car's suspension analyses): the "
                "config's corner and the other side's; figures per the axle in "
                'summary.json <code>models.&lt;label&gt;.axle</code>, definitions in '
                "docs/characteristics.md (hover a row for its definition)."),
           "<h3>Make-up and vehicle data</h3>",
           table(["", "value"], make_up_rows(summary["axle"]), text_columns=(1,))]
    if axles:
        out += ["<h3>Axle characteristics</h3>",
                table(["characteristic", *axles], characteristic_rows(axles)),
                note("Roll centre: the <b>kinematic</b> one is where the lines from each "
                     "contact point normal to its velocity in parallel travel meet (front "
                     "view; its height over the travel is a chart below), the "
                     "<b>force-based</b> one ADAMS/Car's, from the 12x12 wheel-centre "
                     "compliance (none for a model without compliance, e.g. a kinematic "
                     "one); the two agree on a model with ideal joints. Roll stiffness in "
                     "N&middot;m/deg (N&middot;mm/deg in summary.json). &ndash;: the load case "
                     "was not run or the config gives no vehicle data.")]
        header, rows = named_compliance_rows(axles)
        if rows:
            out.append("<details><summary>Named compliances from the 12x12 matrix "
                       f"({len(rows)} per wheel and model; ISO 8855 frame)</summary>"
                       + table(header, rows) + "</details>")
    header, rows = per_wheel_rows(summary)
    out += ["<h3>Per-wheel characteristics, left and right</h3>",
            note("Each wheel's figures as in the K&amp;C characteristics; the corner load "
                 "cases run in phase on both wheels. Wheel angles are per wheel (toe-in +, "
                 "camber top outboard +) but forces and displacements are in the vehicle "
                 "frame (lateral + to the left): on a symmetric axle a lateral figure of a "
                 "wheel angle changes sign from the left wheel to the right."),
            table(header, rows)]
    with_test = "test" in summary["models"]
    with_ideal = bool(summary["axle"].get("wheelbase_mm"))
    figures = [p for p in charts if p.suffix == ".png" and p.stem in AXLE_CHARTS]
    if figures:
        out.append("<h3>Charts of the axle</h3>")
    for k, path in enumerate(figures):
        spec = AXLE_CHARTS[path.stem]
        out.append(figure(path, spec.title, first_number + k,
                          axle_chart_caption(spec, with_test, with_ideal)))
    return out
