"""Virtual CMM: the files a user would bring, made from a nominal config and a seed.

The synthetic **as-built** suspension is the nominal one (its design preloads: spring force and
bushing deflections at the design position) assembled with clearance: every joint that the
config's ``measurements.joints`` declares bolted (bushing inner sleeves, bolted ball joints)
has its true centre shifted from the housing centre by a random vector within dL_max [1]
(bushings: uniform over the disc normal to the housing axis; other joints: uniform over the
ball). Its static equilibrium under the design wheel load (a force at the contact patch) is the
"assembled, loaded" state that the virtual CMM measures.

What is written (``measurements.folder``), each file in IGES and in CSV:

- one file per part measured alone, in the part's own frame (a random rigid transform of the
  design position; the ground part in the config frame): its 4 marks, its joint centres
  (bushing outer sleeve: centre, axis ``.Z`` and radial ``.X`` lines; inner sleeve: housing
  centre and axis; other joints: centre, and axis when the joint has one), spring seats, wheel
  centre and spin axis;
- the assembled-mark file: every part's marks in the CMM frame (a random rigid transform of
  the config frame), in scrambled order, one of them grossly wrong;
- ``truth.yaml``: the clearance shifts, the CMM frame, the as-built part poses and the true
  joint locations (the numbers identification is scored against).

CMM noise: a "0.1 mm CMM" (``synthetic.noise_mm``) puts 95 % of its points within 0.1 mm of
the true point: isotropic Gaussian noise on every measured point with sigma = noise_mm / 2.796
per coordinate (2.796 = the 95 % quantile of the chi distribution with 3 degrees of freedom),
i.e. a 3-D RMS error of 0.062 mm. Everything is
drawn from ``numpy.random.default_rng(seed)`` in a fixed order, so the files regenerate byte
for byte. Units mm.
"""

from __future__ import annotations

import dataclasses
import fnmatch
import re
from pathlib import Path

import numpy as np
import yaml
from scipy.spatial.transform import Rotation

from elastokin.config.confined import data_file
from elastokin.config.measurements import check_measurements, hardpoint_name
from elastokin.config.schema.suspension import (
    BushingSpec,
    LinkSpec,
    MeasurementsSpec,
    PartMeasurementSpec,
    SuspensionFile,
    SyntheticSpec,
)
from elastokin.config.suspension import Suspension
from elastokin.config.variants import (
    DesignState,
    ModelVariant,
    corner,
    relabelled,
    with_joint_shifts,
)
from elastokin.errors import ConfigError, SolverError
from elastokin.formats.cmm import write_points
from elastokin.mbs.design import build_model, design_state, settle_by_continuation
from elastokin.mbs.model import ModelOptions
from elastokin.physics.pose import mark_layout_warnings, pose_error_gain
from elastokin.rig.load_cases import static_equilibrium

#: 95 % quantile of the 3-D distance of an isotropic unit Gaussian (chi, 3 dof)
CHI3_95 = 2.7955
AXIS_LINE_MM = 100.0  # length of the axis / radial lines written for a joint
MARK_MIN_DISTANCE_MM = 60.0
MARK_MIN_RADIUS_MM = 100.0  # marks sit at least this far out from the joints' centroid
MARK_MAX_GAIN = 1.3  # a pose from any 3 marks amplifies mark noise at the joints at most this


def random_rotation(rng: np.random.Generator) -> np.ndarray:
    return Rotation.from_quat(rng.normal(size=4)).as_matrix()


def _disc(rng, radius: float, axis: np.ndarray) -> np.ndarray:
    a = axis / np.linalg.norm(axis)
    e1 = np.cross(a, [1.0, 0, 0] if abs(a[0]) < 0.9 else [0, 1.0, 0])
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(a, e1)
    r, phi = radius * np.sqrt(rng.uniform()), rng.uniform(0, 2 * np.pi)
    return r * (np.cos(phi) * e1 + np.sin(phi) * e2)


def random_in_ball(rng, radius: float) -> np.ndarray:
    d = rng.normal(size=3)
    return radius * rng.uniform() ** (1 / 3) * d / np.linalg.norm(d)


