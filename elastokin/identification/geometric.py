"""Geometric identification from CMM data: the reference paper's sections 2-4, from the
config's ``measurements``. Numbers in brackets are the equation numbers of the paper itself
(Meissonnier et al., Proc. IMechE Part D 220, 2006); in the text extracted from its PDF the
label "(20)" is out of place: by the equations' order (20) is the z-x-z Euler angles, (21)
the terms a_ij of the bushing frame they are computed from.

1. Every part measured alone gives its 4 marks [6] and joint features [3-5] in its own frame;
   the ground part is measured in the vehicle frame, so its pose fixes the CMM frame.
2. The marks measured again on the assembled, loaded suspension [7] (unordered, maybe one
   wrong) give every part's pose: ordering [8-10] (a wrong point dropped, the text after
   (10)), then the absolute-orientation fit [11-12].
3. Joint features in the vehicle frame at the loaded state [19]. Bushings: the outer sleeve
   (exactly measured) gives the bushing frame; the inner sleeve is bolted: only its housing
   centre and axis are known, within dL_max [1] (beyond it: a warning).
4. Two models:

   - **initial**: joints at the housing centres of the parts measured alone, bushing frames on
     the housing axis with zero torsion [13-18], bushings undeflected; the spring preload
     carries the wheel load at the measured ride height;
   - **identified**: joints where the assembled measurement puts them: bushings at their outer
     sleeve frame with the deflection that the static equilibrium under the wheel load gives
     (bushing loads of the model held at the measured poses [22], then the inverse laws [23]);
     the inner-sleeve frame follows as B* [24-26] (reported), bolted spherical joints at the
     exactly measured centre S* [27].

5. The paper's check (its section 5, no equation): at the identified model's static
   equilibrium (wheel load applied as a force) every joint sits at its measured location;
   the largest deviation is reported.

Pure geometry: the two solves (the bushing loads at the measured poses, the verification) are
steps of :mod:`elastokin.studies.identification`, which passes their results to
:func:`apply_design_loads` and :func:`verification_deviations`.

Units mm, N, N*mm, deg; vehicle = config frame.
"""

from __future__ import annotations

import copy
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from elastokin.config.measurements import check_measurements, hardpoint_name
from elastokin.config.schema.suspension import BushingSpec, LinkSpec, SuspensionFile
from elastokin.config.suspension import Suspension
from elastokin.config.variants import DesignState, corner
from elastokin.errors import ConfigError, MeasurementError
from elastokin.formats.cmm_parts import PartMeasurement, read_measurements
from elastokin.physics.pose import (
    MarkMatch,
    deflection_operator,
    euler_zxz_deg,
    match_marks,
    zero_torsion_frame,
)
from elastokin.physics.states import PartPoses

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
    euler_zxz_deg: np.ndarray | None = None  # identified inner-sleeve frame B* [20, 26]
    deflection: np.ndarray | None = None  # bushing: mm, mm, mm, deg, deg, deg
    housing_axis: np.ndarray | None = None  # a bushing's (unit, vehicle frame)

    @property
    def shift_mm(self) -> np.ndarray:
        return self.identified_mm - self.initial_mm

    @property
    def clearance_shift_mm(self) -> float:
        """The part of the shift the clearance bounds (mm): a bushing's normal to its housing
        axis (the sleeve moves in the bolt hole), a bolted joint's whole shift."""
        shift = self.shift_mm
        if self.housing_axis is not None:
            shift = shift - (shift @ self.housing_axis) * self.housing_axis
        return float(np.linalg.norm(shift))

    @property
    def exceeds_clearance(self) -> bool:
        """True when the joint is identified farther from its housing centre than dL_max."""
        return self.max_shift_mm is not None and self.clearance_shift_mm > self.max_shift_mm

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
    #: each bushing's identified (outer sleeve) frame B2, vehicle frame (columns x y z)
    outer_frames: dict[str, np.ndarray] = field(default_factory=dict)

    def clearance_warnings(self) -> list[str]:
        """A warning for every joint identified farther from its housing centre than its
        clearance dL_max [1] allows (measurement error, or a wrong clearance or housing)."""
        out = []
        for name, j in self.joints.items():
            if j.exceeds_clearance:
                where = " normal to the housing axis" if j.housing_axis is not None else ""
                out.append(f"joint '{name}': identified {j.clearance_shift_mm:.3f} mm from its "
                           f"housing centre{where}, beyond its clearance dL_max = "
                           f"{j.max_shift_mm:.3f} mm (eq. (1) of Meissonnier et al. 2006): "
                           "CMM noise, or the clearance or the housing is not as measured")
        return out

    @property
    def all_warnings(self) -> list[str]:
        """Mark matching, dropped marks, unused hardpoints, shifts beyond the clearance."""
        return [*self.warnings, *self.clearance_warnings()]

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
                           "clearance_shift_mm": j.clearance_shift_mm,
                           "exceeds_clearance": j.exceeds_clearance,
                           "euler_zxz_deg": vec(j.euler_zxz_deg),
                           "deflection_mm_deg": vec(j.deflection)}
                       for n, j in self.joints.items()},
            "verification_max_deviation_mm": self.verification_max_deviation_mm,
            "verification_deviation_mm": self.verification_mm,
            "warnings": self.all_warnings,
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
            label = pm.label(hp, {"point": "", "axis": ".Z", "radial": ".X"}[kind])
            entity = "point" if kind == "point" else "line"
            raise MeasurementError(f"{pm.source}: part '{part}': no {entity} labelled "
                                   f"{label} ({what})")
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


