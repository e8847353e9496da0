"""Joint locations from the parts' motion (the config's ``motion`` section), no disassembly:
every marked body's pose at every rig position from its marks (:mod:`.poses`), each joint
located by its functional method (:mod:`.joints`, :mod:`.functional`) with its uncertainty
from the CMM noise, and the model ``identified_motion``: the config with its hardpoints and
axes where the motion puts them at the design position. A joint the motion cannot locate
within ``motion.max_uncertainty_mm`` (an axis: ``max_axis_uncertainty_deg``) stops with a
message naming the joint, the conditioning and the positions that would locate it.

Units mm, deg; vehicle (config) frame at the design position.
"""

from __future__ import annotations

import copy
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from elastokin.config.measurements import check_motion
from elastokin.config.schema.motion import MotionSpec
from elastokin.config.suspension import Suspension
from elastokin.config.variants import corner
from elastokin.errors import ConfigError
from elastokin.formats.cmm_motion import (
    WHEEL,
    MotionMeasurement,
    motion_paths,
    read_motion,
    read_motion_truth,
)
from elastokin.identification.motion.conditioning import (
    check_located,
    located_condition,
    vector_text,
)
from elastokin.identification.motion.functional import rack_score
from elastokin.identification.motion.joints import (
    ON_THE_RACK,
    SLIDING_SARA,
    JointPlan,
    MotionJoint,
    plans,
)
from elastokin.identification.motion.poses import (
    MotionMarks,
    Poses,
    noise_sigma,
    order_marks,
    propagate,
    vehicle_poses,
)


@dataclass
class MotionIdentification:
    """The joints located from the motion and the config of the model ``identified_motion``
    (plain data). ``noise_sigma_mm``: the CMM noise per coordinate the residuals of the pose
    fits show (``noise_dof`` degrees of freedom), which the uncertainties stand on."""

    suspension: Suspension
    joints: dict[str, MotionJoint]
    config: dict
    noise_sigma_mm: float
    noise_dof: int
    design_position: str
    positions: dict[str, dict[str, float]]  # name -> rig state
    warnings: list[str] = field(default_factory=list)
    sources: dict[str, str] = field(default_factory=dict)  # position (and ground) -> file
    dropped_marks: list[dict] = field(default_factory=list)

    def to_json(self) -> dict:
        """``motion_identification.json``'s body (plain data; mm, deg, vehicle frame at the
        design position)."""
        def vec(v):
            return None if v is None else [float(x) for x in np.asarray(v).ravel()]

        return {
            "design_position": self.design_position,
            "positions": self.positions,
            "noise_sigma_mm": self.noise_sigma_mm,
            "noise_dof": self.noise_dof,
            "joints": {n: {"kind": j.plan.kind, "method": j.plan.method,
                           "bodies": list(j.plan.bodies), "hardpoint": j.plan.hardpoint,
                           "located_mm": vec(j.point_mm) if j.plan.locates_point else None,
                           "config_mm": vec(j.plan.config_mm),
                           "uncertainty_mm": j.uncertainty_mm if j.plan.locates_point
                           else None,
                           "worst_std_mm": j.worst_std_mm if j.plan.locates_point else None,
                           "covariance_mm2": vec(j.covariance_mm2),
                           "axis": vec(j.axis), "axis_uncertainty_deg": j.axis_uncertainty_deg,
                           "condition_number": j.condition,
                           "residual_rms_mm": j.residual_rms_mm,
                           "from_config_along": [vec(d) for d, _ in j.from_config],
                           "truth_mm": vec(j.truth_mm), "truth_axis": vec(j.truth_axis),
                           "error_vs_truth_mm": j.error_vs_truth_mm,
                           "axis_error_deg": j.axis_error_deg}
                       for n, j in self.joints.items()},
            "dropped_marks": self.dropped_marks,
            "warnings": self.warnings,
            "files": self.sources,
        }


