"""The shipped twist-beam axle (configs/twist_beam_axle.yaml) against results that do not
come from the model: the cross beam's roll stiffness in closed form, the parallel travel of
the same axle with a rigid cross beam (a rotation about the pivots' line), and on the bushed
axle Maxwell-Betti symmetry of the 12x12 compliance and the force-based roll centre against
the kinematic one in roll.

The beam alone (closed form). Each trailing arm turns about the common pivot axis (revolute
joints at the body bushings, x_p, z_p; no spring): an anti-phase wheel travel turns the left
arm by +phi and the right by -phi, so the beam's end sections turn by +-phi about y and
their shear centres (x_s, z_s) move by +-phi (z_s - z_p) fore-aft and +-phi (x_p - x_s)
vertically. The beam (length L, clamped in the arms) twists by 2 phi and bends through the
arms as a clamped-guided Timoshenko beam in each plane (end displacement D: stiffness
12 EI / (L^3 (1 + 12 EI / (GA L^2)))), the axial force is nil (the ends do not move along
the beam). Its energy is ``U = 1/2 k phi^2`` with

    k = 4 GJ / L + 48 EI_y (x_p - x_s)^2 / (L^3 (1 + P_y)) + 48 EI_z (z_p - z_s)^2 / (L^3 (1 + P_z))

(``P = 12 EI / (GA L^2)``, the vertical plane bending EI_y with GA_z, the horizontal EI_z
with GA_y). The patches, a lever ``a`` behind the pivots, move by ``+-a phi``: the roll angle
is ``2 a phi / t`` (t the track) and the roll stiffness ``k (t / (2 a))^2``.
"""

from __future__ import annotations

import copy
import warnings
from pathlib import Path

import numpy as np
import pytest

from elastokin.config.loading import read_yaml, suspension_from_dict
from elastokin.config.variants import kinematic
from elastokin.mbs.design import build_model, design_state
from elastokin.physics.axle_compliance import roll_from_compliance
from elastokin.physics.axle_sweeps import roll_stiffness_Nmm_per_deg
from elastokin.physics.instant_centres import force_based_roll_centre
from elastokin.physics.wheel import toe_deg
from elastokin.rig.axle_channels import design_track_mm
from elastokin.rig.axle_summary import iso_compliance
from elastokin.rig.load_cases import (
    drives,
    run_drive_sides,
    static_equilibrium,
    wheel_compliance,
)
from elastokin.rig.steering import SteeringAxisWarning

TWIST_BEAM = Path(__file__).resolve().parents[1] / "configs" / "twist_beam_axle.yaml"


def config() -> dict:
    return copy.deepcopy(read_yaml(TWIST_BEAM)[0])


def run(s, case: str, **spec):
    """The sweeps of one load case by side, with the rig of ``spec``."""
    model = build_model(s)
    drive = next(d for d in drives(s, kinematic=s.kinematic) if d.load_case == case)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", SteeringAxisWarning)  # a rear axle: no steering
        return {sw.side: sw for sw in run_drive_sides(model, "m", drive)}


def beam_alone(data: dict, rig: dict) -> dict:
    """The axle without spring and stops, the arms on revolute joints about the pivots'
    common axis (y), nothing balanced at the design position."""
    data["springs"], data["stops"] = {}, {}
    data["design"] = {"wheel_load_N": data["design"]["wheel_load_N"]}
    data["connections"]["arm_bushing"] = {"type": "revolute", "parts": ["body", "trailing_arm"],
                                          "at": "arm_pivot", "axis": [0.0, 1.0, 0.0]}
    data["rig"] = rig
    # the beam bends through the arms here (the shipped axle's ball joints let the arms roll
    # with it): 8 elements per half, whose error in bending is 0.4 %
    data["parts"]["cross_beam"]["beam"]["elements_per_segment"] = 8
    return data


