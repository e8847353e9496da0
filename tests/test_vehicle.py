"""The whole car on the rig (``elastokin kc --vehicle``): the vehicle file's checks, the car's
figures against hand calculations from the two axles' own summaries, and the table's body
roll against the two axles rolled separately. The car runs on a short rig (both axles:
travel, lateral force, roll of 1 deg; compliant models only) to keep the test quick."""

from __future__ import annotations

import hashlib
import json
import math
import shutil
import warnings

import numpy as np
import pytest
import yaml
from click.testing import CliRunner

from elastokin.cli.main import main
from elastokin.config.loading import load_suspension_with_rig
from elastokin.config.vehicle import VehicleDataWarning, load_vehicle
from elastokin.errors import ConfigError
from elastokin.physics import vehicle as car
from elastokin.report.vehicle_files import read_vehicle_results
from elastokin.rig.sweeps import find_sweep
from elastokin.studies.kc_job import run_kc

from .conftest import ROOT

G = 9.80665
RIG = {"parallel_travel": {"rebound_mm": -50, "bump_mm": 50, "step_mm": 10,
                           "unloading": False},
       "vertical_force": None, "lateral_force": {"amplitude_N": 1000, "step_N": 500},
       "longitudinal_force_patch": None, "longitudinal_force_centre": None,
       "aligning_torque": None, "opposite_travel": None, "single_wheel_travel": None,
       "steering": None, "lateral_force_anti_phase": None}
ROLL = {"amplitude_deg": 1.0, "step_deg": 0.5}
#: the axles' design loads as masses (kg): 2 x 5286.9 N and 2 x 8174.7 N
MASSES = {"front": 2 * 5286.9 / G, "rear": 2 * 8174.7 / G}


def vehicle_file(folder, **changes) -> dict:
    data = {"elastokin": 1, "name": "test car", "units": {"length": "mm", "mass": "kg"},
            "front": {"config": "front.yaml"}, "rear": {"config": "rear.yaml"},
            "wheelbase_mm": 3378.0, "cg_height_mm": 883.2, "axle_mass_kg": dict(MASSES),
            # the axles' own files say 0.5: the vehicle's split differs on purpose
            "brake_fraction_front": 0.7, "drive_fraction_front": 0.5, "body_roll": ROLL}
    data.update(changes)
    return data


@pytest.fixture(scope="module")
def car_folder(tmp_path_factory):
    folder = tmp_path_factory.mktemp("car")
    shutil.copy(ROOT / "configs" / "double_wishbone_axle.yaml", folder / "front.yaml")
    shutil.copy(ROOT / "configs" / "multilink_axle.yaml", folder / "rear.yaml")
    (folder / "rig.yaml").write_text(yaml.safe_dump({**RIG, "roll_vertical_force": ROLL}))
    (folder / "car.yaml").write_text(yaml.safe_dump(vehicle_file(folder)))
    return folder


@pytest.fixture(scope="module")
def car_run(car_folder):
    """`elastokin kc --vehicle` on the short rig, compliant models: its results folder."""
    out = car_folder / "results"
    result = CliRunner().invoke(main, [
        "kc", "--vehicle", str(car_folder / "car.yaml"), "--rig", str(car_folder / "rig.yaml"),
        "--models", "initial", "--out", str(out), "--quiet"])
    assert result.exit_code == 0, result.output
    return out, result.output


@pytest.fixture(scope="module")
def separate(car_folder):
    """Each axle run on its own (its own config and vehicle data, the same rig)."""
    out = {}
    for role in ("front", "rear"):
        s = load_suspension_with_rig(car_folder / f"{role}.yaml", car_folder / "rig.yaml")
        out[role] = run_kc(s, models=["initial"])
    return out


