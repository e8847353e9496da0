import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from elastokin.physics.wheel import camber_deg, slope, spin_axis_from_angles, toe_deg

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
    with pytest.raises(ValueError):
        slope([1.0], [2.0])
