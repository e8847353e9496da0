"""Loads in the 3D view (:mod:`elastokin.report.view3d`): at every frame of a load case, the
load each body pickup receives (an arrow from the pickup along the force on the body) and
the rig's load on each tyre (an arrow from the contact patch along the force on the tyre),
drawn at one scale per view that the legend states (:func:`arrow_scale`); and each pickup's
worst case (the largest force of the model's load cases, as summary.json's ``pickups``),
which the page's picker jumps to. The loads are those of loads.csv (:mod:`elastokin.rig
.loads`). Config frame; N, mm.
"""

from __future__ import annotations

import numpy as np

from elastokin.physics.loads import peak_step
from elastokin.report.view3d_traces import Traces
from elastokin.rig.scene_motion import SceneFrames

#: the largest force of a view is drawn at most this fraction of the scene's longest side
ARROW_FRACTION = 0.2
#: the colours of the pickups' arrows and of the contact patches'
PICKUP_COLOUR, PATCH_COLOUR = "#c51b7d", "#4d9221"
#: the arrows' place in the legend: before the rest (plotly's default rank is 1000)
LEGEND_RANK = 900


def arrow_scale(frames: list[SceneFrames], longest_mm: float) -> float:
    """mm per kN: a round number (1, 2 or 5 times a power of ten) that draws the largest
    force of ``frames`` (pickups and contact patches) at most :data:`ARROW_FRACTION` of
    ``longest_mm`` (the scene's longest side) long; 1 when there are none."""
    largest = max((float(np.nanmax(np.linalg.norm(v, axis=-1))) for f in frames
                   for v in (*f.pickup_N.values(), *f.patch_load_N.values()) if v.size),
                  default=0.0)
    if not largest > 0:
        return 1.0
    room = ARROW_FRACTION * longest_mm * 1e3 / largest  # mm per kN at most
    k = np.floor(np.log10(room))
    return float(max(m for m in (1.0, 2.0, 5.0) if m * 10.0 ** k <= room) * 10.0 ** k)


def arrow_tips_mm(frames: list[SceneFrames], mm_per_N: float) -> np.ndarray:
    """Every arrow's tip at every frame (n, 3), mm: the view's box holds them."""
    tips = [p + mm_per_N * f.pickup_N[n] for f in frames for n, p in f.pickup_mm.items()]
    tips += [f.patch_load_mm[n] + mm_per_N * v for f in frames
             for n, v in f.patch_load_N.items()]
    tips = [t.reshape(-1, 3) for t in tips]
    return np.concatenate(tips) if tips else np.zeros((0, 3))


def loads_payload(f: SceneFrames) -> dict:
    """One load case's loads as the page carries them: each pickup's force (``pickup``,
    (frames, 3) flattened, N) and each contact patch's force and point (``patch``)."""
    if not f.pickup_N and not f.patch_load_N:
        return {}
    return {"pickup": {n: np.round(v, 1).ravel().tolist() for n, v in f.pickup_N.items()},
            "patch": {n: {"f": np.round(v, 1).ravel().tolist(),
                          "at": np.round(f.patch_load_mm[n], 2).ravel().tolist()}
                      for n, v in f.patch_load_N.items()}}


def worst_cases(frames: list[SceneFrames]) -> list[dict]:
    """Each loaded pickup's worst case over a model's load cases: the frame of its largest
    force (``case``, ``frame``; ``step`` 1-based as loads.csv numbers them; ``force_N``),
    the largest first (a pickup that never carries a load, a stop never touched, left
    out)."""
    worst: dict[str, dict] = {}
    for f in frames:
        for name, v in f.pickup_N.items():
            i, force = peak_step(np.linalg.norm(v, axis=1))
            if name not in worst or force > worst[name]["force_N"]:
                worst[name] = {"pickup": name, "case": f.load_case, "frame": i,
                               "step": int(f.steps[i]) + 1, "force_N": round(force, 1)}
    return sorted((w for w in worst.values() if w["force_N"] > 0), key=lambda w: -w["force_N"])


def pickup_points(frames: list[SceneFrames]) -> dict[str, list[float]]:
    """Each pickup's point on the ground (mm)."""
    out: dict[str, list[float]] = {}
    for f in frames:
        for name, p in f.pickup_mm.items():
            out.setdefault(name, np.round(p, 2).tolist())
    return out


def load_traces(t: Traces, model: str, group: str, scale: float, pickups: list[str],
                patches: list[str]) -> list[int]:
    """The arrows of a model's body pickups and contact patches (coordinates and hover text
    per frame: ``view3d.js``, recipe ``arrows``); the legend states the scale."""
    out = []
    for what, names, colour, label in (("pickup", pickups, PICKUP_COLOUR, "pickup loads"),
                                       ("patch", patches, PATCH_COLOUR, "patch loads")):
        if not names:
            continue
        name = f"{label}, 1 kN = {scale:g} mm"
        out.append(t.add({"type": "scatter3d", "mode": "lines", "x": [], "y": [], "z": [],
                          "name": name, "legendgroup": f"{group}:{what} loads", "text": [],
                          "legendrank": LEGEND_RANK,
                          "hovertemplate": "%{text}<extra></extra>",
                          "line": {"color": colour, "width": 6}},
                         {"kind": "arrows", "model": model, "what": what,
                          "names": list(names)}))
    return out
