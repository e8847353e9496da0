"""ADAMS/Car files of an axle (elastokin.formats.adams.axle, adams_assembly_rows, adams_import,
adams_axle_files; docs/adams.md "Axles"): the suspension subsystem with its left/right pairs
(symmetric, or a left and a right row/block where axle.other_side makes the sides differ), the
anti-roll bar subsystem (hardpoints, mount bushing, torsional rate in [PARAMETER]), the steering
subsystem (rack_ratio in rad/m, travel limit), the assembly, and the round trips back into the
axle config: configs/double_wishbone_axle.yaml (hardpoints, bar rate, rack ratio exact; roll
stiffness and steer angles unchanged), the case study's mirrored axle, asymmetric axles; bad
inputs with one-line errors."""

import copy
import math
import shutil
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from elastokin.cli.main import main
from elastokin.config.loading import read_yaml, suspension_from_dict
from elastokin.config.schema.rig import RollSpec, SteeringSweepSpec
from elastokin.config.variants import corner
from elastokin.errors import ConfigError
from elastokin.formats.adams import car as adams_car
from elastokin.formats.adams.assemblies import read_bushing_assemblies, read_spring_assemblies
from elastokin.formats.adams.axle import axle_subsystems, mm_per_rev, rack_ratio_rad_per_m
from elastokin.formats.adams.axle_files import rack_ratio_check, read_parameters
from elastokin.formats.adams.export import export_adams
from elastokin.formats.adams.importing import (
    assembly_subsystems,
    import_adams_axle,
    subsystem_files,
    subsystem_role,
)
from elastokin.formats.adams.mapping import read_mapping
from elastokin.mbs.design import build_model, design_state
from elastokin.mbs.model import ModelOptions
from elastokin.physics.axle_sweeps import roll_stiffness_Nmm_per_deg
from elastokin.rig.characteristics import measured
from elastokin.rig.drives import roll_drive, steering_drive
from elastokin.rig.load_cases import run_drive_sides

from . import suspension_checks
from .suspension_checks import assert_same_bushings

ROOT = Path(__file__).resolve().parents[1]
AXLE = ROOT / "configs" / "double_wishbone_axle.yaml"
CASE = ROOT / "configs" / "pseudo_mcpherson.yaml"
SHARED = ROOT.parent / "shared" / "adams_real"
DEMO = SHARED / "zbingf_MDI_Demo_Vehicle_asy" / "MDI_Demo_Vehicle.asy"
FSAE_ASY = SHARED / "zbingf_asy_file_test_asy" / "asy_file_test.asy"
needs_shared = pytest.mark.skipif(not DEMO.is_file(), reason="../shared/adams_real is absent")
STAMP = "2023/11/14,22:13:20"
NAME = "HMMWV_front_double_wishbone_axle_left_corner_Project_Chrono_data"


@pytest.fixture(scope="module")
def axle():
    """The double wishbone axle config (dict), resolved, with its balanced design state."""
    data = read_yaml(AXLE)[0]
    s = suspension_from_dict(data, "double_wishbone_axle.yaml")
    return data, s, design_state(s)


def export(s, state, out: Path, **kw) -> list[Path]:
    return export_adams(s, out, state.bushing_preload, spring_force=state.spring_force_N,
                        timestamp=STAMP, **kw)


def subs(db: Path) -> dict[str, Path]:
    return {p.stem.removeprefix(NAME).lstrip("_") or "suspension": p
            for p in (db / "subsystems.tbl").glob("*.sub")}


def scrambled(data: dict) -> dict:
    """The axle config with its geometry, bushings, bar rate, rack ratio and travel limit all
    changed: a template whose every exported value must come back from the ADAMS files."""
    t = suspension_checks.scrambled(data)
    t["axle"]["anti_roll_bar"]["rate_Nmm_per_deg"] = 20000.0
    t["axle"]["steering"]["ratio_mm_per_rev"] = 35.0
    t["axle"]["steering"]["limit_mm"] = 80.0
    return t


def roll_stiffness(s) -> float:
    model = build_model(s, ModelOptions(), design_state(s))
    left = run_drive_sides(model, "m", roll_drive(s, RollSpec(amplitude_deg=1.0,
                                                              step_deg=0.5)))[0]
    return roll_stiffness_Nmm_per_deg(measured(left, "roll_angle_deg"),
                                      measured(left, "roll_moment_Nmm"))