# ---------------------------------------------------------------- the mathematics, by hand
def test_car_mathematics_by_hand():
    assert car.cg_behind_front_axle_mm(2700.0, 6000.0, 4000.0) == pytest.approx(1080.0)
    assert car.roll_stiffness_distribution(600.0, 400.0) == pytest.approx(0.6)
    axis = car.roll_axis(50.0, 150.0, 2500.0, 1000.0, 550.0)  # 50 + 100 * 0.4 = 90
    assert (axis.height_under_cg_mm, axis.moment_arm_mm) == pytest.approx((90.0, 460.0))
    assert axis.inclination_deg == pytest.approx(math.degrees(math.atan(100 / 2500)))
    # W h' = 10 kN * 500 mm = 5e6 N*mm per g; K = 1e6 N*mm/deg = 57.3e6 per rad
    k_rad = 1e6 * 180 / math.pi
    assert car.roll_gradient_deg_per_g(1e4, 500.0, 1e6) == pytest.approx(
        math.degrees(5e6 / (k_rad - 5e6)))
    assert np.isnan(car.roll_gradient_deg_per_g(1e4, 500.0, 1e3))  # springs too soft
    # toe-in of the right wheel, toe-out of the left: both steer left
    assert car.axle_steer_deg(-0.1, 0.1) == pytest.approx(0.1)
    front, rear = car.compliance_steer_terms_deg_per_g(1e-4, 2e-4, 6000.0, 4000.0)
    assert (front, rear) == pytest.approx((-0.6, 0.8))  # front steering left: oversteer
    front, rear = car.roll_steer_terms_deg_per_g(-0.1, 0.05, 4.0)
    assert (front, rear) == pytest.approx((0.4, 0.2))
    heave, pitch = car.body_heave_pitch(10.0, 0.0, 2500.0, 1000.0)
    assert heave == pytest.approx(-6.0)  # the front 10 mm down, the CG 0.4 of the way
    assert pitch == pytest.approx(math.degrees(math.atan(10 / 2500)))  # nose down


# ---------------------------------------------------------------- the car against its axles
def test_car_figures_by_hand_from_the_axles_own_summaries(car_run):
    out, _ = car_run
    summary, _, axles = read_vehicle_results(out)
    m = summary["models"]["initial"]
    own = {role: axles[role][0]["models"]["initial"]["axle"] for role in ("front", "rear")}
    kf, kr = (own[r]["roll_stiffness_Nmm_per_deg"] for r in ("front", "rear"))
    assert m["car"]["roll_stiffness_front_percent"] == pytest.approx(
        100 * kf / (kf + kr), rel=1e-12)
    mass = summary["vehicle"]["axle_mass_kg"]
    a = 3378.0 * mass["rear"] / (mass["front"] + mass["rear"])
    hf, hr = (own[r]["roll_centre_height_mm"] for r in ("front", "rear"))
    assert m["car"]["roll_axis_height_under_cg_mm"] == pytest.approx(
        hf + (hr - hf) * a / 3378.0, rel=1e-12)
    # compliance steer: each axle's steer per lateral force from its named compliances, in
    # phase (+ left per + left), times the axle's weight; front steering left is oversteer
    steer = {}
    for r in ("front", "rear"):
        nc = own[r]["named_compliances"]
        steer[r] = 0.5 * (nc["lateral_force_toe_in_phase_right_deg_per_kN"]
                          - nc["lateral_force_toe_in_phase_left_deg_per_kN"]) / 1000.0
    expected = steer["rear"] * mass["rear"] * G - steer["front"] * mass["front"] * G
    assert m["car"]["understeer_compliance_steer_deg_per_g"] == pytest.approx(expected,
                                                                              rel=1e-12)
    assert expected > 0  # the multi-link rear toes in under the cornering force: understeer
    # the vehicle's brake split replaces the axles' own (0.5): anti-dive scales with it
    assert own["front"]["percent_anti_dive"] == pytest.approx(m["front"]["percent_anti_dive"])
    assert axles["front"][0]["axle"]["vehicle"]["brake_fraction"] == 0.7
    assert axles["rear"][0]["axle"]["vehicle"]["brake_fraction"] == pytest.approx(0.3)


def test_the_vehicles_split_against_the_axles_own(car_run, separate):
    """Percent anti-dive is linear in the front brake fraction: the car's (0.7) is the
    separate axle's (its own 0.5) times 0.7 / 0.5; the rear's anti-lift under braking
    0.3 / 0.5 of its own."""
    summary = read_vehicle_results(car_run[0])[0]["models"]["initial"]
    own = {r: separate[r].models["initial"].summary()["axle"] for r in ("front", "rear")}
    assert summary["front"]["percent_anti_dive"] == pytest.approx(
        own["front"]["percent_anti_dive"] * 0.7 / 0.5, rel=1e-9)
    assert summary["rear"]["percent_anti_lift_braking"] == pytest.approx(
        own["rear"]["percent_anti_lift_braking"] * 0.3 / 0.5, rel=1e-9)


