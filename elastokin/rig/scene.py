"""The 3D scene of a suspension as plain data (pure numpy; drawn by
:mod:`elastokin.report.view3d`): every moving part as the body between its points (sticks and
its convex hull), the ground's pickups, every connection (joints by kind, bushings with their
frames, links), springs, dampers, stops, the anti-roll bar's torsion spring, the wheels with their
tyres and contact patches, and the hardpoints no item uses. Everything at the design
position, config frame, mm; each point is carried by one part (the ground's do not move), so
that a step of a load case is the parts' poses (:mod:`elastokin.rig.scene_motion`).

Made from a :class:`~elastokin.config.draft.SuspensionDraft`: a config with errors shows what
resolved, and its errors.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from elastokin.config.draft import SuspensionDraft
from elastokin.physics.beams import node_line

#: one colour per part (its mirrored copy on an axle's other side shares it)
PART_COLOURS = ("#1f77b4", "#ff7f0e", "#2ca02c", "#9467bd", "#8c564b", "#e377c2", "#17becf",
                "#bcbd22", "#d62728", "#7f7f7f", "#aec7e8", "#ffbb78", "#98df8a", "#c5b0d5")
#: the tyre's width drawn, as a fraction of its loaded radius (a config gives no width)
TYRE_WIDTH_PER_RADIUS = 0.7
#: points closer than this (mm) are one point of a part
SAME_POINT_MM = 1e-6
#: a beam's band drawn this wide (mm) along its section's z axis when its shear centre lies
#: on its node line (within 1 mm)
BAND_MM = 40.0


@dataclass(frozen=True)
class ScenePart:
    """A moving part: its points (design position, mm) with what each is (``labels``), the
    sticks between them (``edges``, index pairs) and its convex hull (``triangles``, index
    triples; none for fewer than 3 points or points on a line). ``carriers``: the part whose
    pose moves each point: the part itself, or for a flexible (beam) part, which has no one
    pose, the rigid part attached at that point (a beam part is drawn through its nodes,
    :class:`SceneBeam`: no sticks, no hull)."""

    name: str
    colour: str
    description: str
    labels: tuple[str, ...]
    points_mm: np.ndarray
    edges: tuple[tuple[int, int], ...]
    triangles: tuple[tuple[int, int, int], ...]
    carriers: tuple[str, ...] = ()


@dataclass(frozen=True)
class SceneItem:
    """A connection, spring, damper, stop or the anti-roll bar's torsion spring: ``points_mm``
    (design position) each carried by the part of the same index in ``carriers``; ``frame``
    (columns x y z, config frame) turns with ``carriers[0]``; ``kind``: the joint's kind,
    ``bushing``, ``link``, ``spring``, ``damper``, ``bump stop``, ``rebound stop`` or
    ``anti-roll bar``; ``text``: what it is, for the hover."""

    kind: str
    name: str
    parts: tuple[str, str]
    carriers: tuple[str, ...]
    points_mm: np.ndarray
    frame: np.ndarray | None
    text: str


@dataclass(frozen=True)
class SceneWheel:
    """A wheel on ``side``, carried by ``part``: centre, outboard spin axis, loaded radius,
    the tyre's drawn width (:data:`TYRE_WIDTH_PER_RADIUS`) and the contact patch."""

    side: str
    part: str
    centre_mm: np.ndarray
    spin_axis: np.ndarray
    radius_mm: float
    width_mm: float
    contact_patch_mm: np.ndarray


@dataclass(frozen=True)
class SceneBeam:
    """A flexible (beam) part drawn through its node line's nodes
    (:func:`~elastokin.physics.beams.node_line`): ``nodes_mm`` (m, 3) at the design position,
    ``labels`` (a named node's hardpoint, else its number), and a band from each node to the
    shear centre (``band_mm`` (m, 3), config frame: the shear centre's offset, or
    :data:`BAND_MM` along the section's z axis when it lies on the node line), which turns
    with the section: its twist."""

    part: str
    colour: str
    labels: tuple[str, ...]
    nodes_mm: np.ndarray
    band_mm: np.ndarray


