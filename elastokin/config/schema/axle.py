"""The axle and stop sections of a config (pydantic): a corner config with an ``axle:``
section describes an axle (the other corner mirrored, shared parts, steering rack, anti-roll
bar, vehicle data); ``stops:`` are a corner's bump and rebound stops. Units mm, N, N*mm, deg;
the config frame (README "Axles").
"""

from __future__ import annotations

from typing import Literal

from pydantic import Field, field_validator, model_validator

from elastokin.config import bounds
from elastokin.config.plausibility import fraction, implausible, plausible
from elastokin.config.schema.base import AxisSpec, CurveSpec, Point3, PointSpec, StrictModel


class StopSpec(StrictModel):
    """A bump or rebound stop acting along the line between two points of two parts:
    ``bump`` when the points approach by more than ``clearance_mm`` from the design
    position, ``rebound`` when they separate by more than it; then the force is ``curve``
    (N) of the penetration beyond contact (mm; through (0, 0), increasing)."""

    type: Literal["bump", "rebound"]
    parts: tuple[str, str]
    points: tuple[PointSpec, PointSpec]
    clearance_mm: float = Field(ge=0)
    curve: CurveSpec
    description: str = ""


class StiffnessOverride(StrictModel):
    """Per direction of a bushing frame, a rate or a curve replacing the corner's."""

    x: float | CurveSpec | None = None
    y: float | CurveSpec | None = None
    z: float | CurveSpec | None = None
    rx: float | CurveSpec | None = None
    ry: float | CurveSpec | None = None
    rz: float | CurveSpec | None = None


class ConnectionOverride(StrictModel):
    """What the other side's copy of a bushing changes (asymmetric axles)."""

    stiffness: StiffnessOverride

    @model_validator(mode="after")
    def _changes_something(self) -> ConnectionOverride:
        if not self.stiffness.model_fields_set:
            raise ValueError("stiffness: give at least one direction (x, y, z, rx, ry, rz) "
                             "the other side's bushing changes")
        return self


class OtherSideSpec(StrictModel):
    """The other corner is this one mirrored about the vehicle centre plane (y = 0 of the
    config frame); these entries, by the corner's names, make it asymmetric: where the other
    side's hardpoints are (config frame, mm), and its bushings' stiffness."""

    hardpoints: dict[str, Point3] = {}
    connections: dict[str, ConnectionOverride] = {}


class SteeringSpec(StrictModel):
    """The steering: ``rack`` names the config's connection of type ``rack`` (ground or a
    shared part <-> the rack part); on an axle it slides along its axis, held at its
    ``travel_mm`` except in the steering load case, which drives it from the steering-wheel
    angle through the ratio (mm of rack travel per revolution, constant or a curve). Rack
    travel is + along the connection's axis; a steering-wheel angle + to the left (ISO)."""

    rack: str
    ratio_mm_per_rev: float | None = Field(default=None, gt=0)
    ratio_curve: SteeringRatioCurve | None = None
    limit_mm: float = Field(gt=0)  # rack travel each way from the centre

    _plausible = field_validator("ratio_mm_per_rev", "limit_mm")(plausible)

    @model_validator(mode="after")
    def _one_ratio(self) -> SteeringSpec:
        if (self.ratio_mm_per_rev is None) == (self.ratio_curve is None):
            raise ValueError("give ratio_mm_per_rev or ratio_curve")
        return self


class SteeringRatioCurve(StrictModel):
    """Rack travel (mm) against steering-wheel angle (deg), through (0, 0), increasing."""

    steering_wheel_deg: list[float] = Field(min_length=2, max_length=bounds.MAX_CURVE_POINTS)
    rack_travel_mm: list[float] = Field(min_length=2, max_length=bounds.MAX_CURVE_POINTS)