def identify(suspension: Suspension, progress: Callable[[str], None] = lambda m: None
             ) -> Identification:
    """Identify the geometry of ``suspension`` from its ``measurements`` (see module doc):
    part poses, joints in the vehicle frame, the initial and identified configs (of the
    config's corner, on an axle). The
    identified config still asks for its bushing preloads to be balanced; the study that
    solves them calls :func:`apply_design_loads` (:mod:`elastokin.studies.identification`)."""
    s = corner(suspension)  # on an axle: the measured corner, the config's side
    m = s.measurements
    if m is None:
        raise ConfigError(f"{s.source}: no 'measurements' section: nothing to identify")
    check_measurements(s, m, "measurements")
    progress("reading measurements")
    parts, assembly_file, assembled, truth = read_measurements(s)
    sources = {p: pm.source for p, pm in parts.items()}
    sources["assembly"] = assembly_file
    progress("part poses")
    poses, warnings = part_poses(s, parts, assembled, assembly_file)
    geo = _Geometry(s, _Features(parts, poses))
    geo.locate()
    initial_cfg = geo.config(geo.initial_hp, "initial: parts measured alone", 0)
    ident_cfg = geo.config(geo.ident_hp, "identified", 1)
    design = dict(s.raw["design"])
    initial_cfg["design"] = {**design, "balance_bushing_preloads": False}
    # identified deflections [22-23] come from the model held at the measured poses
    ident_cfg["design"] = {**design, "balance_bushing_preloads": bool(s.bushings)}
    for name, j in geo.joints.items():  # the synthetic truth, when there is one
        if name in truth:
            j.truth_mm = truth[name]
    return Identification(s, poses, geo.joints, initial_cfg, ident_cfg,
                          warnings=warnings + geo.warnings, sources=sources,
                          outer_frames={k: v[1] for k, v in geo.bushing_frames.items()})


