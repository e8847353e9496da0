"""Contact-patch forces of one axle from steady vehicle accelerations: the static-load
analysis of ADAMS/Car's "static loadcase" event ("G loads" from vehicle parameters and
accelerations), as rigid-vehicle statics (docs/characteristics.md "Static loads from vehicle
accelerations").

The vehicle is a rigid body of mass m = m_front + m_rear (the masses the axles carry at rest)
with its centre of gravity on the centre plane at height h, wheelbase L, this axle's track t;
steady accelerations a_x (+ forward: traction; braking -), a_y (+ to the left: a left turn)
and a vertical acceleration a_z (bump, + up, beyond gravity), each in g. Per wheel of this
axle (mass m_a, share of the lateral load transfer chi, default m_a / m):

- vertical: W = m_a g (1 + a_z) -/+ m g a_x h / L (the front axle gains load under braking,
  the rear one under traction), then each wheel W / 2 -/+ chi m g a_y h / t (the outer wheel,
  the right one in a left turn, gains);
- lateral: the axle carries m_a g a_y (a steady turn: no yaw acceleration), shared by the
  wheels in proportion to their vertical loads (equal use of friction);
- longitudinal: braking m g a_x times the axle's brake share, traction times its drive share,
  half on each wheel (equal brake pressure; an open differential), at the contact patch or,
  for inboard brakes or a chassis-mounted drive, at the wheel centre.

ISO 8855 vehicle axes (x forward, y left, z up); N, kg, mm.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: standard gravity (m/s^2)
G = 9.80665


@dataclass(frozen=True)
class VehicleData:
    """What the static-load analysis needs of the vehicle: the masses each axle carries at
    rest (kg), which axle this is, wheelbase, centre-of-gravity height and this axle's track
    (mm), its shares of braking and drive, its share of the lateral load transfer (None: its
    share of the mass), and where the brake and drive forces act on the wheel (``inboard``:
    the wheel centre, ``outboard``: the contact patch)."""

    front_mass_kg: float
    rear_mass_kg: float
    position: str
    wheelbase_mm: float
    cg_height_mm: float
    track_mm: float
    brake_fraction: float
    drive_fraction: float
    lateral_transfer_fraction: float | None = None
    brakes: str = "outboard"
    drive: str = "outboard"

    @property
    def mass_kg(self) -> float:
        return self.front_mass_kg + self.rear_mass_kg

    @property
    def axle_mass_kg(self) -> float:
        return self.front_mass_kg if self.position == "front" else self.rear_mass_kg


@dataclass(frozen=True)
class WheelLoad:
    """What the road applies to one tyre (N, ISO vehicle axes): ``patch`` at the contact
    patch, ``centre`` at the wheel centre (the longitudinal force of inboard brakes or
    drive)."""

    patch: np.ndarray
    centre: np.ndarray


def wheel_loads(v: VehicleData, longitudinal_g: float = 0.0, lateral_g: float = 0.0,
                bump_g: float = 0.0) -> dict[str, WheelLoad]:
    """The force on each tyre of the axle (``left``, ``right``) under steady accelerations
    (g; module docstring). A wheel whose vertical load would be negative is returned as such:
    :func:`lifted_wheels` names it."""
    m, ma, h, L, t = v.mass_kg, v.axle_mass_kg, v.cg_height_mm, v.wheelbase_mm, v.track_mm
    sign = -1.0 if v.position == "front" else 1.0  # load gained by this axle per + a_x
    axle = ma * G * (1.0 + bump_g) + sign * m * G * longitudinal_g * h / L
    chi = v.lateral_transfer_fraction if v.lateral_transfer_fraction is not None else ma / m
    transfer = chi * m * G * lateral_g * h / t  # to the right wheel in a left turn
    vertical = {"left": axle / 2.0 - transfer, "right": axle / 2.0 + transfer}
    lateral = ma * G * lateral_g
    share = v.drive_fraction if longitudinal_g > 0.0 else v.brake_fraction
    longitudinal = m * G * longitudinal_g * share / 2.0
    inboard = (v.drive if longitudinal_g > 0.0 else v.brakes) == "inboard"
    out = {}
    for side, fz in vertical.items():
        fy = lateral * fz / axle if axle > 0.0 else lateral / 2.0
        fx = np.array([longitudinal, 0.0, 0.0])
        patch = np.array([0.0, fy, fz]) + (0.0 if inboard else fx)
        out[side] = WheelLoad(patch, fx if inboard else np.zeros(3))
    return out


def lifted_wheels(loads: dict[str, WheelLoad]) -> list[str]:
    """The wheels whose vertical load is negative (the case lifts them off the road)."""
    return [side for side, w in loads.items() if w.patch[2] < 0.0]
