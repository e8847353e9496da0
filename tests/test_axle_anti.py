"""Percent anti-dive (and its family) of the summary on the real solver match the side-view
formula on a suspension whose side-view instant centre is known (issue 18, correctness 5).

The suspension is tests/data/leading_arm_axle.yaml without its bar: the wheel part is an arm
pivoting on a revolute about y, so its side-view instant centre is the pivot (x = -400 mm,
z = 100 mm, 400 mm behind the wheel centre). The formula (Milliken & Milliken, Race Car
Vehicle Dynamics, ch. 17, "anti" features; Gillespie, Fundamentals of Vehicle Dynamics, ch. 7,
anti-dive): ``% anti = 100 f tan(theta) L / h``, ``f`` this axle's share of the braking
(anti-dive, anti-lift in braking) or traction (anti-lift in traction, anti-squat) force, ``L``
the wheelbase, ``h`` the centre-of-gravity height, ``theta`` the side-view inclination of the
line from the reference point to the instant centre, positive rising towards the centre of
gravity (rearward on a front axle); the reference point is the contact point for outboard
brakes and traction through the contact point, the wheel centre for inboard brakes. It is the
condition MotionView states for 100 % ("the moment about the side view instant center due to
weight transfer is exactly offset by the moment ... due to the braking force"), which its and
ADAMS/Car's compliance-matrix formulas (:mod:`elastokin.physics.axle_compliance`) evaluate.

Tolerance 1e-4 relative: the compliance matrix is central differences of +-10 N and +-1000
N*mm (measured: 1e-5 relative, outboard; 1e-7 inboard).
"""

import warnings

import numpy as np
import pytest

from elastokin.config.variants import ModelVariant
from elastokin.studies.kc_job import load_cases

from .axle_rigs import config, suspension

VEHICLE = {"wheelbase_mm": 2700.0, "cg_height_mm": 500.0, "brake_fraction": 0.6,
           "drive_fraction": 0.4}


def percent_anti(d: dict, reference: str, fraction: float, position: str) -> float:
    """The side-view formula (module docstring) from the config's hardpoints."""
    hp = {k: np.asarray(v, float) for k, v in d["hardpoints"].items()}
    ic = hp["arm_pivot"][[0, 2]]
    centre = hp["wheel_centre"][[0, 2]]
    ref = centre - [0.0, d["wheel"]["loaded_radius_mm"]] if reference == "contact" else centre
    rising_rearward = (ic[1] - ref[1]) / (ref[0] - ic[0])
    tan_theta = rising_rearward if position == "front" else -rising_rearward
    return 100.0 * fraction * tan_theta * VEHICLE["wheelbase_mm"] / VEHICLE["cg_height_mm"]


def summary(position: str, brakes: str, drive: str = "outboard") -> tuple[dict, dict]:
    d = config("leading_arm_axle.yaml")
    d["rig"]["opposite_travel"] = None
    d["axle"] = {"vehicle": {**VEHICLE, "position": position, "brakes": brakes,
                             "drive": drive}}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the arm has no steering axis
        result = load_cases(ModelVariant("m", suspension(d, "leading_arm_axle.yaml")))
    return d, result.summary()["axle"]


@pytest.mark.parametrize("brakes, drive", [("outboard", "outboard"), ("inboard", "inboard")])
def test_front_anti_dive_and_anti_lift(brakes, drive):
    """Brakes and drive torque reacted by the wheel carrier (outboard: the force acts at the
    contact patch) or by the body (inboard: at the wheel centre)."""
    d, ax = summary("front", brakes, drive)
    braking = "contact" if brakes == "outboard" else "centre"
    anti_dive = percent_anti(d, braking, VEHICLE["brake_fraction"], "front")
    assert anti_dive == pytest.approx(81.0 if brakes == "outboard" else -162.0)
    assert ax["percent_anti_dive"] == pytest.approx(anti_dive, rel=1e-4)
    traction = "contact" if drive == "outboard" else "centre"
    lift = percent_anti(d, traction, VEHICLE["drive_fraction"], "front")
    assert ax["percent_anti_lift_traction"] == pytest.approx(lift, rel=1e-4)
    assert ax["percent_anti_squat"] is None and ax["percent_anti_lift_braking"] is None


def test_rear_anti_lift_and_anti_squat():
    """The same arm as a rear axle: its instant centre behind the wheel now lies away from
    the centre of gravity (negative anti-lift at the contact patch); the drive torque reacted
    by the body (inboard) puts the tractive force at the wheel centre, below the instant
    centre's line from the contact patch (positive anti-squat)."""
    d, ax = summary("rear", "outboard", "inboard")
    lift = percent_anti(d, "contact", VEHICLE["brake_fraction"], "rear")
    squat = percent_anti(d, "centre", VEHICLE["drive_fraction"], "rear")
    assert lift < 0 < squat
    assert ax["percent_anti_lift_braking"] == pytest.approx(lift, rel=1e-4)
    assert ax["percent_anti_squat"] == pytest.approx(squat, rel=1e-4)
