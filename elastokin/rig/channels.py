"""The one channel table: every quantity a K&C run records or reports, with its unit, sign
convention, axis label, K&C test-file column and ADAMS/Car request name; the load cases with
their input channel; the summary characteristics (gradients over load cases) and the errors
against test data. kc.csv, summary.json, the charts, the report, the K&C test reader and
writer, the ADAMS export, the stiffness fit and the DOE all read these tables.

Units: mm, N, N*mm, deg (the unit is the column name's suffix). Signs: ISO 8855 / SAE J670
names in the config frame for forces and displacements (+ forward, + to the vehicle's left,
+ up), per wheel for the wheel angles (toe-in +, camber top outboard +). K&C test files are
per wheel (lateral + outboard, aligning torque + in the toe-in sense): ``test_sign`` says how a
test channel converts (``lateral``: times +1 on a left wheel, -1 on a right one;
``toe_in_torque``: times -1 on a left wheel, +1 on a right one).
"""

from __future__ import annotations

from dataclasses import dataclass

from elastokin.rig.item_channels import LOAD_FRAMES, LOAD_SIGN, item_channel_fields

#: the quantity of each unit (K&C test files accept other units of the same quantity)
QUANTITY = {"mm": "length", "deg": "angle", "N": "force", "N*mm": "torque", "-": "fraction"}


@dataclass(frozen=True)
class Channel:
    """One recorded quantity: ``name`` is the kc.csv column (unit suffix included)."""

    name: str
    unit: str
    sign: str  # sign convention (summary.json ``sign_conventions``, docs)
    label: str  # axis label of a chart, unit and sign included
    test: str | None = None  # K&C test-file channel (docs/kc_test_data.md)
    test_meaning: str = ""  # the test channel's per-wheel meaning and sign
    test_sign: str = ""  # "", "lateral" or "toe_in_torque" (module docstring)
    adams: str | None = None  # ADAMS-style channel name (export-adams --kc)
    adams_frame: str | None = None  # config-frame component converted to the ADAMS/Car frame
    fitted: bool = False  # compared with the test by the stiffness fit (when not the input)
    per_axle: bool = False  # one value for the axle (the same in both wheels' sweeps)

    @property
    def quantity(self) -> str:
        return QUANTITY.get(self.unit, "")


STATIC = "from the static state (the model's own under the design wheel load)"
CONTACT = "contact point (the wheel's lowest point)"

