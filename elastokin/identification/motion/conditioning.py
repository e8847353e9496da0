"""Is the motion enough to locate a joint? Functional methods locate a joint only in the
directions about which its two bodies turn relative to each other (Woltring et al. 1985):
a ball joint's centre needs turns about two different axes, a hinge's axis a turn about it.
When the measured positions do not give that, :func:`check_located` stops with a message that
names the joint, the conditioning (the condition number of SCoRE's matrix, the turns measured)
and the positions that would locate it."""

from __future__ import annotations

import numpy as np

from elastokin.config.schema.motion import MotionSpec
from elastokin.errors import MeasurementError
from elastokin.formats.cmm_motion import WHEEL
from elastokin.identification.motion.functional import relative_rotations, weak_direction
from elastokin.identification.motion.joints import SCORE, JointPlan, MotionJoint

#: beyond this condition number the problem is singular: the motion does not locate at all
SINGULAR = 1e8


def vector_text(v) -> str:
    """A direction or point as '(x, y, z)' to 2 decimals (no negative zero)."""
    return "(" + ", ".join(f"{round(x, 2) + 0.0:.2f}" for x in np.asarray(v, float)) + ")"


def located_condition(plan: JointPlan, poses, design: int) -> float:
    """The condition number of the joint's problem: SCoRE's matrix (largest over smallest
    singular value); for an axis the matrix without its null direction (a hinge's axis):
    largest over fifth singular value."""
    Ra, Rb = poses[plan.bodies[0]][0], poses[plan.bodies[1]][0]
    A = np.concatenate([Ra, -Rb], axis=2).reshape(-1, 6)
    s = np.linalg.svd(A, compute_uv=False)
    weakest = s[4] if plan.has_axis else s[5]
    return float(s[0] / weakest) if weakest > 0 else float("inf")


def check_located(plan: JointPlan, poses, design: int, motion: MotionSpec, files: list[str],
                  condition: float | None = None, joint: MotionJoint | None = None) -> None:
    """Raise when the motion does not locate the joint: before solving, a singular problem
    (``condition``); after, an uncertainty beyond ``motion.max_uncertainty_mm`` (the point,
    along its worst direction) or ``motion.max_axis_uncertainty_deg`` (the axis)."""
    if joint is None:
        if condition is not None and condition > SINGULAR:
            raise MeasurementError(_message(plan, poses, design, motion, files, condition,
                                            "cannot be located at all (a singular problem)"))
        return
    if joint.worst_std_mm > motion.max_uncertainty_mm:
        w, v = np.linalg.eigh(joint.covariance_mm2)
        raise MeasurementError(_message(
            plan, poses, design, motion, files, joint.condition,
            f"is located to {joint.worst_std_mm:.2f} mm (1 sigma) along "
            f"{vector_text(v[:, -1])}, "
            f"more than motion.max_uncertainty_mm = {motion.max_uncertainty_mm:g} mm",
            joint.worst_std_mm / motion.max_uncertainty_mm, v[:, -1]))
    unc = joint.axis_uncertainty_deg
    if unc is not None and unc > motion.max_axis_uncertainty_deg:
        raise MeasurementError(_message(
            plan, poses, design, motion, files, joint.condition,
            f"has its axis located to {unc:.2f} deg (1 sigma), more than "
            f"motion.max_axis_uncertainty_deg = {motion.max_axis_uncertainty_deg:g} deg",
            unc / motion.max_axis_uncertainty_deg))


def _message(plan: JointPlan, poses, design: int, motion: MotionSpec, files: list[str],
             condition: float, what: str, ratio: float = float("inf"), direction=None) -> str:
    (Ra, ta), (Rb, tb) = poses[plan.bodies[0]], poses[plan.bodies[1]]
    a, b = plan.bodies
    omega = np.degrees(relative_rotations(Ra, Rb, design))  # (P, 3), vehicle frame
    turned = np.linalg.norm(omega, axis=1)
    names = list(motion.positions)
    head = (f"{files[design]}: joint '{plan.name}' ({plan.kind}, {a} - {b}, {plan.method}): "
            f"the motion is too small to locate it: it {what}; condition number "
            f"{condition:.3g}. Over the {len(names)} positions, {b} turns relative to {a} by "
            f"at most {turned.max():.2f} deg (position '{names[int(turned.argmax())]}')")
    if plan.has_axis:
        axis = Ra[design] @ (Ra[design].T @ plan.config_axis)
        about = np.abs(omega @ axis)
        need = about.max() * ratio
        return (head + f", about its axis by at most {about.max():.2f} deg. Add positions that "
                f"turn {b} relative to {a} about its axis by about "
                f"{_degrees(need)}: {_suggest(plan, axis, motion, about_axis=True)}")
    d = direction if direction is not None else weak_direction(Ra, ta, Rb, tb, design)[0]
    normal = omega - np.outer(omega @ d, d)
    across = np.linalg.norm(normal, axis=1)
    need, dt = across.max() * ratio, vector_text(d)
    return (head + f", and about axes normal to {dt} by at most {across.max():.2f} deg: the "
            f"centre is not located along {dt}. Add positions that turn {b} relative to {a} "
            f"about an axis normal to {dt} by about {_degrees(need)}: "
            f"{_suggest(plan, d, motion)}")


def _degrees(angle: float) -> str:
    return "several degrees" if not np.isfinite(angle) or angle < 0.05 else \
        f"{angle:.1f} deg or more"


def _suggest(plan: JointPlan, d: np.ndarray, motion: MotionSpec, about_axis: bool = False
             ) -> str:
    """Which rig inputs turn the bodies about the axes that are missing: steer about the
    near-vertical steering axis, wheel travel about near-longitudinal axes (the arms' swing),
    the wheel turned by hand about its spin axis."""
    if plan.name == WHEEL:
        return "turn the wheel on its bearing (wheel_turned_deg: 90, 180, 270 deg)"
    d = np.asarray(d, float) / np.linalg.norm(d)
    up = np.array([0.0, 0.0, 1.0])
    out = []
    vertical = abs(d @ up)
    if (about_axis and vertical > 0.5) or (not about_axis and vertical < 0.8):
        out.append("steer (rack_travel_mm, e.g. +-20 mm) turns the wheel carrier about its "
                   "near-vertical steering axis")
    if (about_axis and vertical < 0.8) or (not about_axis and vertical > 0.2):
        out.append("wheel travel (wheel_travel_mm, parallel or opposite, e.g. +-80 mm) "
                   "swings the arms about near-horizontal axes")
    if not out or plan.method != SCORE:
        out.append("larger rig inputs")
    return "; ".join(out)
