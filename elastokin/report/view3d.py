"""The interactive 3D view of a suspension (plotly.js's gl3d bundle embedded: works offline):
every model's drawing (:mod:`elastokin.report.view3d_traces`), a model and load-case picker,
a slider and a play button through the frames of the load case, each model's outline to
overlay on another, and with an identification the CMM marks and the joint shifts, magnified.

The page carries each part's pose per frame (a rotation vector in micro-radians and the
displacement of its reference point in 0.01 mm), not every point: ``view3d.js`` moves the
traces. Config frame, mm. Used by ``report.html`` (:func:`view_fragment`) and by ``elastokin
view`` (:func:`write_view_page`).
"""

from __future__ import annotations

import html
import json
from dataclasses import dataclass
from importlib import resources
from pathlib import Path

import numpy as np

from elastokin.report.view3d_beams import beam_payload, beam_traces, twist_factor
from elastokin.report.view3d_loads import (
    arrow_scale,
    arrow_tips_mm,
    load_traces,
    loads_payload,
    pickup_points,
    worst_cases,
)
from elastokin.report.view3d_traces import (
    Traces,
    connection_traces,
    ghost_trace,
    kinematic_traces,
    part_traces,
    static_traces,
    wheel_traces,
)
from elastokin.rig.scene import Scene
from elastokin.rig.scene_motion import SceneFrames

#: the outline colour of each model (the K&C charts' colours)
MODEL_COLOURS = {"initial": "#1f77b4", "identified": "#d62728", "identified_stiffness": "#2ca02c",
                 "initial_kinematic": "#6baed6", "identified_kinematic": "#fc9272",
                 "design": "#1f77b4"}
PLOT_HEIGHT_PX = 680
#: plotly.js's gl3d partial bundle, in elastokin/report/vendor (:func:`plotly_js`)
PLOTLY_BUNDLE = "plotly-gl3d.min.js"
#: the legend's top (fraction of the plot's height): below plotly's mode bar
LEGEND_TOP = 0.93
#: room around the parts in the view (mm)
MARGIN_MM = 120.0
DESIGN_NOTE = "the hardpoints as given (nothing solved); bushings at their initial deflection"


@dataclass
class ModelView:
    """One model in the view: its scene and its frames (one per load case; the design
    position first)."""

    label: str
    scene: Scene
    frames: list[SceneFrames]


def _flat(values, digits: int) -> list:
    """Numbers rounded for the page; None where not finite (JSON has no NaN)."""
    a = np.round(np.asarray(values, float).ravel(), digits)
    finite = np.isfinite(a)
    if finite.all():
        return a.astype(np.int64).tolist() if digits <= 0 else a.tolist()
    out = a.tolist()
    for k in np.flatnonzero(~finite):
        out[k] = None
    return out


def _references(scene: Scene) -> np.ndarray:
    """Each part's reference point (the mean of its points; mm)."""
    return np.array([p.points_mm.mean(axis=0) if len(p.points_mm) else np.zeros(3)
                     for p in scene.parts])


def case_payload(scene: Scene, f: SceneFrames, ref: np.ndarray, twist: float = 1.0) -> dict:
    """One model's frames of one load case as the page carries them (module docstring)."""
    from scipy.spatial.transform import Rotation

    k = f.frames
    pose = np.zeros((k, len(scene.parts), 6))
    for j, p in enumerate(scene.part_names):
        R, t = f.rotation[p], f.translation_mm[p]
        pose[:, j, :3] = Rotation.from_matrix(R).as_rotvec() * 1e6
        pose[:, j, 3:] = (np.einsum("sij,j->si", R, ref[j]) + t - ref[j]) * 100.0
    from elastokin.rig.channels import LOAD_CASES

    branches = list(dict.fromkeys(f.branch))
    case = LOAD_CASES.get(f.load_case)
    out = {"n": int(f.total_steps), "steps": [int(s) for s in f.steps],
           "branches": branches, "branch": [branches.index(b) for b in f.branch],
           "input": case.label if case is not None else None, "pose": _flat(pose, 0),
           "x": None if f.input_values is None else _flat(f.input_values, 4),
           "wheel": {s: _flat(v, 4) for s, v in f.wheel.items()},
           "bushing": {b: _flat(v, 3) for b, v in f.bushing_mm.items()},
           "stop": {s: _flat(v, 1) for s, v in f.stop_force_N.items()},
           "axis": {s: _flat(v, 1) for s, v in f.steering_axis_mm.items()},
           "ic": {s: _flat(v, 1) for s, v in f.instant_centre_mm.items()},
           "patch": {s: _flat(v, 1) for s, v in f.contact_mm.items()},
           "rc": None if f.roll_centre_mm is None else _flat(f.roll_centre_mm, 1),
           "beam": beam_payload(scene, f, twist), "loads": loads_payload(f)}
    return out


