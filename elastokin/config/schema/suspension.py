"""The config file's schema (pydantic): what a suspension YAML file may say, validated.

Units at this boundary are fixed: lengths mm, forces N, torques N*mm, angles deg; the file
declares them in ``units`` and the frame in ``frame`` so that a reader never guesses. The
format is documented in the README ("Config reference"). :mod:`elastokin.config.suspension`
resolves a validated file into the plain :class:`~elastokin.config.suspension.Suspension`.
"""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import Field, field_validator, model_validator

from elastokin.config import bounds
from elastokin.config.plausibility import plausible
from elastokin.config.schema.axle import AxleSpec, StopSpec
from elastokin.config.schema.base import (
    AxisSpec,
    CurveSpec,
    Point3,
    PointSpec,
    StrictModel,
    Vector3,
)
from elastokin.config.schema.beam import BeamSpec
from elastokin.config.schema.motion import MotionSpec
from elastokin.config.schema.rig import RigSpec


class Units(StrictModel):
    length: Literal["mm"] = "mm"
    force: Literal["N"] = "N"
    angle: Literal["deg"] = "deg"


class Frame(StrictModel):
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


class PartSpec(StrictModel):
    mass_kg: float | None = Field(default=None, gt=0)
    centre_of_mass: PointSpec | None = None
    description: str = ""
    beam: BeamSpec | None = None  # a flexible part made of beam elements (rigid without)


class WheelSpec(StrictModel):
    part: str
    centre: PointSpec
    spin_axis: AxisSpec
    loaded_radius_mm: float = Field(gt=0)
    tyre_rate_N_per_mm: float | None = Field(default=None, gt=0)  # ride rate (in series)

    _plausible = field_validator("loaded_radius_mm", "tyre_rate_N_per_mm")(plausible)


class _Joint(StrictModel):
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


class PlanarSpec(_Joint):
    """Planar joint: part 2 slides in and turns about the normal of a plane of part 1 through
    ``at`` normal to ``axis`` (a guide that leaves heave and roll free)."""

    type: Literal["planar"]
    axis: AxisSpec


class InplaneSpec(_Joint):
    """Point-in-plane joint: the point ``at`` of part 2 stays in the plane of part 1 normal to
    ``axis`` (one constraint)."""

    type: Literal["inplane"]
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


class LinkSpec(StrictModel):
    """Massless two-force rod with ball joints at both ends (e.g. a tie rod): fixed length."""

    type: Literal["link"]
    parts: tuple[str, str]
    at: tuple[PointSpec, PointSpec]
    description: str = ""


DirectionSpec = float | CurveSpec


class BushingStiffness(StrictModel):
    """Per direction of the bushing frame: a rate (N/mm, N*mm/deg) or a curve."""

    x: DirectionSpec
    y: DirectionSpec
    z: DirectionSpec
    rx: DirectionSpec
    ry: DirectionSpec
    rz: DirectionSpec


class Preload(StrictModel):
    force_N: Vector3 = (0.0, 0.0, 0.0)
    torque_Nmm: Vector3 = (0.0, 0.0, 0.0)


class InitialDeflection(StrictModel):
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
    kinematic: bool = False  # modelled by its ideal joint (as the file's ``kinematic: true``)

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
    | PlanarSpec | InplaneSpec | UniversalSpec | RackSpec | LinkSpec | BushingSpec,
    Field(discriminator="type"),
]


class SpringSpec(StrictModel):
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


class DamperSpec(StrictModel):
    """A damper between two points of two parts (along the point-to-point line). The rig is
    quasi-static: a damper carries no force there; its length and its velocity ratio (length
    change per wheel travel) are reported, and it is drawn and exported. ``rate_N_s_per_mm``
    (optional, linear) is the damping ADAMS/Car's damper property file is written with."""

    parts: tuple[str, str]
    points: tuple[PointSpec, PointSpec]
    rate_N_s_per_mm: float | None = Field(default=None, gt=0)
    description: str = ""


class DesignSpec(StrictModel):
    """The design position: the hardpoints are the static equilibrium under this wheel load."""

    wheel_load_N: float = Field(gt=0)
    balance_spring: str | None = None
    balance_bushing_preloads: bool = False


class SolverSpec(StrictModel):
    newton_tolerance: float = Field(default=1e-8, gt=0)  # relative to initial residual
    max_newton_iterations: int = Field(default=25, gt=0)
    modified_newton: bool = True
    adaptive_step: bool = True


class BushingReference(StrictModel):
    radial_mm: float | None = None
    axial_mm: float | None = None
    torsion_deg: float | None = None


class ReferenceSpec(StrictModel):
    """Published or measured figures printed beside the model's own (not used in solving)."""

    source: str = ""
    static_bushings: dict[str, BushingReference] = {}
    steer_amplitude_deg: dict[str, float] = {}


class ClearanceSpec(StrictModel):
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


class JointMeasurementSpec(StrictModel):
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


class PartMeasurementSpec(StrictModel):
    """One part measured alone, in its own frame (the ground part: in the config frame).

    ``labels`` maps a hardpoint name to the label used in the file when they differ (IGES
    labels have at most 8 characters)."""

    file: str
    marks: tuple[str, str, str, str] = ("M1", "M2", "M3", "M4")
    labels: dict[str, str] = {}


