"""The schema's building blocks (pydantic): strict models, points and vectors. Units mm,
N, deg (README "Config reference")."""

from __future__ import annotations

from typing import Annotated

from pydantic import AfterValidator, BaseModel, ConfigDict, Field

from elastokin.config import bounds


def _within_reach(v: float) -> float:
    if abs(v) > bounds.MAX_COORDINATE_MM:
        raise ValueError(f"{v:g} mm: a point more than {bounds.MAX_COORDINATE_MM:,.0f} mm "
                         "from the origin (a typo, or not in mm?)")
    return v


Vector3 = tuple[float, float, float]
#: a point's coordinate (mm), within MAX_COORDINATE_MM of the origin
Coordinate = Annotated[float, AfterValidator(_within_reach)]
Point3 = tuple[Coordinate, Coordinate, Coordinate]
PointSpec = str | Point3


class StrictModel(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False)


class AxisBetween(StrictModel):
    """An axis given by two points: unit vector from ``from`` to ``to``."""

    from_: PointSpec = Field(alias="from")
    to: PointSpec


AxisSpec = Vector3 | AxisBetween


class CurveSpec(StrictModel):
    """A force-deflection curve: deflection (mm or deg) -> force (N) or torque (N*mm)."""

    deflection: list[float] = Field(min_length=2, max_length=bounds.MAX_CURVE_POINTS)
    load: list[float] = Field(min_length=2, max_length=bounds.MAX_CURVE_POINTS)
