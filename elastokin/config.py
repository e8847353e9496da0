"""Suspension configuration: YAML file -> validated, resolved :class:`Suspension`.

The file format is documented in the README ("Config reference"). Units at this boundary are fixed:
lengths mm, forces N, torques N*mm, angles deg; the file declares them in ``units`` and the frame
in ``frame`` so that a reader never guesses. Everything downstream works on the resolved
:class:`Suspension`: hardpoint names replaced by coordinates (mm, config frame), axes normalised,
bushing frames as rotation matrices (columns x, y, z of the bushing frame in the config frame).
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Annotated, Literal

import numpy as np
import yaml
from pydantic import BaseModel, ConfigDict, Field, ValidationError, field_validator, model_validator

from .errors import ConfigError
from .laws import DirectionLaw, law_from_spec

Vector3 = tuple[float, float, float]
PointSpec = str | Vector3

BUSHING_DIRECTIONS = ("x", "y", "z", "rx", "ry", "rz")


class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)


class AxisBetween(_Strict):
    """An axis given by two points: unit vector from ``from`` to ``to``."""

    from_: PointSpec = Field(alias="from")
    to: PointSpec


AxisSpec = Vector3 | AxisBetween


class Units(_Strict):
    length: Literal["mm"] = "mm"
    force: Literal["N"] = "N"
    angle: Literal["deg"] = "deg"


class Frame(_Strict):
    """Direction of the config frame's axes relative to the vehicle (Z is always up)."""

    x: Literal["forward", "rearward"]
    y: Literal["left", "right"]
    z: Literal["up"] = "up"

    @model_validator(mode="after")
    def _right_handed(self) -> Frame:
        if (self.x == "forward") != (self.y == "left"):
            raise ValueError(
                f"x {self.x} with y {self.y} is a left-handed frame; use x forward/y left "
                "(ISO 8855) or x rearward/y right (ADAMS/Car)"
            )
        return self


class PartSpec(_Strict):
    mass_kg: float | None = Field(default=None, gt=0)
    centre_of_mass: PointSpec | None = None
    description: str = ""


class WheelSpec(_Strict):
    part: str
    centre: PointSpec
    spin_axis: AxisSpec
    loaded_radius_mm: float = Field(gt=0)


class _Joint(_Strict):
    parts: tuple[str, str]
    at: PointSpec
    description: str = ""


class SphericalSpec(_Joint):
    type: Literal["spherical"]


class FixedSpec(_Joint):
    type: Literal["fixed"]


class RevoluteSpec(_Joint):
    type: Literal["revolute"]
    axis: AxisSpec


class CylindricalSpec(_Joint):
    type: Literal["cylindrical"]
    axis: AxisSpec


class TranslationalSpec(_Joint):
    type: Literal["translational"]
    axis: AxisSpec


class UniversalSpec(_Joint):
    """Hooke joint: free to bend about the two axes normal to ``torsion_axis``."""

    type: Literal["universal"]
    torsion_axis: AxisSpec


class RackSpec(_Joint):
    """Steering rack: translational joint along ``axis`` held at ``travel_mm`` (0: locked)."""

    type: Literal["rack"]
    axis: AxisSpec
    travel_mm: float = 0.0


class LinkSpec(_Strict):
    """Massless two-force rod with ball joints at both ends (e.g. a tie rod): fixed length."""

    type: Literal["link"]
    parts: tuple[str, str]
    at: tuple[PointSpec, PointSpec]
    description: str = ""


class CurveSpec(_Strict):
    """A force-deflection curve: deflection (mm or deg) -> force (N) or torque (N*mm)."""

    deflection: list[float] = Field(min_length=2)
    load: list[float] = Field(min_length=2)


DirectionSpec = float | CurveSpec


class BushingStiffness(_Strict):
    """Per direction of the bushing frame: a rate (N/mm, N*mm/deg) or a curve."""

    x: DirectionSpec
    y: DirectionSpec
    z: DirectionSpec
    rx: DirectionSpec
    ry: DirectionSpec
    rz: DirectionSpec