def steer_angles(s) -> np.ndarray:
    model = build_model(s, ModelOptions(), design_state(s))
    sw = run_drive_sides(model, "m", steering_drive(s, SteeringSweepSpec(amplitude_deg=360.0,
                                                                          step_deg=90.0)))
    return np.array([x.columns["steer_angle_deg"] for x in sw])


# ----------------------------------------------------------------------------------------------
# Hand-checkable pieces


def test_rack_ratio_units_by_hand():
    # 50 mm of rack per steering-wheel turn: 2*pi rad per 0.05 m = 125.66 rad/m
    assert rack_ratio_rad_per_m(50.0) == pytest.approx(2.0 * math.pi / 0.05, rel=1e-15)
    assert mm_per_rev(rack_ratio_rad_per_m(50.0)) == 50.0  # exact after the 12-digit rounding
    assert mm_per_rev(174.5) == pytest.approx(36.0068, abs=1e-4)  # 2000*pi/174.5


def test_axle_partition_of_the_double_wishbone(axle):
    _, s, _ = axle
    parts = axle_subsystems(s)
    assert list(parts) == ["suspension", "anti_roll_bar", "steering"]
    assert parts["anti_roll_bar"].hardpoints == ("arb_centre", "arb_mount", "arb_link_upper",
                                                 "arb_link_lower")
    assert parts["anti_roll_bar"].bushings == ("arb_bushing",)
    assert parts["steering"].hardpoints == ("rack_centre",)
    assert parts["steering"].bushings == () and parts["steering"].springs == ()
    # tie rods stay in the suspension, as in ADAMS/Car's suspension templates
    assert {"tierod_inner", "tierod_outer", "shock_upper"} <= set(parts["suspension"].hardpoints)
    assert parts["suspension"].bushings == ("lca_bushing", "uca_bushing")
    assert parts["suspension"].springs == ("coil",)
    assert list(axle_subsystems(corner(s))) == ["suspension"]


# ----------------------------------------------------------------------------------------------
# Export of the double wishbone axle


def test_export_of_the_double_wishbone_axle(tmp_path, axle):
    data, s, state = axle
    files = export(s, state, tmp_path / "dw.cdb", spec=None)
    rel = [p.relative_to(tmp_path / "dw.cdb").as_posix() for p in files]
    assert rel == [f"subsystems.tbl/{NAME}.sub", f"subsystems.tbl/{NAME}_antiroll.sub",
                   f"subsystems.tbl/{NAME}_steering.sub", "bushings.tbl/lca_bushing.bus",
                   "bushings.tbl/uca_bushing.bus", "bushings.tbl/arb_bushing.bus",
                   "springs.tbl/coil.spr", f"assemblies.tbl/{NAME}.asy", "mapping.yaml"]
    sub = subs(tmp_path / "dw.cdb")
    assert {k: subsystem_role(v) for k, v in sub.items()} == {
        "suspension": ("suspension", "front"), "antiroll": ("antirollbar", "front"),
        "steering": ("steering", "front")}
    # the mirrored axle: every suspension row a left/right pair storing the left point (Y < 0)
    points = adams_car.read_hardpoints(sub["suspension"])
    assert all(p.symmetry == "left/right" for p in points.values())
    assert points["lca_outer"].position_mm == (36.0, -787.0, -118.0)  # ISO -> ADAMS
    assert "arb_mount" not in points and "rack_centre" not in points
    arb = adams_car.read_hardpoints(sub["antiroll"])
    assert set(arb) == {"arb_centre", "arb_mount", "arb_link_upper", "arb_link_lower"}
    assert arb["arb_centre"].symmetry == "single"  # on the centre plane: the bar's middle
    assert arb["arb_link_lower"].position_mm == (80.0, -640.0, -82.0)
    assert adams_car.read_hardpoints(sub["steering"])["rack_centre"].symmetry == "single"
    # the bar's mount bushing, its rate in [PARAMETER] (N*mm/deg, the subsystem's units)
    assert set(read_bushing_assemblies(sub["antiroll"])) == {"arb_bushing"}
    params = read_parameters(sub["antiroll"])
    assert params.positive("arb_torsion_stiffness", "rotational_stiffness", "x") == 60850.0
    assert "N*mm/deg" in params.rows["arb_torsion_stiffness"][2]
    p = read_parameters(sub["steering"])
    assert p.value("rack_ratio", "x")[0] == 2.0 * math.pi * 1000.0 / 50.0  # rad/m
    assert "(rad/meter)" in p.rows["rack_ratio"][2]
    assert p.positive("max_rack_displacement", "length", "x") == 87.0
    # the assembly names the three subsystems, found in the database
    asy = tmp_path / "dw.cdb" / "assemblies.tbl" / f"{NAME}.asy"
    assert [f for f, _ in assembly_subsystems(asy)] == [sub["suspension"], sub["antiroll"],
                                                        sub["steering"]]
    assert "'__MDI_SUSPENSION_TESTRIG'" in asy.read_text()