CHANNEL_LIST = (
    Channel("pad_z_mm", "mm", f"prescribed vertical displacement of the {CONTACT} {STATIC} "
            "(rig input), + up", "pad height [mm] (+ up)", adams="pad_vertical_displacement"),
    Channel("toe_deg", "deg", "toe angle, positive toe-in (ISO 8855 / SAE J670); 'steer' in "
            "the paper", "toe [deg] (+ toe-in)", test="toe", test_meaning="toe angle, toe-in +",
            adams="toe_angle", fitted=True),
    Channel("camber_deg", "deg", "camber angle, positive top of the wheel leaning outboard",
            "camber [deg] (+ top outboard)", test="camber",
            test_meaning="camber angle, top of the wheel outboard +", adams="camber_angle",
            fitted=True),
    Channel("wheel_centre_longitudinal_mm", "mm", f"wheel-centre displacement {STATIC}, "
            "+ forward", "wheel-centre longitudinal displacement [mm] (+ forward)",
            test="wheel_centre_longitudinal", test_meaning="wheel-centre displacement from "
            "the static state, forward +", adams="wheel_travel_base", fitted=True),
    Channel("wheel_centre_lateral_mm", "mm", f"wheel-centre displacement {STATIC}, + left",
            "wheel-centre lateral displacement [mm] (+ left)", test="wheel_centre_lateral",
            test_meaning="wheel-centre displacement from the static state, outboard +",
            test_sign="lateral", adams="wheel_travel_track", fitted=True),
    Channel("wheel_travel_mm", "mm", f"wheel-centre vertical displacement {STATIC}, + bump",
            "wheel travel [mm] (+ bump)", test="wheel_travel", adams="wheel_travel", fitted=True,
            test_meaning="wheel-centre vertical displacement from the static state, bump +"),
    *(Channel(f"wheel_centre_{a}_mm", "mm", "wheel-centre coordinate, config frame",
              f"wheel-centre {a} [mm] (config frame)", adams=f"wheel_center_{a}",
              adams_frame=a) for a in "xyz"),
    Channel("caster_deg", "deg", "steering-axis inclination from the vertical in side view, "
            "+ top rearward (docs/characteristics.md)", "caster [deg] (+ top rearward)",
            test="caster", test_meaning="caster angle, steering axis top rearward +",
            adams="caster_angle"),
    Channel("kingpin_inclination_deg", "deg", "steering-axis inclination from the vertical in "
            "front view, + top inboard", "kingpin inclination [deg] (+ top inboard)",
            test="kingpin_inclination",
            test_meaning="kingpin inclination, steering axis top inboard +",
            adams="kingpin_incl_angle"),
    Channel("scrub_radius_mm", "mm", "ground-plane offset of the steering axis from the "
            f"{CONTACT} normal to the wheel/ground line, + axis inboard",
            "scrub radius [mm] (+ axis inboard)", test="scrub_radius",
            test_meaning="scrub radius, axis meets the ground inboard +", adams="scrub_radius"),
    Channel("caster_trail_mm", "mm", "ground-plane offset of the steering axis from the "
            "contact point along the wheel/ground line, + axis ahead",
            "caster trail [mm] (+ axis ahead)", test="caster_trail",
            test_meaning="caster trail, axis meets the ground ahead +",
            adams="caster_moment_arm"),
    Channel("track_change_mm", "mm", f"lateral displacement of the {CONTACT} {STATIC}, + "
            "outboard (per wheel; the axle's track changes by the sum of both)",
            "track change at the contact patch [mm] (+ outboard)", test="track_change",
            test_meaning="contact-point lateral displacement, outboard +", test_sign="",
            adams="half_track_change"),
    Channel("wheelbase_change_mm", "mm", f"longitudinal displacement of the {CONTACT} "
            f"{STATIC}, + when the wheelbase grows (forward on a front axle, rearward on a rear "
            "one; forward without vehicle data)", "wheelbase change [mm] (+ longer)",
            test="wheelbase_change", test_meaning="wheelbase change, longer +",
            adams="wheelbase_change"),
    Channel("roll_angle_deg", "deg", "body roll relative to the line through the contact "
            "points, atan((travel right - travel left) / track), + when the body's left side "
            "rises (axle)", "roll angle [deg] (+ body's left side up)", test="roll_angle",
            test_meaning="body roll angle, left side up +", adams="roll_angle", per_axle=True),
    Channel("roll_moment_Nmm", "N*mm", "moment the body needs to hold its roll against the "
            "vertical forces at the contact points, -(y_l Fz_l + y_r Fz_r), + with a positive "
            "roll (axle)", "roll moment [N*mm]", test="roll_moment",
            test_meaning="roll moment of the vertical forces, + with roll",
            adams="roll_moment", per_axle=True),
    Channel("steering_wheel_angle_deg", "deg", "steering-wheel angle, + turning the wheels "
            "to the left (ISO 8855; axle with steering)", "steering-wheel angle [deg] (+ left)",
            test="steering_wheel_angle",
            test_meaning="steering-wheel angle, + turning the wheels to the left",
            adams="steering_wheel_angle", per_axle=True),
    Channel("rack_travel_mm", "mm", "steering rack travel from the centre along its axis "
            "(axle with steering)", "rack travel [mm]", test="rack_travel",
            test_meaning="rack travel from the centre along the rack's axis",
            adams="rack_travel", per_axle=True),
    Channel("steer_angle_deg", "deg", f"wheel steer angle, toe change {STATIC}, not from the "
            "config's design toe, in the vehicle's sense: + turning the wheel left (both)",
            "steer angle [deg] (+ left)", test="steer_angle", adams="steer_angle",
            test_meaning="steer angle, + to the left"),
    Channel("arb_twist_deg", "deg", "twist of the anti-roll bar, the other side's half "
            "relative to the config side's about the bar's axis (axle)",
            "anti-roll bar twist [deg]", adams="arb_twist", per_axle=True),
    Channel("arb_torque_Nmm", "N*mm", "torque in the anti-roll bar's torsion spring (axle)",
            "anti-roll bar torque [N*mm]", adams="arb_torque", per_axle=True),
    Channel("roll_centre_height_mm", "mm", "kinematic roll centre height above the ground "
            "(the lines through each contact point normal to its front-view velocity; axle, "
            "parallel travel (a solid axle: of its roll motion at each step), or opposite "
            "wheel travel on an axle joined by a flexible beam)", "roll centre height [mm]",
            adams="roll_center_location_vertical", per_axle=True),
    Channel("roll_centre_lateral_mm", "mm", "kinematic roll centre's lateral position, + to "
            "the vehicle's left (axle, parallel travel, or opposite wheel travel on an axle "
            "joined by a flexible beam)", "roll centre lateral [mm] (+ left)",
            adams="roll_center_location_lateral", per_axle=True),
    Channel("load_fraction", "-", "fraction of the static load case's loads applied, 0 at "
            "the design wheel loads, 1 at the given loads", "load applied [-]",
            test="load_fraction", test_meaning="fraction of the static load case's loads "
            "applied (0 design, 1 given)", per_axle=True),
    *(Channel(f"contact_patch_f{a}_N", "N", "force the rig applies to the tyre at the contact "
              "patch, config frame", f"contact-patch force {a} [N] (config frame)",
              adams=f"tire_force_{a}", adams_frame=a) for a in "xyz"),
    Channel("vertical_force_N", "N", "vertical force the rig applies to the tyre, + up",
            "vertical force at the contact patch [N]", test="vertical_force",
            test_meaning="force the rig applies to the wheel, up +", adams="vertical_force"),
    Channel("lateral_force_N", "N", "lateral force the rig applies to the tyre, + to the "
            "vehicle's left", "lateral force at the contact patch [N] (+ to the vehicle's "
            "left)", test="lateral_force", test_meaning="force the rig applies to the wheel, "
            "outboard +", test_sign="lateral", adams="lateral_force"),
    Channel("longitudinal_force_N", "N", "longitudinal force the rig applies to the tyre, "
            "+ forward (braking -)", "longitudinal force [N] (+ forward)",
            test="longitudinal_force", test_meaning="force the rig applies to the wheel, "
            "forward +", adams="longitudinal_force"),
    Channel("aligning_torque_Nmm", "N*mm", "torque the rig applies to the tyre about the "
            "upward axis, + about up", "aligning torque [N*mm] (+ about the vertical axis, "
            "up)", test="aligning_torque", test_meaning="moment about the vertical the rig "
            "applies to the wheel, toe-in sense +", test_sign="toe_in_torque",
            adams="aligning_torque"),
)
#: units charts and the report show instead of the interface unit: unit -> (shown unit, factor
#: from the interface unit); torques in N*m, as the summary's kN*m gradients, and so the roll
#: stiffness
DISPLAY_UNITS = {"N*mm": ("N*m", 1.0e-3), "N*mm/deg": ("N*m/deg", 1.0e-3)}


