"""Motion ratios of springs and dampers (pure numpy): how far a spring or damper is
compressed per unit of wheel travel, and the wheel rate its rate gives through that ratio.

Definitions (docs/characteristics.md, "Motion ratios"):

- **motion ratio** (a spring's installation ratio, a damper's velocity ratio) of an element of
  length L along a travel load case: MR = -dL/dz, the element's compression per wheel-centre
  travel z (+ bump) along the rig's motion of that load case (both wheels up in parallel
  travel; this one up, the other down in opposite travel; this one alone in single wheel
  travel). It is the derivative along the solved path, as a rig measures it with a string pot
  on the element and one on the wheel (bushing deflections included); on a model with ideal
  joints it is the instantaneous velocity ratio, equal to the virtual-work ratio of the
  element's force to the vertical force it puts on the wheel. A spring across the car (a heave
  spring between the rockers) is compressed by both wheels: its parallel-travel ratio per
  wheel is twice its single-wheel one, its opposite-travel ratio zero.
- **wheel rate from the springs**: sum over the springs of rate * MR^2 * share, MR from
  parallel travel at the design position; ``share`` is 1 for a spring of this wheel's side and
  1/2 for one that both wheels compress (kept once on an axle: across the car, or between
  parts shared by both sides and the ground): by symmetry each wheel carries half of its
  force. This is the springs' elastic part of the wheel rate; the measured wheel rate also
  holds the change of each spring's lever under its preload, force * dMR/dz.

Units: mm, N; MR dimensionless (mm per mm).
"""

from __future__ import annotations

import numpy as np

#: a sweep whose wheel travel spans less than this (mm) has no motion ratio: the held wheel of
#: single wheel travel, whose centre moves only as much as its bushings let it
MIN_TRAVEL_MM = 0.5
#: steps whose wheel travel differs by less than this fraction of the sweep's span are one
#: point (the same rig position on the loading and the unloading branch)
SAME_TRAVEL = 1e-6


def motion_ratio(travel_mm, length_mm) -> np.ndarray:
    """MR = -dL/dz at every step (module docstring): the element's length ``length_mm`` as a
    function of the wheel travel ``travel_mm`` over all the sweep's steps (steps at the same
    travel, within :data:`SAME_TRAVEL` of the span, averaged: every branch of a rig without
    friction passes the same points), differentiated by second-order differences (central
    between points, one-sided second order at the ends) and read at each step's travel. So a
    step's ratio does not depend on which branch it is on, nor on the direction of travel.
    NaN when the travel spans less than :data:`MIN_TRAVEL_MM` or takes fewer than two
    values."""
    z = np.asarray(travel_mm, float)
    L = np.asarray(length_mm, float)
    out = np.full(z.shape, np.nan)
    good = np.isfinite(z) & np.isfinite(L)
    if good.sum() < 2 or np.ptp(z[good]) < MIN_TRAVEL_MM:
        return out
    order = np.argsort(z[good], kind="stable")
    zs, Ls = z[good][order], L[good][order]
    group = np.cumsum(np.r_[True, np.diff(zs) > SAME_TRAVEL * np.ptp(zs)]) - 1
    count = np.bincount(group)
    zu, Lu = np.bincount(group, zs) / count, np.bincount(group, Ls) / count
    if zu.size < 2:
        return out
    dL = np.gradient(Lu, zu, edge_order=2 if zu.size > 2 else 1)
    out[good] = -np.interp(z[good], zu, dL)
    return out


def wheel_rate_from_springs(springs) -> float:
    """The springs' elastic wheel rate (N/mm): sum of rate * MR^2 * share over ``springs``,
    (rate N/mm, motion ratio, share) triples (module docstring); NaN when a ratio is not
    known."""
    return float(sum(rate * mr * mr * share for rate, mr, share in springs))
