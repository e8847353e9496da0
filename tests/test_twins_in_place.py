"""Twins in place (mbs/geometry.py, mbs/twins.py): the model with another design's
parameters set in place has the residual of a model built for that design (bit for bit, at
any state), and gets its own back afterwards; a change it cannot take in place (a nonlinear
bushing law) builds a model."""

import copy

import numpy as np
import pytest

from elastokin.config.design_variables import DesignVariable, design_suspension
from elastokin.config.loading import read_yaml
from elastokin.config.variants import DesignState
from elastokin.errors import ModelError
from elastokin.mbs.design import build_model, design_state
from elastokin.mbs.model import SuspensionModel
from elastokin.mbs.sensitivity import Residual
from elastokin.mbs.twins import twin_model
from elastokin.rig.pad import attach_pads

from .conftest import ROOT, make_suspension


def residual_at(model, y, t=0.5):
    """The model's static residual at coordinates and multipliers ``y`` (time ``t``)."""
    model.mbs.Assemble()
    res = Residual(model, 1, "test")
    try:
        res.set_state(t, y[:res.n2], y[res.n2:])
        return res.residual().copy()
    finally:
        res.close()


def nominal(name):
    data = read_yaml(ROOT / "configs" / f"{name}.yaml")[0]
    data.pop("measurements", None)
    data.pop("kc_test", None)
    return make_suspension(data, str(ROOT / "configs" / f"{name}.yaml"))


@pytest.mark.parametrize("name, variable, value", [
    ("double_wishbone_axle", DesignVariable("hardpoint", "wheel_centre", 1), 3.0),
    ("double_wishbone_axle", DesignVariable("spring_rate", "coil"), 20.0),
    ("pseudo_mcpherson", DesignVariable("hardpoint", "J3", 2), -2.5),
    ("pseudo_mcpherson", DesignVariable("bushing_scale", "J1", directions=("x", "y")), 0.3),
])
def test_twin_in_place_has_the_residual_of_a_built_model(name, variable, value):
    s = nominal(name)
    design = design_state(s)
    moved = design_suspension(s, [variable], [variable.value(s.raw) + value])
    # the design preloads moved too (as a twin's are: along their derivative)
    preloads = DesignState({k: v + 10.0 for k, v in design.spring_force_N.items()},
                           {k: np.asarray(v) * 1.01 for k, v in design.bushing_preload.items()})
    model = build_model(s, design=design)
    attach_pads(model)
    twin = twin_model(model, moved, preloads)
    assert twin.in_place
    built = SuspensionModel(moved, model.options, preloads, references=model.ref)
    attach_pads(built)
    model.mbs.Assemble()
    sd = model.mbs.systemData
    rng = np.random.default_rng(1)
    y = np.r_[1e-2 * rng.standard_normal(sd.ODE2Size()),
              rng.standard_normal(len(sd.GetAECoordinates()))]  # any state
    own = residual_at(model, y)
    with twin.applied():
        in_place = residual_at(model, y)
    assert np.array_equal(in_place, residual_at(built, y))
    assert not np.array_equal(in_place, own)
    assert np.array_equal(residual_at(model, y), own)  # its own parameters back


def test_a_nonlinear_bushing_law_is_no_change_in_place():
    data = read_yaml(ROOT / "configs" / "double_wishbone_axle.yaml")[0]
    data["connections"]["lca_bushing"]["stiffness"]["x"] = {
        "deflection": [-2, 0, 2, 4], "load": [-50000, 0, 40000, 120000]}
    s = make_suspension(data, "nonlinear.yaml")
    v = DesignVariable("bushing_scale", "lca_bushing", directions=("x",))
    model = build_model(s)
    twin = twin_model(model, design_suspension(s, [v], [1.1]), design_state(s))
    assert not twin.in_place and twin.model is not model


def test_a_change_the_rig_compiled_in_after_the_twin_was_made_is_refused():
    """The contact load (mbs/contact.py) compiles the wheel's loaded radius into its user
    function when the rig attaches it, after the twins were made: a twin with another radius
    is then refused by name, never evaluated with the model's radius."""
    data = read_yaml(ROOT / "configs" / "double_wishbone_axle.yaml")[0]
    s = make_suspension(copy.deepcopy(data), "radius.yaml")
    data["wheel"]["loaded_radius_mm"] += 5.0
    other = make_suspension(data, "radius.yaml")
    design = design_state(s)
    model = build_model(s, design=design)
    twin = twin_model(model, other, design)
    assert twin.in_place
    attach_pads(model)
    with pytest.raises(ModelError, match="loaded radius"):
        with twin.applied():
            pass