def test_body_roll_on_the_table_against_the_axles_rolled_separately(car_run, separate):
    """The table's total roll moment at every step is the sum of the two axles' roll moments
    when each is rolled on its own (1e-6 of the largest), at the same roll steps."""
    _, sweeps, _ = read_vehicle_results(car_run[0])
    (roll,) = [sw for sw in sweeps if sw.load_case == "body_roll"]
    parts = [np.asarray(find_sweep(separate[r].models["initial"].sweeps,
                                   "roll_vertical_force").columns["roll_moment_Nmm"])
             for r in ("front", "rear")]
    total = roll.columns["roll_moment_total_Nmm"]
    assert total.size == parts[0].size == 8
    scale = np.abs(total).max()
    assert scale > 1e6  # N*mm: some 5.7 kN*m at 1 deg
    assert np.abs(total - (parts[0] + parts[1])).max() <= 1e-6 * scale
    assert roll.columns["body_roll_deg"].max() == pytest.approx(1.0)
    # both axles heave alike rolled either way (mirror-symmetric axles): the body's pitch
    # is even in the roll (second order: 0.005 deg at 1 deg)
    phi, pitch = roll.columns["body_roll_deg"], roll.columns["body_pitch_deg"]
    assert pitch[phi == 1.0] == pytest.approx(pitch[phi == -1.0], rel=1e-4)


def test_the_car_results_folder(car_run):
    out, printed = car_run
    summary = json.loads((out / "summary.json").read_text())
    for f in ("car.csv", "report.html", "car_roll_axis.png", "front/kc.csv", "rear/report.html"):
        assert (out / f).is_file(), f
    assert summary["vehicle_sha256"] and summary["front_config_sha256"]
    assert [f["role"] for f in summary["input_files"][:2]] == [
        "vehicle file", "front axle: config"]
    assert set(summary["solver"]) == {"front", "rear"}
    assert "roll stiffness distribution" in (out / "report.html").read_text()
    # the axles' own files said 0.5 for the brake split: one warning each, both files named
    said = [w for w in summary["warnings"] if "'axle.vehicle.brake_fraction'" in w]
    assert len(said) == 2 and all("car.yaml" in w for w in said)


# ---------------------------------------------------------------- the vehicle file's checks
def _write(folder, data) -> str:
    shutil.copy(ROOT / "configs" / "double_wishbone_axle.yaml", folder / "front.yaml")
    shutil.copy(ROOT / "configs" / "multilink_axle.yaml", folder / "rear.yaml")
    path = folder / "car.yaml"
    path.write_text(yaml.safe_dump(data))
    return str(path)


@pytest.mark.parametrize("changes, message", [
    ({"wheelbase_m": 3.378}, "unknown top-level key 'wheelbase_m' (did you mean "
                              "'wheelbase_mm'?)"),
    ({"wheelbase_mm": 3.378}, "key 'wheelbase_mm': 3.378 - in metres?"),
    ({"mass_kg": 2745.0}, "give axle_mass_kg, or mass_kg and front_mass_fraction, not both"),
    ({"axle_mass_kg": None}, "give the masses"),
    ({"axle_mass_kg": None, "mass_kg": 2745.0, "front_mass_fraction": 39.0},
     "39 - a percentage? give 0.39"),
    ({"axle_mass_kg": {"front": 250000.0, "rear": 1667.0}},
     "key 'axle_mass_kg.front': 250000 - in N?"),
    ({"axle_mass_kg": {"front": 3000.0, "rear": 1667.0}},
     "the front axle's mass 3000 kg is 2.78 times what its design wheel loads carry"),
    ({"rear": {"config": "../outside.yaml"}}, "key 'rear.config': axle config "
                                              "'../outside.yaml' leads to"),
    ({"front": {"config": "missing.yaml"}}, "key 'front.config': axle config 'missing.yaml'"),
])
def test_bad_vehicle_files_name_the_file_and_key(tmp_path, monkeypatch, changes, message):
    monkeypatch.chdir(tmp_path)
    path = _write(tmp_path, vehicle_file(tmp_path, **changes))
    with pytest.raises(ConfigError) as err:
        load_vehicle(path)
    assert message in str(err.value) and "car.yaml" in str(err.value)


