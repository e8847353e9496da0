"""Virtual CMM of a motion plan (the config's ``motion`` section): the marks of every part of
the synthetic as-built suspension measured on the assembled car at each rig position.

The as-built suspension is the one of the CMM files (:mod:`.virtual_cmm`: the same clearance
shifts, drawn from ``measurements.synthetic.seed``; without a ``measurements`` section the
nominal suspension). Each position is solved as the rig holds it: the design position under
the design wheel load (force control, as the CMM files measure it), the others with the pad
at ``wheel_travel_mm`` (displacement control, x and y free) and the steering rack at
``rack_travel_mm``, reached quasi-statically from the design position. A corner whose tie rod
is on the ground (steering locked) is steered on a synthetic rack under the ``rack_link``'s
ground end, along the vehicle's left (ISO y). A marked link (the tie rod) turns without spin
about its own axis; the wheel's marks turn with the wheel part and ``wheel_turned_deg`` about
its spin axis.

Written (``motion.folder``), IGES and CSV: the ground's marks in the config frame, one file
per position with every body's marks in the CMM's frame (one frame for all positions: the CMM
stays put), each body's marks in scrambled order, one mark of one body at one position 5-15 mm
wrong; ``truth.yaml``: the true joints and axes at the design position and every body's true
marks (design position, config frame). CMM noise as in
:mod:`.virtual_cmm`. Everything is drawn from ``numpy.random.default_rng(motion.synthetic.
seed)`` in a fixed order: a config and a seed give the same bytes. Units mm, deg.
"""

from __future__ import annotations

import copy
import dataclasses
from pathlib import Path

import numpy as np
import yaml
from scipy.spatial.transform import Rotation

from elastokin.config.confined import data_file
from elastokin.config.loading import suspension_from_dict
from elastokin.config.measurements import check_motion
from elastokin.config.schema.motion import MotionSpec, MotionSyntheticSpec
from elastokin.config.schema.suspension import LinkSpec, SuspensionFile
from elastokin.config.suspension import Suspension
from elastokin.config.variants import corner, side_couplings
from elastokin.errors import ConfigError
from elastokin.formats.cmm import write_points
from elastokin.formats.cmm_motion import WHEEL, MotionMeasurement, mark_patterns, motion_paths
from elastokin.mbs.axle_elements import STEERING_LOCK
from elastokin.mbs.design import build_model, design_state
from elastokin.physics.pose import frame_from_z
from elastokin.rig.load_cases import static_equilibrium
from elastokin.rig.pad import WheelInputs, run_rig
from elastokin.synthetic.virtual_cmm import (
    CHI3_95,
    AsBuilt,
    as_built,
    clearance_shifts,
    features_and_truth,
    mark_labels,
    place_marks,
    random_in_ball,
    random_rotation,
    rounded,
)

RACK_PART = "synthetic_rack"  # the rack a corner with its steering locked is steered on
MAX_STEP_MM = 5.0  # largest step of pad or rack between solved rig states


def steerable(s: Suspension, motion: MotionSpec) -> tuple[Suspension, tuple | None]:
    """``s`` with a rack the rig can move: its own rack joint, or a synthetic one under the
    ``rack_link``'s ground end, made a sliding joint; returns it and the rack (part, position,
    axis) or None when no position steers."""
    if not any(p.rack_travel_mm for p in motion.positions.values()):
        return s, None
    rack = next((j for j in s.joints if j.kind == "rack"), None)
    if rack is None:
        raw = copy.deepcopy(s.raw)
        link = raw["connections"][motion.rack_link]
        end = link["at"][list(link["parts"]).index(s.ground)]
        link["parts"] = [RACK_PART if p == s.ground else p for p in link["parts"]]
        raw["parts"][RACK_PART] = {"description": "synthetic steering rack"}
        raw["connections"][RACK_PART + "_slide"] = {"type": "rack", "parts": [s.ground, RACK_PART],
                                         "at": end, "axis": [float(v) for v in s.left]}
        s = dataclasses.replace(suspension_from_dict(raw, s.source, s.sha256), source=s.source)
        rack = next(j for j in s.joints if j.kind == "rack")
    return s, (rack.parts[1], rack.position_mm, rack.frame[:, 2])


