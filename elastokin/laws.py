"""Force-deflection laws of bushings, one per direction of the bushing frame (pure numpy).

A law maps deflection (mm for x y z, deg for rx ry rz) to load (N, N*mm). It is piecewise linear
through the given points, extrapolated linearly with the end slopes beyond the table, passes
through zero, and is strictly increasing, so that it can be inverted ([23] of the paper's method:
deflection = f^-1(force)). A linear rate is the one-segment special case.

The same law is written as a sum of hinge functions,
``f(u) = k0 * u + sum_i dk_i * max(u - u_i, 0) + c``, which the Exudyn layer turns into a
symbolic (C++-speed) user function.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class DirectionLaw:
    """Piecewise-linear, strictly increasing law through (0, 0); linear beyond the table."""

    deflection: tuple[float, ...]
    load: tuple[float, ...]

    @classmethod
    def linear(cls, rate: float) -> DirectionLaw:
        if not rate > 0:
            raise ValueError(f"stiffness rate must be positive, got {rate}")
        return cls((-1.0, 1.0), (-float(rate), float(rate)))

    def __post_init__(self):
        u = np.asarray(self.deflection, float)
        f = np.asarray(self.load, float)
        if u.shape != f.shape or u.size < 2:
            raise ValueError("a curve needs matching deflection and load lists of >= 2 points")
        if not np.all(np.isfinite(u)) or not np.all(np.isfinite(f)):
            raise ValueError("curve values must be finite numbers")
        if np.any(np.diff(u) <= 0):
            raise ValueError("curve deflections must be strictly increasing")
        if np.any(np.diff(f) <= 0):
            raise ValueError("curve loads must be strictly increasing with deflection "
                             "(a bushing law must be invertible)")
        if abs(self(0.0)) > 1e-9 * np.max(np.abs(f)):
            raise ValueError(f"curve load at zero deflection is {self(0.0):.6g}, expected 0 "
                             "(give a load at zero deflection as a preload)")

    @property
    def slopes(self) -> np.ndarray:
        return np.diff(self.load) / np.diff(self.deflection)

    @property
    def rate_at_zero(self) -> float:
        """Tangent stiffness at zero deflection (right-hand slope at a breakpoint)."""
        u = np.asarray(self.deflection)
        i = int(np.clip(np.searchsorted(u, 0.0, side="right") - 1, 0, u.size - 2))
        return float(self.slopes[i])

    @property
    def is_linear(self) -> bool:
        """True when the curve is one straight line through the origin."""
        s = self.slopes
        return bool(np.all(np.abs(s - s[0]) <= 1e-12 * abs(s[0])))

    def __call__(self, u):
        """Load (N or N*mm) at deflection ``u`` (mm or deg); array-friendly."""
        u = np.asarray(u, float)
        d = np.asarray(self.deflection)
        f = np.asarray(self.load)
        s = self.slopes
        out = np.interp(u, d, f)
        out = np.where(u < d[0], f[0] + s[0] * (u - d[0]), out)
        out = np.where(u > d[-1], f[-1] + s[-1] * (u - d[-1]), out)
        return out if out.ndim else float(out)

    def deflection_at(self, load):
        """Inverse law: deflection (mm or deg) at ``load`` (N or N*mm)."""
        return DirectionLaw(self.load, self.deflection)(load)

    def scaled(self, factor: float) -> DirectionLaw:
        """The same curve with every load multiplied by ``factor`` (> 0)."""
        if not factor > 0:
            raise ValueError(f"scale factor must be positive, got {factor}")
        return DirectionLaw(self.deflection, tuple(factor * x for x in self.load))

    def hinges(self) -> tuple[float, float, list[tuple[float, float]]]:
        """(k0, c, [(u_i, dk_i)]) with f(u) = c + k0*u + sum dk_i*max(u - u_i, 0) everywhere."""
        d = np.asarray(self.deflection)
        s = self.slopes
        k0 = float(s[0])
        c = float(self.load[0] - k0 * d[0])
        return k0, c, [(float(d[i]), float(s[i] - s[i - 1])) for i in range(1, s.size)]


def law_from_spec(spec) -> DirectionLaw:
    """A law from a config entry: a positive number (rate) or an object with
    ``deflection`` and ``load`` lists."""
    if isinstance(spec, (int, float)):
        return DirectionLaw.linear(float(spec))
    return DirectionLaw(tuple(spec.deflection), tuple(spec.load))