def identify_motion(suspension: Suspension, progress: Callable[[str], None] = lambda m: None,
                    ) -> MotionIdentification:
    """Locate the joints of ``suspension`` (on an axle: its config side's corner) from its
    ``motion`` measurements (see module doc)."""
    s = corner(suspension)
    mo = s.motion
    if mo is None:
        raise ConfigError(f"{s.source}: no 'motion' section: nothing to identify from motion")
    check_motion(s, mo, "motion")
    progress("reading the motion measurements")
    data = read_motion(s)
    truth = read_motion_truth(motion_paths(s)["truth"]) if mo.truth else ({}, {})
    ident = locate_joints(s, mo, data, truth, progress)
    config, kept = motion_config(s, ident.joints)
    if kept:
        ident.warnings.append(f"{s.source}: hardpoint(s) {', '.join(kept)} located by no "
                              "joint of the motion: kept at their config values")
    ident.config = config
    return ident


def locate_joints(s: Suspension, mo: MotionSpec, data: MotionMeasurement,
                  truth: tuple[dict, dict] = ({}, {}),
                  progress: Callable[[str], None] = lambda m: None,
                  covariance: bool = True) -> MotionIdentification:
    """The joints of the corner ``s`` located from the marks ``data`` measured at the
    positions of ``mo`` (no config built: :func:`motion_config`); ``truth``: true points and
    axes by joint (synthetic data). Without ``covariance`` (Monte Carlo), no uncertainty and
    no check of it."""
    design = data.positions.index(mo.design_position)
    progress("part poses at every position")
    marks, warnings = order_marks(data, s.ground, design, mo.eps_mm)
    sigma, dof = noise_sigma(marks)
    todo, more = plans(s, mo, list(marks.raw))
    poses = vehicle_poses(marks)
    unknown = sorted(set(mo.partly_located) - {p.name for p in todo})
    if unknown:
        raise ConfigError(f"{s.source}: key 'motion.partly_located': {', '.join(unknown)} "
                          f"is not located from the motion (located: "
                          f"{', '.join(p.name for p in todo)})")
    joints = {}
    for plan in todo:
        progress(f"locating {plan.name} from the motion")
        j = joints[plan.name] = locate(plan, marks, poses, sigma if covariance else None, mo,
                                       data.files)
        j.truth_mm, j.truth_axis = truth[0].get(plan.name), truth[1].get(plan.name)
        more += [f"{s.source}: joint '{plan.name}' keeps its config location along "
                 f"{vector_text(d)} (motion.partly_located): the motion "
                 f"locates it there to {sd:.2f} mm only" for d, sd in j.from_config]
    sources = {"ground": data.ground_file, **dict(zip(data.positions, data.files))}
    dropped = [{"body": b, "position": data.positions[k], "mark": i}
               for b, k, i in marks.dropped]
    return MotionIdentification(s, joints, {}, sigma, dof, mo.design_position,
                                {n: p.model_dump(exclude={"file"})
                                 for n, p in mo.positions.items()},
                                list(dict.fromkeys(warnings + more)), sources, dropped)


def locate(plan: JointPlan, marks: MotionMarks, poses: Poses, sigma_mm: float | None, motion,
           files: list[str]) -> MotionJoint:
    """One joint from the motion, with its covariance from the CMM noise (``sigma_mm``;
    None: none, zeros); raises (:func:`.conditioning.check_located`) when the motion does not
    locate it."""
    design = marks.design
    condition = located_condition(plan, poses, design)
    check_located(plan, poses, design, motion, files, condition=condition)
    value = plan.estimate(poses, design)
    if sigma_mm is None:
        cov = np.zeros((len(value), len(value)))
    else:
        cov = propagate(marks, list(plan.bodies), lambda p: plan.estimate(p, design),
                        sigma_mm)
    weak = None
    if plan.name in motion.partly_located and sigma_mm is not None:  # the config along
        # what the motion cannot fix (from the covariance: none without it)
        w, v = np.linalg.eigh(cov[:3, :3])
        weak, weak_std = v[:, w > motion.max_uncertainty_mm**2], np.sqrt(w[w > motion.
                                                                        max_uncertainty_mm**2])
        keep = np.eye(len(value))
        keep[:3, :3] -= weak @ weak.T
        value = keep @ value + (np.eye(len(value)) - keep) @ np.resize(plan.config_mm,
                                                                        len(value))
        cov = keep @ cov @ keep.T
    joint = MotionJoint(plan, value[:3], cov[:3, :3], condition,
                        residual_rms(plan, poses, value, design) if plan.locates_point
                        else None)
    if plan.has_axis:
        joint.axis, joint.axis_covariance = value[3:], cov[3:, 3:]
    if weak is not None and weak.size:
        joint.from_config = [(np.asarray(d), float(sd)) for d, sd in zip(weak.T, weak_std)]
    check_located(plan, poses, design, motion, files, joint=joint)
    return joint


