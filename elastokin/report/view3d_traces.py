"""The plotly traces of a :class:`~elastokin.rig.scene.Scene` (one model's drawing) and of an
identification overlay, each with its *recipe*: how the view's script
(``view3d.js``) moves its points at a frame (every vertex carried by a part, a spring's coil
between its seats, or a kinematic figure of the frame). Config frame, mm.
"""

from __future__ import annotations

import numpy as np

from elastokin.rig.scene import Scene, SceneItem

#: the marker of each joint kind (plotly's 3D symbols)
JOINT_SYMBOLS = {"spherical": "circle", "revolute": "diamond", "cylindrical": "square",
                 "translational": "square-open", "universal": "cross", "fixed": "x",
                 "rack": "diamond-open", "planar": "circle-open", "inplane": "square-open"}
#: the marker of a joint kind not listed above
OTHER_JOINT_SYMBOL = "circle-open"
#: the scene's items that are not joints
ITEM_KINDS = ("bushing", "link", "spring", "damper", "bump stop", "rebound stop",
              "anti-roll bar")
#: joint kinds drawn with their axis (the joint frame's z)
AXIS_KINDS = ("revolute", "cylindrical", "translational", "rack", "universal",
              "anti-roll bar")
#: lengths drawn (mm): a joint's axis (each way), a bushing frame's axes
AXIS_MM, TRIAD_MM = 45.0, 40.0
#: a spring's coil: turns, and radius as a fraction of its installed length (within limits)
COIL_TURNS, COIL_RADIUS_PER_LENGTH, COIL_RADIUS_MM = 7, 0.12, (22.0, 70.0)
#: bushing deflection colours (translation magnitude, mm)
DEFLECTION_SCALE = "YlOrRd"
GAP = -2  # a recipe's break between polylines
GROUND = -1  # a recipe's vertex on the ground (does not move)


class Traces:
    """The traces of one figure and their recipes (``recipes[k]`` moves trace ``k``; None:
    the trace does not move)."""

    def __init__(self):
        self.traces: list[dict] = []
        self.recipes: list[dict | None] = []

    def add(self, trace: dict, recipe: dict | None = None) -> int:
        self.traces.append(trace)
        self.recipes.append(recipe)
        return len(self.traces) - 1


def _lines(segments: list[np.ndarray]) -> tuple[list, list, list]:
    """x, y, z of polylines separated by None (plotly's gaps)."""
    xs, ys, zs = [], [], []
    for seg in segments:
        for p in seg:
            xs.append(float(p[0]))
            ys.append(float(p[1]))
            zs.append(float(p[2]))
        xs.append(None)
        ys.append(None)
        zs.append(None)
    return xs, ys, zs


def _carrier(scene: Scene, part: str) -> int:
    names = scene.part_names
    return names.index(part) if part in names else GROUND


def _rigid(scene: Scene, segments: list[tuple[str, np.ndarray]]) -> tuple[dict, list]:
    """Coordinates and recipe of polylines each carried by one part."""
    xyz = _lines([seg for _, seg in segments])
    carriers = []
    for part, seg in segments:
        carriers += [_carrier(scene, part)] * len(seg) + [GAP]
    return dict(zip("xyz", xyz)), carriers


def part_traces(t: Traces, scene: Scene, model: str, group: str) -> list[int]:
    """Each part's sticks and points (its hover names the points) and its hull: one trace
    of each for a part and its copy on an axle's other side (one colour, one legend entry)."""
    families: dict[str, list] = {}
    beams = {b.part for b in scene.beams}  # drawn through their nodes (view3d_beams)
    for p in scene.parts:
        if len(p.points_mm) and p.name not in beams:
            families.setdefault(p.name.removesuffix(scene_suffix(scene, p.name)), []).append(p)
    out = []
    for base, parts in families.items():
        segs, text, carriers = [], [], []
        for p in parts:
            for i, j in p.edges or [(k, k) for k in range(len(p.points_mm))]:
                segs.append(p.points_mm[[i, j]])
                text += [f"{p.name}: {p.labels[i]}", f"{p.name}: {p.labels[j]}", ""]
                carriers += [_carrier(scene, p.carriers[i]), _carrier(scene, p.carriers[j]),
                             GAP]
        xyz = dict(zip("xyz", _lines(segs)))
        colour = parts[0].colour
        out.append(t.add({"type": "scatter3d", "mode": "lines+markers", **xyz, "name": base,
                          "legendgroup": f"{group}:{base}", "text": text,
                          "hovertemplate": "%{text}<extra></extra>",
                          "line": {"color": colour, "width": 7},
                          "marker": {"color": colour, "size": 3}},
                         {"kind": "rigid", "model": model, "carriers": carriers}))
        hulls = [p for p in parts if p.triangles]
        if not hulls:
            continue
        pts = np.concatenate([p.points_mm for p in hulls])
        offsets = np.cumsum([0] + [len(p.points_mm) for p in hulls])
        tri = np.concatenate([np.array(p.triangles) + o for p, o in zip(hulls, offsets)])
        out.append(t.add({"type": "mesh3d", **{a: pts[:, k].tolist() for k, a in enumerate("xyz")},
                          **{a: tri[:, k].tolist() for k, a in enumerate("ijk")},
                          "color": colour, "opacity": 0.25, "name": base,
                          "legendgroup": f"{group}:{base}", "showlegend": False,
                          "hovertemplate": f"{base}<extra></extra>", "flatshading": True},
                         {"kind": "rigid", "model": model, "carriers": [
                             _carrier(scene, c) for p in hulls for c in p.carriers]}))
    return out


