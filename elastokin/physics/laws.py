"""Force-deflection laws of bushings, one per direction of the bushing frame (pure numpy).

A law maps deflection (mm for x y z, deg for rx ry rz) to load (N, N*mm). It is piecewise linear
through the given points, extrapolated linearly with the end slopes beyond the table, passes
through zero, and is strictly increasing, so that it can be inverted ([23] of the paper's method:
deflection = f^-1(force)). A linear rate is the one-segment special case.

The same law is written as a sum of hinge functions,
``f(u) = k0 * u + sum_i dk_i * max(u - u_i, 0) + c``, which the Exudyn layer turns into a
symbolic (C++-speed) user function.

:class:`ProgressiveLaw` is the family fitted by the stiffness identification
(:mod:`elastokin.identification.stiffness`): a config law scaled and made progressive,
``F(u) = scale * f(u) * (1 + cubic * u^2)`` (``cubic`` in 1/mm^2 or 1/deg^2), smooth in its
parameters and evaluated exactly (no tabulation).
"""

from __future__ import annotations

import functools
from collections.abc import Mapping
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

    # the arrays and figures below are made once per law (models are built often)
    @functools.cached_property
    def _arrays(self) -> tuple[np.ndarray, np.ndarray]:
        d, f = np.asarray(self.deflection), np.asarray(self.load)
        d.setflags(write=False)
        f.setflags(write=False)
        return d, f

    @functools.cached_property
    def slopes(self) -> np.ndarray:
        s = np.diff(self.load) / np.diff(self.deflection)
        s.setflags(write=False)
        return s

    @functools.cached_property
    def rate_at_zero(self) -> float:
        """Tangent stiffness at zero deflection (right-hand slope at a breakpoint)."""
        u = self._arrays[0]
        i = int(np.clip(np.searchsorted(u, 0.0, side="right") - 1, 0, u.size - 2))
        return float(self.slopes[i])

    @functools.cached_property
    def is_linear(self) -> bool:
        """True when the curve is one straight line through the origin."""
        s = self.slopes
        return bool(np.all(np.abs(s - s[0]) <= 1e-12 * abs(s[0])))

    def __call__(self, u):
        """Load (N or N*mm) at deflection ``u`` (mm or deg); array-friendly."""
        u = np.asarray(u, float)
        d, f = self._arrays
        s = self.slopes
        out = np.interp(u, d, f)
        out = np.where(u < d[0], f[0] + s[0] * (u - d[0]), out)
        out = np.where(u > d[-1], f[-1] + s[-1] * (u - d[-1]), out)
        return out if out.ndim else float(out)

    def deflection_at(self, load):
        """Inverse law: deflection (mm or deg) at ``load`` (N or N*mm)."""
        return self.inverse(load)

    @functools.cached_property
    def inverse(self) -> DirectionLaw:
        """The inverse law, load -> deflection (made once per law)."""
        return DirectionLaw(self.load, self.deflection)

    def __getstate__(self) -> dict:
        """The law's data without its cached inverse: a law pickles the same before and after
        it was inverted (a suspension is not changed by a run: tests/test_contract.py)."""
        return {k: v for k, v in self.__dict__.items() if k != "inverse"}

    def scaled(self, factor: float) -> DirectionLaw:
        """The same curve with every load multiplied by ``factor`` (> 0)."""
        if not factor > 0:
            raise ValueError(f"scale factor must be positive, got {factor}")
        if factor == 1.0:  # the same numbers: no new (validated) curve
            return self
        return DirectionLaw(self.deflection, tuple(factor * x for x in self.load))

    def hinges(self) -> tuple[float, float, list[tuple[float, float]]]:
        """(k0, c, [(u_i, dk_i)]) with f(u) = c + k0*u + sum dk_i*max(u - u_i, 0) everywhere."""
        d = np.asarray(self.deflection)
        s = self.slopes
        k0 = float(s[0])
        c = float(self.load[0] - k0 * d[0])
        return k0, c, [(float(d[i]), float(s[i] - s[i - 1])) for i in range(1, s.size)]

    def expression(self, u, maxf=None):
        """The law in hinge form, for plain floats or Exudyn symbolic reals (``maxf`` the
        matching max function; Python's comparison by default)."""
        maxf = maxf or _max
        k0, c, hinges = self.hinges()
        out = c + k0 * u
        for ui, dk in hinges:
            out = out + dk * maxf(u - ui, 0.0)
        return out


def _max(a, b):
    return a if a > b else b


