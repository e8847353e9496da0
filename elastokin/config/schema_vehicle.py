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
from elastokin.config.schema_base import StrictModel
from elastokin.config.schema_rig import RollSpec

#: plausible mass of a whole vehicle (kg): a go-kart to a heavy truck (README "Limits")
VEHICLE_MASS_RANGE_KG = (50.0, 60_000.0)
#: the standard acceleration of gravity (m/s^2): axle weights from masses, N per g
STANDARD_GRAVITY = 9.80665


def mass_problem(value: float, low: float, high: float) -> str | None:
    """Why ``value`` (kg) is not a plausible mass between ``low`` and ``high``, the unit slip
    that would explain it named (N, tonnes), or None."""
    if low <= value <= high:
        return None
    hint = (f" - in N? {value / STANDARD_GRAVITY:.0f} kg"
            if low <= value / STANDARD_GRAVITY <= high else
            " - in tonnes? give kg" if low <= value * 1000.0 <= high else "")
    return f"{value:g}{hint} (expected {low:,g} ... {high:,g} kg, README 'Limits')"


class VehicleUnits(StrictModel):
    length: Literal["mm"] = "mm"
    force: Literal["N"] = "N"
    angle: Literal["deg"] = "deg"
    mass: Literal["kg"] = "kg"


class AxleEntry(StrictModel):
    """One axle of the car: its config (an axle: a config with an ``axle`` section), the path
    relative to the vehicle file's folder, confined to it and the working folder (README
    "Which paths may point anywhere")."""

    config: str = Field(min_length=1)


class AxleMasses(StrictModel):
    """The masses the front and the rear axle carry at rest (kg): what the scales under each
    axle's wheels read, the unsprung masses included."""

    front: float
    rear: float

    @field_validator("front", "rear")
    @classmethod
    def _plausible(cls, v: float) -> float:
        low, high = VEHICLE_MASS_RANGE_KG
        problem = mass_problem(v, low / 4.0, high / 2.0)
        if problem:
            raise ValueError(problem)
        return v


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
    axle_mass_kg: AxleMasses | None = None
    mass_kg: float | None = None
    front_mass_fraction: float | None = None
    #: the front axle's share of the braking force and of the drive force, 0 ... 1
    brake_fraction_front: float
    drive_fraction_front: float
    #: the body roll the rig's table applies to both axles (each at its axle load)
    body_roll: RollSpec = RollSpec()

    _plausible = field_validator("wheelbase_mm", "cg_height_mm")(plausible)
    _fractions = field_validator("brake_fraction_front", "drive_fraction_front")(fraction)

    @field_validator("front_mass_fraction")
    @classmethod
    def _share(cls, v: float | None) -> float | None:
        if v is not None and not 0.0 < fraction(v) < 1.0:
            raise ValueError(f"{v:g}: each axle carries some of the mass (0 < fraction < 1)")
        return v

    @field_validator("mass_kg")
    @classmethod
    def _plausible_mass(cls, v: float | None) -> float | None:
        problem = None if v is None else mass_problem(v, *VEHICLE_MASS_RANGE_KG)
        if problem:
            raise ValueError(problem)
        return v

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
