import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from elastokin.physics.wheel import (
    UndeterminedSlopeWarning,
    camber_deg,
    slope,
    spin_axis_from_angles,
    toe_deg,
)

# ADAMS/Car frame (x rearward, y right), left wheel: forward = -x, outboard = -y
FWD, OUT, UP = np.array([-1.0, 0, 0]), np.array([0, -1.0, 0]), np.array([0, 0, 1.0])


def test_toe_in_hand_case():
    # left wheel, front of the wheel turned 1 deg towards the centreline (+y here): the
    # outboard spin axis turns forward
    a = np.array([-np.sin(np.radians(1.0)), -np.cos(np.radians(1.0)), 0.0])
    assert toe_deg(a, FWD, OUT) == pytest.approx(1.0)
    assert camber_deg(a, FWD, OUT, UP) == pytest.approx(0.0)


def test_negative_camber_hand_case():
    # top of the wheel leaning inboard by 2 deg: the outboard spin axis points up
    a = np.array([0.0, -np.cos(np.radians(2.0)), np.sin(np.radians(2.0))])
    assert camber_deg(a, FWD, OUT, UP) == pytest.approx(-2.0)


@given(st.floats(-10, 10), st.floats(-10, 10))
@settings(max_examples=50, deadline=None)
def test_angles_round_trip(toe, camber):
    a = spin_axis_from_angles(toe, camber, FWD, OUT, UP)
    assert toe_deg(a, FWD, OUT) == pytest.approx(toe, abs=1e-9)
    assert camber_deg(a, FWD, OUT, UP) == pytest.approx(camber, abs=1e-9)


def test_slope_window():
    x = np.linspace(-90, 90, 181)
    y = 0.002 * x + 1e-5 * x**3
    # over +-50 the cubic's least-squares slope is 0.002 + 1e-5 * 3/5 * 50^2 * (...)
    expected = np.polyfit(x[np.abs(x) <= 50], y[np.abs(x) <= 50], 1)[0]
    assert slope(x, y, (-50, 50)) == pytest.approx(expected)
    with pytest.warns(UndeterminedSlopeWarning, match="1 distinct point in the data"):
        assert np.isnan(slope([1.0], [2.0]))


def test_windowed_slope_is_symmetric_whatever_the_grid():
    """y = a x + b x^2: over a symmetric window the even term has no slope, so the windowed
    slope is a on any grid; a plain fit over the samples inside the window is biased when
    the grid stops short of one end (the rig's pad grid: -49.09 ... +49.96 mm)."""
    from elastokin.physics.wheel import windowed_slope

    a, b = -0.004, 3e-4  # deg/mm, deg/mm^2
    x = np.r_[np.linspace(-90.0, -49.09, 40), np.linspace(-48.2, 49.96, 117), 51.0, 90.0]
    y = a * x + b * x ** 2
    biased = slope(x, y, (-50.0, 50.0))
    assert abs(biased / a - 1.0) > 0.05  # the plain fit inside the window: 7 % off here
    # linear interpolation between samples ~1.3 mm apart adds b h^2 / 8 between nodes, not
    # exactly symmetric about 0: 1.3e-5 of the slope measured, 7e-5 on the short data
    assert windowed_slope(x, y, 50.0) == pytest.approx(a, rel=2e-4)
    # data short of the window: the largest symmetric window they cover
    short = np.abs(x) <= 30.0
    assert windowed_slope(x[short], y[short], 50.0) == pytest.approx(a, rel=2e-4)


def test_gradients_leave_the_approach_out():
    """Summary gradients use the measured rows: an approach with another slope (the path from
    the design position to rebound) must not bend bump camber."""
    from elastokin.rig.characteristics import summary_figures
    from elastokin.rig.sweeps import Sweep

    stroke = np.linspace(-90.0, 90.0, 19)
    approach = np.linspace(-10.0, -80.0, 8)
    travel = np.r_[approach, stroke]
    camber = np.r_[0.5 * approach, -0.02 * stroke]  # deg: the stroke's slope is -0.02 deg/mm
    branch = np.array(["approach"] * approach.size + ["stroke"] * stroke.size)
    sw = Sweep("m", "parallel_travel", {"branch": branch, "wheel_travel_mm": travel,
                                        "camber_deg": camber, "toe_deg": 0.001 * travel,
                                        "pad_z_mm": travel})
    figures = summary_figures([sw], False)
    assert figures["bump_camber_deg_per_m"] == pytest.approx(-20.0, rel=1e-12)
    assert figures["bump_steer_deg_per_m"] == pytest.approx(1.0, rel=1e-12)