class Preload(_Strict):
    force_N: Vector3 = (0.0, 0.0, 0.0)
    torque_Nmm: Vector3 = (0.0, 0.0, 0.0)


class InitialDeflection(_Strict):
    translation_mm: Vector3 = (0.0, 0.0, 0.0)
    rotation_deg: Vector3 = (0.0, 0.0, 0.0)


IdealJoint = Literal["spherical", "revolute", "universal", "cylindrical", "fixed"]


class BushingSpec(_Joint):
    """A 6-DOF rubber bushing. Frame fixed to ``parts[0]``; deflection is ``parts[1]`` relative."""

    type: Literal["bushing"]
    axis: AxisSpec | None = None
    radial: AxisSpec | None = None
    euler_zxz_deg: Vector3 | None = None
    stiffness: BushingStiffness
    preload: Preload | None = None
    initial_deflection: InitialDeflection | None = None
    ideal_joint: IdealJoint = "spherical"

    @model_validator(mode="after")
    def _one_orientation(self) -> BushingSpec:
        if self.euler_zxz_deg is None and (self.axis is None or self.radial is None):
            raise ValueError("give either euler_zxz_deg or both axis (z) and radial (x)")
        if self.euler_zxz_deg is not None and (self.axis is not None or self.radial is not None):
            raise ValueError("give euler_zxz_deg or axis/radial, not both")
        if self.preload is not None and self.initial_deflection is not None:
            raise ValueError("give preload or initial_deflection, not both")
        return self


ConnectionSpec = Annotated[
    SphericalSpec | FixedSpec | RevoluteSpec | CylindricalSpec | TranslationalSpec
    | UniversalSpec | RackSpec | LinkSpec | BushingSpec,
    Field(discriminator="type"),
]


class SpringSpec(_Strict):
    """Coil spring between two seats; force along the seat-to-seat line."""

    parts: tuple[str, str]
    seats: tuple[PointSpec, PointSpec]
    rate_N_per_mm: float = Field(gt=0)
    free_length_mm: float | None = Field(default=None, gt=0)
    preload_N: float | None = None
    description: str = ""

    @model_validator(mode="after")
    def _length_or_preload(self) -> SpringSpec:
        if self.free_length_mm is not None and self.preload_N is not None:
            raise ValueError("give free_length_mm or preload_N, not both")
        return self


class DesignSpec(_Strict):
    """The design position: the hardpoints are the static equilibrium under this wheel load."""

    wheel_load_N: float = Field(gt=0)
    balance_spring: str | None = None
    balance_bushing_preloads: bool = False


class SolverSpec(_Strict):
    newton_tolerance: float = Field(default=1e-8, gt=0)  # relative to initial residual
    max_newton_iterations: int = Field(default=25, gt=0)
    modified_newton: bool = True
    adaptive_step: bool = True


class TravelSpec(_Strict):
    rebound_mm: float = -90.0
    bump_mm: float = 90.0
    step_mm: float = Field(default=1.0, gt=0)
    unloading: bool = True  # return from bump to rebound after the loading stroke

    @model_validator(mode="after")
    def _ordered(self) -> TravelSpec:
        if not self.rebound_mm < 0 < self.bump_mm:
            raise ValueError("need rebound_mm < 0 < bump_mm (travel about the design position)")
        return self


class VerticalForceSpec(_Strict):
    """Vertical force at the contact patch swept from the design wheel load down to ``min_N``,
    up to ``max_N`` and back to ``min_N`` (force control, N)."""

    min_N: float = Field(default=1000.0, gt=0)
    max_N: float = Field(default=7500.0, gt=0)
    step_N: float = Field(default=50.0, gt=0)

    @model_validator(mode="after")
    def _ordered(self) -> VerticalForceSpec:
        if not self.min_N < self.max_N:
            raise ValueError("need min_N < max_N")
        return self


class ForceSweepSpec(_Strict):
    """A force swept 0 -> +amplitude -> -amplitude -> 0 at the design wheel load (N)."""

    amplitude_N: float = Field(default=2000.0, gt=0)
    step_N: float = Field(default=50.0, gt=0)


