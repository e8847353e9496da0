"""Loads (issue 27): every part's free-body balance from the reported loads, the body pickups
against the contact patches, a two-force member, a double wishbone against statics written
here, the contact-patch forces of vehicle accelerations against the rigid vehicle's balance,
bad vehicle data, and what ``elastokin kc`` writes.

Tolerances: the solves here run full Newton to a relative tolerance of 1e-10, so that the
residual of every part's equations is ~1e-11 of the loads; "1e-9 of the applied load" is
then a check of the reported loads, not of the solver.
"""

from __future__ import annotations

import json
import warnings

import numpy as np
import pytest
from click.testing import CliRunner

from elastokin.cli.main import main
from elastokin.config.variants import kinematic
from elastokin.errors import ConfigError
from elastokin.mbs.design import build_model
from elastokin.physics.loads import (
    FORCE,
    FORCE_LOCAL,
    MOMENT,
    POINT,
    ground_loads,
    part_balance,
    resultant,
)
from elastokin.physics.vehicle_loads import G, VehicleData, wheel_loads
from elastokin.rig.load_cases import run_load_cases_sides
from elastokin.rig.pad import run_pad
from elastokin.rig.steering import SteeringAxisWarning

from .axle_rigs import config, rig, suspension

TIGHT = {"newton_tolerance": 1e-10, "modified_newton": False, "max_newton_iterations": 50}
#: a few steps of the cases that load a suspension differently (vertical, lateral, traction at
#: the wheel centre, roll on the heave beam, steering, a vehicle-acceleration case)
CASES = rig(parallel_travel={"rebound_mm": -40, "bump_mm": 40, "step_mm": 40,
                             "unloading": False},
            lateral_force={"amplitude_N": 2000, "step_N": 2000},
            longitudinal_force_centre={"amplitude_N": 2000, "step_N": 2000},
            roll_vertical_force={"amplitude_deg": 2, "step_deg": 2},
            steering={"amplitude_deg": 100, "step_deg": 100},
            vehicle_loads={"steps": 5, "cases": {
                "braking_cornering": {"longitudinal_g": -0.6, "lateral_g": 0.5}}})
MASSES = {"front": 1077.8, "rear": 1008.7}


def tight(name: str, **changes) -> dict:
    data = config(name)
    data["solver"] = {**data.get("solver", {}), **TIGHT}
    data.pop("measurements", None)
    data.pop("kc_test", None)
    data.update(changes)
    return data


def dw(**changes) -> dict:
    data = tight("double_wishbone_axle.yaml", **changes)
    data["axle"]["vehicle"]["axle_mass_kg"] = dict(MASSES)
    return data


def solved(data: dict, kinematic_model: bool = False):
    s = suspension(data)
    s = kinematic(s) if kinematic_model else s
    with warnings.catch_warnings():  # the twist beam has no steering axis, and says so
        warnings.simplefilter("ignore", SteeringAxisWarning)
        return s, run_load_cases_sides(build_model(s), "test")[s.side]


@pytest.fixture(scope="module")
def runs():
    """Every load case of CASES on five models: the double wishbone axle (bushings, rack,
    anti-roll bar, stops), its kinematic twin, the case study (bushings, a strut), the twist
    beam (a flexible cross beam welded to the arms) and a solid axle (one part carrying both
    wheels, a planar guide, an in-plane joint, a Panhard rod)."""
    corner_cases = {k: v for k, v in CASES.items() if k not in ("steering", "vehicle_loads")}
    return {"double_wishbone": solved(dw(rig=CASES)),
            "double_wishbone_kinematic": solved(dw(rig=CASES), True),
            "case_study": solved(tight("pseudo_mcpherson.yaml", rig=corner_cases)),
            "twist_beam": solved(tight("twist_beam_axle.yaml", rig=corner_cases)),
            "solid_axle": solved(tight("solid_axle_panhard.yaml", rig=corner_cases))}