def display_unit(unit: str) -> tuple[str, float]:
    """The unit a chart or the report shows for ``unit`` and the factor that converts to it."""
    return DISPLAY_UNITS.get(unit, (unit, 1.0))


def display_label(label: str, unit: str) -> str:
    """An axis label (``name [unit] (sign)``) in the unit a chart shows (:data:`DISPLAY_UNITS`)."""
    return label.replace(f"[{unit}]", f"[{display_unit(unit)[0]}]")


#: channels by kc.csv name
CHANNELS: dict[str, Channel] = {c.name: c for c in CHANNEL_LIST}
#: the channels the stiffness fit compares with the test, in residual order
FITTED_CHANNELS = tuple(c.name for c in CHANNEL_LIST if c.fitted)
#: channels by K&C test-file name
TEST_CHANNELS: dict[str, Channel] = {c.test: c for c in CHANNEL_LIST if c.test}

def channel(name: str) -> Channel | None:
    """The channel of a kc.csv column, the columns named after an item (a spring, damper,
    stop, bushing, an element's load: :mod:`elastokin.rig.item_channels`) included (None when
    the column is not elastokin's)."""
    if name in CHANNELS:
        return CHANNELS[name]
    fields = item_channel_fields(name)
    return None if fields is None else Channel(**fields)