def test_export_is_deterministic(tmp_path, axle, monkeypatch):
    _, s, state = axle
    monkeypatch.setenv("SOURCE_DATE_EPOCH", "1700000000")
    a = export_adams(s, tmp_path / "x" / "db.cdb", state.bushing_preload,
                     spring_force=state.spring_force_N)
    b = export_adams(s, tmp_path / "y" / "db.cdb", state.bushing_preload,
                     spring_force=state.spring_force_N)
    assert len(a) == 9
    for pa, pb in zip(a, b):
        assert pa.read_bytes() == pb.read_bytes(), pa.name
    assert f"TIMESTAMP       =  '{STAMP}'" in a[-2].read_text()  # the assembly's


# ----------------------------------------------------------------------------------------------
# Round trips


def test_round_trip_double_wishbone_axle(tmp_path, axle):
    data, s, state = axle
    db = tmp_path / "dw.cdb"
    export(s, state, db)
    template = scrambled(data)
    mapping = read_mapping(db / "mapping.yaml")
    cfg, warnings, read = import_adams_axle(template, subsystem_files(mapping, db),
                                            db / "mapping.yaml")
    assert warnings == []
    assert cfg["hardpoints"] == data["hardpoints"]  # ISO -> ADAMS -> ISO, to the bit
    assert cfg["axle"] == data["axle"]  # bar rate, rack ratio and travel limit exact
    assert {p.name for p in read} == {"lca_bushing.bus", "uca_bushing.bus", "arb_bushing.bus"}
    back = suspension_from_dict(cfg, "imported.yaml")
    assert_same_bushings(s, back, np.linspace(-20.0, 20.0, 81))
    assert back.axle.anti_roll_bar.law == s.axle.anti_roll_bar.law
    assert back.axle.steering.ratio == s.axle.steering.ratio
    assert back.axle.steering.limit_mm == 87.0
    k0 = roll_stiffness(s)
    assert roll_stiffness(suspension_from_dict(template, "scrambled.yaml")) != pytest.approx(
        k0, rel=1e-3)  # the template alone would not give it
    assert roll_stiffness(back) == pytest.approx(k0, rel=1e-9)
    np.testing.assert_allclose(steer_angles(back), steer_angles(s), rtol=1e-9, atol=1e-9)


def test_round_trip_case_study_axle_is_the_corner_export(tmp_path, case_dict):
    """The case study's mirrored axle (no bar, no steering) exports as one suspension
    subsystem, byte for byte the export of its corner, and imports back unchanged."""
    data = copy.deepcopy(case_dict)
    s = suspension_from_dict(data, "pseudo_mcpherson.yaml")
    c = corner(s)
    state = design_state(c)
    a = export(s, state, tmp_path / "axle" / "pm.cdb")
    b = export(c, state, tmp_path / "corner" / "pm.cdb")
    assert [p.name for p in a] == [p.name for p in b]
    assert len(list((tmp_path / "axle" / "pm.cdb" / "subsystems.tbl").glob("*.sub"))) == 1
    for pa, pb in zip(a, b):
        assert pa.read_bytes() == pb.read_bytes(), pa.name
    t = copy.deepcopy(data)
    t["hardpoints"] = {k: [v[0] + 1.0, v[1], v[2]] for k, v in t["hardpoints"].items()}
    db = tmp_path / "axle" / "pm.cdb"
    cfg, warnings, _ = import_adams_axle(t, subsystem_files(read_mapping(db / "mapping.yaml"),
                                                            db), db / "mapping.yaml")
    assert warnings == [] and cfg["hardpoints"] == data["hardpoints"]
    assert cfg["axle"] == data["axle"] == {}  # still the mirrored axle