def closed_form_roll_stiffness_Nmm_per_deg(data: dict) -> float:
    hp = data["hardpoints"]
    sec = data["parts"]["cross_beam"]["beam"]["section"]
    L = 2.0 * hp["beam_end"][1]
    x_p, z_p = hp["arm_pivot"][0], hp["arm_pivot"][2]
    x_s, z_s = hp["beam_end"][0], hp["beam_end"][2] + sec["shear_centre_mm"][1]
    a = hp["arm_pivot"][0] - hp["wheel_centre"][0]  # the patch is below the wheel centre
    t = 2.0 * hp["wheel_centre"][1]
    EA = {k: float(v) for k, v in sec.items() if k != "z_axis" and k != "shear_centre_mm"}

    def bending(EI, GA, d):
        return 48.0 * EI * d**2 / (L**3 * (1.0 + 12.0 * EI / (GA * L**2)))

    k = (4.0 * EA["GJ_Nmm2"] / L + bending(EA["EI_y_Nmm2"], EA["GA_z_N"], x_p - x_s)
         + bending(EA["EI_z_Nmm2"], EA["GA_y_N"], z_p - z_s))
    return k * (t / (2.0 * a)) ** 2 * np.pi / 180.0


SMALL_TRAVEL = {"parallel_travel": {"rebound_mm": -2, "bump_mm": 2, "step_mm": 1},
                "vertical_force": None, "lateral_force": None,
                "longitudinal_force_patch": None, "longitudinal_force_centre": None,
                "aligning_torque": None,
                "opposite_travel": {"rebound_mm": -1, "bump_mm": 1, "step_mm": 0.5,
                                    "unloading": False}}


@pytest.mark.parametrize("where", ["shipped", "shear_centre_on_the_pivot_axis"])
def test_roll_stiffness_of_the_beam_alone_is_the_closed_form(where):
    """The shipped layout (bending through the arms dominates: 2 % of k is torsion) and the
    beam moved so that its shear centre lies on the pivots' axis (torsion alone)."""
    data = beam_alone(config(), SMALL_TRAVEL)
    if where != "shipped":
        e = data["parts"]["cross_beam"]["beam"]["section"]["shear_centre_mm"][1]
        x_p, _, z_p = data["hardpoints"]["arm_pivot"]
        for name in ("beam_centre", "beam_end"):
            data["hardpoints"][name] = [x_p, data["hardpoints"][name][1], z_p - e]
    sw = run(suspension_from_dict(data, "beam.yaml"), "opposite_travel")["left"]
    model = roll_stiffness_Nmm_per_deg(sw.columns["roll_angle_deg"],
                                       sw.columns["roll_moment_Nmm"])
    expected = closed_form_roll_stiffness_Nmm_per_deg(data)
    # the elements' error, 0.4 % with 8 per half in bending (docs/beams.md), none in torsion
    assert model == pytest.approx(expected, rel=0.01 if where == "shipped" else 1e-4)
    if where == "shipped":  # 4.45e5 N*mm/deg: 97.6 % bending, the mesh 0.37 % stiff
        assert model / expected - 1 == pytest.approx(0.0037, abs=0.002)


def test_parallel_travel_is_that_of_a_rigid_cross_beam():
    """Without spring and loads (ideal joints) the beam does not deform in parallel travel:
    each wheel moves as on a rigid axle turning about the line through the two pivots' ball
    joints (y, by symmetry). That rotation, found for each step from the wheel centre's
    height (written here), gives its fore-aft and lateral position, and leaves toe and camber
    at the design's: the wheel's lowest point (the contact point, where the pad holds it) then
    moves as the centre does, by the pad's height from the static state. 2e-4 mm: twice the
    Newton solver's absolute tolerance with this beam (9.7e-5, 100 times its round-off floor),
    to which the joints close; a load on the beam moves the wheel by tenths of a mm."""
    data = config()
    data["springs"], data["stops"] = {}, {}
    data["design"] = {"wheel_load_N": data["design"]["wheel_load_N"]}
    # the bushings' ideal joints as joints (a kinematic bushing keeps a regularising rate)
    data["connections"]["arm_bushing"] = {"type": "spherical", "parts": ["body", "trailing_arm"],
                                          "at": "arm_pivot"}
    data["rig"] = {**SMALL_TRAVEL, "parallel_travel": {"rebound_mm": -60, "bump_mm": 60,
                                                       "step_mm": 20, "unloading": False},
                   "opposite_travel": None}
    sweeps = run(suspension_from_dict(data, "beam.yaml"), "parallel_travel")
    hp = data["hardpoints"]
    centre0 = np.asarray(hp["wheel_centre"], float)
    r_centre = centre0 - hp["arm_pivot"]  # x, z relative to the pivots' line
    for side in ("left", "right"):
        cols = sweeps[side].columns
        z = cols["wheel_centre_z_mm"] - centre0[2]
        # the turn a about y lifting the centre by z: -r_x sin(a) + r_z cos(a) = r_z + z
        rho = np.hypot(r_centre[0], r_centre[2])
        a = np.arctan2(-r_centre[2], -r_centre[0]) + np.arcsin((r_centre[2] + z) / rho)
        x = r_centre[0] * np.cos(a) + r_centre[2] * np.sin(a) - r_centre[0]
        rest = z[cols["pad_z_mm"] == 0.0]  # the static state (the pads move from it)
        np.testing.assert_allclose(cols["wheel_centre_x_mm"] - centre0[0], x, atol=2e-4)
        np.testing.assert_allclose(np.abs(cols["wheel_centre_y_mm"]), centre0[1], atol=2e-4)
        np.testing.assert_allclose(z - rest, cols["pad_z_mm"], atol=2e-4)
        for c in ("toe_deg", "camber_deg"):
            np.testing.assert_allclose(cols[c], 0.0, atol=1e-12)
    assert np.ptp(sweeps["left"].columns["pad_z_mm"]) == 120.0


