"""The motion of a :class:`~elastokin.rig.scene.Scene` through a load case, as plain data:
at selected steps of a model's sweeps, every moving part's rigid transform, the bushings'
deflections, the stops' and springs' forces, and the kinematic figures drawn with the
parts: each wheel's steering axis (springs locked, :func:`~elastokin.rig.steering
.steering_skeleton`), its front-view instant centre (steering held, springs released:
:func:`~elastokin.rig.steering.travel_skeleton`) and the roll centre (the lines from each
contact point through its instant centre, :func:`~elastokin.physics.instant_centres
.kinematic_roll_centre`; a corner's with its mirror image). All three from the parts' poses
at the step (velocity level: ideal joints, bushings by their ideal joints), so the design
position has them too (:func:`design_frames`). Also each beam part's nodes (positions and
rotations), the load each body pickup receives and the rig's load at each contact patch
(the steps where a pickup's load peaks are among the frames). Config frame, mm, N, deg.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from elastokin.config.suspension import Suspension
from elastokin.physics.instant_centres import (
    front_view_instant_centre,
    kinematic_roll_centre,
    point_velocity,
)
from elastokin.physics.loads import FORCE, MOMENT, POINT, ground_loads, peak_step
from elastokin.physics.states import LoadTable, PartPoses, PoseSeries
from elastokin.physics.steering_axis import steering_axes_from_poses
from elastokin.physics.steering_geometry import axis_ground_point, contact_point
from elastokin.rig.axle_channels import iso_rotation
from elastokin.rig.channels import LOAD_CASES
from elastokin.rig.item_channels import bushing_columns, spring_column, stop_column
from elastokin.rig.loads import PICKUP_KINDS
from elastokin.rig.scene import Scene
from elastokin.rig.steering import steering_skeleton, travel_skeleton
from elastokin.rig.sweeps import Sweep

#: at most this many frames of a load case (steps picked evenly, branch ends kept)
MAX_FRAMES = 61
#: the steering axis is drawn from the ground up to this multiple of the loaded radius
AXIS_HEIGHT_PER_RADIUS = 1.6


@dataclass
class SceneFrames:
    """One model at some steps of one load case (``steps``: indices of the sweep's
    ``total_steps``). Per frame: the branch, the case's input (``input_column``), each
    wheel's toe, camber (deg) and travel (mm), each moving part's transform (``x_now =
    rotation @ x + translation_mm`` for a point x at the design position), each bushing's
    deflection (translation magnitude mm, rotation magnitude deg), each stop's and spring's
    force (N), each wheel's steering axis (two points: on the ground, and above), contact
    point and front-view instant centre, and the roll centre (NaN where undefined)."""

    model: str
    load_case: str
    steps: np.ndarray
    total_steps: int
    branch: list[str] = field(default_factory=list)
    input_column: str | None = None
    input_values: np.ndarray | None = None
    wheel: dict[str, np.ndarray] = field(default_factory=dict)  # side -> (k, 3) toe camber travel
    rotation: dict[str, np.ndarray] = field(default_factory=dict)
    translation_mm: dict[str, np.ndarray] = field(default_factory=dict)
    bushing_mm: dict[str, np.ndarray] = field(default_factory=dict)
    bushing_deg: dict[str, np.ndarray] = field(default_factory=dict)
    stop_force_N: dict[str, np.ndarray] = field(default_factory=dict)
    spring_force_N: dict[str, np.ndarray] = field(default_factory=dict)
    steering_axis_mm: dict[str, np.ndarray] = field(default_factory=dict)
    instant_centre_mm: dict[str, np.ndarray] = field(default_factory=dict)
    contact_mm: dict[str, np.ndarray] = field(default_factory=dict)
    roll_centre_mm: np.ndarray | None = None
    #: each beam part's node line: positions (k, m, 3) and rotations from the design position
    #: (k, m, 3, 3) of its nodes (:class:`~elastokin.rig.scene.SceneBeam`'s)
    beam_mm: dict[str, np.ndarray] = field(default_factory=dict)
    beam_rotation: dict[str, np.ndarray] = field(default_factory=dict)
    #: the load each body pickup receives (k, 3) N, at its point (3,) mm on the ground
    #: (:func:`~elastokin.physics.loads.ground_loads`, :data:`~elastokin.rig.loads
    #: .PICKUP_KINDS`)
    pickup_N: dict[str, np.ndarray] = field(default_factory=dict)
    pickup_mm: dict[str, np.ndarray] = field(default_factory=dict)
    #: the rig's load on each tyre (k, 3) N at its contact patch (k, 3) mm, by its load item
    patch_load_N: dict[str, np.ndarray] = field(default_factory=dict)
    patch_load_mm: dict[str, np.ndarray] = field(default_factory=dict)

    @property
    def frames(self) -> int:
        return len(self.steps)


def frame_steps(branch: np.ndarray, most: int = MAX_FRAMES, keep=()) -> np.ndarray:
    """Up to ``most`` step indices evenly spread over a sweep, every branch's first and last
    step kept (where the rig turns), and the steps ``keep`` (e.g. where a load peaks)."""
    n = len(branch)
    if n <= most:
        return np.arange(n)
    b = np.asarray(branch)
    ends = np.flatnonzero(np.r_[True, b[1:] != b[:-1]] | np.r_[b[1:] != b[:-1], True])
    room = max(most - ends.size, 2)
    even = np.round(np.linspace(0, n - 1, room)).astype(int)
    return np.unique(np.r_[ends, even, np.asarray(keep, int)])


def _pose_list(poses: PoseSeries, steps: np.ndarray) -> list[PartPoses]:
    return [poses.at(int(i)) for i in steps]




def kinematics(s: Suspension, poses: list[PartPoses], frames: SceneFrames) -> None:
    """Each wheel's steering axis and front-view instant centre and the roll centre at the
    ``poses`` (one per frame) into ``frames`` (module docstring)."""
    T = iso_rotation(s)
    contact, velocity = {}, {}
    for side in s.sides:
        sv = s.on_side(side)
        w = sv.wheel
        R, t = _wheel_transform(poses, w.part)
        centre = np.einsum("sij,j->si", R, w.centre_mm) + t
        spin = np.einsum("sij,j->si", R, w.spin_axis)
        patch = contact_point(centre, spin, w.loaded_radius_mm, sv.up)
        steer = steering_axes_from_poses(steering_skeleton(sv), poses, centre)
        ground = axis_ground_point(steer.point, steer.direction, patch, sv.up)
        top = ground + AXIS_HEIGHT_PER_RADIUS * w.loaded_radius_mm * steer.direction \
            / np.maximum(steer.direction @ sv.up, 1e-3)[:, None]
        frames.steering_axis_mm[side] = np.stack([ground, top], axis=1)
        travel = steering_axes_from_poses(travel_skeleton(sv), poses, centre)
        omega = travel.direction @ T.T  # ISO frame; rad per unit input (any scale)
        v = (travel.pitch_mm_per_rad[:, None] * travel.direction) @ T.T
        at = travel.point @ T.T
        ic = front_view_instant_centre(np.degrees(omega), v, at, side, centre @ T.T)
        iso = np.stack([(centre @ T.T)[:, 0], ic.horizontal_mm, ic.z_mm], axis=1)
        frames.instant_centre_mm[side] = iso @ T
        frames.contact_mm[side] = patch
        contact[side] = patch @ T.T
        velocity[side] = point_velocity(np.degrees(omega), v, at, contact[side])
    if "right" not in contact:  # a corner: the roll centre of it and its mirror image
        side = next(iter(contact))
        flip = np.array([1.0, -1.0, 1.0])
        contact["right" if side == "left" else "left"] = contact[side] * flip
        velocity["right" if side == "left" else "left"] = velocity[side] * flip
    rc = kinematic_roll_centre(contact["left"], velocity["left"], contact["right"],
                               velocity["right"])
    ground_z = 0.5 * (contact["left"][:, 2] + contact["right"][:, 2])
    x = 0.5 * (contact["left"][:, 0] + contact["right"][:, 0])
    frames.roll_centre_mm = np.stack([x, rc.lateral_mm, rc.height_mm + ground_z], axis=1) @ T


def _wheel_transform(poses: list[PartPoses], part: str) -> tuple[np.ndarray, np.ndarray]:
    if part not in poses[0].rotation:
        return np.broadcast_to(np.eye(3), (len(poses), 3, 3)), np.zeros((len(poses), 3))
    R = np.array([p.rotation[part] for p in poses])
    ref = poses[0].reference_mm[part]
    t = ref + np.array([p.displacement_mm[part] for p in poses]) - R @ ref
    return R, t


def _column(sweeps: list[Sweep], name: str, steps: np.ndarray) -> np.ndarray | None:
    for sw in sweeps:
        if name in sw.columns:
            return np.asarray(sw.columns[name], float)[steps]
    return None


def _rig_columns(sweeps: list[Sweep], frames: SceneFrames) -> None:
    """The branch, the case's input and each wheel's toe, camber and travel per frame."""
    steps = frames.steps
    frames.branch = [str(b) for b in np.asarray(sweeps[0].columns["branch"])[steps]]
    case = LOAD_CASES.get(frames.load_case)
    if case is not None:
        frames.input_column = case.input
        frames.input_values = _column(sweeps, case.input, steps)
    for sw in sweeps:
        cols = [sw.columns.get(c) for c in ("toe_deg", "camber_deg", "wheel_travel_mm")]
        if all(c is not None for c in cols):
            frames.wheel[sw.side] = np.array([np.asarray(c, float)[steps] for c in cols]).T


def sweep_frames(s: Suspension, scene: Scene, sweeps: list[Sweep],
                 most: int = MAX_FRAMES) -> SceneFrames | None:
    """The frames of one model's sweeps of one load case (every wheel's; the config side's
    first) on the model's suspension ``s``; None when the sweeps carry no part poses."""
    first = sweeps[0]
    if first.poses is None or first.poses.steps != first.steps:
        return None
    loads = scene_loads(first.loads)
    peaks = [peak_step(np.linalg.norm(v[:, 0], axis=1))[0] for v in loads[0].values()]
    steps = frame_steps(first.columns["branch"], most, peaks)
    poses = _pose_list(first.poses, steps)
    frames = SceneFrames(first.model, first.load_case, steps, first.steps)
    _rig_columns(sweeps, frames)
    for p in scene.part_names:
        R, t = first.poses.transforms(p, steps)
        frames.rotation[p], frames.translation_mm[p] = np.array(R), t
    for b in scene.beams:
        if b.part in first.poses.node_mm:
            frames.beam_mm[b.part] = first.poses.node_mm[b.part][steps]
            frames.beam_rotation[b.part] = first.poses.node_rotation[b.part][steps]
    pickups, patches = loads
    for name, v in pickups.items():
        frames.pickup_N[name], frames.pickup_mm[name] = v[steps, 0], v[0, 2]
    for name, v in patches.items():
        frames.patch_load_N[name], frames.patch_load_mm[name] = v[steps, 0], v[steps, 2]
    for b in s.bushings:
        cols = [_column(sweeps, c, steps) for c in bushing_columns(b.name)]
        if all(c is not None for c in cols):
            u = np.array(cols).T
            frames.bushing_mm[b.name] = np.linalg.norm(u[:, :3], axis=1)
            frames.bushing_deg[b.name] = np.linalg.norm(u[:, 3:], axis=1)
    for st in s.stops:
        f = _column(sweeps, stop_column(st.name), steps)
        if f is not None:
            frames.stop_force_N[st.name] = f
    for sp in s.springs:
        f = _column(sweeps, spring_column(sp.name), steps)
        if f is not None:
            frames.spring_force_N[sp.name] = f
    kinematics(s, poses, frames)
    return frames