class TorqueSweepSpec(_Strict):
    """A torque swept 0 -> +amplitude -> -amplitude -> 0 at the design wheel load (N*mm)."""

    amplitude_Nmm: float = Field(default=1.0e5, gt=0)
    step_Nmm: float = Field(default=2500.0, gt=0)


class RigSpec(_Strict):
    """The load cases of the virtual K&C rig (defaults: the reference paper's; ``null``
    leaves a case out). Signs: ISO 8855 vehicle axes, forces on the tyre (see README)."""

    parallel_travel: TravelSpec = TravelSpec()
    vertical_force: VerticalForceSpec | None = VerticalForceSpec()
    lateral_force: ForceSweepSpec | None = ForceSweepSpec()
    longitudinal_force_patch: ForceSweepSpec | None = ForceSweepSpec()
    longitudinal_force_centre: ForceSweepSpec | None = ForceSweepSpec()
    aligning_torque: TorqueSweepSpec | None = TorqueSweepSpec()


class BushingReference(_Strict):
    radial_mm: float | None = None
    axial_mm: float | None = None
    torsion_deg: float | None = None


class ReferenceSpec(_Strict):
    """Published or measured figures printed beside the model's own (not used in solving)."""

    source: str = ""
    static_bushings: dict[str, BushingReference] = {}
    steer_amplitude_deg: dict[str, float] = {}


class ClearanceSpec(_Strict):
    """Diameters of a bolted joint (mm) giving the clearance bound dL_max [1]: the hole in the
    part (phi_out), the bolt (phi_bolt) and the inner sleeve's or flange's bore (phi_in)."""

    hole_mm: float = Field(gt=0)
    bolt_mm: float = Field(gt=0)
    inner_bore_mm: float = Field(gt=0)

    @model_validator(mode="after")
    def _bolt_fits(self) -> ClearanceSpec:
        if self.bolt_mm > min(self.hole_mm, self.inner_bore_mm):
            raise ValueError(f"a {self.bolt_mm:g} mm bolt does not fit a {self.hole_mm:g} mm "
                             f"hole and a {self.inner_bore_mm:g} mm bore")
        return self

    @property
    def max_shift_mm(self) -> float:
        """dL_max = phi_out/2 - phi_bolt + phi_in/2 [1]."""
        return self.hole_mm / 2.0 - self.bolt_mm + self.inner_bore_mm / 2.0


class JointMeasurementSpec(_Strict):
    """How a joint is measured. Bushings: ``inner`` names the part holding the inner sleeve
    (bolted: only its housing centre and axis are measured) - the other part holds the outer
    sleeve, whose centre and axes are measured exactly. Other joints: ``bolted`` names the
    part whose attachment has assembly clearance (its centre is a housing centre)."""

    inner: str | None = None
    bolted: str | None = None
    clearance: ClearanceSpec | None = None

    @model_validator(mode="after")
    def _one_side(self) -> JointMeasurementSpec:
        if self.inner is not None and self.bolted is not None:
            raise ValueError("give 'inner' (bushings) or 'bolted' (other joints), not both")
        return self


class PartMeasurementSpec(_Strict):
    """One part measured alone, in its own frame (the ground part: in the config frame).

    ``labels`` maps a hardpoint name to the label used in the file when they differ (IGES
    labels have at most 8 characters)."""

    file: str
    marks: tuple[str, str, str, str] = ("M1", "M2", "M3", "M4")
    labels: dict[str, str] = {}


class AssemblyMeasurementSpec(_Strict):
    """The marks measured on the assembled, loaded suspension; ``marks`` maps each part to a
    label pattern (``fnmatch`` syntax, e.g. ``"FA*"``) selecting its marks in the file."""

    file: str
    marks: dict[str, str]


class SyntheticSpec(_Strict):
    """Parameters of the virtual CMM (``elastokin synthesize``)."""

    seed: int = 0
    noise_mm: float = Field(default=0.1, ge=0)  # 95 % of points within this of the truth
    gross_error_mm: tuple[float, float] = (5.0, 15.0)  # one bad assembled mark, length range