def identification_traces(t: Traces, overlay) -> list[int]:
    """The CMM marks (fitted, and measured drawn at the fitted one plus the magnified
    residual) and the joint shifts (arrows from the initial location, magnified)."""
    F = overlay.factor
    shown = overlay.fitted_mm + F * (overlay.measured_mm - overlay.fitted_mm)
    ok = np.all(np.isfinite(shown), axis=1)
    out = []
    for name, pts, symbol in (("CMM marks, fitted", overlay.fitted_mm, "circle-open"),
                              (f"CMM marks, measured (residual x{F:g})", shown, "x")):
        out.append(t.add({"type": "scatter3d", "mode": "markers", "x": _flat(pts[ok, 0], 2),
                          "y": _flat(pts[ok, 1], 2), "z": _flat(pts[ok, 2], 2),
                          "name": name, "legendgroup": "identification",
                          "text": [lab for lab, o in zip(overlay.mark_labels, ok) if o],
                          "hovertemplate": "%{text}<extra></extra>", "visible": "legendonly",
                          "marker": {"symbol": symbol, "size": 4, "color": "#6a3d9a"}}))
    tips = overlay.initial_mm + F * (overlay.identified_mm - overlay.initial_mm)
    xs, ys, zs, text = [], [], [], []
    for name, a, b, beyond in zip(overlay.joint_names, overlay.initial_mm, tips,
                                  overlay.beyond_clearance):
        shift = np.linalg.norm((b - a) / F)
        label = f"{name}: shift {shift:.3f} mm" + (" (beyond dL_max)" if beyond else "")
        for v in (a, b, np.full(3, np.nan)):
            xs.append(None if np.isnan(v[0]) else float(v[0]))
            ys.append(None if np.isnan(v[1]) else float(v[1]))
            zs.append(None if np.isnan(v[2]) else float(v[2]))
        text += [label, label, ""]
    out.append(t.add({"type": "scatter3d", "mode": "lines+markers", "x": xs, "y": ys,
                      "z": zs, "name": f"joint shifts, identified - initial (x{F:g})",
                      "legendgroup": "identification", "text": text, "visible": "legendonly",
                      "hovertemplate": "%{text}<extra></extra>",
                      "line": {"color": "#e7298a", "width": 6},
                      "marker": {"size": [3, 7, 0] * len(overlay.joint_names),
                                 "color": "#e7298a", "symbol": "diamond"}}))
    return out


def _camera_buttons(scene: Scene) -> list[dict]:
    """View buttons: 3D, front, side (the config side's wheel), top."""
    frame = scene.frame_text
    fwd = np.array([1.0 if "x forward" in frame else -1.0, 0.0, 0.0])
    left = np.array([0.0, 1.0 if "y left" in frame else -1.0, 0.0])
    up = {"x": 0, "y": 0, "z": 1}

    def eye(v):
        return dict(zip("xyz", (float(c) for c in v)))

    views = (("3D", eye(0.95 * fwd + 0.7 * left + 0.5 * np.array([0, 0, 1])), up),
             ("front", eye(1.25 * fwd + [0, 0, 0.05]), up),
             ("side", eye(1.25 * left + [0, 0, 0.05]), up),
             ("top", eye([0, 0, 1.25]), eye(fwd)))
    return [{"label": name, "method": "relayout",
             "args": [{"scene.camera": {"eye": e, "up": u, "center": {"x": 0, "y": 0, "z": 0}}}]}
            for name, e, u in views]