def scene_suffix(scene: Scene, name: str) -> str:
    """The axle's other-side suffix of a part name ("" when it has none)."""
    for other in scene.part_names:
        if name != other and name.startswith(other + "_"):
            return name[len(other):]
    return ""


def _item_points(t: Traces, scene: Scene, model: str, items: list[SceneItem], name: str,
                 marker: dict, group: str) -> int:
    pts = [(i.carriers[0], i.points_mm[:1]) for i in items]
    xyz, carriers = _rigid(scene, pts)
    text = [x for i in items for x in (i.text, "")]
    return t.add({"type": "scatter3d", "mode": "markers", **xyz, "name": name,
                  "legendgroup": f"{group}:{name}", "text": text,
                  "hovertemplate": "%{text}<extra></extra>", "marker": marker},
                 {"kind": "rigid", "model": model, "carriers": carriers})


def connection_traces(t: Traces, scene: Scene, model: str, group: str) -> list[int]:
    """Joints by kind (markers), joint axes, bushings (coloured by deflection) with their
    frames, links, dampers (a thick line under the coil of a coil-over), springs, stops."""
    out = []
    joints = [i for i in scene.items if i.kind not in ITEM_KINDS]
    for kind in dict.fromkeys(i.kind for i in joints):
        mine = [i for i in joints if i.kind == kind]
        out.append(_item_points(t, scene, model, mine, f"{kind} joints",
                                {"symbol": JOINT_SYMBOLS.get(kind, OTHER_JOINT_SYMBOL),
                                 "size": 6, "color": "#222",
                                 "line": {"color": "#222", "width": 1}}, group))
    axes = [(i.carriers[0], np.array([i.points_mm[0] - AXIS_MM * i.frame[:, 2],
                                      i.points_mm[0] + AXIS_MM * i.frame[:, 2]]))
            for i in scene.items if i.kind in AXIS_KINDS and i.frame is not None]
    if axes:
        xyz, carriers = _rigid(scene, axes)
        out.append(t.add({"type": "scatter3d", "mode": "lines", **xyz, "name": "joint axes",
                          "legendgroup": f"{group}:joint axes", "hoverinfo": "skip",
                          "line": {"color": "#555", "width": 3}},
                         {"kind": "rigid", "model": model, "carriers": carriers}))
    out += bushing_traces(t, scene, model, group)
    for kind, style in (("link", {"color": "#333", "width": 6}),
                        ("damper", {"color": "#8b0000", "width": 12}),
                        ("bump stop", {"width": 10}), ("rebound stop", {"width": 10})):
        mine = [i for i in scene.items if i.kind == kind]
        if not mine:
            continue
        xyz, _ = _rigid(scene, [(i.carriers[0], i.points_mm) for i in mine])
        carriers = [c for i in mine for c in (_carrier(scene, i.carriers[0]),
                                              _carrier(scene, i.carriers[1]), GAP)]
        recipe = {"kind": "rigid", "model": model, "carriers": carriers}
        line = dict(style)
        if kind.endswith("stop"):  # grey, red in contact
            recipe.update(stops=[i.name for i in mine])
            line.update(color=[0.0] * len(carriers), colorscale=[[0, "#9a9a9a"], [1, "#d62728"]],
                        cmin=0.0, cmax=1.0)
        out.append(t.add({"type": "scatter3d", "mode": "lines", **xyz, "name": f"{kind}s",
                          "legendgroup": f"{group}:{kind}", "text": [
                              x for i in mine for x in (i.text, i.text, "")],
                          "hovertemplate": "%{text}<extra></extra>", "line": line}, recipe))
    springs = [i for i in scene.items if i.kind == "spring"]
    if springs:
        ends = [[_carrier(scene, i.carriers[0]), *i.points_mm[0].tolist(),
                 _carrier(scene, i.carriers[1]), *i.points_mm[1].tolist(),
                 float(np.clip(COIL_RADIUS_PER_LENGTH * np.linalg.norm(
                     i.points_mm[1] - i.points_mm[0]), *COIL_RADIUS_MM))] for i in springs]
        out.append(t.add({"type": "scatter3d", "mode": "lines", "x": [], "y": [], "z": [],
                          "name": "springs", "legendgroup": f"{group}:springs",
                          "hoverinfo": "skip", "line": {"color": "#2f4f4f", "width": 4}},
                         {"kind": "helix", "model": model, "ends": ends,
                          "turns": COIL_TURNS}))
    return out


