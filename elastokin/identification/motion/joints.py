"""Which joint is located how from the motion, and the located joint with its uncertainty.

A connection between two marked bodies (parts, the ground, a marked link) is located by the
functional method its kind calls for (:mod:`.functional`):

- spherical joint, universal joint, link end: the centre, SCoRE;
- revolute joint: the axis and the point of it nearest the config's hardpoint (the motion
  does not fix a point along a hinge), SARA; cylindrical joint: the same, the slide along the
  axis left out;
- a link's end on the ground when the rig steers (``motion.rack_link``) or on an unmarked
  steering rack: the centre, riding on the rack with the rig's stated rack travel
  (:func:`.functional.rack_score`);
- the wheel (``motion.wheel_marks``): its spin axis, SARA between the wheel's marks and the
  wheel part; the wheel centre is the axis point nearest the config's;
- a bushing working as a hinge (``ideal_joint: revolute`` or ``cylindrical``): its axis,
  SARA's direction, which the rotations alone fix. A bushing's centre is not located: it
  deflects with the rig's loads, and a deflection that grows with the turn is the same
  motion as a turn about another point (its effective pivot can lie centimetres from the
  sleeves); bushings keep their config location (or the part measurements' identification).

Units mm, deg; vehicle (config) frame at the design position.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from elastokin.config.schema.motion import MotionSpec
from elastokin.config.schema.suspension import BushingSpec, LinkSpec, SuspensionFile
from elastokin.config.suspension import Suspension
from elastokin.formats.cmm_motion import WHEEL
from elastokin.identification.motion.functional import (
    rack_score,
    sara,
    score,
    world_axis,
    world_point,
)

SCORE, SARA, SLIDING_SARA, ON_THE_RACK, AXIS_ONLY = (
    "SCoRE", "SARA", "SARA, sliding", "SCoRE, on the rack", "SARA, axis only")
_METHOD = {"spherical": SCORE, "universal": SCORE, "revolute": SARA,
           "cylindrical": SLIDING_SARA}


@dataclass(frozen=True)
class JointPlan:
    """How one joint is located: ``bodies`` (a, b) whose relative motion locates it (a is
    the ground for a link end on the rack), the config's ``hardpoint`` and location
    (``config_mm``), for an axis the config's direction (``config_axis``), on the rack the
    rig's rack travel at every position."""

    name: str
    kind: str
    method: str
    bodies: tuple[str, str]
    hardpoint: str
    config_mm: np.ndarray
    config_axis: np.ndarray | None = None
    rack_travel_mm: tuple[float, ...] = ()

    @property
    def has_axis(self) -> bool:
        return self.method in (SARA, SLIDING_SARA, AXIS_ONLY)

    @property
    def locates_point(self) -> bool:
        return self.method != AXIS_ONLY

    def estimate(self, poses, design: int) -> np.ndarray:
        """The located point (3,) or point and unit axis (6,), vehicle frame, design
        position (a bushing's axis: with the config's point)."""
        (Ra, ta), (Rb, tb) = poses[self.bodies[0]], poses[self.bodies[1]]
        if self.method == ON_THE_RACK:
            c, c0, v, _ = rack_score(Rb, tb, self.rack_travel_mm)
            return 0.5 * (c0 + self.rack_travel_mm[design] * v + world_point(Rb, tb, c, design))
        if self.method == SCORE:
            ca, cb, _ = score(Ra, ta, Rb, tb)
            return 0.5 * (world_point(Ra, ta, ca, design) + world_point(Rb, tb, cb, design))
        hint = Ra[design].T @ self.config_axis
        ca, cb, axis, _ = sara(Ra, ta, Rb, tb, slide=self.method == SLIDING_SARA, hint=hint)
        m = world_axis(Ra, axis, design)
        if self.method == AXIS_ONLY:
            return np.concatenate([self.config_mm, m])
        p = 0.5 * (world_point(Ra, ta, ca, design) + world_point(Rb, tb, cb, design))
        return np.concatenate([p + m * (m @ (self.config_mm - p)), m])