def position_poses(built: AsBuilt, rack, motion: MotionSpec) -> dict[str, object]:
    """The as-built suspension's part poses at every position (name -> PartPoses)."""
    poses = {}
    sliding = built.suspension
    if rack is not None:  # the rack slides, held by the rig's steering lock
        sliding = dataclasses.replace(sliding, joints=tuple(
            dataclasses.replace(j, constrained=(1, 1, 0, 1, 1, 1)) if j.kind == "rack" else j
            for j in sliding.joints))

    def model():
        m = build_model(dataclasses.replace(built.variant(), suspension=sliding))
        if rack is not None:
            m.add_support(STEERING_LOCK, rack[0], rack[1], (0, 0, 1, 0, 0, 0),
                          frame=frame_from_z(rack[2]), lock=np.zeros(6))
        return m

    design = model()
    static_equilibrium(design)
    design_poses = design.part_poses()
    states = sorted({(p.rack_travel_mm, p.wheel_travel_mm) for p in motion.positions.values()})
    path, index = [np.zeros(2)], {}
    for state in states:
        start = path[-1]
        n = int(np.ceil(np.max(np.abs(np.array(state) - start)) / MAX_STEP_MM))
        path += [start + (np.array(state) - start) * (i / n) for i in range(1, n + 1)]
        index[state] = len(path) - 1
    path = np.array(path)
    m = model()
    side = m.suspension.side
    steps = run_rig(m, {side: WheelInputs(path[:, 1], np.zeros((len(path), 3)),
                                          np.zeros((len(path), 6)))},
                    rack_travel_mm=path[:, 0] if rack is not None else None,
                    what="virtual CMM: the rig positions of the motion plan")
    for name, p in motion.positions.items():
        poses[name] = design_poses if p.is_design else steps[
            index[(p.rack_travel_mm, p.wheel_travel_mm)]][side].poses
    return poses


def _link_transform(s: Suspension, rack, link: LinkSpec, poses) -> np.ndarray:
    """A link's pose (4x4, from the design position): its ends where the parts put them,
    turned without spin about its own axis (the smallest rotation of its axis)."""
    x0, x1 = (np.asarray(s.hardpoints[a], float) for a in link.at)
    on_rack = rack is not None and rack[0] == RACK_PART
    p0, p1 = (poses.moved(RACK_PART if on_rack and p == s.ground else p, x)
              for p, x in zip(link.parts, (x0, x1)))
    d0, d1 = (x1 - x0) / np.linalg.norm(x1 - x0), (p1 - p0) / np.linalg.norm(p1 - p0)
    axis = np.cross(d0, d1)
    angle = np.arctan2(np.linalg.norm(axis), d0 @ d1)
    R = Rotation.from_rotvec(axis / max(np.linalg.norm(axis), 1e-300) * angle).as_matrix()
    T = np.eye(4)
    T[:3, :3], T[:3, 3] = R, p0 - R @ x0
    return T


def body_transforms(s: Suspension, rack, motion: MotionSpec, poses) -> dict[str, np.ndarray]:
    """Every marked body's pose (4x4, design position -> this position; config frame)."""
    spec = SuspensionFile.model_validate(s.raw)
    out = {}
    for body in motion.marks:
        if body in spec.connections:
            out[body] = _link_transform(s, rack, spec.connections[body], poses)
        else:
            out[body] = poses.transform(body) if body != s.ground else np.eye(4)
    return out


