"""The right side of a mirrored axle is the mirror image of the left in every load case
(issue 18, correctness 6), on the real solver: the shipped double wishbone axle (shared rack,
anti-roll bar, rubber bushings, bump and rebound stops), the case study (decoupled
McPherson axle) and the double wishbone of tests/data with a bushing whose laws are not odd,
every load case of the rig.

The mirror (y -> -y about the centre plane) maps each load case onto itself, the right wheel
onto the left:

- symmetric inputs (parallel travel, vertical force, braking and traction in phase, lateral
  force in anti-phase, a static load given as mirror images): the right wheel at a step is the
  left wheel at the same step;
- inputs the mirror reverses (opposite travel, roll angle, steering-wheel angle, a lateral force
  or aligning torque in phase): the right wheel at input +x is the left wheel at -x;
- single wheel travel: the right wheel moving is the left wheel moving (two runs).

Per-wheel channels keep their meaning on each side (toe, camber, travel, outboard track
change, forces up and forward ...); those along the vehicle's y (wheel-centre lateral and y,
the lateral patch force, the steer angle) change sign, and of a mirrored bushing the deflection
along y, about x and about z (its frame is made right-handed again: config/axle.py). The axle
channels, the same in both wheels' sweeps, map onto themselves: at the mirrored step the roll
angle, roll moment, bar twist and torque and the roll centre's lateral position change sign
(so they are zero in the symmetric cases), the roll centre's height does not.

Tolerance: 1e-7 of each channel's largest magnitude over the whole run, plus 1e-6 (mm, deg,
N, N*mm: for the channels the symmetry makes zero throughout, ~1e-9 here): the
Newton tolerance is set to 1e-10 here, where the worst difference is 5e-9 of a channel's
scale (measured; at the default 1e-8 it is 6e-7, a bar bushing's deflection in roll).
"""

import warnings

import numpy as np
import pytest

from .axle_rigs import config, rig, run_cases, suspension

MIRRORED = {"wheel_centre_lateral_mm", "wheel_centre_y_mm", "contact_patch_fy_N",
            "steer_angle_deg"}
AXLE_ODD = {"roll_angle_deg", "roll_moment_Nmm", "arb_twist_deg", "arb_torque_Nmm",
            "roll_centre_lateral_mm"}
AXLE_EVEN = {"roll_centre_height_mm"}
#: drive columns (the same on both sides), and the input each reversed case mirrors
REVERSED = {"opposite_travel": "pad_z_mm", "roll_vertical_force": "roll_angle_deg",
            "steering": "steering_wheel_angle_deg", "lateral_force": "lateral_force_N",
            "aligning_torque": "aligning_torque_Nmm"}
INPUTS = {"branch", "pad_z_mm", "vertical_force_N", "lateral_force_N", "longitudinal_force_N",
          "aligning_torque_Nmm", "steering_wheel_angle_deg", "rack_travel_mm", "load_fraction",
          "roll_angle_deg"}
COARSE = rig(
    parallel_travel={"rebound_mm": -60, "bump_mm": 60, "step_mm": 10},
    vertical_force={"min_N": 3000, "max_N": 6000, "step_N": 250},
    lateral_force={"amplitude_N": 3000, "step_N": 500},
    longitudinal_force_patch={"amplitude_N": 3000, "step_N": 500},
    longitudinal_force_centre={"amplitude_N": 3000, "step_N": 500},
    aligning_torque={"amplitude_Nmm": 150000, "step_Nmm": 25000},
    opposite_travel={"rebound_mm": -40, "bump_mm": 40, "step_mm": 10},
    single_wheel_travel={"rebound_mm": -40, "bump_mm": 40, "step_mm": 10},
    roll_vertical_force={"amplitude_deg": 2.0, "step_deg": 0.5},
    steering={"amplitude_deg": 360.0, "step_deg": 45.0},
    static_load={"left": {"force_N": [-1000.0, 2000.0, 6000.0],
                          "torque_Nmm": [3000.0, 10000.0, 50000.0]},
                 "right": {"force_N": [-1000.0, -2000.0, 6000.0],
                           "torque_Nmm": [-3000.0, 10000.0, -50000.0]}, "steps": 4},
    lateral_force_anti_phase={"amplitude_N": 3000, "step_N": 500})
