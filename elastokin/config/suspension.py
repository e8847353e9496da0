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

from dataclasses import FrozenInstanceError, dataclass, field, fields

import numpy as np

from elastokin.config.bounds import MIN_AXIS_ANGLE_DEG
from elastokin.config.frozen import FrozenMapping, freeze, readonly
from elastokin.config.schema import (
    AxisBetween,
    AxisSpec,
    BushingSpec,
    DesignSpec,
    Frame,
    KCTestSpec,
    LinkSpec,
    MeasurementsSpec,
    PartSpec,
    PointSpec,
    RackSpec,
    ReferenceSpec,
    RigSpec,
    SolverSpec,
    SuspensionFile,
)
from elastokin.errors import ConfigError
from elastokin.physics.joints import BUSHING_DIRECTIONS, CONSTRAINED
from elastokin.physics.laws import DirectionLaw, law_from_spec

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
class Wheel(ReadOnlyArrays):
    part: str
    centre_mm: np.ndarray
    spin_axis: np.ndarray  # unit, pointing outboard
    loaded_radius_mm: float
    array_fields = ("centre_mm", "spin_axis")

    @property
    def contact_patch_mm(self) -> np.ndarray:
        """Contact patch at design: below the centre in the wheel plane (config frame)."""
        down = np.array([0.0, 0.0, -1.0])
        radial = down - (down @ self.spin_axis) * self.spin_axis
        return self.centre_mm + self.loaded_radius_mm * radial / np.linalg.norm(radial)


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
    kc_test: KCTestSpec | None = None
    rig_source: str = ""  # a rig file given apart from the config ("": the config's rig)
    label: str = "initial"  # the model's label in results (the config's ``label``)
    config_sha256: str = ""  # "": the same as sha256
    rig_sha256: str | None = None

    def __post_init__(self) -> None:
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
    def forward(self) -> np.ndarray:
        """Unit vector pointing forward (vehicle), in the config frame."""
        return np.array([1.0 if self.frame.x == "forward" else -1.0, 0.0, 0.0])

    @property
    def outboard(self) -> np.ndarray:
        """Unit vector pointing away from the vehicle centreline on this wheel's side."""
        left = np.array([0.0, 1.0 if self.frame.y == "left" else -1.0, 0.0])
        return left if self.side == "left" else -left

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



