"""Joints from motion as a study on synthetic data: the spread of the located joints over
many draws of the CMM noise (Monte Carlo) against the uncertainty each draw states, and
their error against the truth for a given motion plan (number and spread of rig positions).
Units mm, deg; vehicle frame at the design position."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from elastokin.config.schema_motion import MotionSpec
from elastokin.config.suspension import Suspension
from elastokin.config.variants import corner
from elastokin.identification.motion.identify import MotionIdentification, locate_joints
from elastokin.synthetic.virtual_motion import TrueMotion, measure


@dataclass
class JointSpread:
    """One joint over the Monte-Carlo draws: the spread of the located point (3-D RMS about
    the mean, mm; an axis joint's and a partly located joint's along the directions located)
    and of the axis (RMS angle about the mean axis, deg), the uncertainty the first draw
    states, and the error against the truth (3-D RMS over the draws; an axis joint's across
    the true axis)."""

    spread_mm: float
    stated_mm: float
    rms_error_mm: float | None
    axis_spread_deg: float | None = None
    axis_stated_deg: float | None = None
    axis_rms_error_deg: float | None = None


def _located(j) -> np.ndarray:
    """The projector on the directions a joint is located in."""
    P = np.eye(3)
    for d, _ in j.from_config:
        P -= np.outer(d, d)
    return P


def monte_carlo(suspension: Suspension, true: TrueMotion, motion: MotionSpec,
                sigma_mm: float, draws: int, seed: int) -> tuple[dict[str, JointSpread],
                                                                 MotionIdentification]:
    """Locate the joints from ``draws`` + 1 noisy measurements of ``true`` at ``motion``'s
    positions (noise ``sigma_mm`` per coordinate, no gross error); the first states the
    uncertainty. Returns each joint's spread and the first draw's identification."""
    s = corner(suspension)
    rng = np.random.default_rng(seed)
    truth = (true.joints, true.axes)
    data, _ = measure(true, motion, s.ground, sigma_mm, rng)
    stated = locate_joints(s, motion, data, truth)
    values: dict[str, list[np.ndarray]] = {n: [] for n in stated.joints}
    for _ in range(draws):
        data, _ = measure(true, motion, s.ground, sigma_mm, rng)
        ident = locate_joints(s, motion, data, truth, covariance=False)
        for name, j in ident.joints.items():
            values[name].append(np.concatenate([j.point_mm, [] if j.axis is None else j.axis]))
    out = {}
    for name, j in stated.joints.items():
        v = np.array(values[name])
        P = _located(j)
        dev = (v[:, :3] - v[:, :3].mean(axis=0)) @ P
        err = (v[:, :3] - (j.truth_mm if j.truth_mm is not None else np.nan)) @ P
        if j.truth_axis is not None:
            err -= np.outer(err @ j.truth_axis, j.truth_axis)
        spread = JointSpread(float(np.sqrt(np.mean(np.sum(dev**2, axis=1)))),
                             float(np.sqrt(np.trace(P @ j.covariance_mm2 @ P))),
                             float(np.sqrt(np.mean(np.sum(err**2, axis=1))))
                             if j.truth_mm is not None and j.plan.locates_point else None)
        if j.axis is not None:
            axes = v[:, 3:] * np.sign(v[:, 3:] @ j.axis)[:, None]
            mean = axes.mean(axis=0) / np.linalg.norm(axes.mean(axis=0))
            spread.axis_spread_deg = _rms_angle(axes, mean)
            spread.axis_stated_deg = j.axis_uncertainty_deg
            if j.truth_axis is not None:
                spread.axis_rms_error_deg = _rms_angle(axes, j.truth_axis)
        out[name] = spread
    return out, stated


def _rms_angle(axes: np.ndarray, reference: np.ndarray) -> float:
    c = np.clip(np.abs(axes @ reference) / np.linalg.norm(reference), 0.0, 1.0)
    return float(np.degrees(np.sqrt(np.mean(np.arccos(c) ** 2))))