def place_marks(rng, points: list[np.ndarray], eps_mm: float, part: str) -> np.ndarray:
    """4 marks spread over the part: around the centroid of its joints, at 60-100 % of the
    joints' spread (at least ``MARK_MIN_RADIUS_MM``); their 6 distances differ by more than
    4 eps [2] and any 3 of them still give a pose that amplifies CMM noise at the joints by
    less than ``MARK_MAX_GAIN`` (a wrong mark may have to be dropped)."""
    pts = np.array(points, float)
    c = pts.mean(axis=0)
    radius = max(float(np.max(np.linalg.norm(pts - c, axis=1))), MARK_MIN_RADIUS_MM)
    for _ in range(5000):
        u = rng.normal(size=(4, 3))
        u *= rng.uniform(0.6, 1.0, size=(4, 1)) / np.linalg.norm(u, axis=1, keepdims=True)
        marks = c + radius * u
        d = np.linalg.norm(marks[:, None] - marks[None], axis=2)[np.triu_indices(4, 1)]
        if d.min() < MARK_MIN_DISTANCE_MM or mark_layout_warnings(marks, 2 * eps_mm):
            continue
        if all(pose_error_gain(marks[list(t)], pts) < MARK_MAX_GAIN
               for t in ((0, 1, 2), (0, 1, 3), (0, 2, 3), (1, 2, 3))):
            return marks
    raise ConfigError(f"synthesize: could not place 4 distinct marks on part '{part}'")


def mark_labels(pattern: str, n: int, part: str) -> list[str]:
    prefix = re.split(r"[*?\[]", pattern, maxsplit=1)[0]
    labels = [f"{prefix}{k}" for k in range(1, n + 1)]
    if not all(fnmatch.fnmatchcase(lb, pattern) for lb in labels):
        raise ConfigError(f"synthesize: cannot make mark labels for part '{part}' from the "
                          f"pattern '{pattern}' (use a prefix pattern such as 'FA*')")
    return labels


def rounded(v, nd: int = 6):
    a = np.round(np.asarray(v, float), nd) + 0.0
    return a.tolist()


def clearance_shifts(suspension: Suspension, rng: np.random.Generator) -> dict[str, np.ndarray]:
    """Random assembly-clearance shifts (mm, config frame) of every joint that
    ``measurements.joints`` gives a clearance: bushings uniform over the disc of radius dL_max
    normal to the housing axis, other joints uniform over the ball of radius dL_max [1].
    Joints are drawn in the order of ``measurements.joints``, so a seed gives the same shifts.
    """
    m = suspension.measurements
    bushings = {b.name: b for b in suspension.bushings}
    shifts: dict[str, np.ndarray] = {}
    for name, jm in m.joints.items():
        if jm.clearance is None:
            continue
        if name in bushings:
            shifts[name] = _disc(rng, jm.clearance.max_shift_mm, bushings[name].frame[:, 2])
        else:
            shifts[name] = random_in_ball(rng, jm.clearance.max_shift_mm)
    return shifts


@dataclasses.dataclass
class AsBuilt:
    """An as-built suspension: the config with joints shifted by assembly clearance.

    ``suspension`` carries the shifts as per-part joint attachment offsets
    (``Joint.part_shift_mm``); ``bushing_preload`` (N, N*mm, bushing frame) is each bushing's
    load at the design position with its inner sleeve shifted; ``spring_force_N`` the design
    spring preloads; ``housing_mm`` each bushing's inner-sleeve housing centre (config frame,
    design position). :meth:`variant` is the model variant to build."""

    suspension: Suspension
    shifts_mm: dict[str, np.ndarray]
    bushing_preload: dict[str, np.ndarray]
    spring_force_N: dict[str, float]
    housing_mm: dict[str, np.ndarray]

    def variant(self, label: str = "as_built") -> ModelVariant:
        """The as-built model: these joints and preloads."""
        return ModelVariant(label, self.suspension,
                            DesignState(self.spring_force_N, self.bushing_preload))


