import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from elastokin.config.schema.base import CurveSpec
from elastokin.physics.laws import DirectionLaw, law_from_spec


def progressive():
    # a typical rubber curve: soft about zero, stiffening with deflection (mm, N)
    return DirectionLaw((-4.0, -2.0, 0.0, 2.0, 4.0), (-3000.0, -800.0, 0.0, 800.0, 3000.0))


def test_linear_law_is_rate_times_deflection():
    law = DirectionLaw.linear(300.0)
    assert law(2.0) == pytest.approx(600.0)
    assert law.deflection_at(-450.0) == pytest.approx(-1.5)
    assert law.is_linear and law.rate_at_zero == 300.0


def test_piecewise_values_and_linear_extrapolation():
    law = progressive()
    assert law(1.0) == pytest.approx(400.0)
    assert law(3.0) == pytest.approx(1900.0)
    # beyond the table: the last segment's slope (1100 N/mm) continues
    assert law(5.0) == pytest.approx(3000.0 + 1100.0)
    assert law(-5.0) == pytest.approx(-4100.0)
    assert not law.is_linear


@given(st.floats(-10.0, 10.0))
@settings(max_examples=60, deadline=None)
def test_inverse_and_hinge_form_agree(u):
    law = progressive()
    assert law.deflection_at(law(u)) == pytest.approx(u, abs=1e-9)
    k0, c, hinges = law.hinges()
    hinge_value = c + k0 * u + sum(dk * max(u - ui, 0.0) for ui, dk in hinges)
    assert hinge_value == pytest.approx(law(u), abs=1e-9)


def test_scaled_law_scales_loads_only():
    law = progressive().scaled(10.0)
    assert law(3.0) == pytest.approx(19000.0)
    assert law.deflection_at(19000.0) == pytest.approx(3.0)


@pytest.mark.parametrize("deflection, load", [
    ((0.0, 1.0, 1.0), (0.0, 1.0, 2.0)),      # deflection not strictly increasing
    ((-1.0, 0.0, 1.0), (1.0, 0.0, -1.0)),    # load decreasing
    ((1.0, 2.0), (100.0, 300.0)),            # extrapolates to -100 N at zero
])
def test_bad_curves_are_rejected(deflection, load):
    with pytest.raises(ValueError):
        DirectionLaw(deflection, load)


def test_law_from_a_rate_a_curve_spec_and_a_config_dict():
    """A config entry as validated (CurveSpec) and as read (a dict) gives the same law."""
    curve = {"deflection": [-4.0, -2.0, 0.0, 2.0, 4.0], "load": [-3000.0, -800.0, 0.0, 800.0,
                                                                   3000.0]}
    assert law_from_spec(curve) == law_from_spec(CurveSpec(**curve)) == progressive()
    assert law_from_spec(300) == law_from_spec(300.0) == DirectionLaw.linear(300.0)
    with pytest.raises(ValueError, match="strictly increasing"):
        law_from_spec({"deflection": [0.0, 1.0, 1.0], "load": [0.0, 1.0, 2.0]})
