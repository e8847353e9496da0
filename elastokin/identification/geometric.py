"""Geometric identification from CMM data: the reference paper's stages 2 and 3
(``shared/paper/method.md``; equation numbers in brackets), from the config's ``measurements``.

1. Every part measured alone gives its 4 marks and its joint features in its own frame; the
   ground part is measured in the config (vehicle) frame, so its pose fixes the CMM frame.
2. The marks measured again on the assembled, loaded suspension (unordered, maybe one wrong)
   give every part's pose [8-12].
3. Joint features in the vehicle frame at the loaded state [19]. Bushings: the outer sleeve
   (exactly measured) gives the bushing frame; the inner sleeve is bolted, so only its housing
   centre and axis are known, within dL_max [1].
4. Two models:

   - **initial**: joints at the housing centres of the parts measured alone, bushing frames on
     the housing axis with zero torsion [15-18], bushings undeflected; the spring preload
     carries the wheel load at the measured ride height;
   - **identified**: joints where the assembled measurement puts them: bushings at their outer
     sleeve frame with the deflection that the static equilibrium under the wheel load gives
     (bushing loads of the model held at the measured poses, then the inverse laws [22-23]);
     the inner-sleeve frame follows as B* = B2 D^-1 [24-26] (reported), bolted spherical joints
     at the exactly measured centre S* [27].

5. The paper's check: at the identified model's static equilibrium (wheel load applied as a
   force) every joint sits at its measured location; the largest deviation is reported.

Units mm, N, N*mm, deg; vehicle = config frame. Exudyn is used through :mod:`elastokin.model`.
"""

from __future__ import annotations

import copy
import fnmatch
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import yaml

from elastokin.config.loading import suspension_from_dict
from elastokin.config.measurements import check_measurements, hardpoint_name
from elastokin.config.schema import BushingSpec, LinkSpec, SuspensionFile
from elastokin.config.suspension import Suspension
from elastokin.errors import ConfigError, MeasurementError
from elastokin.formats.cmm import read_points
from elastokin.physics.pose import (
    MarkMatch,
    deflection_operator,
    euler_zxz_deg,
    match_marks,
    zero_torsion_frame,
)

# ---------------------------------------------------------------------------------- data in


@dataclass
class PartMeasurement:
    """One part measured alone (mm, the part's own frame)."""

    part: str
    source: str
    marks: np.ndarray  # (4, 3)
    points: dict[str, np.ndarray]  # hardpoint -> centre
    axes: dict[str, np.ndarray]  # hardpoint -> unit axis (``<label>.Z`` line)
    radials: dict[str, np.ndarray]  # hardpoint -> unit radial (``<label>.X`` line)


def _unit(seg: np.ndarray) -> np.ndarray:
    v = seg[1] - seg[0]
    return v / np.linalg.norm(v)


def read_part(part: str, spec, folder: Path) -> PartMeasurement:
    """Read a part's file; labels -> marks and hardpoints (see ``docs/measurements.md``)."""
    data = read_points(folder / spec.file)
    missing = [m for m in spec.marks if m not in data.points]
    if missing:
        raise MeasurementError(
            f"{data.source}: part '{part}': mark(s) {', '.join(missing)} not found (labels in "
            f"the file: {', '.join(data.order) or 'none'}); a part needs its 4 marks "
            f"({', '.join(spec.marks)})")
    to_hardpoint = {label: hp for hp, label in spec.labels.items()}
    points, axes, radials = {}, {}, {}
    for label, xyz in data.points.items():
        if label not in spec.marks:
            points[to_hardpoint.get(label, label)] = xyz
    for label, seg in data.lines.items():
        base, _, kind = label.rpartition(".")
        target = {"Z": axes, "X": radials}.get(kind.upper())
        if base and target is not None:
            target[to_hardpoint.get(base, base)] = _unit(seg)
    marks = np.array([data.points[m] for m in spec.marks])
    return PartMeasurement(part, data.source, marks, points, axes, radials)