class AssemblyMeasurementSpec(StrictModel):
    """The marks measured on the assembled, loaded suspension; ``marks`` maps each part to a
    label pattern (``fnmatch`` syntax, e.g. ``"FA*"``) selecting its marks in the file."""

    file: str
    marks: dict[str, str]


class SyntheticSpec(StrictModel):
    """Parameters of the virtual CMM (``elastokin synthesize``)."""

    seed: int = 0
    noise_mm: float = Field(default=0.1, ge=0)  # 95 % of points within this of the truth
    gross_error_mm: tuple[float, float] = (5.0, 15.0)  # one bad assembled mark, length range


class MeasurementsSpec(StrictModel):
    """CMM data for geometric identification (see docs/measurements.md)."""

    folder: str = "."  # relative to the config file
    eps_mm: float = Field(default=0.4, gt=0)
    parts: dict[str, PartMeasurementSpec]
    assembly: AssemblyMeasurementSpec
    joints: dict[str, JointMeasurementSpec] = {}
    truth: str | None = None  # synthetic data only: the as-built truth written by synthesize
    synthetic: SyntheticSpec | None = None


class RealBushingSpec(StrictModel):
    """A bushing of the synthetic real suspension: its law per direction is
    ``F = scale * k * v * (1 + (v / progression)^2)`` with k the config's rate at zero
    (Table 1) and v the deflection (mm or deg); its design load is the as-built one."""

    translation_scale: float = Field(default=1.0, gt=0)
    rotation_scale: float = Field(default=1.0, gt=0)
    progression_mm: float | None = Field(default=None, gt=0)  # None: linear
    progression_deg: float | None = Field(default=None, gt=0)


class KCTestNoiseSpec(StrictModel):
    """Rig noise of the synthetic test data: Gaussian, standard deviation per quantity."""

    angle_deg: float = Field(default=0.0, ge=0)
    length_mm: float = Field(default=0.0, ge=0)


class RealSuspensionSpec(StrictModel):
    """How ``elastokin synthesize`` makes the SYNTHETIC K&C test data: the as-built
    suspension of the measurements (same seed) plus physics the models do not have."""

    seed: int | None = None  # None: measurements.synthetic.seed
    bushings: dict[str, RealBushingSpec] = {}
    ball_joint_friction_Nmm: dict[str, float] = {}  # breakaway torque per spherical joint
    presliding_deg: float = Field(default=0.05, gt=0)  # stick rotation before the joint slips
    substeps: int = Field(default=4, ge=1, le=bounds.MAX_SUBSTEPS)  # per recorded rig step
    noise: KCTestNoiseSpec = KCTestNoiseSpec()


StiffnessParameterName = Literal["translation_scale", "rotation_scale", "translation_cubic",
                                 "rotation_cubic"]


class StiffnessIdentificationSpec(StrictModel):
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
    # RMS (maximum likelihood with an unknown error level per curve, starting from "range");
    # never finer than the uncertainty
    weighting: Literal["range", "uncertainty", "residual"] = "range"
    # no longer used (the curve scales are estimated in closed form at every iterate of one
    # maximum-likelihood pass); accepted so that older configs load, with a warning
    reweighting_passes: int | None = Field(default=None, ge=2, le=50)
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


class KCTestSpec(StrictModel):
    """K&C rig test data compared with every model (docs/kc_test_data.md)."""

    folder: str = "."  # relative to the config file
    files: dict[str, str] = {}  # load case -> file; default <load case>.csv when it exists
    synthetic: RealSuspensionSpec | None = None
    stiffness_identification: StiffnessIdentificationSpec = StiffnessIdentificationSpec()


class SuspensionFile(StrictModel):
    """Top-level schema of a suspension config file."""
    elastokin: Literal[1]
    name: str
    label: str = Field("initial", pattern=r"^[A-Za-z][A-Za-z0-9_]*$")  # the model's, README
    units: Units
    frame: Frame
    side: Literal["left", "right"]
    ground: str
    hardpoints: dict[str, Point3]
    parts: dict[str, PartSpec]
    wheel: WheelSpec
    connections: dict[str, ConnectionSpec]
    springs: dict[str, SpringSpec] = {}
    dampers: dict[str, DamperSpec] = {}
    stops: dict[str, StopSpec] = {}
    design: DesignSpec
    kinematic: bool = False
    solver: SolverSpec = SolverSpec()
    rig: RigSpec = RigSpec()
    reference: ReferenceSpec = ReferenceSpec()
    measurements: MeasurementsSpec | None = None
    motion: MotionSpec | None = None  # joints from motion (docs/measurements.md)
    kc_test: KCTestSpec | None = None
    axle: AxleSpec | None = None

    @field_validator("parts")
    @classmethod
    def _some_parts(cls, v: dict) -> dict:
        if not v:
            raise ValueError("at least one moving part is needed")
        return v

    @model_validator(mode="after")
    def _bounded_approach(self) -> SuspensionFile:
        v, w = self.rig.vertical_force, self.design.wheel_load_N
        if v is not None:
            bounds.check_steps(bounds.vertical_force_steps(v.min_N, v.max_N, v.step_N, w),
                               "rig.vertical_force.step_N", f"{v.step_N:g} N",
                               f"from design.wheel_load_N {w:g} to min_N {v.min_N:g}, to max_N "
                               f"{v.max_N:g} and back")
        return self