@dataclass(frozen=True)
class ProgressiveLaw:
    """``F(u) = scale * base(u) * (1 + cubic * u^2)``: a config law ``base`` scaled by
    ``scale`` (> 0) and stiffened by ``cubic`` (>= 0; 1/mm^2 for translations, 1/deg^2 for
    rotations: the secant stiffness at deflection u is ``1 + cubic * u^2`` times the scaled
    base's). Strictly increasing and through (0, 0) like its base, hence invertible."""

    base: DirectionLaw
    scale: float = 1.0
    cubic: float = 0.0

    def __post_init__(self):
        if not self.scale > 0 or not np.isfinite(self.scale):
            raise ValueError(f"scale factor must be positive, got {self.scale}")
        if not self.cubic >= 0 or not np.isfinite(self.cubic):
            raise ValueError(f"progression coefficient must be >= 0, got {self.cubic}")

    @property
    def rate_at_zero(self) -> float:
        return self.scale * self.base.rate_at_zero

    @property
    def is_linear(self) -> bool:
        return self.cubic == 0.0 and self.base.is_linear

    def __call__(self, u):
        u = np.asarray(u, float)
        out = self.scale * np.asarray(self.base(u)) * (1.0 + self.cubic * u * u)
        return out if out.ndim else float(out)

    def deflection_at(self, load):
        """Inverse law by bracketed Newton (bisection safeguard); array-friendly."""
        f = np.asarray(load, float)
        # the base law's deflection bounds |u| from above: the cubic only stiffens
        hi = np.asarray(self.base.deflection_at(f / self.scale), float)
        lo = np.zeros_like(hi)
        a, b = np.minimum(lo, hi), np.maximum(lo, hi)
        u = hi.copy()
        for _ in range(200):
            r = np.asarray(self(u)) - f
            a = np.where(r < 0, u, a)
            b = np.where(r > 0, u, b)
            h = 1e-6 * np.maximum(1.0, np.abs(u))
            slope = (np.asarray(self(u + h)) - np.asarray(self(u - h))) / (2 * h)
            newton = u - r / slope
            inside = (newton > a) & (newton < b)
            u_next = np.where(inside, newton, 0.5 * (a + b))
            if np.all(np.abs(u_next - u) <= 1e-13 * np.maximum(1.0, np.abs(u))):
                u = u_next
                break
            u = u_next
        return u if u.ndim else float(u)

    def scaled(self, factor: float) -> ProgressiveLaw:
        """The same curve with every load multiplied by ``factor`` (> 0)."""
        if not factor > 0:
            raise ValueError(f"scale factor must be positive, got {factor}")
        return ProgressiveLaw(self.base, self.scale * factor, self.cubic)

    def expression(self, u, maxf=None):
        """The law for plain floats or Exudyn symbolic reals (see DirectionLaw.expression)."""
        return self.scale * self.base.expression(u, maxf) * (1.0 + self.cubic * u * u)

    def tabulated(self, span: float, points: int = 81) -> DirectionLaw:
        """The curve as a piecewise-linear :class:`DirectionLaw` on ``points`` deflections
        spaced more densely near zero, out to +-``span`` (mm or deg), linear beyond: what a
        config or an ADAMS property file holds."""
        if self.is_linear:
            return DirectionLaw.linear(self.rate_at_zero)
        half = np.linspace(0.0, 1.0, points // 2 + 1)[1:] ** 1.5 * span
        u = np.r_[-half[::-1], 0.0, half]
        return DirectionLaw(tuple(u.tolist()), tuple(float(x) for x in self(u)))


def law_from_spec(spec) -> DirectionLaw:
    """A law from a config entry: a positive number (rate), or ``deflection`` and ``load``
    lists (an object's attributes, or a mapping's keys as in a config dict). Laws are
    immutable: one made from the same numbers before is returned again (a config resolved
    again for every design variable makes the same laws)."""
    if isinstance(spec, (int, float)):
        return _linear(float(spec))
    if isinstance(spec, Mapping):
        return _curve(tuple(spec["deflection"]), tuple(spec["load"]))
    return _curve(tuple(spec.deflection), tuple(spec.load))


@functools.lru_cache(maxsize=4096)
def _linear(rate: float) -> DirectionLaw:
    return DirectionLaw.linear(rate)


@functools.lru_cache(maxsize=4096)
def _curve(deflection: tuple, load: tuple) -> DirectionLaw:
    return DirectionLaw(deflection, load)