def asymmetric(data: dict) -> dict:
    """The axle made asymmetric (a right tie-rod end and lower-arm bushing of its own) with a
    nonlinear bar and a variable rack ratio."""
    d = copy.deepcopy(data)
    d["axle"]["other_side"] = {
        "hardpoints": {"tierod_outer": [-176.0, -823.0, -15.0]},
        "connections": {"lca_bushing": {"stiffness": {"x": 25000.0, "rz": {
            "deflection": [-10.0, 0.0, 10.0], "load": [-90000.0, 0.0, 110000.0]}}}}}
    st_ = d["axle"]["steering"]
    del st_["ratio_mm_per_rev"]
    st_["ratio_curve"] = {"steering_wheel_deg": [-600.0, -180.0, 0.0, 180.0, 600.0],
                          "rack_travel_mm": [-90.0, -25.0, 0.0, 25.0, 90.0]}
    arb = d["axle"]["anti_roll_bar"]
    del arb["rate_Nmm_per_deg"]
    arb["curve"] = {"deflection": [-20.0, -5.0, 0.0, 5.0, 20.0],
                    "load": [-1.5e6, -3.0e5, 0.0, 3.0e5, 1.5e6]}
    return d


def test_round_trip_asymmetric_axle_with_curves(tmp_path, axle):
    data = asymmetric(axle[0])
    s = suspension_from_dict(data, "asymmetric.yaml")
    state = design_state(s)
    db = tmp_path / "asym.cdb"
    files = export(s, state, db)
    rel = {p.relative_to(db).as_posix() for p in files}
    assert {"bushings.tbl/lca_bushing_right.bus", "curves.tbl/anti_roll_bar.crv",
            "curves.tbl/steering.crv"} <= rel
    sub = subs(db)["suspension"]
    tierod = adams_car.read_hardpoints(sub)["tierod_outer"]
    assert tierod.symmetry == "asymmetric"  # a 'left' and a 'right' row
    assert tierod.sides == {"left": (176.0, -821.0, -16.0), "right": (176.0, 823.0, -15.0)}
    lca = read_bushing_assemblies(sub)["lca_bushing"]
    assert lca["left"].property_file.endswith("/lca_bushing.bus")
    assert lca["right"].property_file.endswith("/lca_bushing_right.bus")
    springs = read_spring_assemblies(sub)["coil"]  # the two sides balance to other forces
    assert springs["left"].values["USER_VALUE"] == pytest.approx(
        round(state.spring_force_N["coil"], 6), abs=1e-9)
    assert springs["right"].values["USER_VALUE"] == pytest.approx(
        round(state.spring_force_N["coil_right"], 6), abs=1e-9)
    # imported onto the mirrored, linear axle: the other side and the curves come back
    template = copy.deepcopy(axle[0])
    cfg, _, _ = import_adams_axle(template, subsystem_files(
        read_mapping(db / "mapping.yaml"), db), db / "mapping.yaml")
    assert cfg["axle"]["other_side"]["hardpoints"] == data["axle"]["other_side"]["hardpoints"]
    assert set(cfg["axle"]["other_side"]["connections"]["lca_bushing"]["stiffness"]) == {
        "x", "rz"}  # the directions that are not the mirror's
    assert cfg["axle"]["anti_roll_bar"]["curve"] == data["axle"]["anti_roll_bar"]["curve"]
    assert cfg["axle"]["steering"]["ratio_curve"] == data["axle"]["steering"]["ratio_curve"]
    back = suspension_from_dict(cfg, "back.yaml")
    for k, p in s.hardpoints.items():
        np.testing.assert_array_equal(back.hardpoints[k], p)
    assert_same_bushings(s, back, np.linspace(-30.0, 30.0, 121))
    assert back.axle.anti_roll_bar.law == s.axle.anti_roll_bar.law
    assert back.axle.steering.ratio == s.axle.steering.ratio


@settings(max_examples=20, deadline=None, suppress_health_check=[HealthCheck.too_slow,
                                                                 HealthCheck.function_scoped_fixture])
@given(st.lists(st.integers(-8, 8), min_size=3, max_size=3),
       st.sampled_from(["lca_outer", "uca_front", "arb_link_lower", "spring_upper"]))
