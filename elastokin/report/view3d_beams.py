"""Flexible (beam) parts in the 3D view (:mod:`elastokin.report.view3d`): each drawn through
its node line's nodes as the model solved them (true positions: the line meets the parts it
is welded to), with a band from each node to the shear centre that turns with the section.
A twist beam's twist is a few degrees: the band's turn away from the beam's mean rotation
(its rigid motion) is drawn magnified by a round factor the legend states
(:func:`twist_factor`), as the identification's shifts are. Config frame, mm, deg.
"""

from __future__ import annotations

import numpy as np

from elastokin.identification.overlay import magnification
from elastokin.physics.beams import magnified_rotations, twist_deg
from elastokin.report.view3d_traces import Traces
from elastokin.rig.scene import Scene, SceneBeam
from elastokin.rig.scene_motion import SceneFrames

#: the largest magnified twist of a view (a node's turn from the beam's mean rotation) is
#: drawn at most this large (deg)
TWIST_DRAWN_DEG = 30.0


def twist_factor(frames: list[SceneFrames]) -> float:
    """The round factor (:func:`~elastokin.identification.overlay.magnification`: 1, 2 or 5
    times a power of ten, at least 1) that draws the largest twist of every beam in
    ``frames`` at most :data:`TWIST_DRAWN_DEG`."""
    largest = max((float(np.nanmax(twist_deg(R))) for f in frames
                   for R in f.beam_rotation.values() if R.size), default=0.0)
    return magnification(largest, TWIST_DRAWN_DEG)


def band_edge_mm(beam: SceneBeam, positions: np.ndarray, rotations: np.ndarray,
                 factor: float) -> np.ndarray:
    """The band's far edge (k, m, 3) at each frame: each node's position plus its band turned
    by the node's rotation with its twist magnified ``factor`` times."""
    R = magnified_rotations(rotations, factor) if factor != 1.0 else np.asarray(rotations)
    return positions + np.einsum("kmij,mj->kmi", R, beam.band_mm)


def beam_payload(scene: Scene, f: SceneFrames, factor: float) -> dict:
    """The page's data of the beams at the frames of one load case: per beam part its nodes
    (``line``) and its band's edge (``edge``), (frames, m, 3) flattened, mm."""
    out = {}
    for b in scene.beams:
        if b.part not in f.beam_mm:
            continue
        x = f.beam_mm[b.part]
        out[b.part] = {"line": np.round(x, 2).ravel().tolist(),
                       "edge": np.round(band_edge_mm(b, x, f.beam_rotation[b.part], factor),
                                        2).ravel().tolist()}
    return out


def beam_traces(t: Traces, scene: Scene, model: str, group: str, factor: float) -> list[int]:
    """Each beam part: its node line (the part's colour, its nodes named on hover), its band
    (translucent) and the band's edge: coordinates per frame (``view3d.js``, recipe
    ``beam``)."""
    out = []
    for b in scene.beams:
        x = b.nodes_mm
        edge = x + b.band_mm
        m = len(x)
        recipe = {"kind": "beam", "model": model, "part": b.part}
        legend = f"{group}:{b.part}"
        out.append(t.add({"type": "scatter3d", "mode": "lines+markers",
                          **{a: x[:, k].tolist() for k, a in enumerate("xyz")}, "name": b.part,
                          "legendgroup": legend, "text": [f"{b.part}: {lab}" for lab in b.labels],
                          "hovertemplate": "%{text}<extra></extra>",
                          "line": {"color": b.colour, "width": 9},
                          "marker": {"color": b.colour, "size": 3}}, {**recipe, "what": "line"}))
        name = f"{b.part} twist x{factor:g}"
        band = np.concatenate([x, edge])
        tri = [(k, k + 1, m + k) for k in range(m - 1)] + \
            [(k + 1, m + k + 1, m + k) for k in range(m - 1)]
        out.append(t.add({"type": "mesh3d", **{a: band[:, k].tolist() for k, a in enumerate("xyz")},
                          **{a: [int(v[k]) for v in tri] for k, a in enumerate("ijk")},
                          "color": b.colour, "opacity": 0.45, "name": name,
                          "legendgroup": f"{legend}:band", "showlegend": True,
                          "hovertemplate": f"{b.part}: its section from the node line to "
                          f"the shear centre, turned by its twist x{factor:g}<extra></extra>",
                          "flatshading": True},
                         {**recipe, "what": "band"}))
        out.append(t.add({"type": "scatter3d", "mode": "lines",
                          **{a: edge[:, k].tolist() for k, a in enumerate("xyz")}, "name": name,
                          "legendgroup": f"{legend}:band", "showlegend": False,
                          "hoverinfo": "skip", "line": {"color": b.colour, "width": 3}},
                         {**recipe, "what": "edge"}))
    return out