def bushing_traces(t: Traces, scene: Scene, model: str, group: str) -> list[int]:
    """The bushings as markers coloured by deflection and as their frames (x y z axes)."""
    bushings = [i for i in scene.items if i.kind == "bushing"]
    if not bushings:
        return []
    marker = {"size": 9, "color": [0.0] * len(bushings), "colorscale": DEFLECTION_SCALE,
              "reversescale": True,  # plotly's YlOrRd runs from red to yellow
              "cmin": 0.0, "cmax": 1.0, "line": {"color": "#222", "width": 1},
              "colorbar": {"title": {"text": "bushing deflection [mm]", "side": "top"},
                           "orientation": "h", "len": 0.3, "x": 0.02, "xanchor": "left",
                           "y": 0.02, "yanchor": "bottom", "thickness": 10}}
    points = _item_points(t, scene, model, bushings, "bushings", marker, group)
    t.recipes[points].update(bushings=[i.name for i in bushings])
    triads = [(i.carriers[0], np.array([i.points_mm[0], i.points_mm[0] + TRIAD_MM * i.frame[:, a]]))
              for i in bushings for a in range(3)]
    xyz, carriers = _rigid(scene, triads)
    colour = [a / 2.0 for _ in bushings for a in range(3) for _ in range(3)]
    frames = t.add({"type": "scatter3d", "mode": "lines", **xyz, "name": "bushing frames",
                    "legendgroup": f"{group}:bushing frames", "hoverinfo": "skip",
                    "line": {"color": colour, "width": 4, "cmin": 0.0, "cmax": 1.0,
                             "colorscale": [[0, "#e41a1c"], [0.5, "#4daf4a"], [1, "#377eb8"]]}},
                   {"kind": "rigid", "model": model, "carriers": carriers})
    return [points, frames]


def _circle(centre, axis, radius, n=48) -> np.ndarray:
    a = np.asarray(axis, float) / np.linalg.norm(axis)
    e1 = np.cross(a, [0.0, 0.0, 1.0])
    e1 = e1 / np.linalg.norm(e1) if np.linalg.norm(e1) > 1e-9 else np.array([1.0, 0.0, 0.0])
    e2 = np.cross(a, e1)
    th = np.linspace(0.0, 2 * np.pi, n + 1)
    return centre + radius * (np.cos(th)[:, None] * e1 + np.sin(th)[:, None] * e2)


def wheel_traces(t: Traces, scene: Scene, model: str, group: str) -> list[int]:
    """Each tyre (a translucent band between its two sidewall circles), its rim, spin axis
    and contact patch, carried by the wheel part."""
    if not scene.wheels:
        return []
    band_x, band_i, rims, patches = [], [], [], []
    for w in scene.wheels:
        half = 0.5 * w.width_mm * w.spin_axis
        inner, outer = (_circle(w.centre_mm + s * half, w.spin_axis, w.radius_mm)[:-1]
                        for s in (-1.0, 1.0))
        n, base = len(inner), len(band_x)
        band_x += [(w.part, p) for p in np.concatenate([inner, outer])]
        for k in range(n):
            a, b, c, d = base + k, base + (k + 1) % n, base + n + k, base + n + (k + 1) % n
            band_i += [(a, b, c), (b, d, c)]
        for s in (-1.0, 1.0):
            rims.append((w.part, _circle(w.centre_mm + s * half, w.spin_axis, w.radius_mm)))
        rims.append((w.part, _circle(w.centre_mm, w.spin_axis, 0.6 * w.radius_mm, 24)))
        rims.append((w.part, np.array([w.centre_mm - half, w.centre_mm + 1.4 * half])))
        fwd = np.cross(w.spin_axis, [0.0, 0.0, 1.0])
        fwd = fwd / np.linalg.norm(fwd) * 0.6 * w.width_mm
        c = w.contact_patch_mm
        patches.append((w.part, np.array([c - fwd - half, c + fwd - half, c + fwd + half,
                                          c - fwd + half, c - fwd - half])))
    x, y, z = (np.array([p for _, p in band_x])[:, a].tolist() for a in range(3))
    i, j, k = (list(c) for c in zip(*band_i))
    out = [t.add({"type": "mesh3d", "x": x, "y": y, "z": z, "i": i, "j": j, "k": k,
                  "color": "#3a3a3a", "opacity": 0.18, "name": "wheels and tyres",
                  "legendgroup": f"{group}:wheels", "hoverinfo": "skip", "flatshading": True,
                  "showlegend": True},
                 {"kind": "rigid", "model": model,
                  "carriers": [_carrier(scene, part) for part, _ in band_x]})]
    xyz, carriers = _rigid(scene, rims)
    out.append(t.add({"type": "scatter3d", "mode": "lines", **xyz, "name": "wheels and tyres",
                      "legendgroup": f"{group}:wheels", "showlegend": False,
                      "hoverinfo": "skip", "line": {"color": "#222", "width": 3}},
                     {"kind": "rigid", "model": model, "carriers": carriers}))
    xyz, carriers = _rigid(scene, patches)
    out.append(t.add({"type": "scatter3d", "mode": "lines", **xyz, "name": "contact patches",
                      "legendgroup": f"{group}:patches", "hoverinfo": "skip",
                      "line": {"color": "#000", "width": 6}},
                     {"kind": "rigid", "model": model, "carriers": carriers}))
    return out