def read_assembly(spec, folder: Path, parts: list[str]) -> tuple[str, dict[str, np.ndarray]]:
    """The assembled marks of each part (unordered), selected by the label patterns."""
    data = read_points(folder / spec.file)
    out: dict[str, list] = {p: [] for p in parts}
    for label in data.order:
        owners = [p for p in parts if fnmatch.fnmatchcase(label, spec.marks[p])]
        if len(owners) > 1:
            raise MeasurementError(f"{data.source}: mark '{label}' matches the patterns of "
                                   f"parts {', '.join(owners)}")
        if owners:
            out[owners[0]].append(data.points[label])
    for p, pts in out.items():
        if len(pts) < 3:
            raise MeasurementError(
                f"{data.source}: part '{p}': {len(pts)} assembled mark(s) match the label "
                f"pattern '{spec.marks[p]}'; at least 3 usable marks are needed for its pose")
        if len(pts) > 4:
            raise MeasurementError(f"{data.source}: part '{p}': {len(pts)} assembled marks "
                                   f"match '{spec.marks[p]}'; a part has 4 marks")
    return data.source, {p: np.array(v) for p, v in out.items()}


# ---------------------------------------------------------------------------------- results


@dataclass
class PartPose:
    """A part's pose in the vehicle frame at the loaded state: x_vehicle = R x_part + t."""

    part: str
    R: np.ndarray
    t: np.ndarray
    match: MarkMatch

    def point(self, x) -> np.ndarray:
        return np.asarray(x, float) @ self.R.T + self.t


@dataclass
class JointResult:
    """One joint (or one end of a link): locations in the vehicle frame at the loaded state."""

    name: str
    kind: str
    initial_mm: np.ndarray
    identified_mm: np.ndarray
    truth_mm: np.ndarray | None = None
    max_shift_mm: float | None = None  # dL_max [1] when the joint is bolted
    euler_zxz_deg: np.ndarray | None = None  # identified inner-sleeve frame B* [20-21, 26]
    deflection: np.ndarray | None = None  # bushing: mm, mm, mm, deg, deg, deg

    @property
    def shift_mm(self) -> np.ndarray:
        return self.identified_mm - self.initial_mm

    @property
    def error_vs_truth_mm(self) -> float | None:
        if self.truth_mm is None:
            return None
        return float(np.linalg.norm(self.identified_mm - self.truth_mm))


@dataclass
class Identification:
    """Everything identification produced (see :func:`identify`)."""

    suspension: Suspension
    poses: dict[str, PartPose]
    joints: dict[str, JointResult]
    initial_config: dict
    identified_config: dict
    verification_max_deviation_mm: float = float("nan")
    verification_mm: dict[str, float] = field(default_factory=dict)
    warnings: list[str] = field(default_factory=list)
    sources: dict[str, str] = field(default_factory=dict)

    def to_json(self) -> dict:
        def vec(v):
            return None if v is None else [float(x) for x in v]

        return {
            "parts": {p: {"residual_rms_mm": pose.match.residual_rms_mm,
                          "dropped_mark": pose.match.dropped_mark,
                          "mark_order": pose.match.order,
                          "rotation": [vec(r) for r in pose.R],
                          "translation_mm": vec(pose.t)}
                      for p, pose in self.poses.items()},
            "joints": {n: {"kind": j.kind,
                           "shift_mm": vec(j.shift_mm),
                           "error_vs_truth_mm": j.error_vs_truth_mm,
                           "initial_mm": vec(j.initial_mm),
                           "identified_mm": vec(j.identified_mm),
                           "truth_mm": vec(j.truth_mm),
                           "max_shift_mm": j.max_shift_mm,
                           "euler_zxz_deg": vec(j.euler_zxz_deg),
                           "deflection_mm_deg": vec(j.deflection)}
                       for n, j in self.joints.items()},
            "verification_max_deviation_mm": self.verification_max_deviation_mm,
            "verification_deviation_mm": self.verification_mm,
            "warnings": self.warnings,
            "files": self.sources,
        }


# ---------------------------------------------------------------------------- identification