class Resolver:
    """Resolves a validated config file into a :class:`Suspension` (errors name the key)."""

    def __init__(self, spec: SuspensionFile, source: str):
        self.spec = spec
        self.source = source
        self.hardpoints = {k: np.asarray(v, float) for k, v in spec.hardpoints.items()}

    def fail(self, key: str, msg: str) -> ConfigError:
        return ConfigError(f"{self.source}: key '{key}': {msg}")

    def point(self, p: PointSpec, key: str) -> np.ndarray:
        if isinstance(p, str):
            if p not in self.hardpoints:
                raise self.fail(key, f"hardpoint '{p}' is not defined under 'hardpoints'")
            return self.hardpoints[p].copy()
        return np.asarray(p, float)

    def axis(self, a: AxisSpec, key: str) -> np.ndarray:
        if isinstance(a, AxisBetween):
            v = self.point(a.to, key + ".to") - self.point(a.from_, key + ".from")
            n = np.linalg.norm(v)
            if n < 1e-9:
                raise self.fail(key, "'from' and 'to' are the same point: the axis is undefined")
            return v / n
        v = np.asarray(a, float)
        n = np.linalg.norm(v)
        if n < 1e-9:
            raise self.fail(key, "axis vector is zero; give a unit vector")
        if abs(n - 1.0) > 1e-3:
            raise self.fail(key, f"axis vector {list(v)} has length {n:.4g}; give a unit vector")
        return v / n

    def part(self, name: str, key: str) -> str:
        if name != self.spec.ground and name not in self.spec.parts:
            raise self.fail(
                key, f"part '{name}' is not defined (parts: {', '.join(self.spec.parts)}; "
                f"ground: {self.spec.ground})"
            )
        return name

    def parts(self, names: tuple[str, str], key: str) -> tuple[str, str]:
        a, b = (self.part(n, f"{key}.parts") for n in names)
        if a == b:
            raise self.fail(f"{key}.parts", f"connects part '{a}' to itself")
        return a, b

    def frame_from_z(self, z: np.ndarray) -> np.ndarray:
        """A right-handed frame whose z column is ``z`` (x chosen normal to it)."""
        helper = np.array([1.0, 0, 0]) if abs(z[0]) < 0.9 else np.array([0, 1.0, 0])
        x = helper - (helper @ z) * z
        x /= np.linalg.norm(x)
        return np.column_stack([x, np.cross(z, x), z])

    def bushing_frame(self, c: BushingSpec, key: str) -> np.ndarray:
        if c.euler_zxz_deg is not None:
            from scipy.spatial.transform import Rotation

            return Rotation.from_euler("ZXZ", c.euler_zxz_deg, degrees=True).as_matrix()
        z = self.axis(c.axis, key + ".axis")
        x = self.axis(c.radial, key + ".radial")
        angle = np.degrees(np.arccos(min(1.0, abs(float(x @ z)))))
        if angle < MIN_AXIS_ANGLE_DEG:
            raise self.fail(key + ".radial", f"radial direction is parallel to the axis "
                            f"({angle:.2g} deg apart; at least {MIN_AXIS_ANGLE_DEG:g} deg)")
        x = x - (x @ z) * z
        x /= np.linalg.norm(x)
        return np.column_stack([x, np.cross(z, x), z])

    def check_names(self) -> None:
        """The names of the ground, parts, connections and springs are distinct."""
        s = self.spec
        seen = {s.ground: "ground"}
        for section in ("parts", "connections", "springs"):
            for name in getattr(s, section):
                key = f"{section}.{name}"
                if seen.get(name) == "ground" and section == "parts":
                    raise self.fail(key, "the ground part must not be listed under parts "
                                    "(key 'ground')")
                if name in seen:
                    raise self.fail(key, f"the name '{name}' is taken by key '{seen[name]}'; "
                                    "parts, the ground, connections and springs need distinct "
                                    "names")
                seen[name] = key

    def spin_axis(self) -> np.ndarray:
        """The wheel's unit spin axis, refused within MIN_AXIS_ANGLE_DEG of vertical."""
        spin = self.axis(self.spec.wheel.spin_axis, "wheel.spin_axis")
        tilt = np.degrees(np.arcsin(min(1.0, float(np.hypot(spin[0], spin[1])))))
        if tilt < MIN_AXIS_ANGLE_DEG:
            raise self.fail("wheel.spin_axis", f"{tilt:.2g} deg from vertical: a wheel spin "
                            f"axis must be at least {MIN_AXIS_ANGLE_DEG:g} deg from vertical "
                            "(toe and camber are undefined)")
        return spin

    def resolve(self, sha256: str, raw: dict, config_sha256: str = "",
                rig_sha256: str | None = None) -> Suspension:
        """The resolved suspension; ``sha256`` identifies all its inputs, ``config_sha256``
        the config alone ("": the same), ``rig_sha256`` a rig file (see :class:`Suspension`).
        """
        s = self.spec
        self.check_names()
        self.check_label()
        for name, p in s.parts.items():
            if p.centre_of_mass is not None:
                self.point(p.centre_of_mass, f"parts.{name}.centre_of_mass")
        joints, links, bushings = [], [], []
        for name, c in s.connections.items():
            key = f"connections.{name}"
            parts = self.parts(c.parts, key)
            if isinstance(c, LinkSpec):
                pts = (self.point(c.at[0], key + ".at"), self.point(c.at[1], key + ".at"))
                if np.linalg.norm(pts[1] - pts[0]) < 1e-6:
                    raise self.fail(key + ".at", "a link needs two distinct points")
                links.append(Link(name, parts, pts))
                continue
            pos = self.point(c.at, key + ".at")
            if isinstance(c, BushingSpec):
                bushings.append(self.bushing(name, c, parts, pos, key))
                continue
            kind = c.type
            if kind in ("spherical", "fixed"):
                frame = np.eye(3)
            elif kind == "universal":
                frame = self.frame_from_z(self.axis(c.torsion_axis, key + ".torsion_axis"))
            else:
                frame = self.frame_from_z(self.axis(c.axis, key + ".axis"))
            offset = c.travel_mm if isinstance(c, RackSpec) else 0.0
            if offset and (s.design.balance_spring or s.design.balance_bushing_preloads):
                raise self.fail(key + ".travel_mm", "must be 0 when 'design' balances the "
                                "hardpoints (they are the equilibrium with the rack centred)")
            joints.append(Joint(name, kind, parts, pos, frame, CONSTRAINED[kind], offset))
        springs = self.springs()
        self.check_design(bushings)
        w = s.wheel
        wheel_part = self.part(w.part, "wheel.part")
        if wheel_part == s.ground:
            raise self.fail("wheel.part", "the wheel cannot be carried by the ground part")
        centre = self.point(w.centre, "wheel.centre")
        spin = self.spin_axis()
        # orient the spin axis outboard, whatever sign the file used
        left = 1.0 if s.frame.y == "left" else -1.0
        outboard_y = left if s.side == "left" else -left
        if spin[1] * outboard_y < 0:
            spin = -spin
        return Suspension(
            name=s.name, source=self.source, sha256=sha256, frame=s.frame, side=s.side,
            ground=s.ground, parts=dict(s.parts), hardpoints=self.hardpoints,
            wheel=Wheel(wheel_part, centre, spin, w.loaded_radius_mm),
            joints=tuple(joints), links=tuple(links), bushings=tuple(bushings),
            springs=tuple(springs), design=s.design, kinematic=s.kinematic, solver=s.solver,
            rig=s.rig, reference=s.reference, raw=raw, measurements=s.measurements,
            kc_test=s.kc_test, label=s.label, config_sha256=config_sha256,
            rig_sha256=rig_sha256,
        )

    def springs(self) -> list[Spring]:
        springs = []
        for name, sp in self.spec.springs.items():
            key = f"springs.{name}"
            parts = self.parts(sp.parts, key)
            seats = (self.point(sp.seats[0], key + ".seats"),
                     self.point(sp.seats[1], key + ".seats"))
            if np.linalg.norm(seats[1] - seats[0]) < 1e-6:
                raise self.fail(key + ".seats", "the two spring seats coincide")
            springs.append(
                Spring(name, parts, seats, sp.rate_N_per_mm, sp.preload_N, sp.free_length_mm)
            )
        return springs

    def check_label(self) -> None:
        """The model's ``label`` is not that of another model of a K&C run."""
        s = self.spec
        if s.label == "test" or s.label.endswith("_kinematic"):
            raise self.fail("label", f"'{s.label}' is the label of another model of a run "
                            "(test, <label>_kinematic)")
        if s.label == "identified_stiffness" and s.kc_test is not None and \
                s.kc_test.stiffness_identification.enabled:
            raise self.fail("label", "'identified_stiffness' is the stiffness fit's model: set "
                            "kc_test.stiffness_identification.enabled: false in its config")

    def check_design(self, bushings: list[Bushing]) -> None:
        """The ``design`` section agrees with the springs' and bushings' own preloads."""
        s = self.spec
        d = s.design
        if d.balance_spring is not None:
            if d.balance_spring not in s.springs:
                raise self.fail("design.balance_spring", f"spring '{d.balance_spring}' is not "
                                f"defined under 'springs' ({', '.join(s.springs) or 'none'})")
            sp = s.springs[d.balance_spring]
            if sp.free_length_mm is not None or sp.preload_N is not None:
                raise self.fail(f"springs.{d.balance_spring}", "its preload is solved from "
                                "design.wheel_load_N: remove free_length_mm / preload_N")
        for sp_name, sp in s.springs.items():
            if sp_name != d.balance_spring and sp.free_length_mm is None and sp.preload_N is None:
                raise self.fail(f"springs.{sp_name}", "give free_length_mm or preload_N, or "
                                "name it in design.balance_spring")
        if d.balance_bushing_preloads:
            for b in bushings:
                if b.preload_given:
                    raise self.fail(f"connections.{b.name}", "preload / initial_deflection "
                                    "conflicts with design.balance_bushing_preloads: true")

    def bushing(self, name: str, c: BushingSpec, parts, pos, key: str) -> Bushing:
        frame = self.bushing_frame(c, key)
        laws = []
        for d in BUSHING_DIRECTIONS:
            try:
                laws.append(law_from_spec(getattr(c.stiffness, d)))
            except ValueError as exc:
                raise self.fail(f"{key}.stiffness.{d}", str(exc)) from None
        laws = tuple(laws)
        if c.initial_deflection is not None:
            u0 = np.r_[c.initial_deflection.translation_mm, c.initial_deflection.rotation_deg]
        elif c.preload is not None:
            loads = np.r_[c.preload.force_N, c.preload.torque_Nmm]
            try:
                u0 = np.array([law.deflection_at(f) for law, f in zip(laws, loads)])
            except ValueError as exc:
                raise self.fail(f"{key}.preload", str(exc)) from None
        else:
            u0 = np.zeros(6)
        return Bushing(name, parts, pos, frame, laws, u0, c.ideal_joint,
                       c.preload is not None or c.initial_deflection is not None,
                       kinematic=c.kinematic or self.spec.kinematic)


#: constrained axes (tx ty tz rx ry rz) in the joint frame, whose z is the joint axis