def _wheel_transform(s: Suspension, poses, turned_deg: float) -> np.ndarray:
    """The wheel's pose: the wheel part's, turned about the spin axis through the centre."""
    w = s.wheel
    T = np.eye(4)
    T[:3, :3] = Rotation.from_rotvec(np.radians(turned_deg) * w.spin_axis).as_matrix()
    T[:3, 3] = w.centre_mm - T[:3, :3] @ w.centre_mm
    return poses.transform(w.part) @ T


def body_points(s: Suspension, motion: MotionSpec) -> dict[str, list[np.ndarray]]:
    """The points marks are placed around, per body (config frame, design position): its
    joints, seats and wheel centre; a link's ends; the wheel's centre."""
    hp = s.hardpoints
    pts: dict[str, list[np.ndarray]] = {b: [] for b in mark_patterns(motion)}
    spec = SuspensionFile.model_validate(s.raw)
    for name, c in spec.connections.items():
        ats = c.at if isinstance(c, LinkSpec) else (c.at, c.at)
        for part, at in zip(c.parts, ats):
            for body in (part, name):
                if body in pts and isinstance(at, str):
                    pts[body].append(np.asarray(hp[at], float))
    for sp in s.springs:
        for part, x in zip(sp.parts, sp.seats_mm):
            if part in pts:
                pts[part].append(np.asarray(x, float))
    for body in (s.wheel.part, WHEEL):
        if body in pts:
            pts[body].append(np.asarray(s.wheel.centre_mm, float))
    return pts


def _truth(s: Suspension, built: AsBuilt, poses) -> tuple[dict, dict]:
    """The true joints (as the CMM files' truth; without clearance: every joint where its
    parts put it) and axes at the design position: revolute, cylindrical and universal
    joints, revolute bushings and the wheel (``wheel``: centre and spin axis)."""
    spec = SuspensionFile.model_validate(s.raw)
    if s.measurements is not None:
        points = features_and_truth(s, spec, poses, built.housing_mm, built.shifts_mm)[1]
    else:
        points = {}
        for name, c in spec.connections.items():
            if isinstance(c, LinkSpec):
                points.update({f"{name}:{at}": poses.moved(p, s.hardpoints[at])
                               for p, at in zip(c.parts, c.at)})
            else:
                points[name] = np.mean([poses.moved(p, s.hardpoints[c.at]) for p in c.parts],
                                       axis=0)
    axes = {}
    for j in s.joints:
        if j.kind in ("revolute", "cylindrical", "universal"):
            axes[j.name] = poses.rotation.get(j.parts[1], np.eye(3)) @ j.frame[:, 2]
    for b in s.bushings:
        if b.ideal_joint in ("revolute", "cylindrical"):
            axes[b.name] = poses.rotation.get(b.parts[1], np.eye(3)) @ b.frame[:, 2]
    w = s.wheel
    points[WHEEL] = poses.moved(w.part, w.centre_mm)
    axes[WHEEL] = poses.rotation[w.part] @ w.spin_axis
    return points, axes


def as_built_corner(suspension: Suspension) -> tuple[Suspension, AsBuilt, tuple | None]:
    """The config's corner, its as-built suspension (steerable when the plan steers) and the
    rack (see :func:`steerable`)."""
    s = corner(suspension)
    if s.motion is None:
        raise ConfigError(f"{s.source}: no 'motion' section: it names the files to write")
    check_motion(s, s.motion, "motion")
    if side_couplings(suspension) and any(p.other_wheel_travel_mm for p in
                                          s.motion.positions.values()):
        raise ConfigError(f"{s.source}: key 'motion.positions': the virtual CMM measures one "
                          "corner; this axle's sides are coupled, so other_wheel_travel_mm "
                          "must be 0")
    moving, rack = steerable(s, s.motion)
    design = design_state(moving)
    if s.measurements is not None and s.measurements.joints:
        syn = s.measurements.synthetic
        shifts = clearance_shifts(s, np.random.default_rng(syn.seed if syn else 0))
        return s, as_built(moving, shifts, design), rack
    built = AsBuilt(moving, {}, dict(design.bushing_preload), dict(design.spring_force_N), {})
    return s, built, rack


