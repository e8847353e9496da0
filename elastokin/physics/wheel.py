"""Wheel characteristics from part poses (pure numpy; ISO 8855 / SAE J670 definitions).

Every function takes vectors in one frame (the config frame) together with the unit vectors
``forward``, ``outboard`` (away from the vehicle centreline on this wheel's side) and ``up`` of
that frame, so the same code serves ISO (x forward, y left) and ADAMS/Car (x rearward, y right)
files and both sides of the car.

Signs (per wheel, as a K&C rig reports them):

- toe (steer) angle: positive **toe-in**, the front of the wheel turned towards the centreline;
- camber angle: positive when the **top of the wheel leans outboard**;
- wheel travel: positive **bump** (wheel moving up relative to the body).
"""

from __future__ import annotations

import warnings

import numpy as np


def toe_deg(spin_axis, forward, outboard) -> np.ndarray:
    """Toe angle, deg, positive toe-in, from the outboard wheel spin axis (..., 3).

    With toe-in the heading turns inboard, so the outboard spin axis turns forward:
    ``toe = atan2(a . forward, a . outboard)``.
    """
    a = np.asarray(spin_axis, float)
    return np.degrees(np.arctan2(a @ np.asarray(forward), a @ np.asarray(outboard)))


def camber_deg(spin_axis, forward, outboard, up) -> np.ndarray:
    """Camber angle, deg, positive top outboard (the outboard spin axis then points down)."""
    a = np.asarray(spin_axis, float)
    horizontal = np.hypot(a @ np.asarray(forward), a @ np.asarray(outboard))
    return np.degrees(np.arctan2(-(a @ np.asarray(up)), horizontal))


def spin_axis_from_angles(toe, camber, forward, outboard, up) -> np.ndarray:
    """Inverse of :func:`toe_deg` / :func:`camber_deg`: unit outboard spin axis."""
    t, c = np.radians(toe), np.radians(camber)
    f, o, u = (np.asarray(v, float) for v in (forward, outboard, up))
    return np.cos(c) * (np.cos(t) * o + np.sin(t) * f) - np.sin(c) * u


#: a least-squares slope needs at least this many distinct x values among its points
MIN_SLOPE_POINTS = 3


class UndeterminedSlopeWarning(UserWarning):
    """A least-squares slope with fewer than :data:`MIN_SLOPE_POINTS` distinct points in its
    window: not determined (NaN), the message says why."""


def distinct_count(x, scale: float | None = None) -> int:
    """How many distinct values ``x`` holds, values closer than 1e-9 of ``scale`` (default:
    the range of ``x``) counted as one: a rig's loading and unloading steps at one input give
    outputs (wheel travel, steer angles) equal to the solver's rounding, not distinct points."""
    x = np.sort(np.asarray(x, float).ravel())
    if x.size == 0:
        return 0
    scale = float(np.ptp(x)) if scale is None else float(scale)
    return 1 + int(np.count_nonzero(np.diff(x) > 1e-9 * max(scale, 1e-300)))


def slope(x, y, window=None, *, keep=None, what: str = "slope", where: str = "",
          remedy: str = "") -> float:
    """Least-squares slope dy/dx over the points with ``window[0] <= x <= window[1]`` (all
    points when ``window`` is None; ``keep``, a boolean mask, chooses them instead, e.g. by a
    window on another variable that ``where`` describes). Points with a non-finite x or y are
    left out.

    **Not determined is not zero**: with fewer than :data:`MIN_SLOPE_POINTS` distinct x values
    among the points (:func:`distinct_count`, on the scale of all the data's x; a rig step as
    wide as the window fits a line through one or two points, which says nothing of a slope)
    the result is NaN and an :class:`UndeterminedSlopeWarning` names ``what``, ``where`` and
    the ``remedy``. This is the one rule of every windowed characteristic."""
    x = np.asarray(x, float)
    y = np.asarray(y, float)
    good = np.isfinite(x) & np.isfinite(y)
    if keep is None:
        keep = np.ones(x.shape, bool)
        if window is not None:
            keep = (x >= window[0]) & (x <= window[1])
            where = where or f"within {window[0]:g} <= x <= {window[1]:g}"
    keep = np.asarray(keep, bool) & good
    n = distinct_count(x[keep], float(np.ptp(x[good])) if good.any() else 0.0)
    if n < MIN_SLOPE_POINTS:
        warnings.warn(UndeterminedSlopeWarning(
            f"{what} not determined (null): {n} distinct point{'s' * (n != 1)} "
            f"{where or 'in the data'}, a least-squares slope needs at least "
            f"{MIN_SLOPE_POINTS}" + (f"; {remedy}" if remedy else "")), stacklevel=2)
        return float("nan")
    return float(np.polyfit(x[keep], y[keep], 1)[0])


def windowed_slope(x, y, half_width: float, *, what: str = "slope", where: str = "",
                   remedy: str = "") -> float:
    """Least-squares slope dy/dx over the symmetric window |x| <= ``half_width`` exactly: y
    interpolated linearly (x sorted) on an even grid spanning the window, as many points as the
    data have inside it. A grid that stops short of one end (the rig's pad steps give wheel
    travel of -49.1 ... +49.96 mm for a +-50 mm window) would bias the slope of a curved
    characteristic. When the data do not reach +-``half_width``, the largest symmetric window
    they cover is used; data on one side of 0 only are fitted where they lie in the window.
    Fewer than :data:`MIN_SLOPE_POINTS` distinct data points in that window: NaN, with the
    warning of :func:`slope` (``what``, ``where``, ``remedy``)."""
    x = np.asarray(x, float)
    y = np.asarray(y, float)
    good = np.isfinite(x) & np.isfinite(y)
    order = np.argsort(x[good])
    xs, ys = x[good][order], y[good][order]
    lo = max(-float(half_width), float(xs[0])) if xs.size else 0.0
    hi = min(float(half_width), float(xs[-1])) if xs.size else 0.0
    if lo < 0.0 < hi:
        hi = min(-lo, hi)
        lo = -hi
    inside = (xs >= lo) & (xs <= hi)
    note = {"what": what, "where": where or f"within |x| <= {half_width:g}", "remedy": remedy}
    if distinct_count(xs[inside], float(np.ptp(xs)) if xs.size else 0.0) < MIN_SLOPE_POINTS:
        return slope(xs, ys, keep=inside, **note)  # NaN, and the warning
    grid = np.linspace(lo, hi, int(np.count_nonzero(inside)))
    return slope(grid, np.interp(grid, xs, ys), **note)