def build_view(models: list[ModelView], overlay=None) -> tuple[dict, dict]:
    """(the plotly figure as a dict, the page's data for ``view3d.js``)."""
    t = Traces()
    every = [f for m in models for f in m.frames]
    first = models[0].scene
    lo, hi = first.extent_mm()
    twist, scale = twist_factor(every), arrow_scale(every, float(np.max(hi - lo)))
    payload: dict = {"order": [m.label for m in models], "models": {}, "recipes": [],
                     "ident": [], "design_note": DESIGN_NOTE, "twist_factor": twist,
                     "load_mm_per_N": scale / 1e3}
    static_traces(t, first, "static")
    cmax = 0.1
    for m in models:
        sc = m.scene
        group = f"model:{m.label}"
        for make in (part_traces, connection_traces, wheel_traces, kinematic_traces):
            make(t, sc, m.label, group)
        beam_traces(t, sc, m.label, group, twist)
        pickups = pickup_points(m.frames)
        load_traces(t, m.label, group, scale, list(pickups),
                    list(dict.fromkeys(n for f in m.frames for n in f.patch_load_N)))
        ref = _references(sc)
        payload["models"][m.label] = {
            "parts": list(sc.part_names), "ref": ref.round(3).tolist(),
            "cases": [f.load_case for f in m.frames], "pickups": pickups,
            "worst": worst_cases(m.frames),
            "data": {f.load_case: case_payload(sc, f, ref, twist) for f in m.frames}}
        cmax = max([cmax] + [float(np.nanmax(v)) for f in m.frames
                             for v in f.bushing_mm.values() if np.isfinite(v).any()])
    if len(models) > 1:
        for m in models:
            ghost_trace(t, m.scene, m.label, MODEL_COLOURS.get(m.label, "#555"))
    if overlay is not None:
        payload["ident"] = identification_traces(t, overlay)
    payload["recipes"] = t.recipes
    payload["bushing_cmax"] = round(cmax, 3)
    for trace, recipe in zip(t.traces, t.recipes):
        if recipe is not None and not recipe.get("ghost") and recipe["model"] != models[0].label:
            trace["visible"] = False
    tips = arrow_tips_mm(every, scale / 1e3)
    tips = tips[np.all(np.isfinite(tips), axis=1)]
    if len(tips):  # every arrow inside the box
        lo, hi = np.minimum(lo, tips.min(axis=0)), np.maximum(hi, tips.max(axis=0))
    lo, hi = lo - MARGIN_MM, hi + MARGIN_MM
    axis = {"showbackground": True, "backgroundcolor": "#f7f7f7", "gridcolor": "#dddddd"}
    names = first.frame_text.removeprefix("config frame: ").split(", ")
    ratio = (hi - lo) / np.max(hi - lo)  # true proportions, kept while the parts move
    layout = {"scene": {"aspectmode": "manual", "domain": {"x": [0.0, 0.8], "y": [0.0, 1.0]},
                        "aspectratio": dict(zip("xyz", ratio.round(4).tolist())),
                        **{f"{a}axis": {**axis, "title": {"text": f"{n} [mm]"},
                                        "range": [float(lo[i]), float(hi[i])]}
                           for i, (a, n) in enumerate(zip("xyz", names))},
                        "camera": _camera_buttons(first)[0]["args"][0]["scene.camera"]},
              "uirevision": "keep", "height": PLOT_HEIGHT_PX,
              "margin": {"l": 0, "r": 0, "t": 10, "b": 0},
              "legend": {"itemsizing": "constant", "groupclick": "togglegroup",
                         "font": {"size": 11}, "x": 0.81, "xanchor": "left",
                         "y": LEGEND_TOP, "yanchor": "top"},
              "updatemenus": [{"type": "buttons", "direction": "right", "x": 0.0, "y": 1.0,
                               "xanchor": "left", "yanchor": "top", "pad": {"l": 4, "t": 4},
                               "buttons": _camera_buttons(first)}]}
    return {"data": t.traces, "layout": layout}, payload


_CSS = """.ekv-controls{display:flex;flex-wrap:wrap;gap:0.6em;align-items:center;margin:0.4em 0}
.ekv-controls input[type=range]{flex:1;min-width:14em}.ekv-info{font-size:88%;color:#303030;
min-height:2.6em}.ekv-errors{color:#b00000}"""


def _json_script(element_id: str, value) -> str:
    text = json.dumps(value, separators=(",", ":"), allow_nan=False).replace("</", "<\\/")
    return f'<script type="application/json" id="{element_id}">{text}</script>'


def plotly_js() -> str:
    """plotly.js as the view embeds it: the official gl3d partial bundle (npm
    ``plotly.js-gl3d-dist-min``, MIT), shipped in ``elastokin/report/vendor/`` (its version
    and checksum in ``plotly-gl3d.json``; ``scripts/vendor_plotly.py`` updates it)."""
    return resources.files("elastokin.report").joinpath(
        "vendor", PLOTLY_BUNDLE).read_text("utf-8")


