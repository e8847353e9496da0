"""Joints from motion as a study on synthetic data: the spread of the located joints over
many draws of the CMM noise (Monte Carlo) against the uncertainty each draw states, and
their error against the truth for a given motion plan (number and spread of rig positions).
Units mm, deg; vehicle frame at the design position."""

from __future__ import annotations

import copy
import dataclasses
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from elastokin.config.confined import data_folders, typed_folders
from elastokin.config.loading import suspension_from_dict
from elastokin.config.schema.motion import MotionSpec
from elastokin.config.suspension import Suspension
from elastokin.config.variants import corner
from elastokin.errors import MeasurementError
from elastokin.identification.motion.identify import MotionIdentification, locate_joints
from elastokin.studies.identification import identify_geometry
from elastokin.synthetic.virtual_cmm import CHI3_95, synthesize
from elastokin.synthetic.virtual_motion import TrueMotion, measure, true_motion


@dataclass
class JointSpread:
    """One joint over the Monte-Carlo draws: the spread of the located point (3-D RMS about
    the mean, mm; an axis joint's and a partly located joint's along the directions located)
    and of the axis (RMS angle about the mean axis, deg), the uncertainty the first draw
    states, and the error against the truth (3-D RMS over the draws and its 95th percentile;
    an axis joint's across the true axis)."""

    spread_mm: float
    stated_mm: float
    rms_error_mm: float | None
    p95_error_mm: float | None = None
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
        known = j.truth_mm is not None and j.plan.locates_point
        norms = np.linalg.norm(err, axis=1)
        spread = JointSpread(float(np.sqrt(np.mean(np.sum(dev**2, axis=1)))),
                             float(np.sqrt(np.trace(P @ j.covariance_mm2 @ P))),
                             float(np.sqrt(np.mean(norms**2))) if known else None,
                             float(np.percentile(norms, 95)) if known else None)
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


def motion_grid_positions(travel_mm: float, rack_mm: float, levels: int,
                   wheel_turns: tuple[float, ...] = (90.0, 180.0, 270.0)) -> dict[str, dict]:
    """A motion plan's positions: a ``levels`` x ``levels`` grid of wheel travel in
    [-travel_mm, travel_mm] and rack travel in [-rack_mm, rack_mm] (the design position at
    its centre; ``rack_mm`` 0: travel only) and the wheel turned by hand to ``wheel_turns``
    at the design position. Name -> rig state (with a file name)."""
    out = {"design": {"file": "design.csv"}}
    for z in np.linspace(-travel_mm, travel_mm, levels):
        for r in np.linspace(-rack_mm, rack_mm, levels) if rack_mm else [0.0]:
            z, r = round(float(z), 3) + 0.0, round(float(r), 3) + 0.0
            if z or r:
                out[f"t{z:g}_r{r:g}"] = {"file": f"t{z:g}_r{r:g}.csv", "wheel_travel_mm": z,
                                         "rack_travel_mm": r}
    for a in wheel_turns:
        out[f"wheel_{a:g}"] = {"file": f"wheel_{a:g}.csv", "wheel_turned_deg": a}
    return out


def with_positions(suspension: Suspension, positions: dict[str, dict]) -> Suspension:
    """The suspension with its motion plan's positions replaced (rig states as in a config)."""
    raw = copy.deepcopy(suspension.raw)
    raw["motion"]["positions"] = positions
    return suspension_from_dict(raw, suspension.source, suspension.sha256)


def motion_position_study(suspension: Suspension, plans: dict[str, dict[str, dict]],
                          draws: int, seed: int, sigma_mm: float | None = None
                          ) -> dict[str, dict]:
    """Each motion plan (name -> positions, :func:`motion_grid_positions`) of the
    suspension's as-built corner (its ``motion`` section's; the truth drawn from ``seed``),
    ``draws`` draws of the CMM noise each (``sigma_mm`` per coordinate; None: the config's
    ``motion.synthetic.noise_mm`` as the virtual CMM draws it): per plan and joint the RMS
    error against the truth (mm; axes: deg) and the spread against the stated uncertainty;
    a plan whose motion is too small to locate a joint keeps the message instead."""
    if sigma_mm is None:
        sigma_mm = suspension.motion.synthetic.noise_mm / CHI3_95
    union = {n: p for positions in plans.values() for n, p in positions.items()}
    everything = with_positions(suspension, union)
    true = true_motion(everything, np.random.default_rng(seed))
    out = {}
    for name, positions in plans.items():
        motion = everything.motion.model_copy(update={"positions": {
            n: everything.motion.positions[n] for n in positions}})
        try:
            spreads, _ = monte_carlo(everything, true, motion, sigma_mm, draws, seed + 1)
        except MeasurementError as exc:
            out[name] = {"positions": len(positions), "too_small": str(exc)}
            continue
        out[name] = {"positions": len(positions),
                     "joints": {j: dataclasses.asdict(v) for j, v in spreads.items()}}
    return out


def disassembly_errors(suspension: Suspension, seeds: list[int], folder: Path
                       ) -> dict[str, list[float]]:
    """The paper's method on the same car's kind of data: for each seed the virtual CMM's
    files (:func:`elastokin.synthetic.virtual_cmm.synthesize`: its own clearance shifts and
    noise) identified, every joint's error against the truth (mm)."""
    out: dict[str, list[float]] = {}
    for seed in seeds:
        target = folder / f"seed_{seed}"
        raw = copy.deepcopy(suspension.raw)
        raw["measurements"]["folder"] = str(target.resolve())
        s = suspension_from_dict(raw, suspension.source, suspension.sha256)
        synthesize(s, seed, target)
        # the study's own folder (it writes the files it reads), beside the folders given
        with data_folders([*typed_folders(), folder]):
            joints = identify_geometry(s, verify=False).joints
        for name, j in joints.items():
            if j.error_vs_truth_mm is not None:
                out.setdefault(name, []).append(j.error_vs_truth_mm)
    return out