class MeasurementsSpec(_Strict):
    """CMM data for geometric identification (see docs/measurements.md)."""

    folder: str = "."  # relative to the config file
    eps_mm: float = Field(default=0.4, gt=0)
    parts: dict[str, PartMeasurementSpec]
    assembly: AssemblyMeasurementSpec
    joints: dict[str, JointMeasurementSpec] = {}
    truth: str | None = None  # synthetic data only: the as-built truth written by synthesize
    synthetic: SyntheticSpec | None = None


class RealBushingSpec(_Strict):
    """A bushing of the synthetic real suspension: its law per direction is
    ``F = scale * k * v * (1 + (v / progression)^2)`` with k the config's rate at zero
    (Table 1) and v the deflection (mm or deg); its design load is the as-built one."""

    translation_scale: float = Field(default=1.0, gt=0)
    rotation_scale: float = Field(default=1.0, gt=0)
    progression_mm: float | None = Field(default=None, gt=0)  # None: linear
    progression_deg: float | None = Field(default=None, gt=0)


class KCTestNoiseSpec(_Strict):
    """Rig noise of the synthetic test data: Gaussian, standard deviation per quantity."""

    angle_deg: float = Field(default=0.0, ge=0)
    length_mm: float = Field(default=0.0, ge=0)


class RealSuspensionSpec(_Strict):
    """How ``elastokin synthesize`` makes the SYNTHETIC K&C test data: the as-built
    suspension of the measurements (same seed) plus physics the models do not have."""

    seed: int | None = None  # None: measurements.synthetic.seed
    bushings: dict[str, RealBushingSpec] = {}
    ball_joint_friction_Nmm: dict[str, float] = {}  # breakaway torque per spherical joint
    presliding_deg: float = Field(default=0.05, gt=0)  # stick rotation before the joint slips
    substeps: int = Field(default=4, ge=1)  # solver steps per recorded rig step (friction)
    noise: KCTestNoiseSpec = KCTestNoiseSpec()


StiffnessParameterName = Literal["translation_scale", "rotation_scale", "translation_cubic",
                                 "rotation_cubic"]


class StiffnessIdentificationSpec(_Strict):
    """Bushing-stiffness identification against the K&C test data (elastokin.stiffness).

    Each fitted bushing's law per direction becomes ``scale * f(u) * (1 + cubic * u^2)``
    (f the config's law; translations x y z share one scale and one cubic, rotations
    another); ``parameters`` picks which of the four are fitted for every bushing in
    ``bushings`` (default: all bushings)."""

    enabled: bool = True
    bushings: list[str] | None = None
    parameters: list[StiffnessParameterName] = ["translation_scale", "rotation_scale",
                                                "translation_cubic"]
    # residual weights: "range": each test curve divided by its range (every chart counts
    # alike), "uncertainty": by the rig's uncertainty, "residual": by the curve's own residual
    # RMS at the previous pass (iteratively reweighted, starting from "range"; at most
    # ``reweighting_passes`` fits); never finer than the uncertainty
    weighting: Literal["range", "uncertainty", "residual"] = "range"
    reweighting_passes: int = Field(default=10, ge=2, le=50)
    residual_scale_deg: float = Field(default=0.01, gt=0)
    residual_scale_mm: float = Field(default=0.1, gt=0)
    # determined: 95 % confidence half-width of the stiffness effect <= this fraction
    determined_within: float = Field(default=0.10, gt=0, lt=1)

    @field_validator("parameters")
    @classmethod
    def _distinct(cls, v: list[str]) -> list[str]:
        if not v:
            raise ValueError("name at least one parameter")
        if len(set(v)) != len(v):
            raise ValueError("parameters must not repeat")
        return v


class KCTestSpec(_Strict):
    """K&C rig test data compared with every model (docs/kc_test_data.md)."""

    folder: str = "."  # relative to the config file
    files: dict[str, str] = {}  # load case -> file; default <load case>.csv when it exists
    synthetic: RealSuspensionSpec | None = None
    stiffness_identification: StiffnessIdentificationSpec = StiffnessIdentificationSpec()