class AntiRollBarSpec(StrictModel):
    """An anti-roll bar: ``part`` is this corner's half of the bar (mirrored to the other
    side); the halves are joined by a torsion spring about ``axis`` at ``point`` (on the
    vehicle centre plane), rate N*mm/deg or a curve (N*mm against deg of twist)."""

    part: str
    point: PointSpec
    axis: AxisSpec
    rate_Nmm_per_deg: float | None = Field(default=None, gt=0)
    curve: CurveSpec | None = None

    _plausible = field_validator("rate_Nmm_per_deg")(plausible)

    @model_validator(mode="after")
    def _one_law(self) -> AntiRollBarSpec:
        if (self.rate_Nmm_per_deg is None) == (self.curve is None):
            raise ValueError("give rate_Nmm_per_deg or curve")
        return self


class AxleMassesSpec(StrictModel):
    """The masses the front and the rear axle carry at rest (kg; their sum is the vehicle's
    mass in the static-load analysis), as the suspensions carry them: without the unsprung
    masses when the design wheel load leaves them out; each within its plausible range."""

    front: float
    rear: float

    @field_validator("front", "rear")
    @classmethod
    def _plausible(cls, v: float) -> float:
        problem = implausible("axle_mass_kg", v)
        if problem:
            raise ValueError(problem)
        return v


class VehicleSpec(StrictModel):
    """Vehicle data for the axle's characteristics (anti-dive, anti-lift, anti-squat,
    Ackermann, turn diameter) and the static-load analysis from vehicle accelerations
    (``axle_mass_kg``, ``lateral_transfer_fraction``: the rig's ``vehicle_loads``), each
    within its plausible range (:mod:`elastokin.config.plausibility`)."""

    position: Literal["front", "rear"] = "front"
    wheelbase_mm: float = Field(gt=0)
    cg_height_mm: float = Field(gt=0)
    brake_fraction: float = Field(default=0.6, ge=0)  # this axle's share of braking, 0 ... 1
    drive_fraction: float = Field(default=1.0, ge=0)  # this axle's share of drive, 0 ... 1
    brakes: Literal["outboard", "inboard"] = "outboard"
    #: where the brake and the drive torques are reacted: ``outboard`` by the wheel carrier
    #: (the force acts at the contact patch, ADAMS/Car's convention), ``inboard`` by the body
    #: (inboard brakes, a chassis-mounted final drive: at the wheel centre)
    drive: Literal["outboard", "inboard"] = "outboard"
    #: a driven solid axle (ADAMS/Car's "dependent" suspension type): the final drive ratio
    #: (propeller-shaft turns per wheel turn); the axle housing reacts the pinion torque,
    #: which adds -/+ T/track to the wheel loads in anti-squat and traction anti-lift
    live_axle_ratio: float | None = Field(default=None, gt=0)
    #: the masses the axles carry at rest (kg): the static-load analysis
    axle_mass_kg: AxleMassesSpec | None = None
    #: this axle's share of the lateral load transfer (roll stiffness distribution), 0 ... 1
    #: (None: its share of the mass)
    lateral_transfer_fraction: float | None = Field(default=None, ge=0)

    # values outside a plausible range are refused with the likely unit slip named
    _plausible = field_validator("wheelbase_mm", "cg_height_mm")(plausible)
    _fractions = field_validator("brake_fraction", "drive_fraction")(fraction)
    _transfer = field_validator("lateral_transfer_fraction")(
        lambda v: None if v is None else fraction(v))


class AxleSpec(StrictModel):
    """The axle: the other corner (mirrored, ``other_side`` overrides), parts declared once
    (``shared``; a shared part may carry both wheels: a solid axle), the connections, springs
    and stops among shared parts and the ground that exist on both sides (``both_sides``:
    mirrored as a corner's are, e.g. a solid axle's trailing links and springs), the steering
    rack, the anti-roll bar and vehicle data."""

    other_side: OtherSideSpec = OtherSideSpec()
    shared: list[str] = []
    both_sides: list[str] = []
    steering: SteeringSpec | None = None
    anti_roll_bar: AntiRollBarSpec | None = None
    vehicle: VehicleSpec | None = None


SteeringSpec.model_rebuild()