@dataclass(frozen=True)
class Scene:
    """The scene of one suspension model (module docstring). ``ground_labels`` /
    ``ground_mm``: the ground's pickups; ``loose_labels`` / ``loose_mm``: hardpoints that no
    item uses; ``errors``: the config's errors (what did not resolve is not drawn)."""

    name: str
    source: str
    ground: str
    frame_text: str
    parts: tuple[ScenePart, ...]
    items: tuple[SceneItem, ...]
    wheels: tuple[SceneWheel, ...]
    ground_labels: tuple[str, ...] = ()
    ground_mm: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    loose_labels: tuple[str, ...] = ()
    loose_mm: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    errors: tuple[str, ...] = ()
    beams: tuple[SceneBeam, ...] = ()

    @property
    def part_names(self) -> tuple[str, ...]:
        return tuple(p.name for p in self.parts)

    def extent_mm(self) -> tuple[np.ndarray, np.ndarray]:
        """(lower, upper) corners of the box around every point drawn (mm)."""
        pts = [p.points_mm for p in self.parts] + [i.points_mm for i in self.items]
        pts += [self.ground_mm, self.loose_mm]
        for w in self.wheels:
            reach = w.radius_mm + 0.5 * w.width_mm
            pts.append(np.array([w.centre_mm - reach, w.centre_mm + reach, w.contact_patch_mm]))
        allp = np.concatenate([p.reshape(-1, 3) for p in pts if p.size])
        return allp.min(axis=0), allp.max(axis=0)


def _fmt(x) -> str:
    return "[" + ", ".join(f"{v:.1f}" for v in np.asarray(x, float)) + "]"


class _Points:
    """Points collected per part (merged within :data:`SAME_POINT_MM`), named by the
    hardpoint at the same place when there is one."""

    def __init__(self, hardpoints):
        self.names: dict[tuple, str] = {}
        for k, v in hardpoints.items():  # the first name of a place (a mirror may repeat it)
            self.names.setdefault(tuple(np.round(np.asarray(v, float), 6)), k)
        self.by_part: dict[str, list[tuple[str, np.ndarray]]] = {}
        self.used: set[str] = set()

    def name(self, x, fallback: str) -> str:
        name = self.names.get(tuple(np.round(np.asarray(x, float), 6)))
        if name is not None:
            self.used.add(name)
        return name or fallback

    def add(self, part: str, x, what: str) -> None:
        x = np.asarray(x, float)
        label = f"{self.name(x, what)} ({what})" if self.name(x, what) != what else what
        pts = self.by_part.setdefault(part, [])
        for k, (lab, y) in enumerate(pts):
            if np.linalg.norm(y - x) < SAME_POINT_MM:
                pts[k] = (f"{lab}; {what}", y)
                return
        pts.append((label, x))


def _hull(points: np.ndarray) -> tuple[tuple[int, int], ...] | tuple:
    """Triangles of the convex hull of 4 or more points (none when they are flat or on a
    line); 3 points not on a line are one triangle."""
    n = len(points)
    if n < 3:
        return ()
    centred = points - points.mean(axis=0)
    sv = np.linalg.svd(centred, compute_uv=False)
    if sv[1] < 1e-6 * max(sv[0], 1e-12):
        return ()
    if n == 3:
        return ((0, 1, 2),)
    from scipy.spatial import ConvexHull, QhullError

    try:
        hull = ConvexHull(points, qhull_options="QJ")
    except QhullError:  # pragma: no cover - QJ joggles degenerate inputs
        return ()
    return tuple(tuple(int(i) for i in t) for t in hull.simplices)


def _sticks(points: np.ndarray) -> tuple[tuple[int, int], ...]:
    """The sticks of a part: every pair of up to 4 points (a bar, a triangle, a
    tetrahedron); of more, the shortest tree joining them (minimum spanning tree)."""
    n = len(points)
    if n <= 4:
        return tuple((i, j) for i in range(n) for j in range(i + 1, n))
    from scipy.sparse.csgraph import minimum_spanning_tree

    d = np.linalg.norm(points[:, None, :] - points[None, :, :], axis=-1)
    tree = minimum_spanning_tree(d + 1e-9 * (d == 0) * (1 - np.eye(n))).tocoo()
    return tuple(sorted((int(min(i, j)), int(max(i, j))) for i, j in zip(tree.row, tree.col)))