def test_other_side_points_round_trip_exactly(tmp_path_factory, axle, offset, name):
    """Any other-side override of a corner hardpoint (in the suspension or the bar subsystem)
    is written as a left and right row and comes back as the same override; none for a zero
    offset."""
    data = copy.deepcopy(axle[0])
    p = data["hardpoints"][name]
    q = [p[0] + offset[0] * 0.25, -p[1] + offset[1] * 0.25, p[2] + offset[2] * 0.25]
    data["axle"]["other_side"] = {"hardpoints": {name: q}}
    s = suspension_from_dict(data, "moved.yaml")
    db = tmp_path_factory.mktemp("p") / "db.cdb"
    zero = {b.name: np.zeros(6) for b in s.bushings}
    export_adams(s, db, zero, timestamp=STAMP)
    cfg, _, _ = import_adams_axle(copy.deepcopy(axle[0]), subsystem_files(
        read_mapping(db / "mapping.yaml"), db), db / "mapping.yaml")
    expected = {name: q} if any(offset) else None
    assert (cfg["axle"].get("other_side") or {}).get("hardpoints") == expected
    shutil.rmtree(db)


# ----------------------------------------------------------------------------------------------
# Commands


def test_cli_axle_export_then_import_three_ways(tmp_path, axle):
    data = axle[0]
    template = tmp_path / "template.yaml"
    from elastokin.formats.config_yaml import dump_config

    template.write_text(dump_config(scrambled(data), "scrambled"))
    db = tmp_path / "dw.cdb"
    runner = CliRunner()
    r = runner.invoke(main, ["export-adams", "--config", str(AXLE), "--out", str(db),
                             "--template-name", "_double_wishbone"])
    assert r.exit_code == 0, r.output
    assert "wrote 9 files" in r.output
    sub = subs(db)
    ways = {"database": ["--hardpoints", str(db)],
            "assembly": ["--assembly", str(db / "assemblies.tbl" / f"{NAME}.asy")],
            "files": ["--hardpoints", str(sub["suspension"]), "--subsystem",
                      str(sub["steering"]), "--subsystem", str(sub["antiroll"])]}
    for way, args in ways.items():
        out = tmp_path / f"{way}.yaml"
        r = runner.invoke(main, ["import-adams", *args, "--mapping", str(db / "mapping.yaml"),
                                 "--template", str(template), "--out", str(out)])
        assert r.exit_code == 0, (way, r.output)
        cfg = read_yaml(out)[0]
        assert cfg["hardpoints"] == data["hardpoints"] and cfg["axle"] == data["axle"], way
        assert "_antiroll.sub (sha256" in out.read_text()
    for args in ([], ["--hardpoints", str(db), *ways["assembly"]]):
        r = runner.invoke(main, ["import-adams", *args, "--mapping", str(db / "mapping.yaml"),
                                 "--template", str(template), "--out", str(tmp_path / "x")])
        assert r.exit_code == 1 and r.output.count("\n") == 1
        assert "give --hardpoints (a subsystem file or database) or --assembly" in r.output


# ----------------------------------------------------------------------------------------------
# Bad inputs


@pytest.fixture
def exported(tmp_path, axle):
    data, s, state = axle
    db = tmp_path / "dw.cdb"
    export(s, state, db)
    return data, db


def _import(data, db):
    return import_adams_axle(copy.deepcopy(data), subsystem_files(
        read_mapping(db / "mapping.yaml"), db), db / "mapping.yaml")


def _edit(path: Path, old: str, new: str) -> None:
    text = path.read_text()
    assert old in text
    path.write_text(text.replace(old, new))


def test_missing_bar_stiffness_is_named(exported):
    data, db = exported
    arb = subs(db)["antiroll"]
    _edit(arb, "'arb_torsion_stiffness       '", "'arb_torsion_rate            '")
    with pytest.raises(ConfigError) as exc:
        _import(data, db)
    msg = str(exc.value)
    assert msg.startswith(f"{arb}: no [PARAMETER] 'arb_torsion_stiffness'")
    assert "torsional rate" in msg and "arb_torsion_rate" in msg


@pytest.mark.parametrize("value, words", [
    ("-125.66370614359171", "must be positive"),
    ("0.12566370614359171", "gives 5e+04 mm of rack per steering-wheel revolution"),  # rad/mm
    ("7.2", "expected rad/m"),  # deg per mm
])
def test_bad_rack_ratio_is_refused_with_its_line(exported, value, words):
    data, db = exported
    steering = subs(db)["steering"]
    _edit(steering, "125.66370614359171", value)
    line = next(i for i, ln in enumerate(steering.read_text().splitlines(), 1)
                if "'rack_ratio" in ln)
    with pytest.raises(ConfigError) as exc:
        _import(data, db)
    msg = str(exc.value)
    assert msg.startswith(f"{steering}, line {line}, block [PARAMETER]: 'rack_ratio'")
    assert words in msg


