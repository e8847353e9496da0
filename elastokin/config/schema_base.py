"""The schema's building blocks (pydantic): strict models, points and vectors. Units mm,
N, deg (README "Config reference")."""

from __future__ import annotations

from pydantic import BaseModel, ConfigDict, Field

from elastokin.config import bounds

Vector3 = tuple[float, float, float]
PointSpec = str | Vector3


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
