"""One bushing between the ground and a block: a known force or torque in each of its six
directions, in a rotated bushing frame, must give the inverse of the force-deflection law."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from elastokin.config.variants import DesignState
from elastokin.mbs.design import build_model
from elastokin.mbs.model import ModelOptions
from elastokin.physics.laws import DirectionLaw
from elastokin.rig.pad import run_pad

from .conftest import make_suspension

EULER = [30.0, 50.0, 70.0]  # z-x-z, deg: a frame far from the global axes
CENTRE = [100.0, 200.0, 300.0]
LINEAR = {"x": 300.0, "y": 500.0, "z": 900.0, "rx": 1600.0, "ry": 2500.0, "rz": 4000.0}
PROGRESSIVE_T = {"deflection": [-6.0, -2.0, 0.0, 2.0, 6.0],
                 "load": [-4000.0, -800.0, 0.0, 800.0, 4000.0]}         # mm, N
PROGRESSIVE_R = {"deflection": [-20.0, -5.0, 0.0, 5.0, 20.0],
                 "load": [-60000.0, -8000.0, 0.0, 8000.0, 60000.0]}     # deg, N*mm
NONLINEAR = {"x": PROGRESSIVE_T, "y": PROGRESSIVE_T, "z": PROGRESSIVE_T,
             "rx": PROGRESSIVE_R, "ry": PROGRESSIVE_R, "rz": PROGRESSIVE_R}


def block_on_bushing(stiffness):
    return make_suspension({
        "elastokin": 1, "name": "block on one bushing", "units": {},
        "frame": {"x": "forward", "y": "left"}, "side": "left", "ground": "ground",
        "hardpoints": {"C": CENTRE},
        "parts": {"block": {}},
        "wheel": {"part": "block", "centre": "C", "spin_axis": [0, 1, 0],
                  "loaded_radius_mm": 300},
        "connections": {"B": {"type": "bushing", "parts": ["ground", "block"], "at": "C",
                              "euler_zxz_deg": EULER, "stiffness": stiffness,
                              "ideal_joint": "fixed"}},
        "design": {"wheel_load_N": 1000},  # not balanced: no spring
    })


def law(spec) -> DirectionLaw:
    if isinstance(spec, float):
        return DirectionLaw.linear(spec)
    return DirectionLaw(tuple(spec["deflection"]), tuple(spec["load"]))


@pytest.mark.parametrize("stiffness", [LINEAR, NONLINEAR], ids=["linear", "nonlinear"])
@pytest.mark.parametrize("user_functions", ["symbolic", "python"])
@pytest.mark.parametrize("direction", range(6))
@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_deflection_is_inverse_law(stiffness, user_functions, direction, sign):
    s = block_on_bushing(stiffness)
    frame = Rotation.from_euler("ZXZ", EULER, degrees=True).as_matrix()
    assert np.allclose(s.bushings[0].frame, frame)
    name = ("x", "y", "z", "rx", "ry", "rz")[direction]
    magnitude = 2500.0 if direction < 3 else 30000.0   # N or N*mm: beyond the first segment
    load_local = np.zeros(3)
    load_local[direction % 3] = sign * magnitude
    wrench = np.zeros(6)
    wrench[3 * (direction // 3):3 * (direction // 3) + 3] = frame @ load_local  # global
    # no design balancing and no assembly check: the block is not a suspension
    model = build_model(s, ModelOptions(user_functions=user_functions), DesignState({}, {}))
    state = run_pad(model, pad_loads=np.zeros((1, 3)), centre_loads=wrench[None, :])[-1]
    u = state.bushing_deflection["B"]
    expected = np.zeros(6)
    expected[direction] = law(stiffness[name]).deflection_at(sign * magnitude)
    # solver tolerance: Newton residual 1e-8 relative, 1e-6 absolute -> 1e-6 mm / deg
    np.testing.assert_allclose(u, expected, atol=1e-6 * max(1.0, abs(expected[direction])))
    # the bushing's own load output is the applied load, in its frame
    np.testing.assert_allclose(state.bushing_load["B"][direction], sign * magnitude, rtol=1e-6)