@dataclasses.dataclass
class TrueMotion:
    """The truth of a motion plan: every body's marks at the design position (config frame),
    its pose at every position (4x4, from the design position), the true joint locations and
    axes at the design position and the clearance shifts (mm, config frame)."""

    marks: dict[str, np.ndarray]
    poses: dict[str, dict[str, np.ndarray]]
    joints: dict[str, np.ndarray]
    axes: dict[str, np.ndarray]
    shifts_mm: dict[str, np.ndarray]


def true_motion(suspension: Suspension, rng: np.random.Generator) -> TrueMotion:
    """Solve the as-built corner at every position of the config's motion plan and place
    every body's marks (drawn from ``rng``)."""
    s, built, rack = as_built_corner(suspension)
    mo = s.motion
    poses = position_poses(built, rack, mo)
    points, axes = _truth(s, built, poses[mo.design_position])
    marks = {b: place_marks(rng, pts, mo.eps_mm, b) for b, pts in body_points(s, mo).items()}
    true_poses = {}
    for name, p in mo.positions.items():
        T = body_transforms(s, rack, mo, poses[name])
        if WHEEL in marks:
            T[WHEEL] = _wheel_transform(s, poses[name], p.wheel_turned_deg)
        true_poses[name] = T
    return TrueMotion(marks, true_poses, points, axes, dict(built.shifts_mm))


def measure(true: TrueMotion, motion: MotionSpec, ground: str, sigma_mm: float,
            rng: np.random.Generator, gross_error_mm: tuple[float, float] | None = None
            ) -> tuple[MotionMeasurement, dict]:
    """The virtual CMM at ``motion``'s positions (a subset of ``true``'s): the CMM frame,
    the ground's marks in the config frame and every body's marks at every position in the
    CMM frame, each with isotropic noise ``sigma_mm`` per coordinate, in scrambled order;
    with ``gross_error_mm`` one mark of one body at one position that far off. Returns the
    measurement (file names: the positions') and the CMM frame and the gross error."""
    cmm_R, cmm_t = random_rotation(rng), rng.uniform(-2000, 2000, size=3)
    ground_marks = true.marks[ground] + rng.normal(scale=sigma_mm, size=(4, 3))
    names = list(motion.positions)
    gross: dict = {}
    if gross_error_mm is not None:
        error = random_in_ball(rng, 1.0)
        gross = {"position": names[int(rng.integers(len(names)))],
                 "body": list(true.marks)[int(rng.integers(len(true.marks)))],
                 "mark": int(rng.integers(4)),
                 "error_mm": rng.uniform(*gross_error_mm) * error / np.linalg.norm(error)}
    measured = []
    for name in names:
        T, out = true.poses[name], {}
        for body, local in true.marks.items():
            q = (local @ T[body][:3, :3].T + T[body][:3, 3]) @ cmm_R.T + cmm_t
            q = q + rng.normal(scale=sigma_mm, size=q.shape)
            order = rng.permutation(4)
            if gross and (name, body) == (gross["position"], gross["body"]):
                q[gross["mark"]] += gross["error_mm"]
                gross["index_in_file"] = int(np.flatnonzero(order == gross["mark"])[0])
            out[body] = q[order]
        measured.append(out)
    return (MotionMeasurement(names, names, measured, ground_marks, "ground"),
            {"cmm_frame": (cmm_R, cmm_t), "gross_error": gross})