class _Features:
    """Measured features of every part, mapped to the vehicle frame by the part poses."""

    def __init__(self, parts: dict[str, PartMeasurement], poses: dict[str, PartPose]):
        self.parts, self.poses = parts, poses

    def _table(self, kind: str, part: str) -> dict[str, np.ndarray]:
        pm = self.parts[part]
        return {"point": pm.points, "axis": pm.axes, "radial": pm.radials}[kind]

    def _get(self, kind: str, part: str, hp: str, what: str) -> np.ndarray:
        pm = self.parts[part]
        table = self._table(kind, part)
        if hp not in table:
            label = {"point": hp, "axis": f"{hp}.Z", "radial": f"{hp}.X"}[kind]
            entity = "point" if kind == "point" else "line"
            raise MeasurementError(f"{pm.source}: part '{part}': no {entity} labelled "
                                   f"'{label}' ({what})")
        v = table[hp]
        pose = self.poses[part]
        return pose.point(v) if kind == "point" else pose.R @ v

    def point(self, part: str, hp: str, what: str) -> np.ndarray:
        return self._get("point", part, hp, what)

    def axis(self, part: str, hp: str, what: str) -> np.ndarray:
        return self._get("axis", part, hp, what)

    def radial(self, part: str, hp: str, what: str) -> np.ndarray:
        return self._get("radial", part, hp, what)

    def has(self, kind: str, part: str, hp: str) -> bool:
        return hp in self._table(kind, part)


def _frame(z: np.ndarray, x: np.ndarray) -> np.ndarray:
    z = z / np.linalg.norm(z)
    x = x - (x @ z) * z
    x = x / np.linalg.norm(x)
    return np.column_stack([x, np.cross(z, x), z])


def _clean(v, digits: int = 9) -> list[float]:
    return [float(f"{x:.{digits}g}") + 0.0 for x in np.asarray(v, float).ravel()]