@dataclass
class MotionJoint:
    """A joint located from the motion (vehicle frame, design position; mm, deg).

    ``covariance_mm2``: of the point, from the CMM noise (first order, :func:`.poses.
    propagate`); ``axis_covariance``: of the unit axis; ``condition``: SCoRE's matrix's
    largest over smallest singular value; ``residual_rms_mm``: how far the two bodies' points
    part over the positions (CMM noise for a ball joint, more for a bushing, which deflects);
    ``truth_mm``, ``truth_axis``: the synthetic truth, when there is one."""

    plan: JointPlan
    point_mm: np.ndarray
    covariance_mm2: np.ndarray
    condition: float
    residual_rms_mm: float | None
    axis: np.ndarray | None = None
    axis_covariance: np.ndarray | None = None
    truth_mm: np.ndarray | None = None
    truth_axis: np.ndarray | None = None
    # directions along which the point keeps the config's location (motion.partly_located)
    from_config: list[tuple[np.ndarray, float]] = field(default_factory=list)  # (d, std)

    @property
    def uncertainty_mm(self) -> float:
        """3-D RMS standard uncertainty of the point (1 sigma)."""
        return float(np.sqrt(np.trace(self.covariance_mm2)))

    @property
    def worst_std_mm(self) -> float:
        """Standard uncertainty along the point's worst direction."""
        return float(np.sqrt(max(np.linalg.eigvalsh(self.covariance_mm2)[-1], 0.0)))

    @property
    def axis_uncertainty_deg(self) -> float | None:
        """RMS standard uncertainty of the axis direction (deg)."""
        if self.axis_covariance is None:
            return None
        return float(np.degrees(np.sqrt(np.trace(self.axis_covariance))))

    @property
    def error_vs_truth_mm(self) -> float | None:
        """Distance from the true location (an axis joint: from the true axis, along which
        the motion fixes no point)."""
        if self.truth_mm is None or not self.plan.locates_point:
            return None
        d = self.point_mm - self.truth_mm
        if self.truth_axis is not None:
            d = d - (d @ self.truth_axis) * self.truth_axis
        return float(np.linalg.norm(d))

    @property
    def axis_error_deg(self) -> float | None:
        if self.axis is None or self.truth_axis is None:
            return None
        c = abs(float(self.axis @ self.truth_axis)) / np.linalg.norm(self.truth_axis)
        return float(np.degrees(np.arccos(min(c, 1.0))))


def plans(s: Suspension, motion: MotionSpec, bodies: list[str]) -> tuple[list[JointPlan],
                                                                          list[str]]:
    """The joints the motion can locate, and warnings naming those it cannot (a body without
    marks, a joint kind with no functional method)."""
    spec = SuspensionFile.model_validate(s.raw)
    joints = {j.name: j for j in s.joints}
    bushings = {b.name: b for b in s.bushings}
    out, warnings = [], []

    def skip(name, why):
        warnings.append(f"{s.source}: connection '{name}' is not located from the motion "
                        f"({why}): kept at its config value")

    for name, c in spec.connections.items():
        if isinstance(c, LinkSpec):
            out += _link_plans(s, motion, name, c, bodies, skip)
            continue
        a, b = c.parts
        if a not in bodies or b not in bodies:
            skip(name, f"part '{a if a not in bodies else b}' has no marks")
            continue
        x = np.asarray(s.hardpoints[c.at], float)
        if isinstance(c, BushingSpec):
            bush = bushings[name]
            if bush.ideal_joint not in ("revolute", "cylindrical"):
                skip(name, "a bushing deflects with the rig's loads: the motion does not "
                     "locate its centre")
                continue
            out.append(JointPlan(name, "bushing", AXIS_ONLY, (a, b), c.at, x,
                                 bush.frame[:, 2]))
            continue
        if c.type not in _METHOD:
            skip(name, f"a {c.type} joint has no functional method")
            continue
        axis = None if c.type == "spherical" else joints[name].frame[:, 2]
        kind = "ball joint" if c.type == "spherical" else c.type
        out.append(JointPlan(name, kind, _METHOD[c.type], (a, b), c.at, x, axis))
    if WHEEL in bodies:
        w = s.wheel
        out.append(JointPlan(WHEEL, "wheel spin axis", SARA, (w.part, WHEEL),
                             spec.wheel.centre, np.asarray(w.centre_mm, float), w.spin_axis))
    else:
        warnings.append(f"{s.source}: the wheel's spin axis and centre are kept at their config "
                        "values (no motion.wheel_marks)")
    return out, warnings


def _link_plans(s: Suspension, motion: MotionSpec, name: str, c: LinkSpec,
                bodies: list[str], skip) -> list[JointPlan]:
    """A marked link's two ends: ball joints with the parts at its ends; an end on the
    ground that rides on the rack (``motion.rack_link``) or on an unmarked rack part: on the
    rack."""
    if name not in bodies:
        skip(name, "the link has no marks (motion.marks)")
        return []
    racks = {j.parts[1]: j for j in s.joints if j.kind == "rack" and j.parts[0] == s.ground}
    travel = tuple(p.rack_travel_mm for p in motion.positions.values())
    out = []
    for part, at in zip(c.parts, c.at):
        x = np.asarray(s.hardpoints[at], float)
        if part in racks and part not in bodies:
            out.append(JointPlan(f"{name}:{at}", "link end", ON_THE_RACK, (s.ground, name), at,
                                 x, racks[part].frame[:, 2], travel))
        elif part == s.ground and motion.rack_link == name:
            out.append(JointPlan(f"{name}:{at}", "link end", ON_THE_RACK, (s.ground, name), at,
                                 x, s.left, travel))
        elif part not in bodies:
            skip(f"{name}:{at}", f"part '{part}' has no marks")
        else:
            out.append(JointPlan(f"{name}:{at}", "link end", SCORE, (part, name), at, x))
    return out