@dataclass(frozen=True)
class LoadCase:
    """A load case of the rig: its input channel (kc.csv), where a force acts (``patch``,
    ``centre``, ``torque`` at the centre; None: the pad moves or carries the wheel load) and
    along which vehicle axis, the input's chart label, the test file's required channels."""

    name: str
    input: str
    label: str
    meaning: str
    test_required: tuple[str, ...]
    where: str | None = None
    direction: str | None = None
    vertical: bool = False  # run on kinematic models too
    corner: bool = True  # a corner's load case (False: an axle's only)

    @property
    def test_input(self) -> str:
        return CHANNELS[self.input].test


LOAD_CASE_LIST = (
    LoadCase("parallel_travel", "wheel_travel_mm", "wheel travel [mm] (+ bump)",
             "both wheels of the axle moved up and down together (displacement control)",
             ("toe",), vertical=True),
    LoadCase("vertical_force", "vertical_force_N", "vertical force at the contact patch [N]",
             "vertical force at the contact patch", ("wheel_travel",), vertical=True),
    LoadCase("lateral_force", "lateral_force_N",
             "lateral force at the contact patch [N] (+ to the vehicle's left)",
             "lateral force at the contact patch", ("toe",), "patch", "left"),
    LoadCase("longitudinal_force_patch", "longitudinal_force_N",
             "longitudinal force at the contact patch [N] (+ forward; braking -)",
             "longitudinal force at the contact patch (braking)",
             ("wheel_centre_longitudinal",), "patch", "forward"),
    LoadCase("longitudinal_force_centre", "longitudinal_force_N",
             "longitudinal force at the wheel centre [N] (+ forward: traction)",
             "longitudinal force at the wheel centre (traction)",
             ("wheel_centre_longitudinal",), "centre", "forward"),
    LoadCase("aligning_torque", "aligning_torque_Nmm",
             "aligning torque [N*mm] (+ about the vertical axis, up)",
             "moment about the vertical at the contact patch", ("toe",), "torque", "up"),
    LoadCase("opposite_travel", "wheel_travel_mm", "wheel travel [mm] (+ bump)",
             "the wheels of the axle moved against each other (displacement control)",
             ("toe",), vertical=True, corner=False),
    LoadCase("single_wheel_travel", "wheel_travel_mm", "wheel travel [mm] (+ bump)",
             "one wheel moved, the other held at its design height (displacement control)",
             ("toe",), vertical=True, corner=False),
    LoadCase("roll_vertical_force", "roll_angle_deg", "roll angle [deg] (+ body's left up)",
             "body roll at constant total vertical load", ("toe",), vertical=True, corner=False),
    LoadCase("steering", "steering_wheel_angle_deg", "steering-wheel angle [deg]",
             "steering lock to lock, wheels at the design load", ("toe",), vertical=True,
             corner=False),
    LoadCase("static_load", "load_fraction", "load applied [-]",
             "given loads at each contact patch", ("toe",), corner=False),
    LoadCase("lateral_force_anti_phase", "lateral_force_N",
             "lateral force at the contact patch [N] (+ to the vehicle's left)",
             "lateral force at the contact patches in anti-phase", ("toe",), "patch", "left",
             corner=False),
    LoadCase("vehicle_loads", "load_fraction", "load applied [-]",
             "static loads from vehicle accelerations (one case each, vehicle_loads:<case>)",
             ("toe",), corner=False),
)
LOAD_CASES: dict[str, LoadCase] = {c.name: c for c in LOAD_CASE_LIST}
#: the load case of one static-load case from vehicle accelerations (input load_fraction)
VEHICLE_LOAD_CASE = "vehicle_loads:{}"
#: the force-controlled load cases at the design wheel load
FORCE_CASES = tuple(c.name for c in LOAD_CASE_LIST if c.where is not None)