def part_poses(s: Suspension, parts: dict[str, PartMeasurement],
               assembled: dict[str, np.ndarray], assembly_file: str
               ) -> tuple[dict[str, PartPose], list[str]]:
    """Every part's pose in the vehicle frame [8-12]: the marks ordered [8-10] and fitted
    [11-12] in the CMM frame, then expressed relative to the ground part's pose (which fixes
    the CMM frame)."""
    m = s.measurements
    warnings: list[str] = []
    matches = {}
    for p, pm in parts.items():
        try:
            matches[p] = match_marks(pm.marks, assembled[p], m.eps_mm, p)
        except MeasurementError as exc:
            hint = _unit_hint(parts, assembled, p, m.eps_mm, assembly_file)
            raise MeasurementError(f"{assembly_file}: {exc}{hint}") from None
        warnings += [f"{assembly_file}: {w}" for w in matches[p].warnings]
        if matches[p].dropped_mark is not None:
            warnings.append(f"{assembly_file}: part '{p}': mark "
                            f"{m.parts[p].marks[matches[p].dropped_mark]} of {pm.source} was "
                            "not found within eps: the wrong point was dropped and the pose "
                            "fitted to the other three")
    g = matches[s.ground]
    poses = {p: PartPose(p, g.R.T @ mm.R, g.R.T @ (mm.t - g.t), mm) for p, mm in matches.items()}
    return poses, warnings


#: common unit mix-ups (a file whose unit flag is not the unit of its numbers): factor, shown as
_UNIT_SCALES = ((25.4, "25.4"), (1 / 25.4, "1/25.4"), (10.0, "10"), (0.1, "0.1"),
               (1000.0, "1000"), (0.001, "0.001"), (304.8, "304.8"), (1 / 304.8, "1/304.8"))


def _fits(local: np.ndarray, measured: np.ndarray, eps_mm: float, part: str) -> bool:
    try:
        match_marks(local, measured, eps_mm, part)
    except MeasurementError:
        return False
    return True


def _unit_hint(parts: dict[str, PartMeasurement], assembled: dict[str, np.ndarray], part: str,
               eps_mm: float, assembly_file: str) -> str:
    """When a part's marks match no ordering: the common unit factor after which they would
    (the distance test [8-9] is scale-sensitive) and the file whose unit flag to check: the
    assembly's when every part fits after scaling the assembled marks, else the part's."""
    for factor, shown in _UNIT_SCALES:
        if all(_fits(parts[q].marks, assembled[q] * factor, eps_mm, q) for q in parts):
            return (f"; every part's marks fit after scaling the assembled marks by {shown}: "
                    f"check the unit flag of {assembly_file}")
    for factor, shown in _UNIT_SCALES:
        if _fits(parts[part].marks * factor, assembled[part], eps_mm, part):
            return (f"; the marks fit after scaling by {shown}: check the unit flag of "
                    f"{parts[part].source}")
    return ""