def identify(suspension: Suspension, progress: Callable[[str], None] = lambda m: None,
             verify: bool = True) -> Identification:
    """Identify the geometry of ``suspension`` from its ``measurements`` (see module doc)."""
    from elastokin.mbs.model import build_model, design_state

    s = suspension
    m = s.measurements
    if m is None:
        raise ConfigError(f"{s.source}: no 'measurements' section: nothing to identify")
    key = "measurements"
    check_measurements(s, m, key)
    folder = Path(s.source).parent / m.folder
    progress("reading measurements")
    parts = {p: read_part(p, spec, folder) for p, spec in m.parts.items()}
    assembly_file, assembled = read_assembly(m.assembly, folder, list(m.parts))
    sources = {p: pm.source for p, pm in parts.items()}
    sources["assembly"] = assembly_file
    warnings: list[str] = []

    # ---- part poses [8-12]; the ground's pose fixes the CMM frame
    progress("part poses")
    matches = {}
    for p, pm in parts.items():
        try:
            matches[p] = match_marks(pm.marks, assembled[p], m.eps_mm, p)
        except MeasurementError as exc:
            raise MeasurementError(f"{assembly_file}: {exc}") from None
        warnings += [f"{assembly_file}: {w}" for w in matches[p].warnings]
        if matches[p].dropped_mark is not None:
            warnings.append(f"{assembly_file}: part '{p}': mark "
                            f"{m.parts[p].marks[matches[p].dropped_mark]} of {pm.source} was "
                            "not found within eps: the wrong point was dropped and the pose "
                            "fitted to the other three")
    g = matches[s.ground]
    poses = {p: PartPose(p, g.R.T @ mm.R, g.R.T @ (mm.t - g.t), mm) for p, mm in matches.items()}
    feats = _Features(parts, poses)

    # ---- joints in the vehicle frame [19] and the two geometries
    raw = s.raw
    initial_hp: dict[str, np.ndarray] = {}
    ident_hp: dict[str, np.ndarray] = {}
    joints: dict[str, JointResult] = {}
    bushing_frames: dict[str, tuple[np.ndarray, np.ndarray]] = {}  # initial, identified
    axes_measured: dict[str, np.ndarray] = {}

    def place(hp: str, initial: np.ndarray, identified: np.ndarray) -> None:
        if hp not in ident_hp:
            initial_hp[hp], ident_hp[hp] = initial, identified

    spec_file = SuspensionFile.model_validate(raw)
    for name, c in spec_file.connections.items():
        ckey = f"connections.{name}"
        jm = m.joints.get(name)
        if isinstance(c, LinkSpec):
            for part, at in zip(c.parts, c.at):
                hp = hardpoint_name(at, ckey + ".at", s.source)
                x = feats.point(part, hp, f"end of link '{name}'")
                place(hp, x, x)
                joints[f"{name}:{hp}"] = JointResult(f"{name}:{hp}", "link end", x, x)
            continue
        hp = hardpoint_name(c.at, ckey + ".at", s.source)
        dl = jm.clearance.max_shift_mm if jm is not None and jm.clearance else None
        if isinstance(c, BushingSpec):
            inner = jm.inner
            outer = c.parts[1] if c.parts[0] == inner else c.parts[0]
            what = f"bushing '{name}'"
            o2 = feats.point(outer, hp, what + ", outer sleeve centre")
            z2 = feats.axis(outer, hp, what + ", outer sleeve axis")
            x2 = feats.radial(outer, hp, what + ", outer sleeve radial direction")
            housing = feats.point(inner, hp, what + ", inner sleeve housing centre")
            w_h = feats.axis(inner, hp, what + ", housing axis")
            w_h = w_h if w_h @ z2 >= 0 else -w_h
            F2 = _frame(z2, x2)
            F1 = zero_torsion_frame(w_h, F2[:, 1])  # [15-18]
            bushing_frames[name] = (F1, F2)
            place(hp, housing, o2)
            joints[name] = JointResult(name, "bushing", housing, o2, max_shift_mm=dl)
            continue
        kind = c.type
        sides = [p for p in c.parts if feats.has("point", p, hp)]
        if not sides:
            raise MeasurementError(f"{', '.join(parts[p].source for p in c.parts)}: joint "
                                   f"'{name}': no point labelled '{hp}' on part "
                                   f"'{c.parts[0]}' or '{c.parts[1]}'")
        bolted = jm.bolted if jm is not None else None
        if bolted is not None:
            exact = c.parts[1] if c.parts[0] == bolted else c.parts[0]
            ident = feats.point(exact, hp, f"joint '{name}', exactly measured centre")
            initial = feats.point(bolted, hp, f"joint '{name}', housing centre")
        else:
            ident = initial = np.mean([feats.point(p, hp, "") for p in sides], axis=0)
        place(hp, initial, ident)
        joints[name] = JointResult(name, kind, initial, ident, max_shift_mm=dl)
        axis_sides = [p for p in c.parts if feats.has("axis", p, hp)]
        if axis_sides:
            a = [feats.axis(p, hp, "") for p in axis_sides]
            a = [v if v @ a[0] >= 0 else -v for v in a]
            axes_measured[name] = np.mean(a, axis=0) / np.linalg.norm(np.mean(a, axis=0))
    for sname, sp in spec_file.springs.items():
        for part, seat in zip(sp.parts, sp.seats):
            hp = hardpoint_name(seat, f"springs.{sname}.seats", s.source)
            x = feats.point(part, hp, f"seat of spring '{sname}'")
            place(hp, x, x)
    w = raw["wheel"]
    hp = hardpoint_name(w["centre"], "wheel.centre", s.source)
    x = feats.point(w["part"], hp, "wheel centre")
    place(hp, x, x)
    spin = feats.axis(w["part"], hp, "wheel spin axis") if feats.has(
        "axis", w["part"], hp) else None
    for hp_name in raw["hardpoints"]:
        if hp_name not in ident_hp:
            warnings.append(f"{s.source}: hardpoint '{hp_name}' is used by no measured joint: "
                            "kept at its config value")

    # ---- the two configs
    def config(hardpoints, label):
        d = copy.deepcopy(raw)
        d.pop("measurements", None)
        d.pop("kc_test", None)
        d["name"] = f"{raw['name']} ({label})"
        d["hardpoints"] = {k: _clean(hardpoints.get(k, v)) for k, v in raw["hardpoints"].items()}
        for name, a in axes_measured.items():
            spec = d["connections"][name]
            k = "torsion_axis" if spec["type"] == "universal" else "axis"
            if k in spec and not isinstance(spec[k], dict):  # an explicit vector: measured
                sign = 1.0 if np.dot(spec[k], a) >= 0 else -1.0
                spec[k] = _clean(sign * a)
        if spin is not None and not isinstance(d["wheel"]["spin_axis"], dict):
            sign = 1.0 if np.dot(d["wheel"]["spin_axis"], spin) >= 0 else -1.0
            d["wheel"]["spin_axis"] = _clean(sign * spin)
        return d

    initial_cfg = config(initial_hp, "initial: parts measured alone")
    ident_cfg = config(ident_hp, "identified")
    for name, (F1, F2) in bushing_frames.items():
        for d, F in ((initial_cfg, F1), (ident_cfg, F2)):
            spec = d["connections"][name]
            for k in ("axis", "radial", "euler_zxz_deg", "preload", "initial_deflection"):
                spec.pop(k, None)
            spec["euler_zxz_deg"] = _clean(euler_zxz_deg(F))
    design = dict(raw["design"])
    initial_cfg["design"] = {**design, "balance_bushing_preloads": False}

    # ---- identified deflections [22-23]: the model held at the measured poses
    progress("bushing loads at the measured poses")
    ident_cfg["design"] = {**design, "balance_bushing_preloads": bool(s.bushings)}
    balanced = suspension_from_dict(ident_cfg, f"{s.source} (identified)")
    state = design_state(balanced)
    for b in balanced.bushings:
        u0 = np.array([law.deflection_at(f) for law, f in zip(b.laws, state.bushing_preload[
            b.name])])
        ident_cfg["connections"][b.name]["initial_deflection"] = {
            "translation_mm": _clean(u0[:3]), "rotation_deg": _clean(u0[3:])}
        inner = m.joints[b.name].inner
        sign = 1.0 if b.parts[0] == inner else -1.0  # deflection = parts[1] rel. parts[0]
        F2 = bushing_frames[b.name][1]
        D = deflection_operator(sign * u0[:3], sign * u0[3:])  # outer rel. inner [24-25]
        B_inner = F2 @ D[:3, :3].T  # B* = B2 D^-1 [26], in the vehicle frame
        j = joints[b.name]
        j.identified_mm = j.identified_mm - B_inner @ D[:3, 3]
        j.euler_zxz_deg = euler_zxz_deg(B_inner)
        j.deflection = u0
    for sname, force in state.spring_force_N.items():
        spec = ident_cfg["springs"][sname]
        if design.get("balance_spring") == sname:
            spec["preload_N"] = _clean([force])[0]
    ident_cfg["design"] = {"wheel_load_N": design["wheel_load_N"]}

    # ---- the synthetic truth, when there is one
    if m.truth is not None:
        truth = _read_truth(folder / m.truth)
        for name, j in joints.items():
            if name in truth:
                j.truth_mm = truth[name]

    result = Identification(s, poses, joints, initial_cfg, ident_cfg, warnings=warnings,
                            sources=sources)
    if verify:
        progress("verifying the identified model")
        _verify(result, build_model)
    return result