@pytest.fixture(scope="module")
def bushed():
    """The shipped axle, its design state and its model."""
    s = suspension_from_dict(config(), str(TWIST_BEAM))
    state = design_state(s)
    return s, state, build_model(s, design=state)


def test_maxwell_betti_on_the_bushed_axle(bushed):
    """The 12x12 compliance (rotations in rad per N*mm) is symmetric: 1e-3 of the diagonal
    scale (central differences of a nonlinear model, as the corner's test)."""
    s, _, model = bushed
    C = wheel_compliance(model)
    Cr = C.copy()
    for k in (3, 4, 5, 9, 10, 11):
        Cr[k, :] = np.radians(Cr[k, :])
    scale = np.sqrt(np.outer(np.abs(np.diag(Cr)), np.abs(np.diag(Cr))))
    assert np.max(np.abs(Cr - Cr.T) / scale) < 1e-3
    # the sides are coupled by the beam: a vertical force on one wheel moves the other
    assert abs(C[8, 2]) > 0.05 * C[2, 2]


def test_roll_centre_and_roll_steer_in_roll():
    """The twist beam's kinematic roll centre comes from opposite wheel travel; with every
    bushing an ideal joint it is ADAMS/Car's force-based one (opposing vertical forces, the
    12x12 compliance) to 1 mm. The roll test's roll camber is ADAMS/Car's (SVCROL, from the
    compliance) to 0.5 %; its roll steer, the heading of the spin axis, is the compliance's
    response turning the static spin axis to 0.5 %, while ADAMS/Car's steer change (the
    rotation about the vertical, C(6,3) - C(6,9)) leaves out the static camber (0.1 deg here,
    the beam's deflection under the design load) turned by the arm's large pitch: 2.4 %."""
    data = config()
    data["rig"] = {**SMALL_TRAVEL, "roll_vertical_force": {"amplitude_deg": 0.5,
                                                          "step_deg": 0.125}}
    s = kinematic(suspension_from_dict(data, "beam.yaml"))
    model = build_model(s)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", SteeringAxisWarning)
        sweeps = {d.load_case: {sw.side: sw for sw in run_drive_sides(model, "m", d)}
                  for d in drives(s, kinematic=True) if d.load_case in (
                      "parallel_travel", "opposite_travel", "roll_vertical_force")}
    Ci = iso_compliance(wheel_compliance(model), s)  # the config frame is ISO's
    wc = {side: w.centre_mm for side, w in s.wheels.items()}
    cp = {side: w.contact_patch_mm for side, w in s.wheels.items()}
    force_based = force_based_roll_centre(Ci, wc["left"], wc["right"], cp["left"],
                                          cp["right"]).height_mm
    opposite = sweeps["opposite_travel"]["left"].columns
    kinematic_rc = opposite["roll_centre_height_mm"][np.flatnonzero(
        opposite["pad_z_mm"] == 0.0)[0]]
    assert kinematic_rc == pytest.approx(force_based, abs=1.0)
    assert 150.0 < kinematic_rc < 250.0  # between the ground and the beam's shear centre
    # parallel travel: no kinematic roll centre for an axle joined by a flexible beam
    assert "roll_centre_height_mm" not in sweeps["parallel_travel"]["left"].columns
    cols = sweeps["roll_vertical_force"]["left"].columns
    steer, camber = (np.polyfit(cols["roll_angle_deg"], cols[c], 1)[0]
                     for c in ("toe_deg", "camber_deg"))
    adams = roll_from_compliance(Ci, design_track_mm(s))
    assert camber == pytest.approx(adams["roll_camber_left_deg_per_deg"], rel=0.005)
    assert steer / adams["roll_steer_left_deg_per_deg"] - 1 == pytest.approx(0.024, abs=0.003)
    # the compliance's response to opposing vertical forces turning the static spin axis
    u = Ci[:, 2] - Ci[:, 8]
    roll_deg = -np.degrees(np.arctan((u[2] - u[8]) / design_track_mm(s)))
    spin = static_equilibrium(model).state.spin_axis
    turn = np.cross(np.radians(u[3:6]), spin) * 1e-3  # per mN: linear
    forward, outboard = np.array([1.0, 0.0, 0.0]), np.array([0.0, 1.0, 0.0])
    toe_change = (toe_deg(spin + turn, forward, outboard)
                  - toe_deg(spin - turn, forward, outboard)) / 2e-3
    assert steer == pytest.approx(toe_change / roll_deg, rel=0.005)
    # the bumped (outer, right) wheel toes in: roll understeer of a rear axle ([S1])
    assert steer < 0 < adams["roll_steer_right_deg_per_deg"]


