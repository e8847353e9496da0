"""The resolved suspension: a validated config with hardpoint names replaced by coordinates
(mm, config frame), axes normalised, bushing frames as rotation matrices (columns x, y, z of the
bushing frame in the config frame) and laws as callables. Plain data that never changes:
everything downstream works on it.

Read-only throughout: fields cannot be assigned, mappings (``hardpoints``, ``parts``,
``raw``) are :class:`~elastokin.config.frozen.FrozenMapping` and arrays are read-only, so a
change that would be silently ignored raises instead, naming the function that makes a
changed copy (:mod:`elastokin.config.variants`: ``with_hardpoints``, ``with_bushing_laws``,
``with_joint_shifts``, ``kinematic``; or ``dataclasses.replace``). Pickling and
``dataclasses.replace`` keep every part read-only.
"""

from __future__ import annotations

from dataclasses import FrozenInstanceError, dataclass, field, fields, replace

import numpy as np

from elastokin.config.frozen import FrozenMapping, freeze, readonly
from elastokin.config.schema.axle import VehicleSpec
from elastokin.config.schema.motion import MotionSpec
from elastokin.config.schema.rig import RigSpec
from elastokin.config.schema.suspension import (
    DesignSpec,
    Frame,
    KCTestSpec,
    MeasurementsSpec,
    PartSpec,
    ReferenceSpec,
    SolverSpec,
)
from elastokin.errors import ConfigError
from elastokin.physics.laws import DirectionLaw
from elastokin.physics.steering_geometry import contact_point

# ----------------------------------------------------------------------------------------------
# Resolved model description (plain numbers, no names left to look up)

#: how to change a resolved suspension (the end of the message of a refused assignment)
HOW_TO_CHANGE = ("make a changed copy with elastokin.config.variants.with_hardpoints("
                 "suspension, {'J3': [x, y, z]}) (or with_bushing_laws, with_joint_shifts, "
                 "kinematic, dataclasses.replace), or edit copy.deepcopy(suspension.raw) and "
                 "load it with elastokin.suspension_from_dict")


def _frozen_value(value):
    """An array field's value made read-only: an array, or a tuple of arrays (None kept)."""
    if value is None:
        return None
    if isinstance(value, tuple):
        return tuple(readonly(v) for v in value)
    return readonly(value)


class ReadOnlyArrays:
    """Base of the resolved dataclasses: the fields named in ``array_fields`` are made
    read-only arrays on construction and again after unpickling (numpy does not pickle the
    flag)."""

    array_fields: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        for name in self.array_fields:
            object.__setattr__(self, name, _frozen_value(getattr(self, name)))

    def __setstate__(self, state: dict) -> None:
        self.__dict__.update(state)
        self.__post_init__()


@dataclass(frozen=True)
class Joint(ReadOnlyArrays):
    """An ideal joint. ``frame``: rotation matrix, columns = joint axes in the config frame;
    ``constrained``: 6 flags (translation x y z, rotation x y z) in that frame."""

    name: str
    kind: str
    parts: tuple[str, str]
    position_mm: np.ndarray
    frame: np.ndarray
    constrained: tuple[int, int, int, int, int, int]
    offset_mm: float = 0.0
    #: as-built only (virtual CMM): each part's attachment relative to ``position_mm``
    part_shift_mm: tuple[np.ndarray, np.ndarray] | None = None
    array_fields = ("position_mm", "frame", "part_shift_mm")


@dataclass(frozen=True)
class Link(ReadOnlyArrays):
    name: str
    parts: tuple[str, str]
    points_mm: tuple[np.ndarray, np.ndarray]
    array_fields = ("points_mm",)


@dataclass(frozen=True)
class Bushing(ReadOnlyArrays):
    """6-DOF bushing; ``frame`` columns are its x (radial), y, z (axial) axes in the config frame.

    ``laws`` map deflection (mm, deg) to load (N, N*mm) per direction x y z rx ry rz;
    ``initial_deflection`` (mm, mm, mm, deg, deg, deg) is the deflection at the design position.
    """

    name: str
    parts: tuple[str, str]
    position_mm: np.ndarray
    frame: np.ndarray
    laws: tuple[DirectionLaw, ...]
    initial_deflection: np.ndarray
    ideal_joint: str
    preload_given: bool
    #: modelled by its ideal joint (the config's ``kinematic: true``, for every bushing or
    #: this one's); the model is then exact kinematics in this connection
    kinematic: bool = False
    array_fields = ("position_mm", "frame", "initial_deflection")