def scales(table) -> tuple[float, float]:
    """The applied load (the largest contact-patch force, N) and its moment scale (times the
    largest distance of a point from the origin, N*mm)."""
    patches = [k for k, item in enumerate(table.items) if item.kind == "contact_patch"]
    force = float(np.abs(table.values[:, patches, FORCE]).max())
    return force, force * float(np.abs(table.values[:, :, POINT]).max())


@pytest.mark.parametrize("model", ["double_wishbone", "double_wishbone_kinematic",
                                   "case_study", "twist_beam", "solid_axle"])
def test_every_part_is_in_equilibrium_under_the_reported_loads(runs, model):
    s, sweeps = runs[model]
    cases = 0
    for sw in sweeps:
        force, moment = scales(sw.loads)
        for part, total in part_balance(sw.loads).items():
            if part == s.ground:
                continue
            assert np.abs(total[..., 0, :]).max() <= 1e-9 * force, (sw.load_case, part)
            assert np.abs(total[..., 1, :]).max() <= 1e-9 * moment, (sw.load_case, part)
        cases += 1
    assert cases >= 4


@pytest.mark.parametrize("model", ["double_wishbone", "case_study", "twist_beam",
                                   "solid_axle"])
def test_body_pickups_balance_the_contact_patches(runs, model):
    """The loads every ground pickup receives (connections, springs, stops, the steering
    gear) add up to the contact-patch loads at every step, force and moment."""
    s, sweeps = runs[model]
    for sw in sweeps:
        force, moment = scales(sw.loads)
        pickups = resultant(ground_loads(sw.loads, s.ground))
        patches = resultant(ground_loads(sw.loads, s.ground, ("contact_patch",)))
        # a patch's load is the road's on the wheel: as a ground item, the opposite of the body's
        assert np.abs(pickups[..., 0, :] + patches[..., 0, :]).max() <= 1e-9 * force
        assert np.abs(pickups[..., 1, :] + patches[..., 1, :]).max() <= 1e-9 * moment


def test_links_springs_and_stops_push_along_their_line(runs):
    _, sweeps = runs["double_wishbone"]
    sw = sweeps[0]
    for k, item in enumerate(sw.loads.items):
        if item.two_point:
            f = sw.loads.values[:, k, FORCE_LOCAL]
            assert np.abs(f[:, :2]).max() <= 1e-9 * max(1.0, np.abs(f).max()), item.name


def test_a_tie_rod_made_a_part_is_a_two_force_member():
    """The tie rod as a part between a ball joint (knuckle) and a universal joint (rack, its
    spin held): the forces on it are opposite and along its current axis, and its axial force
    is the link's of the shipped config."""
    cases = rig(parallel_travel={"rebound_mm": -60, "bump_mm": 60, "step_mm": 30,
                                 "unloading": False},
                lateral_force={"amplitude_N": 3000, "step_N": 1500})
    data = dw(rig=cases)
    _, as_link = solved(data)
    data["parts"]["tie_rod"] = {"description": "tie rod as a part"}
    data["connections"].pop("tie_rod")
    data["connections"]["tie_rod_outer"] = {"type": "spherical", "parts": ["tie_rod", "knuckle"],
                                            "at": "tierod_outer"}
    data["connections"]["tie_rod_inner"] = {
        "type": "universal", "parts": ["rack", "tie_rod"], "at": "tierod_inner",
        "torsion_axis": {"from": "tierod_inner", "to": "tierod_outer"}}
    _, as_part = solved(data)
    for link_sweep, part_sweep in zip(as_link, as_part):
        t = part_sweep.loads
        outer = t.values[:, t.names().index("tie_rod_outer")]  # on the rod, from the knuckle
        inner = t.values[:, t.names().index("tie_rod_inner")]  # on the rack, from the rod
        on_rod = [outer[:, FORCE], -inner[:, FORCE]]
        axis = outer[:, POINT] - inner[:, POINT]
        axis /= np.linalg.norm(axis, axis=1, keepdims=True)
        size = np.linalg.norm(on_rod[0], axis=1).max()
        assert np.abs(on_rod[0] + on_rod[1]).max() <= 1e-9 * size
        assert np.abs(np.cross(on_rod[0], axis)).max() <= 1e-8 * size
        assert np.abs(inner[:, MOMENT]).max() <= 1e-8 * size * 400.0  # the rod is ~400 mm
        link = link_sweep.loads.values[:, link_sweep.loads.names().index("tie_rod")]
        # the link's tension (local z from the rack to the knuckle) is the rod's
        tension = np.einsum("ni,ni->n", on_rod[0], axis)
        assert np.allclose(tension, link[:, FORCE_LOCAL, 2], rtol=1e-6, atol=1e-6 * size)