def kinematic_traces(t: Traces, scene: Scene, model: str, group: str) -> list[int]:
    """The steering axes, the front-view instant centres, the roll centre and the lines from
    each contact point through its instant centre to it (coordinates per frame)."""
    if not scene.wheels:
        return []
    empty = {"x": [], "y": [], "z": []}
    specs = (("steering axes", "axis", {"mode": "lines", "line": {"color": "#7b3294",
                                                                  "width": 6,
                                                                  "dash": "dash"}}),
             ("instant centres", "ic", {"mode": "markers", "marker": {
                 "symbol": "cross", "size": 6, "color": "#008080"}}),
             ("roll centre", "rc", {"mode": "markers", "marker": {
                 "symbol": "diamond", "size": 8, "color": "#008080"}}),
             ("roll-centre lines", "rcl", {"mode": "lines", "line": {
                 "color": "#008080", "width": 2, "dash": "dot"}}))
    return [t.add({"type": "scatter3d", **empty, **style, "name": name,
                   "legendgroup": f"{group}:{key}", "hovertemplate": f"{name}<br>"
                   "[%{x:.1f}, %{y:.1f}, %{z:.1f}] mm<extra></extra>"},
                  {"kind": key, "model": model}) for name, key, style in specs]


def ghost_trace(t: Traces, scene: Scene, model: str, colour: str) -> int:
    """A model's outline (every part's sticks and the wheels' sidewalls), for overlays."""
    segs = [p.points_mm[[i, j]] for p in scene.parts for i, j in p.edges]
    carriers = [c for p in scene.parts for i, j in p.edges
                for c in (_carrier(scene, p.carriers[i]), _carrier(scene, p.carriers[j]), GAP)]
    for w in scene.wheels:
        segs.append(_circle(w.centre_mm + 0.5 * w.width_mm * w.spin_axis, w.spin_axis,
                            w.radius_mm, 36))
        carriers += [_carrier(scene, w.part)] * 37 + [GAP]
    xyz = dict(zip("xyz", _lines(segs)))
    return t.add({"type": "scatter3d", "mode": "lines", **xyz, "name": f"{model} (outline)",
                  "legendgroup": f"ghost:{model}", "visible": "legendonly",
                  "hoverinfo": "name", "line": {"color": colour, "width": 3, "dash": "dash"}},
                 {"kind": "rigid", "model": model, "carriers": carriers, "ghost": True})


def static_traces(t: Traces, scene: Scene, group: str) -> list[int]:
    """The ground's pickups and the hardpoints no item uses (they do not move)."""
    out = []
    for name, labels, pts, marker in (
            (f"ground ({scene.ground}) pickups", scene.ground_labels, scene.ground_mm,
             {"symbol": "square", "size": 5, "color": "#000"}),
            ("other hardpoints", scene.loose_labels, scene.loose_mm,
             {"symbol": "circle-open", "size": 4, "color": "#888"})):
        if len(pts):
            out.append(t.add({"type": "scatter3d", "mode": "markers", "x": pts[:, 0].tolist(),
                              "y": pts[:, 1].tolist(), "z": pts[:, 2].tolist(), "name": name,
                              "legendgroup": f"{group}:{name}", "text": list(labels),
                              "hovertemplate": "%{text}<br>[%{x:.1f}, %{y:.1f}, %{z:.1f}] mm"
                              "<extra></extra>", "marker": marker}))
    return out
