"""The beam section of a part (pydantic): a flexible part made of beam elements, its nodes at
named hardpoints on its centroid line, its mesh and its cross-section's stiffness. Units mm, N,
N*mm^2; the config frame (docs/beams.md).
"""

from __future__ import annotations

from pydantic import Field, field_validator

from elastokin.config import bounds
from elastokin.config.schema.base import AxisSpec, StrictModel


class BeamSectionSpec(StrictModel):
    """The cross-section, uniform along the beam, in its section axes: x along each segment
    (from a node to the next), z the ``z_axis`` projected normal to x, y = z x x. Axial
    stiffness ``EA_N``; bending stiffness about y and about z (N*mm^2, about the centroid);
    torsion ``GJ_Nmm2`` (N*mm^2: N*mm of torque per rad/mm of twist); shear stiffness along y
    and z (N, the shear correction factor included: the elements are shear deformable); the
    shear centre's position relative to the node line, (y, z) in mm."""

    z_axis: AxisSpec
    EA_N: float = Field(gt=0)
    EI_y_Nmm2: float = Field(gt=0)
    EI_z_Nmm2: float = Field(gt=0)
    GJ_Nmm2: float = Field(gt=0)
    GA_y_N: float = Field(gt=0)
    GA_z_N: float = Field(gt=0)
    shear_centre_mm: tuple[float, float] = (0.0, 0.0)


class BeamSpec(StrictModel):
    """A flexible part: ``nodes`` names hardpoints along its centroid line, in order (its
    stress-free shape; connections attach at them), each segment between two nodes meshed
    with ``elements_per_segment`` beam elements; ``section`` its cross-section."""

    nodes: list[str] = Field(min_length=2, max_length=bounds.MAX_BEAM_NODES)
    elements_per_segment: int = Field(ge=1, le=bounds.MAX_ELEMENTS_PER_SEGMENT)
    section: BeamSectionSpec

    @field_validator("nodes")
    @classmethod
    def _distinct(cls, v: list[str]) -> list[str]:
        repeated = sorted({n for n in v if v.count(n) > 1})
        if repeated:
            raise ValueError(f"node {', '.join(repeated)} is listed twice (a beam's nodes are "
                             "distinct hardpoints, in order along it)")
        return v
