"""The report's "Joints from motion" section (a run whose config has a motion plan):
``motion_identification.json``'s joints with their uncertainty from the CMM noise and, on
synthetic data, their error against the truth beside the disassembly method's."""

from __future__ import annotations

from elastokin.report.html.parts import esc, note, num, table

EHRIG = ("SCoRE: Ehrig et al. 2006, J. Biomech. 39:2798; SARA: Ehrig et al. 2007, "
         "J. Biomech. 40:2150")


def _position_rows(doc: dict) -> list[list[str]]:
    rows = []
    for name, p in doc["positions"].items():
        rows.append([esc(name), *(num(p[k], "g") for k in (
            "wheel_travel_mm", "other_wheel_travel_mm", "rack_travel_mm", "wheel_turned_deg"))])
    return rows


def motion_section(doc: dict) -> list[str]:
    """The joints located from the parts' motion, the positions measured, the marks
    dropped."""
    both = any(j.get("disassembly_error_vs_truth_mm") is not None
               for j in doc["joints"].values())
    synthetic = any(j["error_vs_truth_mm"] is not None for j in doc["joints"].values())
    rows = []
    for name, j in doc["joints"].items():
        x = j["located_mm"]
        loc = ["&ndash;"] * 3 if x is None else [f"{v:.2f}" for v in x]
        rows.append([esc(name), esc(j["kind"]), esc(j["method"]), *loc,
                     num(j["uncertainty_mm"], ".3f"), num(j["worst_std_mm"], ".3f"),
                     num(j["axis_uncertainty_deg"], ".3f"), num(j["residual_rms_mm"], ".3f"),
                     *([num(j["error_vs_truth_mm"], ".3f"), num(j["axis_error_deg"], ".3f")]
                       if synthetic else []),
                     *([num(j["disassembly_error_vs_truth_mm"], ".3f")] if both else [])])
    header = ["joint", "kind", "method", "x mm", "y mm", "z mm", "uncertainty mm",
              "worst dir. mm", "axis uncertainty deg", "residual mm",
              *(["error mm", "axis error deg"] if synthetic else []),
              *(["disassembly error mm"] if both else [])]
    out = [note(f"The model <b>identified_motion</b> puts its joints where the parts' relative "
                f"motion over {len(doc['positions'])} rig positions locates them, without "
                "taking the suspension apart: every part's pose at every position from its "
                "marks (the paper's ordering and fit, eqs. (8)&ndash;(12)), a ball joint's "
                "centre as the point fixed in both parts (SCoRE), a hinge's or cylindrical "
                f"joint's axis (SARA), the wheel's spin axis ({esc(EHRIG)}). Bushings deflect "
                "with the rig's loads and keep the config's location. Vehicle frame at the "
                f"design position '{esc(doc['design_position'])}'; uncertainty: 1-sigma 3-D "
                f"RMS from the CMM noise the pose fits show (&sigma; = "
                f"{doc['noise_sigma_mm']:.4f} mm per coordinate); residual: how far the two "
                "parts' points part over the positions."
                + (" <i>Error</i>: against the synthetic truth (an axis joint's across the "
                   "true axis)" + (", beside the disassembly method's (model identified)."
                                   if both else ".") if synthetic else "")),
           table(header, rows, text_columns=(1, 2))]
    out += ["<h3>Rig positions measured</h3>",
            note("Rig inputs from the design position: pad heights (+ bump), steering rack "
                 "travel, the wheel turned on its bearing."),
            table(["position", "wheel travel mm", "other wheel mm", "rack travel mm",
                   "wheel turned deg"], _position_rows(doc))]
    if doc["dropped_marks"]:
        out.append(note("Wrong marks dropped: " + "; ".join(
            f"{esc(d['body'])} at '{esc(d['position'])}' (mark '{esc(d['mark'])}')"
            for d in doc["dropped_marks"]) + "."))
    return out
