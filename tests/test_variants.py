"""Model variants as typed overrides of one template (elastokin.config.variants)."""

import pickle

import numpy as np
import pytest

from elastokin.config.loading import load_suspension
from elastokin.config.variants import (
    compliant,
    kinematic,
    with_bushing_laws,
    with_hardpoints,
    with_joint_shifts,
)
from elastokin.errors import ConfigError
from elastokin.physics.laws import DirectionLaw

from .conftest import ROOT

DW = ROOT / "tests" / "data" / "double_wishbone.yaml"


@pytest.fixture(scope="module")
def dw():
    return load_suspension(DW)


def test_overrides_leave_the_template_alone(dw):
    before = pickle.dumps(dw)
    k = kinematic(dw)
    assert all(b.kinematic for b in k.bushings) and k.kinematic
    assert not any(b.kinematic for b in compliant(k).bushings)
    law = DirectionLaw.linear(123.0)
    name = dw.bushings[0].name
    stiff = with_bushing_laws(dw, {name: (law,) * 6})
    assert stiff.bushings[0].laws[0](1.0) == pytest.approx(123.0)
    joint = dw.joints[0]
    shifted = with_joint_shifts(dw, {joint.name: (np.zeros(3), np.array([0.1, 0.0, 0.0]))})
    assert shifted.joints[0].part_shift_mm[1][0] == 0.1
    assert pickle.dumps(dw) == before  # frozen: nothing edited in place


def test_moved_hardpoint_moves_what_refers_to_it(dw):
    """A joint at the hardpoint moves with it by exactly the shift; the rest stays."""
    joint = next(j for j in dw.joints if j.kind == "spherical")
    name = next(k for k, v in dw.hardpoints.items() if np.array_equal(v, joint.position_mm))
    moved = with_hardpoints(dw, {name: dw.hardpoints[name] + [0.0, 0.0, 2.5]})
    again = next(j for j in moved.joints if j.name == joint.name)
    np.testing.assert_array_equal(again.position_mm - joint.position_mm, [0.0, 0.0, 2.5])
    others = [(a, b) for a, b in zip(dw.joints, moved.joints) if a.name != joint.name]
    assert all(np.array_equal(a.position_mm, b.position_mm) for a, b in others)


def test_unknown_names_are_clear_errors(dw):
    with pytest.raises(ConfigError, match="no bushing nope"):
        with_bushing_laws(dw, {"nope": ()})
    with pytest.raises(ConfigError, match="no hardpoint nowhere"):
        with_hardpoints(dw, {"nowhere": [0.0, 0.0, 0.0]})