# ------------------------------------------------------------------ a double wishbone by hand
HAND = {
    "elastokin": 1, "name": "hand double wishbone", "units": {"length": "mm", "force": "N",
                                                              "angle": "deg"},
    "frame": {"x": "forward", "y": "left", "z": "up"}, "side": "left", "ground": "body",
    "hardpoints": {"lca_pivot": [0.0, 350.0, 0.0], "lca_outer": [0.0, 750.0, -20.0],
                   "uca_pivot": [-30.0, 460.0, 300.0], "uca_outer": [10.0, 700.0, 290.0],
                   "tr_inner": [-150.0, 380.0, 80.0], "tr_outer": [-140.0, 720.0, 90.0],
                   "spring_upper": [50.0, 520.0, 380.0], "spring_lower": [40.0, 560.0, 0.0],
                   "wheel_centre": [0.0, 820.0, 120.0]},
    "parts": {"lower_arm": {}, "upper_arm": {}, "knuckle": {}},
    "wheel": {"part": "knuckle", "centre": "wheel_centre", "spin_axis": [0.0, 1.0, 0.0],
              "loaded_radius_mm": 300.0},
    "connections": {
        "lca": {"type": "revolute", "parts": ["body", "lower_arm"], "at": "lca_pivot",
                "axis": [1.0, 0.0, 0.0]},
        "uca": {"type": "revolute", "parts": ["body", "upper_arm"], "at": "uca_pivot",
                "axis": (np.array([1.0, 0.0, 0.1]) / np.hypot(1.0, 0.1)).tolist()},
        "lbj": {"type": "spherical", "parts": ["lower_arm", "knuckle"], "at": "lca_outer"},
        "ubj": {"type": "spherical", "parts": ["upper_arm", "knuckle"], "at": "uca_outer"},
        "tie_rod": {"type": "link", "parts": ["body", "knuckle"], "at": ["tr_inner", "tr_outer"]}},
    "springs": {"coil": {"parts": ["body", "lower_arm"], "seats": ["spring_upper", "spring_lower"],
                         "rate_N_per_mm": 50.0}},
    "design": {"wheel_load_N": 4000.0, "balance_spring": "coil"},
    "solver": TIGHT,
}


def hand_statics(hp: dict, load: np.ndarray) -> dict[str, np.ndarray]:
    """The forces on the knuckle from the upper and lower ball joints and the tie rod
    (tension +), and the spring's compression, for a patch force ``load`` at the contact
    point: the knuckle's six equations and the upper arm's moment about its pivot axis."""
    p = {k: np.asarray(v, float) for k, v in hp.items()}
    patch = p["wheel_centre"] - [0.0, 0.0, 300.0]
    e = p["tr_inner"] - p["tr_outer"]
    e /= np.linalg.norm(e)
    a_u = np.array([1.0, 0.0, 0.1]) / np.linalg.norm([1.0, 0.0, 0.1])

    def skew(r):
        return np.array([[0, -r[2], r[1]], [r[2], 0, -r[0]], [-r[1], r[0], 0]])

    A = np.zeros((7, 7))
    b = np.zeros(7)
    A[:3, :3] = A[:3, 3:6] = np.eye(3)
    A[:3, 6] = e
    A[3:6, :3], A[3:6, 3:6] = skew(p["uca_outer"]), skew(p["lca_outer"])
    A[3:6, 6] = np.cross(p["tr_outer"], e)
    b[:3], b[3:6] = -load, -np.cross(patch, load)
    # the upper arm: no moment about its pivot axis of the ball joint's force on it (-F_u)
    A[6, :3] = -np.cross(a_u, p["uca_outer"] - p["uca_pivot"])
    u = np.linalg.solve(A, b)
    f_u, f_l, tension = u[:3], u[3:6], u[6]
    # the lower arm: the spring balances the ball joint about the pivot axis (x)
    s_hat = (p["spring_lower"] - p["spring_upper"]) / np.linalg.norm(
        p["spring_lower"] - p["spring_upper"])
    a_l = np.array([1.0, 0.0, 0.0])
    arm = np.cross(p["lca_outer"] - p["lca_pivot"], f_l) @ a_l
    compression = arm / (np.cross(p["spring_lower"] - p["lca_pivot"], s_hat) @ a_l)
    return {"ubj": f_u, "lbj": f_l, "tie_rod": tension, "coil": compression}