def as_built(suspension: Suspension, shifts: dict[str, np.ndarray], design=None) -> AsBuilt:
    """The as-built suspension for given clearance shifts (mm, config frame, keyed by joint or
    bushing name; see :func:`clearance_shifts`). A bushing's inner sleeve shifted by delta
    changes its design deflection by -delta (outer relative to inner); a joint's shift moves
    its attachment on the ``bolted`` part. On an axle: its measured corner (the config's
    side) as built."""
    s = corner(suspension)
    m = s.measurements
    design = design if design is not None else design_state(s)
    preload = dict(design.bushing_preload)
    housing = {}
    for b in s.bushings:
        u0 = np.array([law.deflection_at(f) for law, f in
                       zip(b.laws, design.bushing_preload[b.name])])
        sign = 1.0 if b.parts[0] == m.joints[b.name].inner else -1.0
        housing[b.name] = b.position_mm - sign * b.frame @ u0[:3]
        if b.name in shifts:  # inner sleeve shifted by delta: outer rel. inner less by delta
            u = u0.copy()
            u[:3] -= sign * b.frame.T @ shifts[b.name]
            preload[b.name] = np.array([law(x) for law, x in zip(b.laws, u)])
    attachments = {}
    for j in s.joints:
        if j.name in shifts:
            bolted = m.joints[j.name].bolted
            if bolted is None:
                raise ConfigError(f"{s.source}: key 'measurements.joints.{j.name}': a "
                                  "clearance needs 'bolted: <part>' (the side with the hole)")
            part_shift = [np.zeros(3), np.zeros(3)]
            part_shift[j.parts.index(bolted)] = np.asarray(shifts[j.name], float)
            attachments[j.name] = tuple(part_shift)
    built = relabelled(with_joint_shifts(s, attachments), f"{s.source} (as-built)")
    return AsBuilt(built, dict(shifts), preload, dict(design.spring_force_N), housing)


#: fractions of the clearance shifts solved in turn when the direct solve fails
CONTINUATION = (0.25, 0.5, 0.75, 1.0)


def as_built_by_continuation(suspension: Suspension, shifts: dict[str, np.ndarray], design,
                             options: ModelOptions = ModelOptions()):
    """The model of :func:`as_built` (``options``), started from its settled state, reached by
    continuation from the nominal geometry through :data:`CONTINUATION` fractions of the
    shifts: a large clearance shift of a stiff bushing (J2, 13000 N/mm, shifted 0.69 mm: 9 kN
    out of balance at the design position) is too far from equilibrium for Newton's first
    step."""
    models = [build_model(as_built(suspension, {k: f * np.asarray(v, float)
                                                for k, v in shifts.items()}, design).variant(),
                          options) for f in CONTINUATION]
    return settle_by_continuation(models)


def loaded_poses(suspension: Suspension, shifts: dict[str, np.ndarray], design):
    """The part poses of the as-built suspension (:func:`as_built` of these shifts) in its
    static equilibrium under the design load; solved from the design position, or by
    continuation (:func:`as_built_by_continuation`) when that start is too far."""
    try:
        model = build_model(as_built(suspension, shifts, design).variant())
        static_equilibrium(model)
    except SolverError:
        model = as_built_by_continuation(suspension, shifts, design)
        static_equilibrium(model)
    return model.part_poses()


def features_and_truth(s: Suspension, spec: SuspensionFile, poses,
                        housing: dict[str, np.ndarray], shifts: dict[str, np.ndarray]):
    """Every part's features in the design position (config frame): ``{part: {"points": {name:
    x}, "lines": {name.Z / name.X: (2, 3)}}}``, and the true joint locations of the loaded
    as-built suspension (``poses``), keyed by joint name (links: ``link:hardpoint``)."""
    m = s.measurements
    hp = s.hardpoints
    bushings = {b.name: b for b in s.bushings}
    features: dict[str, dict] = {p: {"points": {}, "lines": {}} for p in m.parts}
    truth: dict[str, np.ndarray] = {}

    def feature(part, name, x, axis=None, radial=None):
        f = features[part]
        f["points"].setdefault(name, np.asarray(x, float))
        for suffix, v in ((".Z", axis), (".X", radial)):
            if v is not None:
                f["lines"].setdefault(name + suffix, np.array([x, x + AXIS_LINE_MM * v]))

    for name, c in spec.connections.items():
        if isinstance(c, LinkSpec):
            for part, at in zip(c.parts, c.at):
                x = hp[hardpoint_name(at, f"connections.{name}.at", s.source)]
                feature(part, at, x)
                truth[f"{name}:{at}"] = poses.moved(part, x)
            continue
        at = hardpoint_name(c.at, f"connections.{name}.at", s.source)
        x = hp[at]
        if isinstance(c, BushingSpec):
            b = bushings[name]
            inner = m.joints[name].inner
            outer = b.parts[1] if b.parts[0] == inner else b.parts[0]
            feature(outer, at, x, b.frame[:, 2], b.frame[:, 0])
            feature(inner, at, housing[name], b.frame[:, 2])
            truth[name] = poses.moved(inner, housing[name] + shifts.get(name, np.zeros(3)))
            continue
        j = next(jt for jt in s.joints if jt.name == name)
        axis = None if c.type in ("spherical", "fixed") else j.frame[:, 2]
        for part in c.parts:
            feature(part, at, x, axis)
        jm = m.joints.get(name)
        if jm is not None and jm.bolted is not None:
            exact = c.parts[1] if c.parts[0] == jm.bolted else c.parts[0]
            truth[name] = poses.moved(exact, x)
        else:
            truth[name] = np.mean([poses.moved(p, x) for p in c.parts], axis=0)
    for sname, sp in spec.springs.items():
        for part, seat in zip(sp.parts, sp.seats):
            feature(part, hardpoint_name(seat, f"springs.{sname}.seats", s.source), hp[seat])
    wc = hardpoint_name(spec.wheel.centre, "wheel.centre", s.source)
    feature(s.wheel.part, wc, s.wheel.centre_mm, s.wheel.spin_axis)
    return features, truth


