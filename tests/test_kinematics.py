"""Kinematic pseudo-McPherson against an independent loop-closure solution, and the
elastokinematic model's convergence to it as the bushings stiffen."""

import copy

import numpy as np
import pytest
from scipy.optimize import least_squares
from scipy.spatial.transform import Rotation

from elastokin.config.variants import kinematic
from elastokin.mbs.design import build_model
from elastokin.mbs.model import ModelOptions
from elastokin.physics.wheel import camber_deg, toe_deg
from elastokin.rig.load_cases import parallel_travel, travel_path

from .conftest import make_suspension


def loop_closure_curves(s, pad_z):
    """Toe and camber of the kinematic pseudo-McPherson by its loop-closure equations.

    Unknown: the knuckle pose (rotation vector r, translation t) relative to the design.
    With the bushings replaced by spherical joints the arms are links J1-J8 and J2-J7, the
    tie rod a link J3-J6, the strut rod pivots at J4 and slides/turns in the knuckle's tube
    (axis J5->J4, so J4 stays on the knuckle's strut axis); the pad sets the height of the
    wheel's lowest point (the contact point, wherever the knuckle's pitch puts it on the
    tyre).
    """
    hp = s.hardpoints
    patch = s.wheel.contact_patch_mm
    axis0 = (hp["J4"] - hp["J5"]) / np.linalg.norm(hp["J4"] - hp["J5"])
    links = [("J1", "J8"), ("J2", "J7"), ("J3", "J6")]
    lengths = [np.linalg.norm(hp[b] - hp[a]) for a, b in links]

    def residual(x, dz):
        R = Rotation.from_rotvec(x[:3]).as_matrix()

        def moved(p):
            return R @ (p - patch) + patch + x[3:]

        res = [np.linalg.norm(moved(hp[b]) - hp[a]) - length
               for (a, b), length in zip(links, lengths)]
        res += list(np.cross(hp["J4"] - moved(hp["J5"]), R @ axis0))
        # the pad holds the wheel's lowest point: the loaded radius below the centre,
        # reduced by the spin axis' vertical component (the wheel plane's tilt)
        spin = R @ s.wheel.spin_axis
        lowest = moved(s.wheel.centre_mm)[2] - s.wheel.loaded_radius_mm * np.sqrt(
            1.0 - spin[2] ** 2)
        res.append(lowest - patch[2] - dz)
        return np.array(res)

    x = np.zeros(6)
    toe, camber = [], []
    for dz in pad_z:
        # solved for x + 1: least_squares' step tolerance is relative to |x|, which at the
        # design position (x ~ 1e-14 on the return to it) would stop it before its first step
        sol = least_squares(lambda y, dz: residual(y - 1.0, dz), x + 1.0, args=(dz,),
                            xtol=1e-15, ftol=1e-15, gtol=1e-15)
        assert np.max(np.abs(sol.fun)) < 1e-9
        x = sol.x - 1.0
        spin = Rotation.from_rotvec(x[:3]).as_matrix() @ s.wheel.spin_axis
        toe.append(toe_deg(spin, s.forward, s.outboard))
        camber.append(camber_deg(spin, s.forward, s.outboard, s.up))
    return np.array(toe), np.array(camber)


@pytest.fixture(scope="module")
def kinematic_sweep(case, case_design):
    return parallel_travel(build_model(kinematic(case), ModelOptions(), case_design),
                           "initial_kinematic")


def test_kinematic_model_matches_loop_closure(case, kinematic_sweep):
    tp = case.rig.parallel_travel
    z, _ = travel_path(tp.rebound_mm, tp.bump_mm, tp.step_mm, tp.unloading)
    toe, camber = loop_closure_curves(case, z)
    np.testing.assert_allclose(kinematic_sweep.columns["toe_deg"], toe, atol=1e-4, rtol=0)
    np.testing.assert_allclose(kinematic_sweep.columns["camber_deg"], camber, atol=1e-4,
                               rtol=0)
    # the sweep covers the whole +-90 mm stroke with a real steer curve, not a flat line
    assert np.ptp(toe) > 0.1


def scaled_case(data: dict, scale: float, directions=("x", "y", "z")) -> dict:
    for c in data["connections"].values():
        if c["type"] == "bushing":
            for d in directions:
                c["stiffness"][d] = c["stiffness"][d] * scale
    return data


def toe_error_to_kinematic(data, toe_kin, scale, directions):
    s = make_suspension(scaled_case(copy.deepcopy(data), scale, directions))
    sweep = parallel_travel(build_model(s), f"x{scale:g}")
    return float(np.max(np.abs(sweep.columns["toe_deg"] - toe_kin)))


def test_stiffer_bushings_converge_to_kinematic(case_dict, kinematic_sweep):
    """The kinematic model replaces each bushing by its ideal joint (spherical here), so the
    stiffness that must grow is that of the joint's constrained directions (translations).
    Each decade of it cuts the compliance steer by about ten."""
    toe_kin = kinematic_sweep.columns["toe_deg"]
    errors = [toe_error_to_kinematic(case_dict, toe_kin, k, ("x", "y", "z"))
              for k in (1.0, 10.0, 100.0, 1000.0)]
    assert all(b < 0.15 * a for a, b in zip(errors, errors[1:])), errors
    assert errors[-1] < 1e-3 * errors[0] * 1.5, errors


def test_all_directions_stiffer_stay_close_to_kinematic(case_dict, kinematic_sweep):
    """Scaling the rotational rates too makes the bushing torques grow as fast as the
    translational stiffness that resists them: the steer difference then levels off at a
    small, scale-independent value (a few thousandths of a degree here) instead of vanishing.
    """
    toe_kin = kinematic_sweep.columns["toe_deg"]
    all_dirs = ("x", "y", "z", "rx", "ry", "rz")
    e1, e100, e1000 = (toe_error_to_kinematic(case_dict, toe_kin, k, all_dirs)
                       for k in (1.0, 100.0, 1000.0))
    assert e100 < 0.1 * e1 and e1000 < 0.1 * e1
    assert e1000 < 0.01  # deg
