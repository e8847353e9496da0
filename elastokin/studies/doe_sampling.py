"""Sampling the assembly clearances of a DOE study (docs/doe.md): every joint with a
``measurements.joints.<name>.clearance`` is shifted uniformly over its clearance region of
radius dL_max [1]: a bushing's inner sleeve over the disc normal to its axis, a bolted joint
over the ball. Unit-cube samples (Latin hypercube, scrambled Sobol, Monte Carlo) from the seed
alone. Shifts in mm, config frame; components in each joint's own directions."""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np

from elastokin.config.suspension import Suspension
from elastokin.errors import ConfigError

METHODS = ("lhs", "sobol", "mc")
#: designs whose first n points are the same whatever the sample count: a study of them
#: extends in place (a Latin hypercube's strata depend on the count: it does not)
EXTENSIBLE = ("sobol", "mc")


@dataclass(frozen=True)
class ClearanceJoint:
    """One joint with assembly clearance: its clearance region and the directions (unit
    vectors, config frame, columns) in which its shift components are counted."""

    name: str
    kind: str  # "disc" (bushing inner sleeve) or "ball" (bolted joint)
    max_shift_mm: float
    axes: np.ndarray  # (3, 2) disc or (3, 3) ball

    @property
    def dimensions(self) -> int:
        return self.axes.shape[1]

    @property
    def components(self) -> list[str]:
        return [f"{self.name}.{c}" for c in "xyz"[:self.dimensions]]


def clearance_joints(suspension: Suspension) -> list[ClearanceJoint]:
    """The joints a study varies, in the order of ``measurements.joints``. Raises
    :class:`ConfigError` when the config gives no clearance."""
    s = suspension
    m = s.measurements
    if m is None:
        raise ConfigError(f"{s.source}: no 'measurements' section: a DOE study samples the "
                          "clearances of 'measurements.joints.<name>.clearance'")
    bushings = {b.name: b for b in s.bushings}
    joints = {j.name: j for j in s.joints}
    out = []
    for name, jm in m.joints.items():
        if jm.clearance is None:
            continue
        radius = float(jm.clearance.max_shift_mm)
        if name in bushings:
            out.append(ClearanceJoint(name, "disc", radius, bushings[name].frame[:, :2].copy()))
        elif name in joints:
            if jm.bolted is None:
                raise ConfigError(f"{s.source}: key 'measurements.joints.{name}': a clearance "
                                  "needs 'bolted: <part>' (the side with the hole)")
            out.append(ClearanceJoint(name, "ball", radius, joints[name].frame.copy()))
        else:
            raise ConfigError(f"{s.source}: key 'measurements.joints.{name}': no bushing or "
                              "joint of that name")
    if not out:
        raise ConfigError(f"{s.source}: key 'measurements.joints': no joint has a "
                          "'clearance': nothing for a DOE study to sample")
    return out


def unit_samples(method: str, samples: int, dimensions: int, seed: int) -> np.ndarray:
    """(samples, dimensions) points of [0, 1)^d: Latin hypercube, scrambled Sobol or Monte
    Carlo, a function of (method, samples, dimensions, seed) only. Sobol points are balanced
    when ``samples`` is a power of 2."""
    from scipy.stats import qmc

    if method not in METHODS:
        raise ConfigError(f"--method: expected one of {', '.join(METHODS)}, got '{method}'")
    if method == "mc":
        return np.random.default_rng(seed).random((samples, dimensions))
    cls = qmc.LatinHypercube if method == "lhs" else qmc.Sobol
    try:
        engine = cls(dimensions, rng=seed)
    except TypeError:  # scipy < 1.15
        engine = cls(dimensions, seed=seed)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)  # Sobol: n not a power of 2
        return engine.random(samples)


def disc_components(u: np.ndarray, radius: float) -> np.ndarray:
    """Unit-square points (..., 2) -> points (..., 2) uniform over the disc of ``radius``:
    r = R sqrt(u1), phi = 2 pi u2."""
    u = np.asarray(u, float)
    r = radius * np.sqrt(u[..., 0])
    phi = 2.0 * np.pi * u[..., 1]
    return np.stack([r * np.cos(phi), r * np.sin(phi)], axis=-1)


def ball_components(u: np.ndarray, radius: float) -> np.ndarray:
    """Unit-cube points (..., 3) -> points (..., 3) uniform over the ball of ``radius``:
    r = R u1^(1/3), cos(theta) = 1 - 2 u2, phi = 2 pi u3."""
    u = np.asarray(u, float)
    r = radius * np.cbrt(u[..., 0])
    cos_t = 1.0 - 2.0 * u[..., 1]
    sin_t = np.sqrt(np.clip(1.0 - cos_t**2, 0.0, None))
    phi = 2.0 * np.pi * u[..., 2]
    return np.stack([r * sin_t * np.cos(phi), r * sin_t * np.sin(phi), r * cos_t], axis=-1)


def shift_components(joints: list[ClearanceJoint], u: np.ndarray) -> np.ndarray:
    """Unit-cube samples (n, d) -> shift components (n, d), mm, each joint's in its own
    directions (``ClearanceJoint.axes``), joints in order."""
    u = np.atleast_2d(np.asarray(u, float))
    cols, k = [], 0
    for j in joints:
        part = u[:, k:k + j.dimensions]
        cols.append(disc_components(part, j.max_shift_mm) if j.kind == "disc"
                    else ball_components(part, j.max_shift_mm))
        k += j.dimensions
    if k != u.shape[1]:
        raise ValueError(f"unit samples have {u.shape[1]} coordinates, the joints need {k}")
    return np.hstack(cols)


def shifts_mm(joints: list[ClearanceJoint], components: np.ndarray) -> dict[str, np.ndarray]:
    """One sample's shift components (d,) -> shift vector (3,) per joint, mm, config frame."""
    out, k = {}, 0
    for j in joints:
        out[j.name] = j.axes @ np.asarray(components[k:k + j.dimensions], float)
        k += j.dimensions
    return out