class _Geometry:
    """The joints in the vehicle frame at the loaded state [19] and the hardpoints of the two
    geometries: initial (housing centres of the parts measured alone) and identified."""

    def __init__(self, s: Suspension, feats: _Features):
        self.s, self.feats = s, feats
        self.initial_hp: dict[str, np.ndarray] = {}
        self.ident_hp: dict[str, np.ndarray] = {}
        self.joints: dict[str, JointResult] = {}
        self.bushing_frames: dict[str, tuple[np.ndarray, np.ndarray]] = {}  # initial, ident.
        self.axes_measured: dict[str, np.ndarray] = {}
        self.spin: np.ndarray | None = None
        self.warnings: list[str] = []

    def place(self, hp: str, initial: np.ndarray, identified: np.ndarray) -> None:
        if hp not in self.ident_hp:
            self.initial_hp[hp], self.ident_hp[hp] = initial, identified

    def locate(self) -> None:
        s, feats, raw = self.s, self.feats, self.s.raw
        spec_file = SuspensionFile.model_validate(raw)
        for name, c in spec_file.connections.items():
            if isinstance(c, LinkSpec):
                self.link(name, c)
            elif isinstance(c, BushingSpec):
                self.bushing(name, c)
            else:
                self.joint(name, c)
        for sname, sp in spec_file.springs.items():
            for part, seat in zip(sp.parts, sp.seats):
                hp = hardpoint_name(seat, f"springs.{sname}.seats", s.source)
                x = feats.point(part, hp, f"seat of spring '{sname}'")
                self.place(hp, x, x)
        w = raw["wheel"]
        hp = hardpoint_name(w["centre"], "wheel.centre", s.source)
        x = feats.point(w["part"], hp, "wheel centre")
        self.place(hp, x, x)
        if feats.has("axis", w["part"], hp):
            self.spin = feats.axis(w["part"], hp, "wheel spin axis")
        for hp_name in raw["hardpoints"]:
            if hp_name not in self.ident_hp:
                self.warnings.append(f"{s.source}: hardpoint '{hp_name}' is used by no "
                                     "measured joint: kept at its config value")

    def link(self, name: str, c: LinkSpec) -> None:
        for part, at in zip(c.parts, c.at):
            hp = hardpoint_name(at, f"connections.{name}.at", self.s.source)
            x = self.feats.point(part, hp, f"end of link '{name}'")
            self.place(hp, x, x)
            self.joints[f"{name}:{hp}"] = JointResult(f"{name}:{hp}", "link end", x, x)

    def _clearance(self, name: str) -> float | None:
        jm = self.s.measurements.joints.get(name)
        return jm.clearance.max_shift_mm if jm is not None and jm.clearance else None

    def bushing(self, name: str, c: BushingSpec) -> None:
        """The outer sleeve (exactly measured) gives the bushing frame; the inner sleeve is
        bolted: its housing centre and axis give the initial frame with zero torsion [13-18]."""
        feats = self.feats
        hp = hardpoint_name(c.at, f"connections.{name}.at", self.s.source)
        inner = self.s.measurements.joints[name].inner
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
        self.bushing_frames[name] = (F1, F2)
        self.place(hp, housing, o2)
        self.joints[name] = JointResult(name, "bushing", housing, o2,
                                        max_shift_mm=self._clearance(name),
                                        housing_axis=w_h / np.linalg.norm(w_h))

    def joint(self, name: str, c) -> None:
        """A joint: a bolted side is known by its housing centre, the other side exactly
        [27]; an axis measured on its parts replaces the config's explicit axis."""
        feats, parts = self.feats, self.feats.parts
        hp = hardpoint_name(c.at, f"connections.{name}.at", self.s.source)
        sides = [p for p in c.parts if feats.has("point", p, hp)]
        if not sides:
            raise MeasurementError(f"{', '.join(parts[p].source for p in c.parts)}: joint "
                                   f"'{name}': no point labelled '{hp}' on part "
                                   f"'{c.parts[0]}' or '{c.parts[1]}'")
        jm = self.s.measurements.joints.get(name)
        bolted = jm.bolted if jm is not None else None
        if bolted is not None:
            exact = c.parts[1] if c.parts[0] == bolted else c.parts[0]
            ident = feats.point(exact, hp, f"joint '{name}', exactly measured centre")
            initial = feats.point(bolted, hp, f"joint '{name}', housing centre")
        else:
            ident = initial = np.mean([feats.point(p, hp, "") for p in sides], axis=0)
        self.place(hp, initial, ident)
        self.joints[name] = JointResult(name, c.type, initial, ident,
                                        max_shift_mm=self._clearance(name))
        axis_sides = [p for p in c.parts if feats.has("axis", p, hp)]
        if axis_sides:
            a = [feats.axis(p, hp, "") for p in axis_sides]
            a = [v if v @ a[0] >= 0 else -v for v in a]
            self.axes_measured[name] = np.mean(a, axis=0) / np.linalg.norm(np.mean(a, axis=0))

    def config(self, hardpoints: dict[str, np.ndarray], label: str, frame: int) -> dict:
        """The config of one geometry: hardpoints, measured axes and spin axis, bushing
        frames (``frame`` 0: initial, 1: identified) as z-x-z Euler angles [20] of their
        rotation terms [21]."""
        raw = self.s.raw
        d = copy.deepcopy(raw)
        d.pop("measurements", None)
        d.pop("kc_test", None)
        d["name"] = f"{raw['name']} ({label})"
        d["hardpoints"] = {k: _clean(hardpoints.get(k, v)) for k, v in raw["hardpoints"].items()}
        for name, a in self.axes_measured.items():
            spec = d["connections"][name]
            k = "torsion_axis" if spec["type"] == "universal" else "axis"
            if k in spec and not isinstance(spec[k], dict):  # an explicit vector: measured
                sign = 1.0 if np.dot(spec[k], a) >= 0 else -1.0
                spec[k] = _clean(sign * a)
        if self.spin is not None and not isinstance(d["wheel"]["spin_axis"], dict):
            sign = 1.0 if np.dot(d["wheel"]["spin_axis"], self.spin) >= 0 else -1.0
            d["wheel"]["spin_axis"] = _clean(sign * self.spin)
        for name, frames in self.bushing_frames.items():
            spec = d["connections"][name]
            for k in ("axis", "radial", "euler_zxz_deg", "preload", "initial_deflection"):
                spec.pop(k, None)
            spec["euler_zxz_deg"] = _clean(euler_zxz_deg(frames[frame]))
        return d


