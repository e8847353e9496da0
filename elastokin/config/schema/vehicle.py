"""The vehicle file's schema (pydantic): the whole car on the K&C rig (README "The whole car").

A vehicle file names a front and a rear axle config and holds the one set of vehicle data
both axles' characteristics use (it replaces each axle's own ``axle.vehicle``): wheelbase, CG
height, the masses the axles carry, the brake and drive split; and the body roll the rig's
table applies to both axles. Units in the key names: mm, kg, deg; fractions 0 ... 1.
"""

from __future__ import annotations

from typing import Literal

from pydantic import Field, field_validator, model_validator

from elastokin.config.plausibility import fraction, plausible
from elastokin.config.schema.axle import AxleMassesSpec
from elastokin.config.schema.base import StrictModel
from elastokin.config.schema.rig import RollSpec

#: the standard acceleration of gravity (m/s^2): axle weights from masses, N per g
STANDARD_GRAVITY = 9.80665


class VehicleUnits(StrictModel):
    length: Literal["mm"] = "mm"
    force: Literal["N"] = "N"
    angle: Literal["deg"] = "deg"
    mass: Literal["kg"] = "kg"


class AxleEntry(StrictModel):
    """One axle of the car: its config (an axle: a config with an ``axle`` section), the path
    relative to the vehicle file's folder, confined to it and the folders typed with ``--data``
    (README "Which paths may point anywhere")."""

    config: str = Field(min_length=1)


class VehicleFile(StrictModel):
    """Top-level schema of a vehicle file (README "The whole car")."""

    elastokin: Literal[1]
    name: str
    units: VehicleUnits
    front: AxleEntry
    rear: AxleEntry
    wheelbase_mm: float
    cg_height_mm: float
    #: the masses per axle, or the whole mass and the front axle's share of it
    axle_mass_kg: AxleMassesSpec | None = None
    mass_kg: float | None = None
    front_mass_fraction: float | None = None
    #: the front axle's share of the braking force and of the drive force, 0 ... 1
    brake_fraction_front: float
    drive_fraction_front: float
    #: the front axle's share of the lateral load transfer in the axles' static-load cases
    #: (``vehicle_loads``), 0 ... 1; None: each axle's own (else its share of the mass)
    lateral_transfer_fraction_front: float | None = None
    #: the body roll the rig's table applies to both axles (each at its axle load)
    body_roll: RollSpec = RollSpec()

    _plausible = field_validator("wheelbase_mm", "cg_height_mm", "mass_kg")(plausible)
    _fractions = field_validator("brake_fraction_front", "drive_fraction_front")(fraction)

    @field_validator("front_mass_fraction")
    @classmethod
    def _share(cls, v: float | None) -> float | None:
        if v is not None and not 0.0 < fraction(v) < 1.0:
            raise ValueError(f"{v:g}: each axle carries some of the mass (0 < fraction < 1)")
        return v

    @field_validator("lateral_transfer_fraction_front")
    @classmethod
    def _transfer(cls, v: float | None) -> float | None:
        return None if v is None else fraction(v)

    @model_validator(mode="after")
    def _one_mass(self) -> VehicleFile:
        whole = (self.mass_kg is not None, self.front_mass_fraction is not None)
        if self.axle_mass_kg is not None and any(whole):
            raise ValueError("give axle_mass_kg, or mass_kg and front_mass_fraction, not both")
        if self.axle_mass_kg is None and not all(whole):
            missing = "front_mass_fraction" if whole[0] else "mass_kg"
            raise ValueError("give the masses: axle_mass_kg {front, rear}, or mass_kg and "
                             f"front_mass_fraction ({missing} is missing)")
        return self

    def masses_kg(self) -> tuple[float, float]:
        """(front, rear): the masses the axles carry (kg)."""
        if self.axle_mass_kg is not None:
            return self.axle_mass_kg.front, self.axle_mass_kg.rear
        return (self.mass_kg * self.front_mass_fraction,
                self.mass_kg * (1.0 - self.front_mass_fraction))
