"""Joint kinds and bushing directions (plain tables)."""

from __future__ import annotations

#: directions of a bushing frame: translations x y z (mm), rotations rx ry rz (deg)
BUSHING_DIRECTIONS = ("x", "y", "z", "rx", "ry", "rz")

#: constrained axes (tx ty tz rx ry rz) in the joint frame, whose z is the joint axis
CONSTRAINED = {
    "spherical": (1, 1, 1, 0, 0, 0),
    "fixed": (1, 1, 1, 1, 1, 1),
    "revolute": (1, 1, 1, 1, 1, 0),
    "cylindrical": (1, 1, 0, 1, 1, 0),
    "translational": (1, 1, 0, 1, 1, 1),
    "rack": (1, 1, 1, 1, 1, 1),
    "universal": (1, 1, 1, 0, 0, 1),
    # the plane normal to the axis slides and turns in the other part's plane (3 constraints)
    "planar": (0, 0, 1, 1, 1, 0),
    # a point of one part kept in a plane of the other (1 constraint: ADAMS's inplane)
    "inplane": (0, 0, 1, 0, 0, 0),
}