def _joint_text(kind: str, name: str, parts, x) -> str:
    return f"{name}: {kind} joint, {parts[0]} / {parts[1]}, at {_fmt(x)} mm"


def scene_items(d: SuspensionDraft, pts: _Points) -> list[SceneItem]:
    """Every item of the draft, its points added to the parts that carry them."""
    items: list[SceneItem] = []
    for j in d.joints:
        kind = "rack" if d.axle is not None and d.axle.steering is not None and \
            j.name == d.axle.steering.joint else j.kind
        for p in j.parts:
            pts.add(p, j.position_mm, j.name)
        items.append(SceneItem(kind, j.name, j.parts, (j.parts[0],), j.position_mm[None, :],
                               np.asarray(j.frame), _joint_text(kind, j.name, j.parts,
                                                                j.position_mm)))
    for b in d.bushings:
        for p in b.parts:
            pts.add(p, b.position_mm, b.name)
        ideal = f"; modelled as its ideal {b.ideal_joint} joint" if b.kinematic else ""
        items.append(SceneItem("bushing", b.name, b.parts, (b.parts[0],),
                               b.position_mm[None, :], np.asarray(b.frame),
                               f"{b.name}: bushing, {b.parts[0]} / {b.parts[1]}, at "
                               f"{_fmt(b.position_mm)} mm (frame: x red, y green, z blue, "
                               f"on {b.parts[0]}){ideal}"))
    for lk in d.links:
        for p, x in zip(lk.parts, lk.points_mm):
            pts.add(p, x, lk.name)
        length = np.linalg.norm(lk.points_mm[1] - lk.points_mm[0])
        items.append(SceneItem("link", lk.name, lk.parts, lk.parts, np.array(lk.points_mm),
                               None, f"{lk.name}: link {lk.parts[0]} - {lk.parts[1]}, "
                               f"{length:.1f} mm"))
    for sp in d.springs:
        for p, x in zip(sp.parts, sp.seats_mm):
            pts.add(p, x, sp.name)
        items.append(SceneItem("spring", sp.name, sp.parts, sp.parts, np.array(sp.seats_mm),
                               None, f"{sp.name}: spring {sp.parts[0]} - {sp.parts[1]}, "
                               f"{sp.rate_N_per_mm:g} N/mm, installed length "
                               f"{sp.installed_length_mm:.1f} mm"))
    for dm in d.dampers:
        for p, x in zip(dm.parts, dm.points_mm):
            pts.add(p, x, dm.name)
        rate = f", {dm.rate_N_s_per_mm:g} N*s/mm" if dm.rate_N_s_per_mm is not None else ""
        items.append(SceneItem("damper", dm.name, dm.parts, dm.parts, np.array(dm.points_mm),
                               None, f"{dm.name}: damper {dm.parts[0]} - {dm.parts[1]}{rate}, "
                               f"installed length {dm.installed_length_mm:.1f} mm"))
    for st in d.stops:
        for p, x in zip(st.parts, st.points_mm):
            pts.add(p, x, st.name)
        items.append(SceneItem(f"{st.kind} stop", st.name, st.parts, st.parts,
                               np.array(st.points_mm), None,
                               f"{st.name}: {st.kind} stop {st.parts[0]} - {st.parts[1]}, "
                               f"contact after {st.clearance_mm:g} mm"))
    bar = d.axle.anti_roll_bar if d.axle is not None else None
    if bar is not None:
        for p in bar.parts:
            pts.add(p, bar.position_mm, "anti-roll bar")
        items.append(SceneItem("anti-roll bar", "anti_roll_bar", bar.parts, (bar.parts[0],),
                               bar.position_mm[None, :], np.asarray(bar.frame),
                               f"anti-roll bar torsion spring {bar.parts[0]} / {bar.parts[1]} "
                               f"at {_fmt(bar.position_mm)} mm"))
    return items