def _read_truth(path: Path) -> dict[str, np.ndarray]:
    try:
        data = yaml.safe_load(path.read_text())
        return {k: np.asarray(v, float) for k, v in data["joints"].items()}
    except (OSError, yaml.YAMLError, KeyError, TypeError, ValueError) as exc:
        raise MeasurementError(f"{path}: unreadable truth file ({exc})") from None


def _verify(result: Identification, build_model) -> None:
    """[7] At the identified model's static equilibrium under the wheel load (a force at the
    contact patch), every joint of every moving part sits at its measured location."""
    from elastokin.rig.load_cases import static_equilibrium

    s = suspension_from_dict(result.identified_config,
                             f"{result.suspension.source} (identified)")
    model = build_model(s)
    static_equilibrium(model)
    poses = model.part_poses()
    dev: dict[str, float] = {}
    for name in result.joints:
        connection, _, end = name.partition(":")  # a link end is "<link>:<hardpoint>"
        spec = result.identified_config["connections"][connection]
        if end:
            at, parts = end, [spec["parts"][spec["at"].index(end)]]
        else:
            at, parts = spec["at"], spec["parts"]
        parts = [p for p in parts if p != s.ground]
        x = np.asarray(s.hardpoints[at])
        dev[name] = max([float(np.linalg.norm(poses.moved(p, x) - x)) for p in parts],
                        default=0.0)
    result.verification_mm = dev
    result.verification_max_deviation_mm = max(dev.values(), default=0.0)


def write_config(path: Path, config: dict, header: str) -> None:
    """A config dict as YAML, with a comment header (units, provenance)."""
    text = yaml.safe_dump(config, sort_keys=False, default_flow_style=None, width=100)
    lines = "".join(f"# {ln}\n" for ln in header.splitlines())
    Path(path).write_text(lines + text)