@dataclass(frozen=True)
class Characteristic:
    """A summary figure of one model (summary.json ``models.<label>``): a least-squares
    slope ``scale * dy/dx`` of ``y`` against ``x`` over the measured rows of ``load_case``
    (no approach; within ``window`` of x when given), or (no load case) a figure the rig
    computes itself."""

    name: str
    label: str
    unit: str
    fmt: str
    definition: str
    load_case: str | None = None
    x: str | None = None
    y: str | None = None
    scale: float = 1.0
    window: tuple[float, float] | None = None


#: half-width of the travel window over which bump steer is fitted (mm)
BUMP_STEER_WINDOW_MM = 50.0

CHARACTERISTIC_LIST = (
    *(Characteristic(c, f"{CHANNELS[c].label.split(' [')[0]} (static)", CHANNELS[c].unit,
                     ".2f", f"{CHANNELS[c].sign}; at the static state")
      for c in ("caster_deg", "kingpin_inclination_deg", "scrub_radius_mm",
                "caster_trail_mm")),
    Characteristic("steer_amplitude_deg", "steer amplitude over the travel stroke", "deg",
                   ".4f", "max - min toe over the measured stroke"),
    Characteristic("bump_steer_deg_per_m", "bump steer (+-50 mm)", "deg/m", ".3f",
                   "least-squares slope of toe vs wheel travel over exactly +-50 mm of the "
                   "stroke (toe interpolated on an even travel grid)",
                   "parallel_travel", "wheel_travel_mm", "toe_deg", 1000.0,
                   (-BUMP_STEER_WINDOW_MM, BUMP_STEER_WINDOW_MM)),
    Characteristic("bump_steer_at_design_deg_per_m", "bump steer at design", "deg/m", ".3f",
                   "toe vs wheel travel's slope at wheel travel 0 (central differences)"),
    Characteristic("bump_camber_deg_per_m", "bump camber", "deg/m", ".3f",
                   "least-squares slope of camber vs wheel travel over the measured stroke "
                   "(loading and unloading)",
                   "parallel_travel", "wheel_travel_mm", "camber_deg", 1000.0),
    Characteristic("wheel_rate_N_per_mm", "wheel rate", "N/mm", ".2f",
                   "least-squares slope of vertical force vs wheel travel",
                   "vertical_force", "wheel_travel_mm", "vertical_force_N"),
    Characteristic("spring_wheel_rate_N_per_mm", "wheel rate from the springs", "N/mm", ".2f",
                   "sum of rate x motion ratio^2 over the springs at the static state, a spring "
                   "both wheels compress counted half (docs/characteristics.md)"),
    Characteristic("lateral_compliance_steer_deg_per_kN", "lateral compliance steer",
                   "deg/kN", ".4f", "toe per lateral force at the contact patch",
                   "lateral_force", "lateral_force_N", "toe_deg", 1000.0),
    Characteristic("lateral_compliance_camber_deg_per_kN", "lateral compliance camber",
                   "deg/kN", ".4f", "camber per lateral force at the contact patch",
                   "lateral_force", "lateral_force_N", "camber_deg", 1000.0),
    Characteristic("lateral_compliance_mm_per_kN", "lateral wheel-centre compliance", "mm/kN",
                   ".3f", "wheel-centre lateral displacement per lateral force",
                   "lateral_force", "lateral_force_N", "wheel_centre_lateral_mm", 1000.0),
    Characteristic("longitudinal_compliance_mm_per_kN", "longitudinal compliance (braking)",
                   "mm/kN", ".3f", "wheel-centre longitudinal displacement per longitudinal "
                   "force at the contact patch", "longitudinal_force_patch",
                   "longitudinal_force_N", "wheel_centre_longitudinal_mm", 1000.0),
    Characteristic("longitudinal_compliance_steer_deg_per_kN", "longitudinal compliance steer",
                   "deg/kN", ".4f", "toe per longitudinal force at the contact patch",
                   "longitudinal_force_patch", "longitudinal_force_N", "toe_deg", 1000.0),
    Characteristic("traction_compliance_mm_per_kN", "traction compliance", "mm/kN", ".3f",
                   "wheel-centre longitudinal displacement per longitudinal force at the "
                   "wheel centre", "longitudinal_force_centre", "longitudinal_force_N",
                   "wheel_centre_longitudinal_mm", 1000.0),
    Characteristic("traction_compliance_steer_deg_per_kN", "traction compliance steer",
                   "deg/kN", ".4f", "toe per longitudinal force at the wheel centre",
                   "longitudinal_force_centre", "longitudinal_force_N", "toe_deg", 1000.0),
    Characteristic("aligning_torque_compliance_steer_deg_per_kNm",
                   "aligning-torque compliance steer", "deg/kNm", ".4f",
                   "toe per aligning torque", "aligning_torque", "aligning_torque_Nmm",
                   "toe_deg", 1.0e6),
)
CHARACTERISTICS: dict[str, Characteristic] = {c.name: c for c in CHARACTERISTIC_LIST}
#: the characteristics fitted over a sweep's measured rows (summary.json)
GRADIENTS = {c.name: c for c in CHARACTERISTIC_LIST if c.load_case is not None
             and c.name != "bump_steer_deg_per_m"}