@dataclass(frozen=True)
class Spring(ReadOnlyArrays):
    name: str
    parts: tuple[str, str]
    seats_mm: tuple[np.ndarray, np.ndarray]
    rate_N_per_mm: float
    preload_N: float | None
    free_length_mm: float | None
    array_fields = ("seats_mm",)

    @property
    def installed_length_mm(self) -> float:
        return float(np.linalg.norm(self.seats_mm[1] - self.seats_mm[0]))

    def design_force_N(self) -> float:
        """Compression force at the design (installed) length, N (positive = pushing apart)."""
        if self.preload_N is not None:
            return self.preload_N
        if self.free_length_mm is not None:
            return self.rate_N_per_mm * (self.free_length_mm - self.installed_length_mm)
        return 0.0


@dataclass(frozen=True)
class Damper(ReadOnlyArrays):
    """A damper between ``points_mm`` of two parts (config frame, design position). Quasi-static
    rig: no force; its length and velocity ratio are reported. ``rate_N_s_per_mm``: linear
    damping for ADAMS/Car's property file (None: not given)."""

    name: str
    parts: tuple[str, str]
    points_mm: tuple[np.ndarray, np.ndarray]
    rate_N_s_per_mm: float | None = None
    array_fields = ("points_mm",)

    @property
    def installed_length_mm(self) -> float:
        return float(np.linalg.norm(self.points_mm[1] - self.points_mm[0]))


@dataclass(frozen=True)
class Wheel(ReadOnlyArrays):
    part: str
    centre_mm: np.ndarray
    spin_axis: np.ndarray  # unit, pointing outboard
    loaded_radius_mm: float
    tyre_rate_N_per_mm: float | None = None  # vertical, for the ride rate
    array_fields = ("centre_mm", "spin_axis")

    @property
    def contact_patch_mm(self) -> np.ndarray:
        """Contact point at design (config frame, z up): the wheel's lowest point, the loaded
        radius below the centre in the wheel plane
        (:func:`~elastokin.physics.steering_geometry.contact_point`, as at every rig step)."""
        return contact_point(self.centre_mm, self.spin_axis, self.loaded_radius_mm,
                             np.array([0.0, 0.0, 1.0]))


@dataclass(frozen=True)
class Stop(ReadOnlyArrays):
    """A bump or rebound stop between ``points_mm`` of two parts (config frame, design
    position): in contact when their distance has closed (bump) or opened (rebound) by
    ``clearance_mm``; then the force (N) is ``law`` of the penetration beyond contact (mm),
    pushing the points apart (bump) or together (rebound)."""

    name: str
    kind: str
    parts: tuple[str, str]
    points_mm: tuple[np.ndarray, np.ndarray]
    clearance_mm: float
    law: DirectionLaw
    array_fields = ("points_mm",)

    @property
    def design_length_mm(self) -> float:
        return float(np.linalg.norm(self.points_mm[1] - self.points_mm[0]))

    @property
    def contact_length_mm(self) -> float:
        """The distance of the points at first contact."""
        sign = -1.0 if self.kind == "bump" else 1.0
        return self.design_length_mm + sign * self.clearance_mm


@dataclass(frozen=True)
class BeamSection:
    """Stiffness of a beam's cross-section in its section axes (x along the beam, y and z
    across it; :mod:`elastokin.physics.beams`): axial ``EA_N`` (N), bending about y and about z
    (N*mm^2), torsion ``GJ_Nmm2`` (N*mm^2, N*mm per rad/mm of twist), shear along y and z
    (N, shear correction included). Uniform along the beam."""

    EA_N: float
    EI_y_Nmm2: float
    EI_z_Nmm2: float
    GJ_Nmm2: float
    GA_y_N: float
    GA_z_N: float