class SuspensionFile(_Strict):
    """Top-level schema of a suspension config file."""

    elastokin: Literal[1]
    name: str
    units: Units
    frame: Frame
    side: Literal["left", "right"]
    ground: str
    hardpoints: dict[str, Vector3]
    parts: dict[str, PartSpec]
    wheel: WheelSpec
    connections: dict[str, ConnectionSpec]
    springs: dict[str, SpringSpec] = {}
    design: DesignSpec
    kinematic: bool = False
    solver: SolverSpec = SolverSpec()
    rig: RigSpec = RigSpec()
    reference: ReferenceSpec = ReferenceSpec()
    measurements: MeasurementsSpec | None = None
    kc_test: KCTestSpec | None = None

    @field_validator("parts")
    @classmethod
    def _some_parts(cls, v: dict) -> dict:
        if not v:
            raise ValueError("at least one moving part is needed")
        return v


# ----------------------------------------------------------------------------------------------
# Resolved model description (plain numbers, no names left to look up)


@dataclass(frozen=True)
class Joint:
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


@dataclass(frozen=True)
class Link:
    name: str
    parts: tuple[str, str]
    points_mm: tuple[np.ndarray, np.ndarray]


@dataclass(frozen=True)
class Bushing:
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


@dataclass(frozen=True)
class Spring:
    name: str
    parts: tuple[str, str]
    seats_mm: tuple[np.ndarray, np.ndarray]
    rate_N_per_mm: float
    preload_N: float | None
    free_length_mm: float | None

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
class Wheel:
    part: str
    centre_mm: np.ndarray
    spin_axis: np.ndarray  # unit, pointing outboard
    loaded_radius_mm: float

    @property
    def contact_patch_mm(self) -> np.ndarray:
        """Contact patch at design: below the centre in the wheel plane (config frame)."""
        down = np.array([0.0, 0.0, -1.0])
        radial = down - (down @ self.spin_axis) * self.spin_axis
        return self.centre_mm + self.loaded_radius_mm * radial / np.linalg.norm(radial)


@dataclass(frozen=True)
class Suspension:
    """A resolved suspension: everything in mm, N, deg, config frame."""

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


# ----------------------------------------------------------------------------------------------
# Loading


def _format_validation_error(path: str, err: ValidationError) -> str:
    first = err.errors()[0]
    loc = ".".join(str(p) for p in first["loc"] if not str(p).startswith("function-"))
    msg = first["msg"]
    extra = f" ({len(err.errors()) - 1} more problems)" if len(err.errors()) > 1 else ""
    return f"{path}: key '{loc}': {msg}{extra}"


def read_yaml(path: str | Path, what: str = "config file") -> tuple[dict, bytes]:
    """Read a YAML mapping; errors name the file (``what`` it is) and line."""
    p = Path(path)
    try:
        text = p.read_bytes()
    except OSError as exc:
        raise ConfigError(f"{p}: cannot read {what} ({exc.strerror})") from None
    try:
        data = yaml.safe_load(text)
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f" line {mark.line + 1}, column {mark.column + 1}" if mark else ""
        problem = getattr(exc, "problem", None) or str(exc)
        raise ConfigError(f"{p}:{where}: malformed YAML: {problem}") from None
    if not isinstance(data, dict):
        raise ConfigError(f"{p}: expected a YAML mapping of keys at the top level of the {what}")
    return data, text


def load_suspension(path: str | Path, overrides: dict | None = None) -> Suspension:
    """Load, validate and resolve a suspension config file.

    ``overrides`` (optional) is merged over the top-level keys before validation (e.g.
    ``{"kinematic": True}``); the hash still identifies the file's bytes plus the overrides.
    """
    data, text = read_yaml(path)
    if overrides:
        data = {**data, **overrides}
    digest = hashlib.sha256(text)
    if overrides:
        digest.update(yaml.safe_dump(overrides, sort_keys=True).encode())
    return suspension_from_dict(data, str(path), digest.hexdigest())


def load_rig(path: str | Path) -> dict:
    """Read and validate a rig file: the load cases of :class:`RigSpec` as a YAML mapping,
    either at the top level or under one ``rig:`` key. Errors name the rig file and key."""
    data, _ = read_yaml(path, "rig file")
    if set(data) == {"rig"}:
        data = data["rig"]
        if not isinstance(data, dict):
            raise ConfigError(f"{path}: key 'rig': expected a mapping of load cases")
    try:
        RigSpec.model_validate(data)
    except ValidationError as err:
        raise ConfigError(_format_validation_error(f"{path} (rig file)", err)) from None
    return data