def _write_part_alone(rng: np.random.Generator, folder: Path, ground: str, part: str,
                      pspec: PartMeasurementSpec, f: dict, marks: np.ndarray, sigma: float,
                      stamp: str) -> list[Path]:
    """Write one part measured alone (IGES and CSV): its marks and features ``f`` in its own
    frame (a random rigid transform of the design position; the ground part in the config
    frame), with CMM noise. Draws the transform, then the noise of marks, points and lines."""
    if part == ground:
        R, t = np.eye(3), np.zeros(3)
    else:
        R, t = random_rotation(rng), rng.uniform(-500, 500, size=3)

    def local(x):  # design-position config frame -> part frame, with noise
        x = np.asarray(x, float)
        return (x - t) @ R + rng.normal(scale=sigma, size=x.shape)

    pts = {lb: local(x) for lb, x in zip(pspec.marks, marks)}
    label = pspec.labels
    for name, x in f["points"].items():
        pts[label.get(name, name)] = local(x)
    lines = {}
    for name, seg in f["lines"].items():
        base, suffix = name[:-2], name[-2:]
        lines[label.get(base, base) + suffix] = local(seg)
    comment = f"part '{part}' measured alone, in its own frame; mm\n{stamp}"
    files = []
    for ext in (".igs", ".csv"):
        path = folder / Path(pspec.file).with_suffix(ext)
        write_points(path, pts, lines, comment)
        files.append(path)
    return files


def _measure_parts(rng: np.random.Generator, s: Suspension, syn: SyntheticSpec, folder: Path,
                   sigma: float, stamp: str, features: dict[str, dict], poses):
    """The CMM frame and the part with the gross error, then part by part: its 4 marks, its
    measured-alone files, and its marks measured on the assembly (CMM frame, noisy, scrambled).
    Returns the files written, the assembly marks per part, the gross error's record and the
    CMM frame (R, t)."""
    m = s.measurements
    files: list[Path] = []
    cmm_R, cmm_t = random_rotation(rng), rng.uniform(-2000, 2000, size=3)
    gross_part = list(m.parts)[int(rng.integers(len(m.parts)))]
    gross = {}
    assembly_points: dict[str, np.ndarray] = {}
    for part, pspec in m.parts.items():
        f = features[part]
        marks = place_marks(rng, [*f["points"].values()], m.eps_mm, part)
        files += _write_part_alone(rng, folder, s.ground, part, pspec, f, marks, sigma, stamp)
        true_marks = poses.moved(part, marks) @ cmm_R.T + cmm_t
        measured = true_marks + rng.normal(scale=sigma, size=true_marks.shape)
        if part == gross_part:
            k = int(rng.integers(4))
            lo, hi = syn.gross_error_mm
            error = random_in_ball(rng, 1.0)
            error = rng.uniform(lo, hi) * error / np.linalg.norm(error)
            measured[k] += error
            gross = {"part": part, "mark": pspec.marks[k], "error_mm": rounded(error)}
        assembly_points[part] = measured[rng.permutation(4)]
    return files, assembly_points, gross, (cmm_R, cmm_t)