@dataclass(frozen=True)
class Beam(ReadOnlyArrays):
    """A flexible part made of beam elements (:mod:`elastokin.mbs.beams`).

    ``nodes_mm`` (n, 3): the named hardpoints ``node_names`` along its centroid line, config
    frame, design position, which is also its stress-free shape; per segment (node i to i + 1)
    ``frames`` (n - 1, 3, 3): its section axes as columns, and ``shear_centre_mm`` (n - 1, 3):
    the shear centre's offset from the node line (config frame); ``elements_per_segment``
    beam elements on each segment. ``rigid``: built as one rigid body (a model variant,
    :func:`elastokin.config.variants.rigid_beams`).
    """

    part: str
    node_names: tuple[str, ...]
    nodes_mm: np.ndarray
    frames: np.ndarray
    shear_centre_mm: np.ndarray
    section: BeamSection
    elements_per_segment: int
    rigid: bool = False
    array_fields = ("nodes_mm", "frames", "shear_centre_mm")

    @property
    def length_mm(self) -> float:
        """Length of the node line (mm)."""
        return float(np.linalg.norm(np.diff(self.nodes_mm, axis=0), axis=1).sum())


@dataclass(frozen=True)
class Steering(ReadOnlyArrays):
    """The steering rack: ``joint`` (the config's type-rack connection, a sliding joint on an
    axle) moves ``part`` along ``axis`` (unit, config frame) at ``position_mm``; held at
    ``travel_mm`` except when the rig steers, within ``limit_mm`` of the centre. ``ratio``
    maps steering-wheel angle (deg) to rack travel (mm)."""

    joint: str
    part: str
    position_mm: np.ndarray
    axis: np.ndarray
    travel_mm: float
    limit_mm: float
    ratio: DirectionLaw
    array_fields = ("position_mm", "axis")

    def rack_travel_mm(self, steering_wheel_deg) -> np.ndarray:
        """Rack travel (mm) for steering-wheel angles (deg)."""
        return np.asarray(self.ratio(np.asarray(steering_wheel_deg, float)), float)


@dataclass(frozen=True)
class AntiRollBar(ReadOnlyArrays):
    """The anti-roll bar's torsion spring between its two halves ``parts`` (config side's
    first) at ``position_mm``; ``frame`` z is the torsion axis; ``law``: torque (N*mm)
    against twist (deg, the second half relative to the first about z)."""

    parts: tuple[str, str]
    position_mm: np.ndarray
    frame: np.ndarray
    law: DirectionLaw
    array_fields = ("position_mm", "frame")


@dataclass(frozen=True)
class Axle:
    """The axle of a :class:`~elastokin.config.suspension.Suspension`: ``sides`` (the config's
    first), the name suffix of the other side's copies, the parts declared once, the steering,
    the anti-roll bar, vehicle data, the springs balanced at the design position (one
    per side) and the items joining the two sides (``across``: a connection, spring, damper
    or stop naming the other side's copy of a corner part, e.g. a heave spring between the
    rockers; kept once)."""

    sides: tuple[str, str]
    suffix: str
    shared: tuple[str, ...]
    steering: Steering | None
    anti_roll_bar: AntiRollBar | None
    vehicle: VehicleSpec | None
    balance_springs: tuple[str, ...]
    across: tuple[str, ...] = ()


def outboard_direction(frame, side: str) -> np.ndarray:
    """Unit vector (config frame) pointing away from the vehicle centreline on ``side``
    ('left'/'right') for a config frame whose y axis points ``frame.y``."""
    left = np.array([0.0, 1.0 if frame.y == "left" else -1.0, 0.0])
    return left if side == "left" else -left


