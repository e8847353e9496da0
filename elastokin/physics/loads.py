"""Loads of a solved model as plain numpy: the quantities recorded per item and step
(:class:`~elastokin.physics.states.LoadTable`), every part's free-body balance, the loads the
ground (body, subframe) receives at its pickups, and peaks.

Conventions (docs/characteristics.md "Loads"): each item's load is the force and moment it
applies to its **first part** (``LoadItem.parts[0]``; a connection's ``parts[0]`` in the
config), the moment taken about the item's point on that part; its second part receives the
opposite force at its own point, with the moment ``moment_b`` about that point. Config frame;
N, N*mm, mm. ``*_local`` components are in the item's own frame, fixed to its first part: a
bushing's frame (z axial, x main radial), a joint's frame (z its axis; a ball joint: the
part's own axes, the config axes at the design position), the steering gear's (z along the
rack), and for a link, spring or stop z from its point on the first part to the point on the
second (``fz_local`` > 0 in tension).
"""

from __future__ import annotations

import numpy as np

from elastokin.physics.states import LoadTable

#: the quantities recorded per item and step, each a 3-vector (the axis before the last of
#: ``LoadTable.values``): force and moment on the first part (about ``point``, the item's
#: point on it), ``point``, the point on the second part ``point_b``, the moment on the second
#: part about ``point_b``, and force and moment on the first part in the item's own frame
QUANTITIES = ("force", "moment", "point", "point_b", "moment_b", "force_local", "moment_local")
FORCE, MOMENT, POINT, POINT_B, MOMENT_B, FORCE_LOCAL, MOMENT_LOCAL = range(len(QUANTITIES))


def part_balance(table: LoadTable, exclude: tuple[str, ...] = ("",)) -> dict[str, np.ndarray]:
    """The sum of every load on each part (a free-body check: zero at equilibrium), by part:
    (..., 2, 3) force (N) and moment about the config frame's origin (N*mm). Parts in
    ``exclude`` (the rig's, named "") are left out."""
    v = table.values
    out: dict[str, np.ndarray] = {}

    def add(part: str, force: np.ndarray, moment: np.ndarray) -> None:
        if part in exclude:
            return
        total = np.stack([force, moment], axis=-2)
        out[part] = out[part] + total if part in out else total

    for k, item in enumerate(table.items):
        f = v[..., k, FORCE, :]
        add(item.parts[0], f, v[..., k, MOMENT, :] + np.cross(v[..., k, POINT, :], f))
        add(item.parts[1], -f, v[..., k, MOMENT_B, :] + np.cross(v[..., k, POINT_B, :], -f))
    return out


def ground_loads(table: LoadTable, ground: str, kinds: tuple[str, ...] | None = None
                 ) -> dict[str, np.ndarray]:
    """The load the ground part ``ground`` receives through each item (a body pickup), by
    item: (..., 3, 3) force (N), moment about the pickup (N*mm) and the pickup's position (mm,
    the item's point on the ground), config frame. It is the reaction of what the item applies
    to the suspension's part, moved to the pickup: the pickups' loads then balance every load
    applied to the suspension exactly (a bushing's sleeves are offset by its deflection d, and
    Exudyn applies opposite moments to them: the body's moment differs from the bushing's own
    by d x F). Items of ``kinds`` only (None: every item but the rig's contact patches)."""
    v = table.values
    out = {}
    for k, item in enumerate(table.items):
        if ground not in item.parts or (kinds is not None and item.kind not in kinds) or (
                kinds is None and item.kind in ("contact_patch", "load")):
            continue
        f = v[..., k, FORCE, :]
        if item.parts[0] == ground:  # the reaction of the second part's load, at the pickup
            p = v[..., k, POINT, :]
            m = -v[..., k, MOMENT_B, :] + np.cross(v[..., k, POINT_B, :] - p, f)
        else:
            f, p = -f, v[..., k, POINT_B, :]
            m = -v[..., k, MOMENT, :] + np.cross(v[..., k, POINT, :] - p, f)
        out[item.name] = np.stack([f, m, p], axis=-2)
    return out


def resultant(loads: dict[str, np.ndarray]) -> np.ndarray:
    """The resultant (..., 2, 3) of loads (:func:`ground_loads` layout): force and moment
    about the config frame's origin."""
    f = sum(x[..., 0, :] for x in loads.values())
    m = sum(x[..., 1, :] + np.cross(x[..., 2, :], x[..., 0, :]) for x in loads.values())
    return np.stack([f, m], axis=-2)


def peak_step(magnitude: np.ndarray) -> tuple[int, float]:
    """(step index, value) of the largest of a series of magnitudes (NaN ignored)."""
    values = np.where(np.isfinite(magnitude), magnitude, -np.inf)
    i = int(np.argmax(values))
    return i, float(magnitude[i])
