"""The rig section of a config (pydantic): the load cases of the virtual K&C rig, corner
and axle ones (README "Config reference", "Rig files"). Units mm, N, N*mm, deg; signs: ISO 8855
vehicle axes, forces and torques the rig applies to the tyre."""

from __future__ import annotations

import re
from typing import Literal

from pydantic import Field, field_validator, model_validator

from elastokin.config import bounds
from elastokin.config.schema.base import StrictModel, Vector3


class TravelSpec(StrictModel):
    rebound_mm: float = -90.0
    bump_mm: float = 90.0
    step_mm: float = Field(default=1.0, gt=0)
    unloading: bool = True  # return from bump to rebound after the loading stroke

    @model_validator(mode="after")
    def _ordered(self) -> TravelSpec:
        if not self.rebound_mm < 0 < self.bump_mm:
            raise ValueError("need rebound_mm < 0 < bump_mm (travel about the design position)")
        n = bounds.travel_steps(self.rebound_mm, self.bump_mm, self.step_mm, self.unloading)
        bounds.check_steps(n, "step_mm", f"{self.step_mm:g} mm",
                           f"from rebound_mm {self.rebound_mm:g} to bump_mm {self.bump_mm:g}")
        return self


class VerticalForceSpec(StrictModel):
    """Vertical force at the contact patch swept from the design wheel load down to ``min_N``,
    up to ``max_N`` and back to ``min_N`` (force control, N)."""

    min_N: float = Field(default=1000.0, gt=0)
    max_N: float = Field(default=7500.0, gt=0)
    step_N: float = Field(default=50.0, gt=0)

    @model_validator(mode="after")
    def _ordered(self) -> VerticalForceSpec:
        if not self.min_N < self.max_N:
            raise ValueError("need min_N < max_N")
        n = bounds.vertical_force_steps(self.min_N, self.max_N, self.step_N)
        bounds.check_steps(n, "step_N", f"{self.step_N:g} N",
                           f"from min_N {self.min_N:g} to max_N {self.max_N:g} and back")
        return self


class ForceSweepSpec(StrictModel):
    """A force swept 0 -> +amplitude -> -amplitude -> 0 at the design wheel load (N)."""

    amplitude_N: float = Field(default=2000.0, gt=0)
    step_N: float = Field(default=50.0, gt=0)

    @model_validator(mode="after")
    def _bounded(self) -> ForceSweepSpec:
        bounds.check_steps(bounds.sweep_steps(self.amplitude_N, self.step_N), "step_N",
                           f"{self.step_N:g} N", f"for amplitude_N {self.amplitude_N:g}")
        return self


class TorqueSweepSpec(StrictModel):
    """A torque swept 0 -> +amplitude -> -amplitude -> 0 at the design wheel load (N*mm)."""

    amplitude_Nmm: float = Field(default=1.0e5, gt=0)
    step_Nmm: float = Field(default=2500.0, gt=0)

    @model_validator(mode="after")
    def _bounded(self) -> TorqueSweepSpec:
        bounds.check_steps(bounds.sweep_steps(self.amplitude_Nmm, self.step_Nmm), "step_Nmm",
                           f"{self.step_Nmm:g} N*mm", f"for amplitude_Nmm {self.amplitude_Nmm:g}")
        return self


class OppositeTravelSpec(TravelSpec):
    """Opposite wheel travel (axle): the left wheel's pad follows the travel, the right's the
    opposite (mm; ADAMS/Car's opposite wheel travel)."""

    rebound_mm: float = -50.0
    bump_mm: float = 50.0
    step_mm: float = Field(default=2.0, gt=0)


class SingleWheelTravelSpec(OppositeTravelSpec):
    """Single wheel travel (axle): the pad of the ``moving`` wheel moves (mm), the other is
    held at its design height."""

    moving: Literal["left", "right"] = "left"


class RollSpec(StrictModel):
    """Roll and vertical force (axle): body roll swept 0 -> +max -> -max -> 0 (deg) with the
    axle's total vertical load held at twice the design wheel load."""

    amplitude_deg: float = Field(default=3.0, gt=0, le=20.0)
    step_deg: float = Field(default=0.1, gt=0)

    @model_validator(mode="after")
    def _bounded(self) -> RollSpec:
        bounds.check_steps(bounds.sweep_steps(self.amplitude_deg, self.step_deg), "step_deg",
                           f"{self.step_deg:g} deg", f"for amplitude_deg {self.amplitude_deg:g}")
        return self