@dataclass(frozen=True)
class Suspension:
    """A resolved suspension: everything in mm, N, deg, config frame; read-only (module
    docstring).

    ``sha256`` identifies everything the suspension was made from (the config file's bytes,
    any overrides and a rig file's content): results are cached under it.
    ``config_sha256`` is the SHA-256 of the config file alone (with overrides given in
    Python), ``rig_sha256`` that of the rig file (None: the config's own ``rig`` section).
    """

    name: str
    source: str
    sha256: str
    frame: Frame
    side: str
    ground: str
    parts: dict[str, PartSpec]
    hardpoints: dict[str, np.ndarray]
    wheel: Wheel
    joints: tuple[Joint, ...]
    links: tuple[Link, ...]
    bushings: tuple[Bushing, ...]
    springs: tuple[Spring, ...]
    design: DesignSpec
    kinematic: bool
    solver: SolverSpec
    rig: RigSpec
    reference: ReferenceSpec = field(default_factory=ReferenceSpec)
    raw: dict = field(repr=False, default_factory=dict)
    measurements: MeasurementsSpec | None = None
    motion: MotionSpec | None = None
    kc_test: KCTestSpec | None = None
    rig_source: str = ""  # a rig file given apart from the config ("": the config's rig)
    label: str = "initial"  # the model's label in results (the config's ``label``)
    config_sha256: str = ""  # "": the same as sha256
    rig_sha256: str | None = None
    stops: tuple[Stop, ...] = ()
    #: every wheel by side (both on an axle; ``wheel`` is the config side's)
    wheels: dict[str, Wheel] = field(default_factory=dict)
    axle: Axle | None = None
    #: the flexible parts (beam elements); every other part is rigid
    beams: tuple[Beam, ...] = ()
    #: dampers (no force on the quasi-static rig: lengths and velocity ratios reported)
    dampers: tuple[Damper, ...] = ()

    def __post_init__(self) -> None:
        if not self.wheels:
            object.__setattr__(self, "wheels", FrozenMapping({self.side: self.wheel},
                                                             HOW_TO_CHANGE))
        elif not isinstance(self.wheels, FrozenMapping):
            object.__setattr__(self, "wheels", FrozenMapping(self.wheels, HOW_TO_CHANGE))
        hp = self.hardpoints
        if not (isinstance(hp, FrozenMapping) and all(not v.flags.writeable
                                                      for v in hp.values())):
            hp = FrozenMapping({k: readonly(v) for k, v in hp.items()}, HOW_TO_CHANGE)
        for name, value in (("hardpoints", hp), ("config_sha256",
                                                 self.config_sha256 or self.sha256)):
            object.__setattr__(self, name, value)
        for name in ("parts", "raw"):
            if not isinstance(getattr(self, name), FrozenMapping):
                object.__setattr__(self, name, freeze(getattr(self, name), HOW_TO_CHANGE))

    def __setstate__(self, state: dict) -> None:
        self.__dict__.update(state)
        self.__post_init__()

    @property
    def sides(self) -> tuple[str, ...]:
        """The sides with a wheel, the config's first."""
        return tuple(self.wheels)

    def rig_key(self, key: str) -> str:
        """Where the rig's ``key`` (e.g. ``steering.amplitude_deg``) is set, as a message
        begins: ``RIG (rig file): key 'KEY'`` when a rig file replaced the config's rig
        section, else ``CONFIG: key 'rig.KEY'``."""
        if self.rig_source:
            return f"{self.rig_source} (rig file): key '{key}'"
        return f"{self.source}: key 'rig.{key}'"

    def on_side(self, side: str) -> Suspension:
        """This suspension as seen from the wheel on ``side``: ``side`` and ``wheel`` are that
        wheel's (everything per wheel - toe, camber, the rig's pad - then reads it)."""
        if side == self.side:
            return self
        if side not in self.wheels:
            raise ConfigError(f"{self.source}: no wheel on the {side} side")
        return replace(self, side=side, wheel=self.wheels[side])

    @property
    def shared_beams(self) -> tuple[str, ...]:
        """The flexible beam parts shared by both sides of an axle (a twist beam's cross
        beam): the wheels' motion in roll is then set by the beam's elasticity, not by the
        joints, and differs from their motion in bump."""
        if self.axle is None:
            return ()
        return tuple(b.part for b in self.beams if not b.rigid and b.part in self.axle.shared)

    @property
    def forward(self) -> np.ndarray:
        """Unit vector pointing forward (vehicle), in the config frame."""
        return np.array([1.0 if self.frame.x == "forward" else -1.0, 0.0, 0.0])

    @property
    def outboard(self) -> np.ndarray:
        """Unit vector pointing away from the vehicle centreline on this wheel's side."""
        return outboard_direction(self.frame, self.side)

    @property
    def up(self) -> np.ndarray:
        return np.array([0.0, 0.0, 1.0])

    @property
    def left(self) -> np.ndarray:
        """Unit vector pointing to the vehicle's left (ISO 8855 +y), in the config frame."""
        return np.array([0.0, 1.0 if self.frame.y == "left" else -1.0, 0.0])


def _refuse_assignment(self, name: str, value=None) -> None:
    if name in {f.name for f in fields(self)}:
        raise FrozenInstanceError(f"cannot assign to field '{name}': a resolved Suspension "
                                  f"is read-only; {HOW_TO_CHANGE}")
    raise FrozenInstanceError(f"cannot assign to '{name}': a Suspension is read-only")


# a frozen dataclass may not define __setattr__ itself: its refusal, with the way to change
# a suspension in the message, replaces the generated one (object.__setattr__, which
# dataclasses use to construct, is unaffected)
Suspension.__setattr__ = _refuse_assignment
Suspension.__delattr__ = _refuse_assignment