#: the same for the softer, lighter double wishbone of tests/data (wheel rate 9 N/mm)
SMALL = {**COARSE,
         "vertical_force": {"min_N": 3500, "max_N": 4500, "step_N": 100},
         "lateral_force": {"amplitude_N": 1500, "step_N": 100},
         "longitudinal_force_patch": {"amplitude_N": 1500, "step_N": 100},
         "longitudinal_force_centre": {"amplitude_N": 1500, "step_N": 100},
         "aligning_torque": {"amplitude_Nmm": 100000, "step_Nmm": 10000},
         "static_load": {"left": {"force_N": [-500.0, 1000.0, 4500.0],
                                  "torque_Nmm": [2000.0, 5000.0, 30000.0]},
                         "right": {"force_N": [-500.0, -1000.0, 4500.0],
                                   "torque_Nmm": [-2000.0, 5000.0, -30000.0]}, "steps": 4},
         "lateral_force_anti_phase": {"amplitude_N": 1500, "step_N": 100}}
TOL = 1e-7


def _run(data: dict) -> dict:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return run_cases(suspension(data, "mirror.yaml"))


def asymmetric_dw() -> dict:
    """tests/data/double_wishbone.yaml as a mirrored axle whose lower-arm bushing has laws
    that are not odd (F(-u) != -F(u)) in every direction: its mirror must reflect them."""
    d = config("double_wishbone.yaml")
    curve = {"deflection": [-3.0, -1.0, 0.0, 1.0, 3.0], "load": [-2.0, -0.8, 0.0, 1.0, 3.0]}
    rates = {"x": 5000, "y": 5000, "z": 1500, "rx": 200000, "ry": 200000, "rz": 1000}
    d["connections"]["lca_bushing"]["stiffness"] = {
        k: {"deflection": curve["deflection"], "load": [r * f for f in curve["load"]]}
        for k, r in rates.items()}
    d["axle"] = {"shared": ["rack"]}
    return d


@pytest.fixture(scope="module", params=["double_wishbone_axle.yaml", "pseudo_mcpherson.yaml",
                                        "asymmetric_bushing"])
def runs(request):
    d = asymmetric_dw() if request.param == "asymmetric_bushing" else config(request.param)
    for key in ("measurements", "kc_test"):
        d.pop(key, None)
    d["solver"] = {**d.get("solver", {}), "newton_tolerance": 1e-10}
    d["rig"] = SMALL if request.param == "asymmetric_bushing" else COARSE
    out = _run(d)
    d["rig"] = rig(single_wheel_travel={**COARSE["single_wheel_travel"], "moving": "right"})
    moved_right = _run(d)
    out[("single_wheel_travel", "right")] = moved_right[("single_wheel_travel", "right")]
    s = suspension(d, "mirror.yaml")
    items = [b.name for b in s.bushings] + [sp.name for sp in s.springs] + [
        st.name for st in s.stops]
    return out, items, s.axle.suffix


def right_name(col: str, items: list[str], suffix: str) -> str:
    """The right wheel's column of the left wheel's ``col`` (mirrored items renamed)."""
    for name in items:
        if f"_{name}_" in col and not name.endswith(suffix):
            return col.replace(f"_{name}_", f"_{name}{suffix}_", 1)
    return col


def sign(col: str) -> float:
    if col in MIRRORED:
        return -1.0
    if col.startswith("bushing_") and col.rsplit("_", 2)[-2] in ("y", "rx", "rz"):
        return -1.0
    return 1.0


def mirrored_steps(case: str, columns: dict) -> np.ndarray:
    """For every step, the left sweep's step that mirrors it."""
    n = columns["branch"].size
    if case not in REVERSED:
        return np.arange(n)
    x = columns[REVERSED[case]]
    return np.array([np.flatnonzero(np.isclose(x, -v, atol=1e-9))[0] for v in x])


def test_right_is_the_mirror_of_the_left_in_every_load_case(runs):
    out, items, suffix = runs
    cases = sorted({case for case, _ in out})
    assert len(cases) >= 10
    scale: dict[str, float] = {}
    for sw in out.values():
        for col, v in sw.columns.items():
            if col != "branch":
                scale[col] = max(scale.get(col, 0.0), float(np.nanmax(np.abs(v))))
    checked = 0
    for case in cases:
        left, right = out[(case, "left")].columns, out[(case, "right")].columns
        idx = mirrored_steps(case, left)
        for col, values in left.items():
            if col in INPUTS:
                continue
            if col in AXLE_ODD or col in AXLE_EVEN:
                expected = (-1.0 if col in AXLE_ODD else 1.0) * values[idx]
                got = right[col]
            else:
                expected, got = sign(col) * values[idx], right[right_name(col, items, suffix)]
            tol = TOL * scale[col] + 1e-6
            np.testing.assert_allclose(got, expected, rtol=0, atol=tol,
                                       err_msg=f"{case}: {col}")
            checked += 1
    assert checked > 200