def view_fragment(models: list[ModelView], overlay=None, lazy: bool = False,
                  prefix: str = "ekv") -> str:
    """The view as an HTML fragment: controls, the frame's description, the plot, plotly.js
    (embedded), the figure and the data, and the script that draws the first frame (one
    plotly.newPlot) and moves it. ``lazy``: plotly.js is run and the view drawn only when the
    plot comes near the window (a report opens without waiting for them)."""
    figure, payload = build_view(models, overlay)  # tests validate it with plotly
    figure["config"] = {"displaylogo": False, "responsive": True,
                        "toImageButtonOptions": {"format": "png", "scale": 2}}
    script = resources.files("elastokin.report").joinpath("view3d.js").read_text("utf-8")
    kind = f' type="text/plain" id="{prefix}-plotlyjs"' if lazy else ""
    library = f"<script{kind}>{plotly_js()}</script>"
    start = "elastokinLazyView" if lazy else "elastokinView"
    controls = (f'<div class="ekv-controls"><label>model <select id="{prefix}-model">'
                f'</select></label><label>load case <select id="{prefix}-case"></select>'
                f'</label><button type="button" id="{prefix}-play">\u25b6 play</button>'
                f'<input type="range" id="{prefix}-slider" min="0" max="0" value="0" '
                f'aria-label="frame"><label>worst case of <select id="{prefix}-worst">'
                f'</select></label></div>')
    return (f"<style>{_CSS}</style>{controls}"
            f'<div class="ekv-info" id="{prefix}-info"></div>'
            f'<div id="{prefix}-plot" class="ekv-plot" style="height:{PLOT_HEIGHT_PX}px"></div>'
            f"{_json_script(f'{prefix}-figure', figure)}{_json_script(f'{prefix}-data', payload)}"
            f"{library}<script>{script}</script>"
            f"<script>{start}('{prefix}');</script>")


def write_view_page(path: Path, title: str, models: list[ModelView], errors: list[str],
                    notes: list[str]) -> Path:
    """A page with the view (``elastokin view``): the config's errors beside it."""
    listed = "".join(f"<li>{html.escape(e)}</li>" for e in errors)
    side = (f'<div class="ekv-errors"><b>{len(errors)} error{"s" if len(errors) > 1 else ""} '
            f"in the config</b> (what they name is not drawn):<ul>{listed}</ul></div>"
            if errors else "")
    body = view_fragment(models)
    note = "".join(f"<p class=\"note\">{html.escape(n)}</p>" for n in notes)
    page = (f'<!DOCTYPE html><html lang="en"><head><meta charset="utf-8"><title>'
            f"{html.escape(title)}</title><style>body{{font-family:system-ui,Helvetica,Arial,"
            f"sans-serif;margin:0.8em 1.2em;color:#1d1d1d}}.note{{color:#505050;"
            f"font-size:90%}}</style></head><body><h2>{html.escape(title)}</h2>{side}"
            f"{body}{note}</body></html>\n")
    Path(path).write_text(page, encoding="utf-8")
    return Path(path)


def model_view(label: str, s, sweeps_by_case: dict[str, list]) -> ModelView:
    """A solved model's view: its scene, its design position and each load case's frames
    (``sweeps_by_case``: every wheel's sweep of each case, the config side's first)."""
    from elastokin.config.draft import draft_of
    from elastokin.rig.scene import build_scene
    from elastokin.rig.scene_motion import design_frames, sweep_frames

    scene = build_scene(draft_of(s))
    frames = [design_frames(scene, s, label)]
    for sweeps in sweeps_by_case.values():
        f = sweep_frames(s, scene, sweeps)
        if f is not None:
            frames.append(f)
    return ModelView(label, scene, frames)


def run_views(run) -> tuple[list[ModelView], object | None]:
    """The views of a K&C run's models that recorded part poses (not the test's), and the
    identification's overlay when there is one."""
    views = []
    for label, m in run.models.items():
        if m.suspension is None or not m.sweeps or m.sweeps[0].poses is None:
            continue
        by_case = {sw.load_case: [sw] for sw in m.sweeps}
        for sweeps in m.other_sides.values():
            for sw in sweeps:
                by_case.setdefault(sw.load_case, []).append(sw)
        views.append(model_view(label, m.suspension, by_case))
    overlay = None
    if run.identification is not None:
        from elastokin.identification.overlay import identification_overlay

        overlay = identification_overlay(run.identification)
    return views, overlay