def load_suspension_with_rig(config_path: str | Path, rig_path: str | Path | None,
                             overrides: dict | None = None) -> Suspension:
    """:func:`load_suspension` with the config's ``rig`` section replaced by a rig file
    (:func:`load_rig`) when ``rig_path`` is given; the config hash then covers the rig too."""
    if rig_path is None:
        return load_suspension(config_path, overrides)
    rig = load_rig(rig_path)
    s = load_suspension(config_path, {**(overrides or {}), "rig": rig})
    return replace(s, rig_source=str(rig_path))


def suspension_from_dict(data: dict, source: str = "<dict>", sha256: str = "") -> Suspension:
    """Validate a config mapping and resolve names, axes and laws (see module docstring)."""
    try:
        spec = SuspensionFile.model_validate(data)
    except ValidationError as err:
        raise ConfigError(_format_validation_error(source, err)) from None
    if not sha256:
        sha256 = hashlib.sha256(yaml.safe_dump(data, sort_keys=True).encode()).hexdigest()
    return _Resolver(spec, source).resolve(sha256, data)


class _Resolver:
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
        x = x - (x @ z) * z
        n = np.linalg.norm(x)
        if n < 1e-6:
            raise self.fail(key + ".radial", "radial direction is parallel to the axis")
        x /= n
        return np.column_stack([x, np.cross(z, x), z])

    def resolve(self, sha256: str, raw: dict) -> Suspension:
        s = self.spec
        for name in s.parts:
            if name == s.ground:
                raise self.fail(f"parts.{name}", "the ground part must not be listed under parts")
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
        springs = []
        for name, sp in s.springs.items():
            key = f"springs.{name}"
            parts = self.parts(sp.parts, key)
            seats = (self.point(sp.seats[0], key + ".seats"),
                     self.point(sp.seats[1], key + ".seats"))
            if np.linalg.norm(seats[1] - seats[0]) < 1e-6:
                raise self.fail(key + ".seats", "the two spring seats coincide")
            springs.append(
                Spring(name, parts, seats, sp.rate_N_per_mm, sp.preload_N, sp.free_length_mm)
            )
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
        w = s.wheel
        wheel_part = self.part(w.part, "wheel.part")
        if wheel_part == s.ground:
            raise self.fail("wheel.part", "the wheel cannot be carried by the ground part")
        centre = self.point(w.centre, "wheel.centre")
        spin = self.axis(w.spin_axis, "wheel.spin_axis")
        res = Suspension(
            name=s.name, source=self.source, sha256=sha256, frame=s.frame, side=s.side,
            ground=s.ground, parts=dict(s.parts), hardpoints=self.hardpoints,
            wheel=Wheel(wheel_part, centre, spin, w.loaded_radius_mm),
            joints=tuple(joints), links=tuple(links), bushings=tuple(bushings),
            springs=tuple(springs), design=d, kinematic=s.kinematic, solver=s.solver, rig=s.rig,
            reference=s.reference, raw=raw, measurements=s.measurements,
            kc_test=s.kc_test,
        )
        # orient the spin axis outboard, whatever sign the file used
        if spin @ res.outboard < 0:
            object.__setattr__(res.wheel, "spin_axis", -spin)
        return res

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
                       c.preload is not None or c.initial_deflection is not None)


#: constrained axes (tx ty tz rx ry rz) in the joint frame, whose z is the joint axis
CONSTRAINED = {
    "spherical": (1, 1, 1, 0, 0, 0),
    "fixed": (1, 1, 1, 1, 1, 1),
    "revolute": (1, 1, 1, 1, 1, 0),
    "cylindrical": (1, 1, 0, 1, 1, 0),
    "translational": (1, 1, 0, 1, 1, 1),
    "rack": (1, 1, 1, 1, 1, 1),
    "universal": (1, 1, 1, 0, 0, 1),
}