def test_bar_stiffness_in_other_units_and_sign(exported):
    data, db = exported
    arb = subs(db)["antiroll"]
    # the same rate in N*m/rad: 60850 N*mm/deg * 180/pi / 1000
    rad = 60850.0 * 180.0 / math.pi / 1000.0
    text = arb.read_text().replace("'mm'", "'meter'").replace("'deg'", "'radians'")
    arb.write_text(text.replace(" 60850.0\n", f" {rad!r}\n"))
    _edit(arb, "-440.0", "-0.44")  # hardpoints are in metres now too
    for a, b in (("330.0", "0.33"), ("-640.0", "-0.64"), ("120.0", "0.12"), ("80.0", "0.08"),
                 ("-82.0", "-0.082")):
        arb.write_text(arb.read_text().replace(f" {a} ", f" {b} ").replace(f" {a}\n",
                                                                          f" {b}\n"))
    cfg, _, _ = _import(data, db)
    assert cfg["axle"]["anti_roll_bar"]["rate_Nmm_per_deg"] == 60850.0
    assert cfg["hardpoints"]["arb_mount"] == data["hardpoints"]["arb_mount"]
    arb.write_text(arb.read_text().replace(f" {rad!r}\n", " -1.0\n"))
    with pytest.raises(ConfigError, match="the anti-roll bar's torsional rate must be "
                                          "positive"):
        _import(data, db)


def test_missing_subsystem_and_corner_template(exported, tmp_path):
    data, db = exported
    mapping = read_mapping(db / "mapping.yaml")
    files = subsystem_files(mapping, subs(db)["suspension"])
    assert files.steering is not None  # found beside the suspension by its name
    lone = tmp_path / "lone"
    lone.mkdir()
    shutil.copy(subs(db)["suspension"], lone / "s.sub")
    with pytest.raises(ConfigError, match="key 'anti_roll_bar': no anti_roll_bar subsystem "
                                          "given"):
        import_adams_axle(copy.deepcopy(data), subsystem_files(mapping, lone / "s.sub"),
                          db / "mapping.yaml")
    cfg = copy.deepcopy(data)
    del cfg["axle"]
    with pytest.raises(ConfigError, match="keys anti_roll_bar, steering: template config is a "
                                          "corner"):
        _import(cfg, db)


def test_mapping_section_errors(exported, tmp_path):
    _, db = exported
    text = (db / "mapping.yaml").read_text()
    bad = tmp_path / "bad.yaml"
    bad.write_text(text.replace("  stiffness: arb_torsion_stiffness",
                                "  stiffnes: arb_torsion_stiffness"))
    with pytest.raises(ConfigError, match=r"key 'anti_roll_bar.stiffnes': unknown key"):
        read_mapping(bad)
    bad.write_text(text.replace("  rack_ratio: rack_ratio", "  rack_ratio: 125.7"))
    with pytest.raises(ConfigError, match=r"key 'steering.rack_ratio': expected an ADAMS "
                                          "parameter name"):
        read_mapping(bad)


# ----------------------------------------------------------------------------------------------
# Real Adams/Car files


@needs_shared
def test_real_assemblies_name_their_subsystems_and_rack_ratio():
    """The Adams/Car demo vehicle assembly names eight subsystems in the acar_shared database
    (not present here: refused with the line), and two real assemblies give rack_ratio in
    rad/m, as their own description row says, for plausible racks."""
    listed = assembly_subsystems(DEMO)
    assert len(listed) == 8
    assert listed[2][0] == DEMO.parent / "subsystems.tbl" / "TR_Steering.sub"
    with pytest.raises(ConfigError, match=r"MDI_Demo_Vehicle.asy, line \d+, block "
                                          r"\[SUBSYSTEM\]: the subsystem file .*"
                                          "TR_Front_Suspension.sub does not exist"):
        subsystem_files(read_mapping(ROOT / "tests" / "data" / "adams" /
                                     "double_wishbone_mapping.yaml"), assembly=DEMO)
    demo = read_parameters(DEMO)
    assert rack_ratio_check(demo, "rack_ratio") == pytest.approx(36.0068, abs=1e-4)
    fsae = read_parameters(FSAE_ASY)
    assert fsae.rows["rack_ratio"][2] == "swa to rack displacement ratio in S.I. (rad/meter)"
    assert rack_ratio_check(fsae, "rack_ratio") == pytest.approx(75.428, abs=1e-3)