def scene_loads(table: LoadTable | None) -> tuple[dict[str, np.ndarray], dict[str, np.ndarray]]:
    """(each body pickup's load, each contact patch's load) at every step of a sweep's load
    table, by item: (steps, 3, 3) force N, moment N*mm (about its point), point mm. A pickup's
    is what the ground receives (:func:`~elastokin.physics.loads.ground_loads`), a contact
    patch's what the rig applies to the tyre. Empty without loads."""
    if table is None:
        return {}, {}
    pickups = ground_loads(table, table.ground, PICKUP_KINDS)
    patches = {item.name: table.values[:, k, [FORCE, MOMENT, POINT]]
               for k, item in enumerate(table.items) if item.kind == "contact_patch"}
    return pickups, patches


def design_frames(scene: Scene, s: Suspension | None, label: str = "design") -> SceneFrames:
    """The design position as one frame: no part moved, each bushing at its initial
    deflection; the steering axes, instant centres and roll centre when the whole suspension
    resolved (``s``)."""
    frames = SceneFrames(label, "design_position", np.zeros(1, int), 1, ["design"])
    for p in scene.part_names:
        frames.rotation[p] = np.eye(3)[None]
        frames.translation_mm[p] = np.zeros((1, 3))
    for b in scene.beams:
        frames.beam_mm[b.part] = b.nodes_mm[None]
        frames.beam_rotation[b.part] = np.broadcast_to(np.eye(3), (1, len(b.nodes_mm), 3, 3))
    if s is None:
        return frames
    for b in s.bushings:
        frames.bushing_mm[b.name] = np.array([np.linalg.norm(b.initial_deflection[:3])])
        frames.bushing_deg[b.name] = np.array([np.linalg.norm(b.initial_deflection[3:])])
    moving = [p for p in s.parts]
    identity = PartPoses({p: np.eye(3) for p in moving}, {p: np.zeros(3) for p in moving},
                         {p: np.zeros(3) for p in moving})
    kinematics(s, [identity], frames)
    return frames