def test_a_double_wishbone_against_its_statics_by_hand():
    s = suspension(HAND, "hand_dw.yaml")
    state = run_pad(build_model(s), pad_z_mm=[0.0])[-1]  # the design position, held
    t = state.loads
    v = {item.name: t.values[k] for k, item in enumerate(t.items)}
    load = v["contact_patch_left"][FORCE]
    assert load == pytest.approx([0.0, 0.0, 4000.0], abs=1e-6)
    hand = hand_statics(HAND["hardpoints"], load)
    tol = 1e-9 * 4000.0  # the pad holds the design position: the geometry is the hardpoints'
    # a ball joint's load is on its first part, the arm: minus the force on the knuckle
    assert np.allclose(v["ubj"][FORCE], -hand["ubj"], rtol=0.0, atol=tol)
    assert np.allclose(v["lbj"][FORCE], -hand["lbj"], rtol=0.0, atol=tol)
    assert v["tie_rod"][FORCE_LOCAL][2] == pytest.approx(hand["tie_rod"], abs=tol)
    assert state.spring_force_N["coil"] == pytest.approx(hand["coil"], rel=1e-9)
    assert -v["coil"][FORCE_LOCAL][2] == pytest.approx(hand["coil"], rel=1e-9)
    assert np.linalg.norm(hand["lbj"]) > 3000.0 and abs(hand["tie_rod"]) > 10.0  # not trivial


# ------------------------------------------------------------------ vehicle accelerations
VEHICLE = {"front": VehicleData(600.0, 500.0, "front", 2600.0, 550.0, 1500.0, 0.65, 0.0,
                                None, "outboard", "inboard"),
           "rear": VehicleData(600.0, 500.0, "rear", 2600.0, 550.0, 1480.0, 0.35, 1.0,
                               None, "inboard", "outboard")}


@pytest.mark.parametrize("ax, ay, az", [(-1.0, 0.0, 0.0), (0.4, 0.0, 0.0), (0.0, 0.9, 0.0),
                                        (-0.7, -0.6, 0.3), (0.0, 0.0, 1.0)])
def test_vehicle_loads_balance_the_rigid_vehicle(ax, ay, az):
    """Both axles' tyre forces hold the vehicle (d'Alembert): they add up to m g (a_x, a_y,
    1 + a_z) and their moment about the centre of gravity is zero in roll and pitch; the
    axles carry m_axle g a_y laterally (no yaw acceleration); braking and drive shares."""
    m = 1100.0
    a = 2600.0 * 500.0 / m  # the CG behind the front axle
    x_axle = {"front": a, "rear": a - 2600.0}
    force, moment = np.zeros(3), np.zeros(3)
    for pos, v in VEHICLE.items():
        loads = wheel_loads(v, ax, ay, az)
        lateral = sum(w.patch[1] for w in loads.values())
        assert lateral == pytest.approx(v.axle_mass_kg * G * ay, abs=1e-9)
        share = v.drive_fraction if ax > 0 else v.brake_fraction
        assert sum((w.patch + w.centre)[0] for w in loads.values()) == pytest.approx(
            m * G * ax * share)
        for side, w in loads.items():
            # the road's forces act at the contact patches, the CG 550 mm above them (a force
            # the suspension takes at the wheel centre is still the road's at the patch)
            r = np.array([x_axle[pos], v.track_mm / 2.0 * (1 if side == "left" else -1), -550.0])
            force += w.patch + w.centre
            moment += np.cross(r, w.patch + w.centre)
    assert force == pytest.approx(m * G * np.array([ax, ay, 1.0 + az]))
    # the inertial forces act at the CG: roll, pitch and yaw of the tyre forces vanish
    assert moment == pytest.approx(np.zeros(3), abs=1e-9 * m * G * 1000)


