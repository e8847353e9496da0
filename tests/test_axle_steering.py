"""Steering on the real solver (issue 18, correctness 4): on a planar steering trapezoid
(tests/data/steering_trapezoid.yaml) the left and right steer angles of the steering load case
match an independent loop-closure solution to 1e-6 deg, and the summary's percent Ackermann at
the lock is its definition evaluated on those angles.

Loop closure (top view, mm): the knuckle turns by the steer angle ``d`` (+ to the left, about
the vertical kingpin ``K``), carrying the tie rod's outer point ``P0`` to ``K + R(d) (P0 -
K)``; the rack carries the inner point ``Q0`` to ``Q0 + (0, s)`` at rack travel ``s`` (the
sweep's ``rack_travel_mm``, both tie rods on the one rack); the tie rod keeps its length
``|P0 - Q0|``. Solved for ``d`` by scipy's brentq, right wheel with the mirrored points.

Percent Ackermann (module :mod:`elastokin.physics.ackermann`; MotionView "Curb to Curb
Diameter and Ackerman"): ``100 L (cot d_outer - cot d_inner) / t`` with the wheelbase ``L``
and the track ``t`` at the contact points: 0 % for parallel wheels, 100 % when both spindle
lines meet on the rear axle's line.
"""

import warnings

import numpy as np
import pytest
from scipy.optimize import brentq

from elastokin.config.variants import ModelVariant
from elastokin.studies.kc_job import load_cases

from .axle_rigs import config, suspension

MIRROR = np.array([1.0, -1.0])


def steer_angle_deg(kingpin, outer, inner, rack_mm: float) -> float:
    """The steer angle (deg, + left) closing the loop at rack travel ``rack_mm`` (points
    (x, y) at the straight-ahead position)."""
    k, p0, q0 = (np.asarray(v, float) for v in (kingpin, outer, inner))
    length = np.linalg.norm(p0 - q0)

    def gap(d):
        c, s = np.cos(d), np.sin(d)
        p = k + np.array([[c, -s], [s, c]]) @ (p0 - k)
        return np.linalg.norm(p - (q0 + [0.0, rack_mm])) - length

    return float(np.degrees(brentq(gap, -1.2, 1.2, xtol=1e-14)))


@pytest.fixture(scope="module")
def trapezoid():
    d = config("steering_trapezoid.yaml")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = load_cases(ModelVariant("m", suspension(d, "steering_trapezoid.yaml")))
    sweeps = {"left": result.sweep("steering"),
              "right": next(sw for sw in result.other_sides["right"]
                            if sw.load_case == "steering")}
    return d, sweeps, result.summary()["axle"]


def loop_closure(d: dict, rack_mm: np.ndarray) -> dict[str, np.ndarray]:
    hp = {k: np.asarray(v, float)[:2] for k, v in d["hardpoints"].items()}
    points = (hp["kingpin"], hp["tierod_outer"], hp["tierod_inner"])
    return {"left": np.array([steer_angle_deg(*points, t) for t in rack_mm]),
            "right": np.array([steer_angle_deg(*(MIRROR * p for p in points), t)
                               for t in rack_mm])}


def test_steer_angles_match_the_loop_closure(trapezoid):
    d, sweeps, _ = trapezoid
    rack = sweeps["left"].columns["rack_travel_mm"]
    np.testing.assert_array_equal(rack, sweeps["right"].columns["rack_travel_mm"])
    assert np.max(np.abs(rack)) == pytest.approx(60.0)  # lock to lock
    swa = sweeps["left"].columns["steering_wheel_angle_deg"]
    assert swa[np.argmax(rack)] < 0  # the rack's + travel (left) turns right here
    hand = loop_closure(d, rack)
    for side in ("left", "right"):
        np.testing.assert_allclose(sweeps[side].columns["steer_angle_deg"], hand[side],
                                   rtol=0, atol=1e-6, err_msg=side)
    turned = swa != 0
    assert np.all(hand["left"][turned] * swa[turned] > 0)  # + steering-wheel angle: left


def test_percent_ackermann_from_its_definition(trapezoid):
    d, sweeps, ax = trapezoid
    hand = loop_closure(d, sweeps["left"].columns["rack_travel_mm"])
    k = int(np.argmax(hand["left"] + hand["right"]))  # the left lock: the left wheel inner
    inner, outer = np.radians(hand["left"][k]), np.radians(hand["right"][k])
    wheelbase = d["axle"]["vehicle"]["wheelbase_mm"]
    track = 2.0 * d["hardpoints"]["wheel_centre"][1]  # contact points below the centres
    percent = 100.0 * wheelbase * (1.0 / np.tan(outer) - 1.0 / np.tan(inner)) / track
    assert 0.0 < percent < 100.0  # between parallel steer and full Ackermann at this lock
    assert ax["percent_ackermann_lock"] == pytest.approx(percent, rel=1e-6)
    assert ax["max_steer_inner_deg"] == pytest.approx(np.degrees(inner), abs=1e-6)
    assert ax["max_steer_outer_deg"] == pytest.approx(np.degrees(outer), abs=1e-6)
