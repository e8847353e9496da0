"""The steering axis at every rig step: caster, kingpin inclination, scrub radius and caster
trail from the wheel part's instantaneous screw axis under a small steering input with the
springs locked (ADAMS/Car's instant-axis method; the method in
:mod:`elastokin.physics.steering_axis`, definitions and signs in docs/characteristics.md).

Config frame; mm and deg.
"""

from __future__ import annotations

import warnings

import numpy as np

from elastokin.config.suspension import Suspension
from elastokin.physics.states import StepState
from elastokin.physics.steering_axis import steering_axes_from_poses, steering_skeleton
from elastokin.physics.steering_geometry import (
    caster_deg,
    caster_trail_mm,
    contact_point,
    kingpin_inclination_deg,
    scrub_radius_mm,
)


class SteeringAxisWarning(UserWarning):
    """The steering axis is undefined at some steps (NaN columns); the message says why."""


def steering_axis_columns(states: list[StepState], suspension: Suspension
                          ) -> dict[str, np.ndarray]:
    """Caster (deg), kingpin inclination (deg), scrub radius (mm) and caster trail (mm) per
    step, the ground plane being the plane normal to ``up`` through the wheel's contact point
    (loaded radius below the centre in the wheel plane). NaN where the axis is undefined, with
    a :class:`SteeringAxisWarning`."""
    s = suspension
    centre = np.array([st.wheel_centre_mm for st in states])
    spin = np.array([st.spin_axis for st in states])
    axes = steering_axes_from_poses(steering_skeleton(s), [st.poses for st in states], centre)
    d, p = axes.direction.copy(), axes.point
    d[np.abs(d @ s.up) < 1e-9] = np.nan  # a horizontal axis has no caster or ground point
    if axes.reason is not None or np.isnan(d).any():
        bad = int(np.isnan(d).any(axis=1).sum())
        warnings.warn(SteeringAxisWarning(
            f"{s.source}: steering axis undefined at {bad} of {len(states)} steps (NaN "
            f"caster, kingpin inclination, scrub radius, caster trail): "
            f"{axes.reason or 'horizontal axis'}"), stacklevel=2)
    contact = contact_point(centre, spin, s.wheel.loaded_radius_mm, s.up)
    return {
        "caster_deg": caster_deg(d, s.forward, s.up),
        "kingpin_inclination_deg": kingpin_inclination_deg(d, s.outboard, s.up),
        "scrub_radius_mm": scrub_radius_mm(p, d, contact, spin, s.forward, s.outboard, s.up),
        "caster_trail_mm": caster_trail_mm(p, d, contact, spin, s.forward, s.outboard, s.up),
    }
