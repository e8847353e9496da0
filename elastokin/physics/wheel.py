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


def slope(x, y, window=None) -> float:
    """Least-squares slope dy/dx over the points with ``window[0] <= x <= window[1]``."""
    x = np.asarray(x, float)
    y = np.asarray(y, float)
    if window is not None:
        keep = (x >= window[0]) & (x <= window[1])
        x, y = x[keep], y[keep]
    if x.size < 2 or np.ptp(x) == 0:
        raise ValueError("need at least two distinct points to fit a slope")
    return float(np.polyfit(x, y, 1)[0])


def windowed_slope(x, y, half_width: float) -> float:
    """Least-squares slope dy/dx over the symmetric window |x| <= ``half_width`` exactly: y
    interpolated linearly (x sorted) on an even grid spanning the window, as many points as the
    data have inside it (at least 3). A grid that stops short of one end (the rig's pad steps
    give wheel travel of -49.1 ... +49.96 mm for a +-50 mm window) would bias the slope of a
    curved characteristic. When the data do not reach +-``half_width``, the largest symmetric
    window they cover is used; data on one side of 0 only are fitted where they lie in the
    window."""
    x = np.asarray(x, float)
    y = np.asarray(y, float)
    order = np.argsort(x)
    xs, ys = x[order], y[order]
    if xs.size < 2:
        raise ValueError("need at least two distinct points to fit a slope")
    lo, hi = max(-float(half_width), float(xs[0])), min(float(half_width), float(xs[-1]))
    if lo < 0.0 < hi:
        hi = min(-lo, hi)
        lo = -hi
    if not hi > lo:
        raise ValueError("need at least two distinct points in the window to fit a slope")
    n = max(3, int(np.count_nonzero((xs >= lo) & (xs <= hi))))
    grid = np.linspace(lo, hi, n)
    return slope(grid, np.interp(grid, xs, ys))
