"""The ``motion`` section of a config (pydantic): joint locations from the parts' motion, the
marks of every part measured on the assembled car at several rig positions
(docs/measurements.md, "Joints from motion"). Units mm, deg; rig inputs from the design
position."""

from __future__ import annotations

from pydantic import Field, field_validator, model_validator

from elastokin.config.schema.base import StrictModel

#: most positions a motion plan may name (each is one CMM file; a bound on the work)
MAX_POSITIONS = 200


class RigStateSpec(StrictModel):
    """The rig's inputs at one measured position, from the design position.

    ``wheel_travel_mm``: the config side's wheel pad height (+ bump; displacement control);
    ``other_wheel_travel_mm``: the other wheel's pad on an axle (opposite travel: the
    negative of ``wheel_travel_mm``); ``rack_travel_mm``: the steering rack (steer; + along
    the rack's axis, a corner without a rack: to the vehicle's left, ISO y);
    ``wheel_turned_deg``: the wheel turned on its bearing by hand (its spin axis), + about
    the outboard spin axis. All zero: the design position, the car at rest under the design
    wheel load (force control), where the paper's CMM measures it."""

    wheel_travel_mm: float = Field(default=0.0, ge=-500.0, le=500.0)
    other_wheel_travel_mm: float = Field(default=0.0, ge=-500.0, le=500.0)
    rack_travel_mm: float = Field(default=0.0, ge=-200.0, le=200.0)
    wheel_turned_deg: float = Field(default=0.0, ge=-360.0, le=360.0)

    @property
    def is_design(self) -> bool:
        return not any((self.wheel_travel_mm, self.other_wheel_travel_mm, self.rack_travel_mm,
                        self.wheel_turned_deg))


class PositionSpec(RigStateSpec):
    """One measured position: its CMM file (every marked body's marks, in the CMM's frame, in
    any order) and the rig's state."""

    file: str


class MotionSyntheticSpec(StrictModel):
    """Parameters of the virtual CMM's motion data (``elastokin synthesize``)."""

    seed: int = 0
    noise_mm: float = Field(default=0.1, ge=0)  # 95 % of points within this of the truth
    gross_error_mm: tuple[float, float] = (5.0, 15.0)  # one bad mark at one position


class GroundMarksSpec(StrictModel):
    """The ground part's marks in the config frame (e.g. from the body's datum points): they
    fix the vehicle frame at every position."""

    file: str
    marks: tuple[str, str, str, str] = ("M1", "M2", "M3", "M4")


class MotionSpec(StrictModel):
    """Joints from motion (docs/measurements.md): the marks of every part, of the ground, of
    marked links (a tie rod) and of the wheel, measured at every position."""

    folder: str = "."  # relative to the config file
    eps_mm: float = Field(default=0.4, gt=0)  # mark-matching tolerance, as measurements.eps_mm
    ground: GroundMarksSpec
    marks: dict[str, str]  # body (part, ground or link) -> label pattern (fnmatch)
    wheel_marks: str | None = None  # label pattern of marks on the wheel (its spin axis)
    # the link whose ground end rides on the steering rack when the rig steers a corner
    # without a rack part (the tie rod of a corner modelled with its steering locked)
    rack_link: str | None = None
    positions: dict[str, PositionSpec] = Field(min_length=3, max_length=MAX_POSITIONS)
    # a joint located worse than this (1-sigma, along its worst direction) stops the run
    max_uncertainty_mm: float = Field(default=0.5, gt=0)
    max_axis_uncertainty_deg: float = Field(default=0.5, gt=0)
    # joints located only along the directions the motion fixes within max_uncertainty_mm,
    # keeping the config's location along the others (e.g. a tie rod's inner end, which
    # steering slides along the rod instead of turning it): a warning names each
    partly_located: list[str] = []
    truth: str | None = None  # synthetic data only: the as-built truth written by synthesize
    synthetic: MotionSyntheticSpec | None = None

    @field_validator("positions")
    @classmethod
    def _one_design_position(cls, v: dict[str, PositionSpec]) -> dict[str, PositionSpec]:
        if not any(p.is_design for p in v.values()):
            raise ValueError("no design position: one position needs every rig input zero "
                             "(the car at rest under the design wheel load)")
        files = [p.file for p in v.values()]
        twice = sorted({f for f in files if files.count(f) > 1})
        if twice:
            raise ValueError(f"file(s) {', '.join(twice)} named by two positions")
        return v

    @model_validator(mode="after")
    def _wheel_pattern(self) -> MotionSpec:
        if self.wheel_marks is not None and self.wheel_marks in self.marks.values():
            raise ValueError(f"wheel_marks '{self.wheel_marks}' is also a body's pattern")
        return self

    @property
    def design_position(self) -> str:
        """The first position with every rig input zero: the reference of the results."""
        return next(name for name, p in self.positions.items() if p.is_design)