def synthesize_motion(suspension: Suspension, seed: int | None = None,
                      folder: Path | None = None) -> list[Path]:
    """Solve the as-built suspension at every position of the config's motion plan and write
    its virtual CMM files (see module doc); returns the paths."""
    s = corner(suspension)
    mo = s.motion
    if mo is None:
        raise ConfigError(f"{s.source}: no 'motion' section: it names the files to write")
    syn = mo.synthetic or MotionSyntheticSpec()
    seed = syn.seed if seed is None else seed
    rng = np.random.default_rng(seed)
    true = true_motion(suspension, rng)
    sigma = syn.noise_mm / CHI3_95
    data, extra = measure(true, mo, s.ground, sigma, rng, syn.gross_error_mm)
    paths = _written_paths(s, folder)
    next(iter(paths.values())).parent.mkdir(parents=True, exist_ok=True)
    stamp = f"elastokin synthesize, seed {seed}, config {Path(s.source).name}"
    files = _write(paths["ground"], dict(zip(mo.ground.marks, data.ground_marks)),
                   f"ground '{s.ground}': its marks in the config frame; mm\n{stamp}")
    patterns = mark_patterns(mo)
    gross = extra["gross_error"]
    gross["label"] = mark_labels(patterns[gross["body"]], 4, gross["body"])[
        gross.pop("index_in_file")]
    for (name, p), measured in zip(mo.positions.items(), data.marks):
        out = {}
        for body, q in measured.items():
            out.update(zip(mark_labels(patterns[body], 4, body), q))
        files += _write(paths[name], out, f"position '{name}' ({_state(p)}): every body's "
                        f"marks in the CMM frame, unordered; mm\n{stamp}")
    if mo.truth is not None:
        files.append(_write_truth(paths["truth"], true, seed, syn.noise_mm, sigma, extra))
    return files


def _written_paths(s: Suspension, folder: Path | None) -> dict[str, Path]:
    """The files to write (:func:`~elastokin.formats.cmm_motion.motion_paths`, in ``folder``
    when given), every one in both formats inside the config's folders (or ``folder``, typed
    on the command line), links followed: a config from someone else writes nothing
    elsewhere."""
    mo = s.motion
    names = {"motion.ground.file": mo.ground.file,
             **{f"motion.positions.{n}.file": p.file for n, p in mo.positions.items()}}
    for key, name in names.items():
        for ext in (".igs", ".csv"):
            data_file(s, "motion", str(Path(name).with_suffix(ext)), key, folder)
    return motion_paths(s, folder)


def _write_truth(path: Path, true: TrueMotion, seed: int, noise_mm: float, sigma: float,
                 extra: dict) -> Path:
    cmm_R, cmm_t = extra["cmm_frame"]
    gross = {k: rounded(v) if k == "error_mm" else v for k, v in extra["gross_error"].items()}
    doc = {"seed": seed, "noise_mm": noise_mm, "noise_sigma_per_coordinate_mm": round(sigma, 9),
           "clearance_shift_mm": {k: rounded(v) for k, v in true.shifts_mm.items()},
           "gross_error": gross,
           "cmm_frame": {"rotation": rounded(cmm_R, 9), "translation_mm": rounded(cmm_t)},
           "joints": {k: rounded(v) for k, v in true.joints.items()},
           "axes": {k: rounded(v / np.linalg.norm(v), 9) for k, v in true.axes.items()},
           "marks": {b: rounded(m) for b, m in true.marks.items()}}
    path.write_text(
        "# Synthetic truth of the motion plan, written by `elastokin synthesize` (see "
        "docs/measurements.md).\n# Units mm; config frame. joints, axes: at the design "
        "position, loaded. marks: every body's\n# marks at the design position. cmm_frame: "
        "x_cmm = R x + t.\n"
        + yaml.safe_dump(doc, sort_keys=False, default_flow_style=None, width=100))
    return path


def _state(p) -> str:
    return ", ".join(f"{k} {v:g}" for k, v in p.model_dump(exclude={"file"}).items()) or "design"


def _write(path: Path, points: dict, comment: str) -> list[Path]:
    files = []
    for ext in (".igs", ".csv"):
        target = path.with_suffix(ext)
        write_points(target, points, {}, comment)
        files.append(target)
    return files