def _write_assembly(folder: Path, m: MeasurementsSpec, assembly_points: dict[str, np.ndarray],
                    stamp: str) -> list[Path]:
    """Write the assembled-mark file (IGES and CSV): every part's marks, labelled from the
    part's ``assembly.marks`` pattern in their scrambled order."""
    pts = {}
    for part, q in assembly_points.items():
        for lb, x in zip(mark_labels(m.assembly.marks[part], 4, part), q):
            pts[lb] = x
    comment = ("assembled, loaded suspension: every part's marks in the CMM frame, unordered; mm"
               f"\n{stamp}")
    files = []
    for ext in (".igs", ".csv"):
        path = folder / Path(m.assembly.file).with_suffix(ext)
        write_points(path, pts, {}, comment)
        files.append(path)
    return files


def _write_truth(path: Path, s: Suspension, seed: int, syn: SyntheticSpec, sigma: float,
                 shifts: dict[str, np.ndarray], gross: dict, cmm: tuple[np.ndarray, np.ndarray],
                 poses, truth: dict[str, np.ndarray]) -> Path:
    """Write ``truth.yaml``: the seed and noise, clearance shifts, gross error, CMM frame,
    loaded as-built part poses and true joint locations."""
    cmm_R, cmm_t = cmm
    doc = {
        "seed": seed,
        "noise_mm": syn.noise_mm,
        "noise_sigma_per_coordinate_mm": round(sigma, 9),
        "clearance_shift_mm": {k: rounded(v) for k, v in shifts.items()},
        "gross_error": gross,
        "cmm_frame": {"rotation": rounded(cmm_R, 9), "translation_mm": rounded(cmm_t)},
        "part_poses": {p: {"rotation": rounded(poses.rotation[p], 9),
                           "translation_mm": rounded(poses.transform(p)[:3, 3])}
                       for p in s.parts},
        "joints": {k: rounded(v) for k, v in truth.items()},
    }
    header = ("# Synthetic as-built truth written by `elastokin synthesize` (see "
              "docs/measurements.md).\n# Units mm; config frame. cmm_frame: x_cmm = R "
              "x_config + t. part_poses: loaded as-built pose\n# relative to the design "
              "position (x = R x_design + t). joints: true joint locations, loaded.\n")
    path.write_text(header + yaml.safe_dump(doc, sort_keys=False, default_flow_style=None,
                                            width=100))
    return path


def _check_written_paths(s: Suspension, m: MeasurementsSpec, folder: Path | None) -> None:
    """Every file to be written lies inside the config's folders (or ``folder``, typed on the
    command line), links followed (:func:`elastokin.config.confined.data_file`): a config
    from someone else writes nothing elsewhere."""
    names = {f"measurements.parts.{p}.file": spec.file for p, spec in m.parts.items()}
    names["measurements.assembly.file"] = m.assembly.file
    for key, name in names.items():
        for ext in (".igs", ".csv"):
            data_file(s, "measurements", str(Path(name).with_suffix(ext)), key, folder)
    if m.truth is not None:
        data_file(s, "measurements", m.truth, "measurements.truth", folder)


def synthesize(suspension: Suspension, seed: int | None = None,
               folder: Path | None = None) -> list[Path]:
    """Make the as-built suspension and write its virtual CMM files; returns the paths (on an
    axle: of its measured corner, the config's side)."""
    s = corner(suspension)
    m = s.measurements
    if m is None:
        raise ConfigError(f"{s.source}: no 'measurements' section: it names the files to write")
    check_measurements(s, m, "measurements")
    syn = m.synthetic or SyntheticSpec()
    seed = syn.seed if seed is None else seed
    rng = np.random.default_rng(seed)
    _check_written_paths(s, m, folder)
    folder = Path(folder) if folder is not None else Path(s.source).parent / m.folder
    sigma = syn.noise_mm / CHI3_95
    spec = SuspensionFile.model_validate(s.raw)
    design = design_state(s)

    # ---- as-built: clearance shifts (config frame, design position), loaded equilibrium
    shifts = clearance_shifts(s, rng)
    built = as_built(s, shifts, design)
    poses = loaded_poses(s, shifts, design)
    features, truth = features_and_truth(s, spec, poses, built.housing_mm, shifts)

    # ---- marks, part frames, CMM frame, noise
    folder.mkdir(parents=True, exist_ok=True)
    stamp = f"elastokin synthesize, seed {seed}, config {Path(s.source).name}"
    files, assembly_points, gross, cmm = _measure_parts(rng, s, syn, folder, sigma, stamp,
                                                        features, poses)
    files += _write_assembly(folder, m, assembly_points, stamp)
    if m.truth is not None:
        files.append(_write_truth(folder / m.truth, s, seed, syn, sigma, shifts, gross, cmm,
                                  poses, truth))
    return files