def test_a_hand_case_of_braking_in_a_turn():
    v = VehicleData(500.0, 500.0, "front", 2500.0, 500.0, 1500.0, 0.6, 0.4)
    loads = wheel_loads(v, longitudinal_g=-1.0, lateral_g=0.6)
    axle = 500 * G + 1000 * G * 500 / 2500  # 700 g: 200 g transferred forward
    transfer = 0.5 * 1000 * G * 0.6 * 500 / 1500  # the axle's mass share of 100 g
    assert loads["left"].patch[2] == pytest.approx(axle / 2 - transfer)
    assert loads["right"].patch[2] == pytest.approx(axle / 2 + transfer)
    assert loads["left"].patch[0] == pytest.approx(-1000 * G * 0.6 / 2)
    assert loads["right"].patch[1] / loads["left"].patch[1] == pytest.approx(
        (axle / 2 + transfer) / (axle / 2 - transfer))


@pytest.mark.parametrize("change, key, words", [
    (lambda d: d["axle"]["vehicle"].update(axle_mass_kg={"front": 10778, "rear": 1008.7}),
     "axle.vehicle.axle_mass_kg.front", "times design.wheel_load_N"),
    (lambda d: d["axle"]["vehicle"].update(axle_mass_kg={"front": 1077.8, "rear": 98900}),
     "axle.vehicle.axle_mass_kg.rear", "in N? (expected 20 ... 30,000 kg"),
    (lambda d: d["axle"]["vehicle"].pop("axle_mass_kg"), "rig.vehicle_loads", "axle_mass_kg"),
    (lambda d: d["rig"]["vehicle_loads"]["cases"].update(hard={"lateral_g": 1.4}),
     "rig.vehicle_loads.cases.hard", "left wheel would lift off"),
    (lambda d: d["rig"]["vehicle_loads"]["cases"].update({"a b": {}}),
     "rig.vehicle_loads.cases", "case name 'a b'"),
])
def test_bad_vehicle_data_is_named(change, key, words):
    from elastokin.rig.drives import drives

    data = dw(rig=rig(vehicle_loads={"cases": {"braking": {"longitudinal_g": -1.0}}}))
    change(data)
    with pytest.raises(ConfigError) as err:
        drives(suspension(data, "dw.yaml"))
    assert f"key '{key}" in str(err.value) and words in str(err.value), str(err.value)