def apply_design_loads(ident: Identification, balanced: Suspension,
                       state: DesignState) -> None:
    """The identified model's bushing deflections [22-23] from the loads its bushings carry
    with the model held at the measured poses (``state``, solved on ``balanced``, the
    identified config's suspension): written into the identified config as initial
    deflections, with the inner-sleeve frame B* [24-26] and its centre reported (the paper's
    D is inner rel. outer sleeve, here outer rel. inner: B* = B2 D^-1, vehicle frame);
    the balanced spring's preload; the design without balancing (the file is the model)."""
    s, cfg = ident.suspension, ident.identified_config
    design = dict(s.raw["design"])
    for b in balanced.bushings:
        u0 = np.array([law.deflection_at(f) for law, f in zip(b.laws, state.bushing_preload[
            b.name])])
        cfg["connections"][b.name]["initial_deflection"] = {
            "translation_mm": _clean(u0[:3]), "rotation_deg": _clean(u0[3:])}
        inner = s.measurements.joints[b.name].inner
        sign = 1.0 if b.parts[0] == inner else -1.0  # deflection = parts[1] rel. parts[0]
        D = deflection_operator(sign * u0[:3], sign * u0[3:])  # outer rel. inner [24-25]
        B_inner = ident.outer_frames[b.name] @ D[:3, :3].T  # B* = B2 D^-1 [26], vehicle frame
        j = ident.joints[b.name]
        j.identified_mm = j.identified_mm - B_inner @ D[:3, 3]
        j.euler_zxz_deg = euler_zxz_deg(B_inner)
        j.deflection = u0
    for sname, force in state.spring_force_N.items():
        if design.get("balance_spring") == sname:
            cfg["springs"][sname]["preload_N"] = _clean([force])[0]
    cfg["design"] = {"wheel_load_N": design["wheel_load_N"]}


def verification_deviations(ident: Identification, identified: Suspension,
                            poses: PartPoses) -> None:
    """The paper's check (its section 5, no equation): the distance of every joint of every
    moving part from its measured location, at the identified model's static equilibrium
    under the wheel load (``poses``, solved on ``identified``): stored in ``ident``."""
    dev: dict[str, float] = {}
    for name in ident.joints:
        connection, _, end = name.partition(":")  # a link end is "<link>:<hardpoint>"
        spec = ident.identified_config["connections"][connection]
        if end:
            at, parts = end, [spec["parts"][spec["at"].index(end)]]
        else:
            at, parts = spec["at"], spec["parts"]
        parts = [p for p in parts if p != identified.ground]
        x = np.asarray(identified.hardpoints[at])
        dev[name] = max([float(np.linalg.norm(poses.moved(p, x) - x)) for p in parts],
                        default=0.0)
    ident.verification_mm = dev
    ident.verification_max_deviation_mm = max(dev.values(), default=0.0)