def scene_wheels(d: SuspensionDraft, pts: _Points) -> list[SceneWheel]:
    out = []
    for side, w in d.wheels.items():
        pts.add(w.part, w.centre_mm, f"wheel centre ({side})")
        out.append(SceneWheel(side, w.part, np.asarray(w.centre_mm), np.asarray(w.spin_axis),
                              float(w.loaded_radius_mm),
                              TYRE_WIDTH_PER_RADIUS * float(w.loaded_radius_mm),
                              np.asarray(w.contact_patch_mm)))
    return out


def _colours(names: list[str], suffix: str | None) -> dict[str, str]:
    """A colour per part; an axle's mirrored copy (``<name><suffix>``) takes its original's."""
    base = [n for n in names if not (suffix and n.endswith(suffix) and
                                     n.removesuffix(suffix) in names)]
    colour = {n: PART_COLOURS[k % len(PART_COLOURS)] for k, n in enumerate(base)}
    return {n: colour.get(n) or colour[n.removesuffix(suffix)] for n in names}


def _carrier(d: SuspensionDraft, part: str, x: np.ndarray, flexible: dict) -> str:
    """What moves point ``x`` of ``part``: the part, or for a flexible part the rigid part a
    joint or bushing attaches at ``x`` (the part itself when none does)."""
    if part not in flexible:
        return part
    for c in (*d.joints, *d.bushings):
        if part in c.parts and np.linalg.norm(c.position_mm - x) < SAME_POINT_MM:
            other = c.parts[1] if c.parts[0] == part else c.parts[0]
            if other not in flexible:
                return other
    return part


def build_scene(d: SuspensionDraft) -> Scene:
    """The scene of a config draft (module docstring)."""
    pts = _Points(d.hardpoints)
    items = scene_items(d, pts)
    wheels = scene_wheels(d, pts)
    for name, spec in d.parts.items():
        com = getattr(spec, "centre_of_mass", None)
        if com is not None and not isinstance(com, str):
            pts.add(name, com, "centre of mass")
        elif isinstance(com, str) and com in d.hardpoints:
            pts.add(name, d.hardpoints[com], "centre of mass")
    colours = _colours(list(d.parts), d.axle.suffix if d.axle is not None else None)
    flexible = {b.part: b for b in d.beams if not b.rigid}
    for b in flexible.values():  # its nodes are hardpoints the beam uses
        pts.used.update(b.node_names)
    parts = []
    for name in d.parts:
        found = pts.by_part.get(name, [])
        x = np.array([p for _, p in found]).reshape(-1, 3)
        carriers = tuple(_carrier(d, name, p, flexible) for p in x)
        about = getattr(d.parts[name], "description", "") + (
            " (flexible: drawn through its nodes)" if name in flexible else "")
        rigid = name not in flexible
        parts.append(ScenePart(name, colours[name], about, tuple(lab for lab, _ in found), x,
                               _sticks(x) if rigid else (), _hull(x) if rigid else (),
                               carriers))
    ground = pts.by_part.get(d.ground, [])
    loose = [k for k in d.hardpoints if k not in pts.used]
    frame = f"config frame: x {d.frame.x}, y {d.frame.y}, z {d.frame.z}"
    return Scene(d.name, d.source, d.ground, frame, tuple(parts), tuple(items), tuple(wheels),
                 tuple(lab for lab, _ in ground),
                 np.array([x for _, x in ground]).reshape(-1, 3), tuple(loose),
                 np.array([d.hardpoints[k] for k in loose], float).reshape(-1, 3), d.errors,
                 tuple(scene_beam(b, colours[b.part]) for b in flexible.values()))


def scene_beam(b, colour: str) -> SceneBeam:
    """The drawing of a flexible part ``b`` (:class:`~elastokin.config.suspension.Beam`)."""
    nodes, segment = node_line(b.nodes_mm, b.elements_per_segment)
    offset = np.asarray(b.shear_centre_mm, float)[segment]
    on_line = np.linalg.norm(offset, axis=1) < 1.0
    band = np.where(on_line[:, None], BAND_MM * np.asarray(b.frames, float)[segment, :, 2],
                    offset)
    per = b.elements_per_segment
    labels = tuple(b.node_names[k // per] if k % per == 0 else f"node {k + 1}"
                   for k in range(len(nodes)))
    return SceneBeam(b.part, colour, labels, nodes, band)
