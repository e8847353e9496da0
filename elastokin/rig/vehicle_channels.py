"""The whole car's entries of the channel table (:mod:`elastokin.rig.channels`, whose types
they use; kept apart only because that module is at the size limit of the house rules): the
columns of the car's body-roll sweep (``car.csv``) and the car's figures (summary.json
``models.<label>.front``, ``.rear`` and ``.car``). An axle's figure the car repeats keeps its
name and definition from the axle's tables (``AXLE_CHARACTERISTICS``, ``CHARACTERISTICS``);
only what the car adds is defined here. Definitions and sources: docs/characteristics.md
"Whole car".

Units mm, N, N*mm, deg, %; signs ISO 8855: steer + to the left, roll + when the body's left
side rises, pitch + nose down, an understeer gradient + understeer.
"""

from __future__ import annotations

from elastokin.rig.channels import (
    AXLE_CHARACTERISTICS,
    CHARACTERISTICS,
    Channel,
    Characteristic,
)

#: the load case of the car on the rig's table (car.csv ``load_case``)
BODY_ROLL = "body_roll"

CAR_CHANNEL_LIST = (
    Channel("body_roll_deg", "deg", "the table's roll of the body relative to the ground (the "
            "line through each axle's contact points turns by it), + when the body's left "
            "side rises (as in a left turn); both axles the same", "body roll [deg] (+ left "
            "side up)"),
    Channel("roll_moment_front_Nmm", "N*mm", "the front axle's roll moment (its "
            "roll_moment_Nmm), + with a positive roll", "front roll moment [N*mm]"),
    Channel("roll_moment_rear_Nmm", "N*mm", "the rear axle's roll moment", "rear roll moment "
            "[N*mm]"),
    Channel("roll_moment_total_Nmm", "N*mm", "the moment the table holds the body's roll with: "
            "the sum of both axles'", "roll moment [N*mm]"),
    Channel("body_heave_mm", "mm", "the body's height change at the CG relative to the ground "
            "(from both axles' mean wheel travel, tyres rigid), + up", "body heave [mm] (+ up)"),
    Channel("body_pitch_deg", "deg", "the body's pitch relative to the ground, + nose down "
            "(ISO 8855)", "body pitch [deg] (+ nose down)"),
    Channel("steer_front_deg", "deg", "the front axle's steer angle (mean of its wheels' steer "
            "angles), + to the left", "front axle steer [deg] (+ left)"),
    Channel("steer_rear_deg", "deg", "the rear axle's steer angle, + to the left",
            "rear axle steer [deg] (+ left)"),
)
CAR_CHANNELS = {c.name: c for c in CAR_CHANNEL_LIST}


def _figure(name: str, label: str, unit: str, fmt: str, definition: str) -> Characteristic:
    return Characteristic(name, label, unit, fmt, definition)


#: figures each axle has in the car beyond its own (summary.json ``models.<label>.front``
#: and ``.rear``)
AXLE_IN_CAR_LIST = (
    _figure("lateral_force_steer_deg_per_kN", "lateral force steer (axle, + left)", "deg/kN",
            ".4f", "the axle's steer angle (+ left) per lateral force (+ left) at its contact "
            "patches in phase, both wheels together: (C_toe,right - C_toe,left)/2 of the "
            "named compliances lateral_force_toe_in_phase_*"),
    _figure("understeer_compliance_steer_deg_per_g", "understeer from compliance steer",
            "deg/g", ".3f", "the axle's term of the understeer gradient from lateral force "
            "steer: front -s_f W_f, rear +s_r W_r (W: its weight from the vehicle's masses)"),
    _figure("understeer_roll_steer_deg_per_g", "understeer from roll steer", "deg/g", ".3f",
            "the axle's term from roll steer: front -e_f dphi/da_y, rear +e_r dphi/da_y"),
)

#: the car's own figures (summary.json ``models.<label>.car``)
CAR_CHARACTERISTIC_LIST = (
    _figure("roll_stiffness_Nmm_per_deg", "roll stiffness (front + rear)", "N*mm/deg", ".1f",
            "the sum of both axles' roll stiffness"),
    _figure("roll_stiffness_front_percent", "roll stiffness distribution, front", "%", ".1f",
            "100 K_front / (K_front + K_rear)"),
    _figure("roll_stiffness_rear_percent", "roll stiffness distribution, rear", "%", ".1f",
            "100 K_rear / (K_front + K_rear)"),
    _figure("roll_stiffness_table_Nmm_per_deg", "roll stiffness on the table", "N*mm/deg",
            ".1f", "slope of the total roll moment against the table's body roll"),
    _figure("roll_axis_height_under_cg_mm", "roll axis height under the CG (kinematic)", "mm",
            ".1f", "the line through the kinematic roll centres, interpolated linearly to the "
            "CG's position"),
    _figure("roll_axis_inclination_deg", "roll axis inclination (kinematic, + rising "
            "rearward)", "deg", ".3f", "atan((h_rear - h_front) / wheelbase)"),
    _figure("roll_moment_arm_mm", "CG height above the roll axis (kinematic)", "mm", ".1f",
            "h_cg - roll axis height under the CG"),
    _figure("roll_axis_height_under_cg_force_based_mm", "roll axis height under the CG "
            "(force-based)", "mm", ".1f", "the same through the force-based roll centres"),
    _figure("roll_axis_inclination_force_based_deg", "roll axis inclination (force-based)",
            "deg", ".3f", "the same through the force-based roll centres"),
    _figure("roll_gradient_deg_per_g", "roll gradient", "deg/g", ".3f",
            "W h' / (K - W h') (rad, K per rad): the whole weight W on the kinematic roll "
            "axis' moment arm h', tyres rigid"),
    _figure("understeer_compliance_steer_deg_per_g", "understeer gradient from compliance "
            "steer", "deg/g", ".3f", "s_r W_r - s_f W_f: both axles' terms"),
    _figure("understeer_roll_steer_deg_per_g", "understeer gradient from roll steer", "deg/g",
            ".3f", "(e_r - e_f) dphi/da_y: both axles' terms"),
    _figure("understeer_suspension_deg_per_g", "understeer gradient from the suspensions",
            "deg/g", ".3f", "compliance steer plus roll steer (the tyres' terms are not in "
            "it)"),
)
CAR_CHARACTERISTICS = {c.name: c for c in CAR_CHARACTERISTIC_LIST}

#: an axle's own figures the car reports front and rear (summary.json models.<label>.front
#: / .rear, beside AXLE_IN_CAR_LIST), by the name of their definition
AXLE_FIGURES = ("roll_stiffness_Nmm_per_deg", "anti_roll_bar_share", "roll_centre_height_mm",
                "roll_centre_height_force_based_mm", "axle_roll_steer_deg_per_deg",
                "roll_camber_left_deg_per_deg", "percent_anti_dive",
                "percent_anti_lift_traction", "percent_anti_lift_braking",
                "percent_anti_squat")
#: a wheel's figures the car reports per axle (its left wheel's)
WHEEL_FIGURES = ("bump_steer_deg_per_m", "bump_camber_deg_per_m")


def figure(name: str, scope: str = "car") -> Characteristic:
    """The definition of a figure the car reports: of the car itself (``scope`` "car") or
    of one of its axles ("axle": the car's additions, then the axle's and the wheel's own
    tables)."""
    tables = ((CAR_CHARACTERISTICS,) if scope == "car" else
              ({c.name: c for c in AXLE_IN_CAR_LIST}, AXLE_CHARACTERISTICS, CHARACTERISTICS))
    for table in tables:
        if name in table:
            return table[name]
    raise KeyError(f"{name} ({scope})")
