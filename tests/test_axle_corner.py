"""A symmetric axle in parallel travel and under in-phase vertical force gives, on each side,
the single corner's toe, camber and wheel rate (issue 18, correctness 1), on the real solver.

The corner is tests/data/double_wishbone.yaml (compliant lower-arm bushing, steering rack);
the axle is the same corner mirrored, the rack shared and driven by the steering (held in these
load cases), with or without an anti-roll bar. The bar's halves turn on ideal revolutes about
one common axis (y) and reach the lower arms by drop links: in parallel travel they turn
together, the bar does not twist and must change nothing.

Tolerance 1e-9 of each channel's range (at least 1e-9: deg, mm, N) and relative on the wheel
rate (the slope of the vertical-force sweep), with the Newton tolerance set to 1e-10 in these
configs. Measured: without the bar the axle matches the corner to 5e-11 deg at the default
1e-8 and 4e-13 deg at 1e-10; with the bar, at the default 1e-8, to 8e-8 deg of toe, 2e-8 deg
of camber, 2.4e-5 N of wheel load and 2e-9 of wheel rate (over 1e-9): the bar's centre joins
its halves by springs of 1e6 N/mm and 1e10 N*mm/rad, which raise the residual a relative
Newton tolerance refers to. At 1e-10 these fall to 6.5e-10 deg, 1.4e-10 deg, 2.4e-7 N and
7e-11: the solver's tolerance, not the model (1e-11 no longer converges: the residual's
round-off floor). The bar's twist: 8e-13 deg. (A bar mounted in rubber bushings does not
give the corner's result: a lone half tilts in its bushing under the drop-link load, the
one-piece bar does not; 0.9 N of wheel load at the ends of travel, measured.)
"""

import warnings

import numpy as np
import pytest

from elastokin.rig.characteristics import summary_figures

from .axle_rigs import config, rig, run_cases, suspension

NEWTON_TOLERANCE = 1e-10
TOL = 1e-9
#: the anti-roll bar added to the corner (hardpoints inboard of the lower arm's spring seat)
BAR_POINTS = {"bar_centre": [-250.0, 0.0, 250.0], "bar_mount": [-250.0, 400.0, 250.0],
              "link_bar": [0.0, 600.0, 250.0], "link_arm": [0.0, 600.0, 147.0]}


def dw_corner() -> dict:
    d = config("double_wishbone.yaml")
    d["solver"] = {"newton_tolerance": NEWTON_TOLERANCE}
    d["rig"] = rig(parallel_travel={"rebound_mm": -60, "bump_mm": 60, "step_mm": 5},
                   vertical_force={"min_N": 3500, "max_N": 4500, "step_N": 100})
    return d


def dw_axle(bar: bool) -> dict:
    d = dw_corner()
    d["axle"] = {"shared": ["rack"],
                 "steering": {"rack": "steering", "ratio_mm_per_rev": 50, "limit_mm": 40}}
    if bar:
        d["hardpoints"].update(BAR_POINTS)
        d["parts"]["bar"] = {}
        d["connections"]["bar_mount"] = {"type": "revolute", "parts": ["body", "bar"],
                                         "at": "bar_mount", "axis": [0, 1, 0]}
        d["connections"]["drop_link"] = {"type": "link", "parts": ["bar", "lower_arm"],
                                         "at": ["link_bar", "link_arm"]}
        d["axle"]["anti_roll_bar"] = {"part": "bar", "point": "bar_centre", "axis": [0, 1, 0],
                                      "rate_Nmm_per_deg": 20000}
    return d


def _run(data: dict) -> dict:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the steering axis of a kinematic wheel: n/a here
        return run_cases(suspension(data))


@pytest.fixture(scope="module")
def corner():
    return _run(dw_corner())


@pytest.mark.parametrize("bar", [False, True], ids=["no_bar", "anti_roll_bar"])
def test_symmetric_axle_gives_the_corner_result_on_each_side(corner, bar):
    axle = _run(dw_axle(bar))
    rate = summary_figures([corner[("vertical_force", "left")]], False)["wheel_rate_N_per_mm"]
    assert 5.0 < rate < 50.0  # the corner's own figure, a plausible wheel rate
    for side in ("left", "right"):
        for case in ("parallel_travel", "vertical_force"):
            a, c = axle[(case, side)].columns, corner[(case, "left")].columns
            for col in ("toe_deg", "camber_deg", "wheel_travel_mm", "contact_patch_fz_N"):
                scale = max(1.0, float(np.max(np.abs(c[col]))))  # deg, mm, N
                np.testing.assert_allclose(a[col], c[col], rtol=0, atol=TOL * scale,
                                           err_msg=f"{case} {side} {col}")
        figures = summary_figures([axle[("vertical_force", side)]], False)
        assert figures["wheel_rate_N_per_mm"] == pytest.approx(rate, rel=TOL, abs=0)
        if bar:
            twist = axle[("parallel_travel", side)].columns["arb_twist_deg"]
            assert np.max(np.abs(twist)) < TOL
        else:
            assert "arb_twist_deg" not in axle[("parallel_travel", side)].columns