class SteeringSweepSpec(StrictModel):
    """Steering (axle with a rack): the steering wheel turned 0 -> +max -> -max -> 0 (deg,
    + to the left), wheels at the design load. ``amplitude_deg`` None: to the rack's travel
    limit (lock to lock)."""

    amplitude_deg: float | None = Field(default=None, gt=0)
    step_deg: float = Field(default=10.0, gt=0)


class WheelLoadSpec(StrictModel):
    """Forces (N) and torques (N*mm) the rig applies at one contact patch, config frame."""

    force_N: Vector3 = (0.0, 0.0, 0.0)
    torque_Nmm: Vector3 = (0.0, 0.0, 0.0)


class StaticLoadSpec(StrictModel):
    """Static load (axle): given loads at each contact patch (``left``, ``right``), ramped from
    the design wheel loads in ``steps`` equal steps (the vertical force is the given one)."""

    left: WheelLoadSpec
    right: WheelLoadSpec
    steps: int = Field(default=10, ge=1, le=bounds.MAX_STEPS_PER_LOAD_CASE)


class VehicleLoadCaseSpec(StrictModel):
    """One static-load case from steady vehicle accelerations (g): ``longitudinal_g`` +
    forward (traction; braking -), ``lateral_g`` + to the left (a left turn), ``bump_g``
    vertical beyond gravity (+ up: 1 doubles the wheel loads)."""

    longitudinal_g: float = Field(default=0.0, ge=-5.0, le=5.0)
    lateral_g: float = Field(default=0.0, ge=-5.0, le=5.0)
    bump_g: float = Field(default=0.0, ge=-1.0, le=10.0)


#: the static-load cases run when ``vehicle_loads`` names none (ADAMS/Car's usual set)
DEFAULT_VEHICLE_LOAD_CASES = {
    "bump_1g": VehicleLoadCaseSpec(bump_g=1.0),
    "braking_1g": VehicleLoadCaseSpec(longitudinal_g=-1.0),
    "traction_0.5g": VehicleLoadCaseSpec(longitudinal_g=0.5),
    "cornering_left_1g": VehicleLoadCaseSpec(lateral_g=1.0),
    "cornering_right_1g": VehicleLoadCaseSpec(lateral_g=-1.0),
    "braking_cornering_left": VehicleLoadCaseSpec(longitudinal_g=-0.7, lateral_g=0.7),
}


class VehicleLoadsSpec(StrictModel):
    """The static-load analysis from vehicle accelerations (axle with ``axle.vehicle`` and its
    ``axle_mass_kg``): each case ramped from the design wheel loads to its contact-patch
    forces in ``steps`` equal steps (load case ``vehicle_loads:<name>``)."""

    cases: dict[str, VehicleLoadCaseSpec] = Field(
        default_factory=lambda: dict(DEFAULT_VEHICLE_LOAD_CASES), min_length=1)
    steps: int = Field(default=10, ge=1, le=bounds.MAX_STEPS_PER_LOAD_CASE)

    @field_validator("cases")
    @classmethod
    def _names(cls, cases: dict) -> dict:
        for name in cases:
            if not re.fullmatch(r"[A-Za-z0-9_.+-]+", name):
                raise ValueError(f"case name '{name}': use letters, digits and _ . + - only")
        return cases


class RigSpec(StrictModel):
    """The load cases of the virtual K&C rig (defaults: the reference paper's for a corner and
    ADAMS/Car's suspension analyses for an axle; ``null`` leaves a case out; axle cases are
    run on axles only). Signs: ISO 8855 vehicle axes, forces on the tyre (see README)."""

    parallel_travel: TravelSpec = TravelSpec()
    vertical_force: VerticalForceSpec | None = VerticalForceSpec()
    lateral_force: ForceSweepSpec | None = ForceSweepSpec()
    longitudinal_force_patch: ForceSweepSpec | None = ForceSweepSpec()
    longitudinal_force_centre: ForceSweepSpec | None = ForceSweepSpec()
    aligning_torque: TorqueSweepSpec | None = TorqueSweepSpec()
    opposite_travel: OppositeTravelSpec | None = OppositeTravelSpec()
    single_wheel_travel: SingleWheelTravelSpec | None = SingleWheelTravelSpec()
    roll_vertical_force: RollSpec | None = RollSpec()
    steering: SteeringSweepSpec | None = SteeringSweepSpec()
    static_load: StaticLoadSpec | None = None
    lateral_force_anti_phase: ForceSweepSpec | None = ForceSweepSpec()
    vehicle_loads: VehicleLoadsSpec | None = None