# ------------------------------------------------------------------ what kc writes
def test_kc_writes_the_loads(tmp_path):
    """loads.csv (every element's columns, one row per step), summary.json (peaks, pickups,
    the vehicle cases' patch forces), the chart and the report's section."""
    data = config("double_wishbone_axle.yaml")  # its own solver settings
    data["axle"]["vehicle"]["axle_mass_kg"] = dict(MASSES)
    data["rig"] = rig(parallel_travel={"rebound_mm": -20, "bump_mm": 20, "step_mm": 20,
                                       "unloading": False},
                      vehicle_loads={"steps": 2, "cases": {
                          "braking_1g": {"longitudinal_g": -1.0},
                          "cornering_left": {"lateral_g": 1.0}}})
    path = tmp_path / "dw.yaml"
    path.write_text(json.dumps(data))
    out = tmp_path / "res"
    result = CliRunner().invoke(main, ["kc", "--config", str(path), "--out", str(out),
                                       "--models", "initial", "--quiet"])
    assert result.exit_code == 0, result.output
    rows = [ln.split(",") for ln in (out / "loads.csv").read_text().splitlines()
            if not ln.startswith("#")]
    header, body = rows[0], rows[1:]
    assert header[:4] == ["model", "load_case", "step", "branch"]
    assert {"lca_bushing_mz_local_Nmm", "tie_rod_fz_local_N", "coil_fx_body_N",
            "lower_ball_joint_fz_body_N", "steering_gear_fz_local_N",
            "contact_patch_right_my_body_Nmm"} <= set(header)
    assert "lower_ball_joint_mx_body_Nmm" not in header  # a ball joint: no moment
    cases = [r[1] for r in body]
    assert cases.count("vehicle_loads:braking_1g") == 2 and "parallel_travel" in cases
    summary = json.loads((out / "summary.json").read_text())
    assert "loads.csv" in summary["files"] and "largest_loads.png" in summary["files"]
    model = summary["models"]["initial"]
    peak = model["loads"]["lca_bushing_right"]["load_cases"]["vehicle_loads:cornering_left"]
    assert peak["force_N"] > 1000.0 and peak["force_step"] == 2
    worst = model["pickups"]["lca_bushing_right"]["worst"]
    assert worst["load_case"] == "vehicle_loads:cornering_left"  # the outer wheel's
    patch = summary["vehicle_loads"]["vehicle_loads:braking_1g"]["contact_patch_force_N"]
    assert patch["left"][2] == pytest.approx((1077.8 + 2086.5 * 883.2 / 3378.0) * G / 2,
                                             rel=1e-4)
    html = (out / "report.html").read_text()
    assert '<section id="loads">' in html and 'class="worst"' in html
    assert 'id="chart-largest_loads"' in html
    view_arrows_are_loads_csv(html, header, body, model)


def view_arrows_are_loads_csv(html: str, header: list, body: list, model: dict) -> None:
    """The report's 3D view: every pickup's arrow at every frame of every load case is the
    load loads.csv lists for that step (the force on the element's first part: the body's
    when the body is its first part, the opposite otherwise); the worst case the view offers
    for a pickup is summary.json's."""
    import re

    raw = re.search(r'<script type="application/json" id="ekv-data">(.*?)</script>', html,
                    re.S).group(1)
    view = json.loads(raw.replace("<\\/", "</"))["models"]["initial"]
    rows = {(r[1], int(r[2])): r for r in body if r[0] == "initial"}
    checked = 0
    for case, data in view["data"].items():
        for name, flat in (data.get("loads") or {}).get("pickup", {}).items():
            sign = 1.0 if model["loads"][name]["parts"][0] == "body" else -1.0
            cols = [header.index(f"{name}_f{a}_body_N") for a in "xyz"]
            for frame, step in enumerate(data["steps"]):
                csv = np.array([float(rows[case, step + 1][c]) for c in cols])
                np.testing.assert_allclose(flat[3 * frame:3 * frame + 3], sign * csv, atol=0.051)
                checked += 1
    assert checked > 50
    for w in view["worst"]:
        worst = model["pickups"][w["pickup"]]["worst"]
        assert (w["case"], w["step"]) == (worst["load_case"], worst["step"])


def test_the_loads_benchmark_quick(tmp_path):
    """benchmarks/bench_loads.py --quick: recording the loads changes no number, and the
    figures the benchmark reports are there (timings themselves are not asserted)."""
    import importlib.util
    from pathlib import Path

    path = Path(__file__).parents[1] / "benchmarks" / "bench_loads.py"
    spec = importlib.util.spec_from_file_location("bench_loads", path)
    bench = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(bench)
    result = bench.main(["--quick", "--out", str(tmp_path / "bench_loads.json")])
    figures = result["suspensions"]["double_wishbone_axle"]
    assert figures["identical_numbers"] and figures["elements"] >= 20
    assert figures["with_loads_s"] > 0.0 and figures["loads_csv_bytes"] > 0
    assert json.loads((tmp_path / "bench_loads.json").read_text())["quick"] is True