def _axle(name: str, label: str, unit: str, fmt: str, definition: str) -> Characteristic:
    return Characteristic(name, label, unit, fmt, definition)


#: the axle's characteristics (summary.json ``models.<label>.axle``; ADAMS/Car's definitions,
#: docs/characteristics.md "Axle characteristics"); computed by elastokin.rig.axle_summary
#: (``fmt``: the report's, of the figure in the unit it shows, :func:`display_unit`)
AXLE_CHARACTERISTIC_LIST = (
    _axle("roll_centre_height_mm", "roll centre height (kinematic)", "mm", ".1f",
          "where the lines from each contact point normal to its velocity in parallel travel "
          "(a solid axle: in its roll motion; in opposite wheel travel on an axle joined by a "
          "flexible beam: a twist beam) meet (front view), above the contact points, at the "
          "static state"),
    _axle("roll_centre_lateral_mm", "roll centre lateral (kinematic)", "mm", ".1f",
          "its lateral position, + to the vehicle's left"),
    _axle("roll_centre_height_force_based_mm", "roll centre height (force-based)", "mm",
          ".1f", "ADAMS/Car's: from the 12x12 compliance under opposing vertical forces at the "
          "contact points"),
    _axle("roll_stiffness_Nmm_per_deg", "roll stiffness (total)", "N*mm/deg", ".1f",
          "slope of the roll moment against the roll angle, roll and vertical force case"),
    _axle("anti_roll_bar_roll_stiffness_Nmm_per_deg", "roll stiffness of the anti-roll bar",
          "N*mm/deg", ".1f", "the bar's torque times its twist per roll angle"),
    _axle("anti_roll_bar_share", "anti-roll bar's share of the roll stiffness", "-", ".3f",
          "the bar's roll stiffness over the total"),
    _axle("roll_steer_left_deg_per_deg", "roll steer, left (toe-in +)", "deg/deg", ".4f",
          "slope of the left wheel's toe against the roll angle"),
    _axle("roll_steer_right_deg_per_deg", "roll steer, right (toe-in +)", "deg/deg", ".4f",
          "slope of the right wheel's toe against the roll angle"),
    _axle("axle_roll_steer_deg_per_deg", "axle roll steer (+ left)", "deg/deg", ".4f",
          "slope of the mean steer angle (+ to the left) against the roll angle"),
    _axle("roll_camber_left_deg_per_deg", "roll camber, left", "deg/deg", ".4f",
          "slope of the left wheel's camber (relative to the body) against the roll angle"),
    _axle("roll_camber_right_deg_per_deg", "roll camber, right", "deg/deg", ".4f",
          "slope of the right wheel's camber against the roll angle"),
    _axle("percent_anti_dive", "anti-dive (front, braking)", "%", ".1f",
          "ADAMS/Car's, from the compliance matrix and the vehicle data"),
    _axle("percent_anti_lift_braking", "anti-lift under braking (rear)", "%", ".1f",
          "ADAMS/Car's, from the compliance matrix and the vehicle data"),
    _axle("percent_anti_lift_traction", "anti-lift under traction (front)", "%", ".1f",
          "ADAMS/Car's, from the compliance matrix and the vehicle data"),
    _axle("percent_anti_squat", "anti-squat (rear, traction)", "%", ".1f",
          "ADAMS/Car's, from the compliance matrix and the vehicle data"),
    _axle("steering_ratio_overall", "steering ratio (lock to lock)", "deg/deg", ".2f",
          "steering-wheel angle range over the mean road-wheel steer angle's change"),
    _axle("steering_ratio_centre", "steering ratio (on centre)", "deg/deg", ".2f",
          "local steering ratio at the steering wheel's centre"),
    _axle("percent_ackermann_lock", "percent Ackermann at the left lock", "%", ".1f",
          "100 L (cot outer - cot inner) / track of the steer angles (from the static state), "
          "0 % equal steer, 100 % the spindle lines meeting on the rear axle"),
    _axle("ackermann_error_lock_deg", "Ackermann error at the left lock", "deg", ".2f",
          "outer wheel's steer less its Ackermann angle for the turn radius"),
    _axle("outside_turn_diameter_mm", "outside turn diameter (curb to curb)", "mm", ".0f",
          "diameter of the outer front contact point's circle at the left lock"),
    _axle("max_steer_inner_deg", "inner wheel steer at the left lock", "deg", ".2f",
          "road-wheel steer angle of the inner (left) wheel at the left lock"),
    _axle("max_steer_outer_deg", "outer wheel steer at the left lock", "deg", ".2f",
          "road-wheel steer angle of the outer (right) wheel at the left lock"),
    _axle("ride_rate_left_N_per_mm", "ride rate, left", "N/mm", ".2f",
          "the left wheel rate in series with the tyre's vertical rate"),
    _axle("ride_rate_right_N_per_mm", "ride rate, right", "N/mm", ".2f",
          "the right wheel rate in series with the tyre's vertical rate"),
)
AXLE_CHARACTERISTICS = {c.name: c for c in AXLE_CHARACTERISTIC_LIST}
#: steering-axis columns reported at the static state
STEERING_AXIS_COLUMNS = ("caster_deg", "kingpin_inclination_deg", "scrub_radius_mm",
                         "caster_trail_mm")