def residual_rms(plan: JointPlan, poses: Poses, value: np.ndarray, design: int) -> float:
    """How far the located point, carried by each body from the design position, parts at
    the other positions (RMS, mm): the CMM noise for an ideal joint; a bushing's deflection
    adds to it. The slide of a cylindrical joint and the rack's travel are not partings."""
    (Ra, ta), (Rb, tb) = poses[plan.bodies[0]], poses[plan.bodies[1]]
    x = value[:3]
    ca = Ra[design].T @ (x - ta[design])
    cb = Rb[design].T @ (x - tb[design])
    gap = (np.einsum("kij,j->ki", Ra, ca) + ta) - (np.einsum("kij,j->ki", Rb, cb) + tb)
    if plan.method == SLIDING_SARA:
        m = np.einsum("kij,j->ki", Ra, Ra[design].T @ value[3:])
        gap -= np.sum(gap * m, axis=1, keepdims=True) * m
    elif plan.method == ON_THE_RACK:  # the rack's travel
        gap += np.outer(plan.rack_travel_mm, rack_score(Rb, tb, plan.rack_travel_mm)[2])
    return float(np.sqrt(np.mean(np.sum(gap**2, axis=1))))


def _clean(v) -> list[float]:
    return [round(float(x), 6) + 0.0 for x in np.asarray(v, float).ravel()]


def motion_config(s: Suspension, joints: dict[str, MotionJoint]) -> tuple[dict, list[str]]:
    """The config of the model ``identified_motion``: the suspension's config with every
    located joint's hardpoint (the first joint at a hardpoint wins), axis and the wheel's spin
    axis and centre where the motion puts them; an axis given by two hardpoints (``axis:
    {from, to}``) by moving both onto the located axis; the ``design`` kept (the
    hardpoints are the static equilibrium under the wheel load). Returns it and the
    hardpoints kept at their config values."""
    raw = s.raw
    d = copy.deepcopy(raw)
    for key in ("measurements", "motion", "kc_test"):
        d.pop(key, None)
    d["name"] = f"{raw['name']} (identified from motion)"
    located: dict[str, np.ndarray] = {}
    lines: dict[str, tuple[np.ndarray, np.ndarray]] = {}  # hardpoint -> a located axis
    for j in joints.values():
        if j.plan.locates_point:
            located.setdefault(j.plan.hardpoint, j.point_mm)
        if j.axis is None:
            continue
        if j.plan.name == WHEEL:
            d["wheel"]["spin_axis"] = _clean(j.axis * np.sign(j.axis @ s.wheel.spin_axis))
            continue
        spec = d["connections"][j.plan.name]
        key = "torsion_axis" if spec["type"] == "universal" else "axis"
        axis = j.axis * np.sign(j.axis @ j.plan.config_axis)
        ends = spec.get(key) if isinstance(spec.get(key), dict) else {}
        if j.plan.locates_point and all(isinstance(e, str) for e in ends.values()) and ends:
            # an axis between two hardpoints: both moved onto the located axis, so that the
            # model's axis is it and a joint at either end stays on it exactly
            for end in ends.values():
                lines.setdefault(end, (j.point_mm, axis))
            continue
        if spec["type"] == "bushing":
            b = next(b for b in s.bushings if b.name == j.plan.name)
            radial = b.frame[:, 0] - (b.frame[:, 0] @ axis) * axis
            for k in ("axis", "radial", "euler_zxz_deg"):
                spec.pop(k, None)
            spec["axis"], spec["radial"] = _clean(axis), _clean(radial / np.linalg.norm(radial))
        else:
            spec[key] = _clean(axis)
    for hp, (p, m) in lines.items():
        if hp not in located:
            x = np.asarray(raw["hardpoints"][hp], float)
            located[hp] = p + m * (m @ (x - p))
    d["hardpoints"] = {k: _clean(located.get(k, v)) for k, v in raw["hardpoints"].items()}
    return d, [k for k in raw["hardpoints"] if k not in located]