def test_a_corner_is_not_an_axle(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    data = yaml.safe_load((ROOT / "configs" / "double_wishbone_axle.yaml").read_text())
    del data["axle"]
    path = _write(tmp_path, vehicle_file(tmp_path))
    (tmp_path / "front.yaml").write_text(yaml.safe_dump(data))
    with pytest.raises(ConfigError, match="describes one corner"):
        load_vehicle(path)


def test_contradicting_axle_data_are_warned_with_both_files(tmp_path, monkeypatch):
    """An axle's own CG height and axle masses, and design loads that do not carry the
    vehicle's masses: one warning each, naming the axle config's key and the vehicle file;
    the vehicle's data are used."""
    monkeypatch.chdir(tmp_path)
    path = _write(tmp_path, vehicle_file(tmp_path, cg_height_mm=700.0, brake_fraction_front=0.5,
                                         axle_mass_kg={"front": 1200.0,
                                                       "rear": MASSES["rear"]},
                                         lateral_transfer_fraction_front=0.6))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        v = load_vehicle(path)
    said = [str(w.message) for w in caught if w.category is VehicleDataWarning]
    assert said == list(v.warnings)
    assert sum("'axle.vehicle.cg_height_mm' is 883.2" in w for w in said) == 2
    # the double wishbone's own axle_mass_kg (the HMMWV's: 1077.8 and 1008.7 kg)
    assert any("front.yaml: key 'axle.vehicle.axle_mass_kg.front' is 1077.8" in w
               and "axle_mass_kg.front 1200" in w for w in said)
    assert any("'axle.vehicle.axle_mass_kg.rear' is 1008.7" in w for w in said)
    (load,) = [w for w in said if "design.wheel_load_N" in w]
    assert "front.yaml" in load and "-10.1 %" in load and "1200.0 kg" in load
    assert len(said) == 5 and all("car.yaml" in w for w in said)
    assert v.front.axle.vehicle.cg_height_mm == v.rear.axle.vehicle.cg_height_mm == 700.0
    assert v.rear.axle.vehicle.position == "rear"
    assert v.rear.axle.vehicle.axle_mass_kg.front == 1200.0  # the static-load cases' too
    assert v.rear.axle.vehicle.lateral_transfer_fraction == pytest.approx(0.4)
    assert v.front.config_sha256 == hashlib.sha256(
        (tmp_path / "front.yaml").read_bytes()).hexdigest()  # the file's own bytes
    assert v.front.rig.roll_vertical_force.amplitude_deg == 1.0  # the table's roll


def test_the_shipped_car_is_one_car(monkeypatch):
    """configs/vehicle_hmmwv.yaml is the HMMWV, front and rear: both axle configs' own vehicle
    data are the vehicle file's and each design wheel load carries the vehicle's mass on its
    axle (0.04 % front, 0.03 % rear, with g = 9.81 in the configs): loading it warns of
    nothing. (The old pairing with the multi-link rear warned of the rear axle mass.)"""
    monkeypatch.chdir(ROOT)
    with warnings.catch_warnings():
        warnings.simplefilter("error", VehicleDataWarning)
        v = load_vehicle("configs/vehicle_hmmwv.yaml")
    assert v.warnings == ()
    assert {role: v.axle(role).source for role in ("front", "rear")} == {
        "front": "configs/double_wishbone_axle.yaml",
        "rear": "configs/double_wishbone_rear_axle.yaml"}
    for role in ("front", "rear"):
        assert 2 * v.axle(role).design.wheel_load_N == pytest.approx(v.data.weight_N(role),
                                                                     rel=5e-4)
        assert v.axle(role).axle.vehicle.position == role


@pytest.mark.slow
def test_the_readme_whole_car_section_runs_and_shows_what_kc_prints(tmp_path, monkeypatch):
    """The README's Python block runs the shipped car, without a warning; the console excerpt
    above it is the table `elastokin kc --vehicle` prints for that run (rebuilt from its
    summary.json, with the command's default results folder), and shows no warning."""
    import contextlib
    import io
    import re
    from pathlib import Path

    from elastokin.report.vehicle_text import vehicle_table

    readme = (ROOT / "README.md").read_text()
    start = readme.index("## The whole car")
    text = readme[start:readme.index("\n## ", start + 10)]
    blocks = dict((lang, body) for lang, body in re.findall(r"```(\w+)\n(.*?)```", text, re.S)
                  if lang in ("console", "python"))
    (tmp_path / "configs").symlink_to(ROOT / "configs")
    monkeypatch.chdir(tmp_path)
    with contextlib.redirect_stdout(io.StringIO()), warnings.catch_warnings():
        warnings.simplefilter("error", VehicleDataWarning)
        exec(compile(blocks["python"], "README, The whole car", "exec"), {})
    summary = json.loads((tmp_path / "results" / "car" / "summary.json").read_text())
    printed = [ln.rstrip() for ln in vehicle_table(
        summary, Path("results/vehicle_hmmwv")).splitlines()]
    command, _, shown = blocks["console"].partition("\n")
    assert command == "$ elastokin kc --vehicle configs/vehicle_hmmwv.yaml"
    expected = [ln.rstrip() for ln in shown.splitlines() if ln.strip() and ln != "..."]
    assert expected and all(line in printed for line in expected), \
        [line for line in expected if line not in printed]
    # one car, front and rear: nothing to warn of, in the run or in the README
    assert summary["warnings"] == [] and "warning" not in shown


@pytest.mark.parametrize("args", [[], ["--config", "a.yaml", "--vehicle", "b.yaml"]])
def test_kc_takes_a_config_or_a_vehicle(args):
    result = CliRunner().invoke(main, ["kc", *args])
    assert result.exit_code == 2
    assert "give --config (one suspension) or --vehicle (the whole car)" in result.output