@dataclass(frozen=True)
class ErrorMetric:
    """An error of a model against the test (summary.json ``errors``): the RMS of the
    model's change from its static state minus the test's, branch by branch."""

    name: str
    label: str
    unit: str
    fmt: str
    load_case: str
    x: str
    y: str


ERROR_LIST = (
    ErrorMetric("steer_vs_travel_rms_deg", "steer vs travel (Fig. 9a)", "deg", ".4f",
                "parallel_travel", "wheel_travel_mm", "toe_deg"),
    ErrorMetric("steer_vs_lateral_force_rms_deg", "steer vs lateral force (Fig. 9b)", "deg",
                ".4f", "lateral_force", "lateral_force_N", "toe_deg"),
    ErrorMetric("longitudinal_displacement_rms_mm",
                "longitudinal displacement vs force (Fig. 9c)", "mm", ".3f",
                "longitudinal_force_patch", "longitudinal_force_N",
                "wheel_centre_longitudinal_mm"),
)
ERRORS: dict[str, ErrorMetric] = {e.name: e for e in ERROR_LIST}


def sign_conventions() -> dict[str, str]:
    """The sign convention of every column and figure (summary.json ``sign_conventions``)."""
    out = {"frame": "the config frame (see its 'frame' key); wheel-centre coordinates in it"}
    out.update({c.name: c.sign for c in CHANNEL_LIST})
    out["spring_*_force_N"] = channel("spring_s_force_N").sign
    out["spring_*_length_mm, damper_*_length_mm"] = channel("spring_s_length_mm").sign
    out["spring_*_motion_ratio, damper_*_motion_ratio"] = channel("spring_s_motion_ratio").sign
    out["bushing_*"] = channel("bushing_b_x_mm").sign
    out["<element>_{fx,fy,fz,mx,my,mz}_{body,local}_{N,Nmm} (loads.csv)"] = (
        f"{LOAD_SIGN}; body: {LOAD_FRAMES['body']}; local: {LOAD_FRAMES['local']}")
    out.update({c.name: c.definition for c in CHARACTERISTIC_LIST})
    return out