def test_adams_car_export_and_import(tmp_path, bushed):
    """The twist beam exports as ADAMS/Car keeps a suspension (hardpoints, bushings, the
    spring) and imports back onto its template config: the hardpoints and the bushing laws
    exactly; the flexible beam is not exported (a warning says why and the subsystem file
    carries its section as comments), the template's is kept."""
    from elastokin.formats.adams.export import export_adams
    from elastokin.formats.adams.importing import import_adams_axle, subsystem_files
    from elastokin.formats.adams.mapping import read_mapping

    from .suspension_checks import assert_same_bushings

    s, state, _ = bushed
    warned: list[str] = []
    db = tmp_path / "tb.cdb"
    export_adams(s, db, state.bushing_preload, spring_force=state.spring_force_N,
                 warnings=warned)
    assert any("'cross_beam' are not exported" in w and "Flexible body" in w
               for w in warned), warned
    (sub,) = (db / "subsystems.tbl").glob("*.sub")
    text = sub.read_text()
    assert "NOT EXPORTED: elastokin flexible beam part 'cross_beam'" in text
    assert "GJ 1.283e+09 N*mm^2" in text
    data = config()
    template = copy.deepcopy(data)
    template["hardpoints"] = {k: [v[0] + 5.0, v[1] if v[1] == 0.0 else v[1] - 5.0, v[2] + 5.0]
                              for k, v in template["hardpoints"].items()}
    template["connections"]["arm_bushing"]["stiffness"] = {
        d: 2.0 * v for d, v in data["connections"]["arm_bushing"]["stiffness"].items()}
    mapping = read_mapping(db / "mapping.yaml")
    cfg, warnings_, _ = import_adams_axle(template, subsystem_files(mapping, db),
                                          db / "mapping.yaml")
    assert warnings_ == []
    assert cfg["hardpoints"] == data["hardpoints"]
    assert cfg["parts"]["cross_beam"] == data["parts"]["cross_beam"]  # the template's beam
    back = suspension_from_dict(cfg, "imported.yaml")
    assert_same_bushings(s, back, np.linspace(-20.0, 20.0, 81))


def test_the_refinement_study_runs_quick(tmp_path, monkeypatch, capsys):
    """benchmarks/beam_refinement.py --quick (1 and 2 elements per half, a short rig): its
    figures written, the roll figures already within 0.1 % of each other (torsion is exact in
    one element)."""
    import json
    import runpy
    import sys

    out = tmp_path / "refinement.json"
    monkeypatch.setattr(sys, "argv", ["beam_refinement.py", "--quick", "--out", str(out)])
    runpy.run_path(str(TWIST_BEAM.parents[1] / "benchmarks" / "beam_refinement.py"),
                   run_name="__main__")
    result = json.loads(out.read_text())
    one, two = (m["figures"] for m in result["meshes"])
    assert result["quick"] and [m["elements_per_segment"] for m in result["meshes"]] == [1, 2]
    assert one["roll_stiffness_Nmm_per_deg"] == pytest.approx(two["roll_stiffness_Nmm_per_deg"],
                                                              rel=1e-3)
    assert "| roll stiffness [N*mm/deg] |" in capsys.readouterr().out
