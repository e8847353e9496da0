"""ADAMS/Car interoperability (elastokin.formats.adams.teimorbit, adams_car, adams_export, adams_kc;
docs/adams.md): the TeimOrbit reader and its unit conversion, bushing property files, hardpoint
tables and frames, the export, the round trip through ADAMS files, and the import-adams /
export-adams commands.

Test data in tests/data/adams/: one nonlinear bushing law written in three unit systems, five
malformed variants (the faulty line carries a ``$ error`` comment), and a subsystem file and a
mapping of the generic double wishbone (tests/data/double_wishbone.yaml, ISO frame)."""

import copy
import math
from pathlib import Path

import numpy as np
import pytest
import yaml
from click.testing import CliRunner

from elastokin.cli.main import main
from elastokin.config.loading import read_yaml, suspension_from_dict
from elastokin.errors import ConfigError
from elastokin.formats.adams import car as adams_car
from elastokin.formats.adams import export as adams_export
from elastokin.formats.adams import kc as adams_kc
from elastokin.formats.adams import teimorbit

from .suspension_checks import assert_same_bushings, scrambled

DATA = Path(__file__).parent / "data"
ADAMS = DATA / "adams"
WISHBONE = DATA / "double_wishbone.yaml"
SUB = ADAMS / "double_wishbone.sub"
MAPPING = ADAMS / "double_wishbone_mapping.yaml"
ISO = {"x": "forward", "y": "left", "z": "up"}
ADAMS_FRAME = {"x": "rearward", "y": "right", "z": "up"}


def travel_only(cfg: dict) -> dict:
    """The config with parallel travel as its only load case (steer amplitude needs no more)."""
    cfg = copy.deepcopy(cfg)
    cfg["rig"] = {"parallel_travel": cfg.get("rig", {}).get("parallel_travel", {}),
                  **{k: None for k in ("vertical_force", "lateral_force",
                                       "longitudinal_force_patch", "longitudinal_force_centre",
                                       "aligning_torque")}}
    return cfg


def steer_amplitude(cfg: dict, name: str) -> float:
    from elastokin.studies.kc_job import run_kc

    run = run_kc(suspension_from_dict(travel_only(cfg), name))
    return run.models["initial"].summary()["steer_amplitude_deg"]


def marked_line(path: Path) -> int:
    """The line of a test file that carries the ``$ error`` marker."""
    lines = path.read_text().splitlines()
    return next(i for i, ln in enumerate(lines, start=1) if "$ error" in ln)


# ----------------------------------------------------------------------------------------------
# TeimOrbit reader


def test_reader_structure_and_line_numbers():
    text = "\n".join([
        "$---------------------------------------------------------------MDI_HEADER",  # 1
        "[MDI_HEADER]",                                                                # 2
        " FILE_TYPE  =  'bus'",                                                        # 3
        " FILE_VERSION = 4.0   $ trailing comment",                                    # 4
        " (COMMENTS)",                                                                 # 5
        " {comment_string}",                                                           # 6
        " 'a $ inside quotes is text'",                                                # 7
        "",                                                                            # 8
        "[FX_CURVE]",                                                                  # 9
        "{ disp force }",                                                              # 10
        " -1.0D+01  -1.2E+04",                                                         # 11
        "  $ a comment inside a table",                                                # 12
        "  10 12000",                                                                  # 13
        "[HARDPOINT]",                                                                 # 14
        "{hardpoint_name symmetry x_value y_value z_value}",                           # 15
        " 'lca_front   '  'left/right'  -200.0  -350  150",                            # 16
        " rack_centre  single  0 0 200",                                               # 17
    ])
    f = teimorbit.parse_teimorbit(text, "t.bus")
    assert [(b.name, b.line) for b in f.blocks] == [("MDI_HEADER", 2), ("FX_CURVE", 9),
                                                     ("HARDPOINT", 14)]
    head = f.block("MDI_HEADER")
    assert head.value("file_type") == "bus" and head.entries["FILE_VERSION"].value == 4.0
    assert head.entries["FILE_VERSION"].line == 4
    (comments,) = head.sub_blocks
    assert (comments.name, comments.line) == ("COMMENTS", 5)
    assert comments.tables[0].rows == [("a $ inside quotes is text",)]
    curve = f.block("FX_CURVE").tables[0]
    assert curve.columns == ("disp", "force") and curve.line == 10
    assert curve.rows == [(-10.0, -12000.0), (10.0, 12000.0)] and curve.row_lines == [11, 13]
    hp = f.block("HARDPOINT").tables[0]
    assert hp.rows[0] == ("lca_front", "left/right", -200.0, -350.0, 150.0)
    assert hp.rows[1][:2] == ("rack_centre", "single")


@pytest.mark.parametrize("text, line, words", [
    ("[A]\n X = 1\n[B\n", 3, "malformed block header"),
    ("[A]\n{a b}\n 'a description before any row'\n", 3, "description row"),
    ("[A]\n{a b}\n 1 2 3 text\n", 3, "row has 4 values"),
    ("[A]\n X = 1 'two'\n", 2, "expected one value"),
    ("[]\n", 1, "malformed block header"),
    ("[A]\n{a b}\n 1 2\n 1 2 3\n", 4, "row has 3 values but the table {a b} (line 2)"),
    ("[A]\n 1 2\n", 2, "unrecognised line"),
    ("X = 1\n", 1, "before the first [BLOCK]"),
    ("[A]\n X = 'open\n", 2, "unclosed quote"),
    ("[A]\n X = 1 2\n", 2, "expected one value"),
])
def test_reader_errors_name_file_line_block(text, line, words):
    with pytest.raises(ConfigError) as exc:
        teimorbit.parse_teimorbit(text, "bad.sub")
    msg = str(exc.value)
    assert msg.startswith(f"bad.sub, line {line}") and words in msg


def test_units_block_converts_known_columns_and_keys(tmp_path):
    p = tmp_path / "m.sub"
    p.write_text("[UNITS]\n LENGTH = 'meter'\n FORCE = 'kilo_newton'\n ANGLE = 'radians'\n"
                 " MASS = 'tonne'\n TIME = 'millisecond'\n"
                 "[HARDPOINT]\n{hardpoint_name symmetry x_value y_value z_value}\n"
                 " 'p' 'single' 0.1 -0.2 0.3\n"
                 "[BUSHING_ASSEMBLY]\n USAGE = 'b'\n T_PRELOAD_Z = 0.5\n R_PRELOAD_X = 0.002\n"
                 " R_OFFSET_Z = 0.1\n INACTIVE_BEHAVIOR = 'normal'\n"
                 "[OTHER]\n{speed  force}\n 3 0.25\n")
    f = teimorbit.read_teimorbit(p)
    assert f.units_declared and f.units.length == "meter"
    hp = f.block("HARDPOINT").tables[0]
    assert hp.rows[0][2:] == pytest.approx((100.0, -200.0, 300.0), rel=1e-12)
    assert hp.units == (None, None, "mm", "mm", "mm")
    ba = f.block("BUSHING_ASSEMBLY")
    assert ba.entries["T_PRELOAD_Z"].value == pytest.approx(500.0)            # N
    assert ba.entries["R_PRELOAD_X"].value == pytest.approx(2.0e3)            # kN*m -> N*mm
    assert ba.entries["R_OFFSET_Z"].value == pytest.approx(math.degrees(0.1))
    assert ba.entries["R_PRELOAD_X"].unit == "N*mm" and ba.entries["USAGE"].unit is None
    other = f.block("OTHER").tables[0]  # unknown column kept as read, known one converted
    assert other.rows == [(3.0, 250.0)] and other.units == (None, "N")
    assert teimorbit.Units("inch", "pound_force", "radians", "slug", "minute").factor(
        "rotational_damping") == pytest.approx(25.4 * 4.4482216152605 * 60 / math.degrees(1))


def test_missing_units_block_means_adams_car_defaults(tmp_path):
    p = tmp_path / "x.sub"
    p.write_text("[HARDPOINT]\n{hardpoint_name symmetry x_value y_value z_value}\n"
                 " 'p' 'single' 1 2 3\n")
    f = teimorbit.read_teimorbit(p)
    assert not f.units_declared and f.units == teimorbit.Units()
    assert f.block("HARDPOINT").tables[0].rows[0][2:] == (1.0, 2.0, 3.0)


# ----------------------------------------------------------------------------------------------
# Bushing property files


@pytest.mark.parametrize("other", ["meter_kilonewton_rad", "inch_poundforce_deg_ms"])
def test_bus_in_other_units_gives_the_same_bushing(other):
    ref = adams_car.read_bushing(ADAMS / "bushing_mm_newton_deg.bus")
    alt = adams_car.read_bushing(ADAMS / f"bushing_{other}.bus")
    assert alt.units != ref.units
    probe = np.linspace(-45.0, 45.0, 181)  # inside and beyond every table (extrapolation)
    for law_ref, law_alt, d in zip(ref.laws(), alt.laws(), ("x", "y", "z", "rx", "ry", "rz")):
        np.testing.assert_allclose(law_alt.deflection, law_ref.deflection, rtol=1e-9, atol=0,
                                   err_msg=d)
        np.testing.assert_allclose(law_alt.load, law_ref.load, rtol=1e-9, atol=0, err_msg=d)
        np.testing.assert_allclose(law_alt(probe), law_ref(probe), rtol=1e-9, atol=1e-9)
    for key, (value, unit) in ref.damping.items():
        assert alt.damping[key][1] == unit
        assert alt.damping[key][0] == pytest.approx(value, rel=1e-9)
    assert ref.damping["FX_DAMPING"] == (1.5, "N*s/mm")
    assert ref.damping["TZ_DAMPING"] == (35.0, "N*mm*s/deg")


def test_bus_is_a_config_stiffness_entry():
    """The stiffness dict goes straight into a config; the law it builds is the file's, and it
    is extrapolated with the end slopes beyond the table."""
    props = adams_car.read_bushing(ADAMS / "bushing_mm_newton_deg.bus")
    data = read_yaml(WISHBONE)[0]
    data["connections"]["lca_bushing"]["stiffness"] = props.stiffness
    b = next(b for b in suspension_from_dict(data).bushings if b.name == "lca_bushing")
    rz = b.laws[5]
    assert rz(12.0) == pytest.approx(11000.0)
    assert rz(40.0) == pytest.approx(50000.0 + (50000 - 11000) / 18 * 10)   # end slope
    assert rz(-40.0) == pytest.approx(-40000.0 - (40000 - 9000) / 20 * 10)
    assert rz.deflection_at(-9000.0) == pytest.approx(-10.0)


@pytest.mark.parametrize("name, block", [
    ("unclosed_table", "FY_CURVE"),
    ("non_monotonic", "FZ_CURVE"),
    ("unknown_unit", "UNITS"),
    ("not_through_zero", "TX_CURVE"),
    ("empty_table", "TZ_CURVE"),
])
def test_malformed_bus_names_file_block_and_line(name, block):
    path = ADAMS / f"malformed_{name}.bus"
    with pytest.raises(ConfigError) as exc:
        adams_car.read_bushing(path)
    msg = str(exc.value)
    assert msg.startswith(f"{path}, line {marked_line(path)}, block [{block}]: "), msg
    assert "\n" not in msg


def test_missing_curve_block(tmp_path):
    text = (ADAMS / "bushing_mm_newton_deg.bus").read_text()
    p = tmp_path / "no_ty.bus"
    p.write_text(text.replace("[TY_CURVE]", "[TY_CURVE_OLD]"))
    with pytest.raises(ConfigError, match=r"no_ty.bus: block \[TY_CURVE\] is missing"):
        adams_car.read_bushing(p)


def test_load_must_increase(tmp_path):
    text = (ADAMS / "bushing_mm_newton_deg.bus").read_text()
    p = tmp_path / "soft.bus"
    p.write_text(text.replace("  10                 12000", "  10                  3000"))
    with pytest.raises(ConfigError, match=r"block \[FX_CURVE\]: force 3000 N does not increase"):
        adams_car.read_bushing(p)


# ----------------------------------------------------------------------------------------------
# Hardpoints, frames, mapping


def test_hardpoint_table_left_right_single():
    points = adams_car.read_hardpoints(SUB)
    lca = points["lca_front"]  # the quoted, padded name is stripped
    assert (lca.symmetry, lca.position_mm, lca.line) == ("left/right", (-202.0, -351.0, 151.0),
                                                         27)
    np.testing.assert_array_equal(lca.at("left"), [-202.0, -351.0, 151.0])
    np.testing.assert_array_equal(lca.at("right"), [-202.0, 351.0, 151.0])  # Y mirror
    ref = points["path_error_reference"]
    assert ref.symmetry == "single"
    np.testing.assert_array_equal(ref.at("right"), ref.at("left"))


def test_frame_conversion_both_frames():
    p = np.array([-202.0, -351.0, 151.0])  # ADAMS: rearward, right, up
    np.testing.assert_array_equal(adams_car.adams_to_config(p, ADAMS_FRAME), p)
    np.testing.assert_array_equal(adams_car.adams_to_config(p, ISO), [202.0, 351.0, 151.0])
    for frame in (ISO, ADAMS_FRAME):
        np.testing.assert_array_equal(
            adams_car.config_to_adams(adams_car.adams_to_config(p, frame), frame), p)
    with pytest.raises(ConfigError, match="expected x rearward, y right"):
        adams_car.adams_to_config(p, {"x": "forward", "y": "right"})


@pytest.mark.parametrize("frame", ["iso", "adams"])
def test_apply_hardpoints_converts_to_the_template_frame(frame):
    data = read_yaml(WISHBONE)[0]
    if frame == "adams":  # the same suspension described in the ADAMS/Car frame
        data["frame"] = ADAMS_FRAME
        data["hardpoints"] = {k: [-v[0], -v[1], v[2]] for k, v in data["hardpoints"].items()}
    cfg, warnings = adams_car.import_adams(data, SUB, MAPPING)
    assert warnings == []
    lca_outer = cfg["hardpoints"]["lca_outer"]  # ADAMS (-1, -721, 131), left point (hpl_)
    assert lca_outer == ([1.0, 721.0, 131.0] if frame == "iso" else [-1.0, -721.0, 131.0])
    assert cfg["hardpoints"]["rack_end"] == ([-141.0, 331.0, 201.0] if frame == "iso"
                                             else [141.0, -331.0, 201.0])
    s = suspension_from_dict(cfg)  # a valid config: left wheel outboard on its side
    assert s.outboard @ s.hardpoints["wheel_centre"] > 700.0
    assert cfg["connections"]["lca_bushing"]["stiffness"]["rz"]["load"][-1] == 50000.0
    if frame == "iso":  # the imported suspension runs on the rig (4.23 deg when written)
        assert 3.0 < steer_amplitude(cfg, "imported.yaml") < 6.0


def test_right_side_and_single_points(tmp_path):
    data = read_yaml(WISHBONE)[0]
    mapping = tmp_path / "m.yaml"
    mapping.write_text(yaml.safe_dump({
        "elastokin_adams_mapping": 1,
        "hardpoints": {"lca_front": "hpr_lca_front", "lca_rear": {"adams": "lca_rear",
                                                                   "side": "right"},
                       "spring_upper": "path_error_reference"}}))
    cfg, warnings = adams_car.import_adams(data, SUB, mapping)
    assert cfg["hardpoints"]["lca_front"] == [202.0, -351.0, 151.0]   # ISO: right is y < 0
    assert cfg["hardpoints"]["lca_rear"] == [-198.0, -351.0, 151.0]
    assert cfg["hardpoints"]["spring_upper"] == [0.0, 0.0, 0.0]        # single: as stored
    assert any("takes the right point of 'lca_front' for a left corner" in w for w in warnings)
    assert any("kept as they were: lca_pivot" in w for w in warnings)


@pytest.mark.parametrize("content, words", [
    ({"elastokin_adams_mapping": 1, "hardpoints": {"nope": "lca_front"}},
     "key 'hardpoints.nope': 'nope' is not a hardpoint of template config"),
    ({"elastokin_adams_mapping": 1, "hardpoints": {"lca_front": "lca_fornt"}},
     "key 'hardpoints.lca_front': ADAMS hardpoint 'lca_fornt' is not in the hardpoint table"),
    ({"elastokin_adams_mapping": 1, "hardpoints": {"lca_front": {"adams": "x", "side": "up"}}},
     "key 'hardpoints.lca_front.side': expected left or right"),
    ({"elastokin_adams_mapping": 1, "hardpoints": {"lca_front": {"adams": "hpl_lca_front",
                                                                 "side": "right"}}},
     "names the left point but side is right"),
    ({"elastokin_adams_mapping": 2, "hardpoints": {"lca_front": "lca_front"}},
     "key 'elastokin_adams_mapping': expected 1"),
    ({"elastokin_adams_mapping": 1, "hardpoints": {"a": "b"}, "colour": "red"},
     "key 'colour': unknown key"),
    ({"elastokin_adams_mapping": 1, "hardpoints": {"lca_front": "lca_front"},
      "bushings": {"upper_pivot": "bushing_mm_newton_deg.bus"}},
     "given for 'upper_pivot', which is not a bushing of template config (bushings: "
     "lca_bushing)"),
])
def test_mapping_errors_name_file_and_key(tmp_path, content, words):
    mapping = tmp_path / "m.yaml"
    mapping.write_text(yaml.safe_dump(content))
    if "bushings" in content:  # the .bus file is found next to the mapping file
        (tmp_path / "bushing_mm_newton_deg.bus").write_text(
            (ADAMS / "bushing_mm_newton_deg.bus").read_text())
    with pytest.raises(ConfigError) as exc:
        adams_car.import_adams(read_yaml(WISHBONE)[0], SUB, mapping)
    assert words in str(exc.value) and str(tmp_path) in str(exc.value)


# ----------------------------------------------------------------------------------------------
# Export


@pytest.fixture(scope="module")
def mcpherson():
    """The shipped pseudo-McPherson without its CMM measurements (its own Table 2 geometry),
    resolved, with its balanced design preloads."""
    from elastokin.mbs.design import design_state

    data = read_yaml(Path(__file__).parents[1] / "configs" / "pseudo_mcpherson.yaml")[0]
    del data["measurements"]
    data.pop("kc_test", None)
    data.pop("axle")  # an ADAMS/Car subsystem is the corner (its left/right pairs symmetric)
    s = suspension_from_dict(data, "pseudo_mcpherson.yaml")
    return data, s, design_state(s).bushing_preload


def sub_file(folder: Path) -> Path:
    """The one subsystem file of an exported database."""
    (sub,) = (folder / "subsystems.tbl").glob("*.sub")
    return sub


def test_export_is_deterministic_and_reads_back(tmp_path, mcpherson, monkeypatch):
    data, s, preload = mcpherson
    monkeypatch.setenv("SOURCE_DATE_EPOCH", "1700000000")  # the subsystem's TIMESTAMP
    a = adams_export.export_adams(s, tmp_path / "a", preload)
    b = adams_export.export_adams(s, tmp_path / "again" / "a", preload)  # same alias
    assert [p.relative_to(tmp_path / "a").as_posix() for p in a] == [
        "subsystems.tbl/pseudo-McPherson_front_left_Meissonnier_et_al._2006.sub",
        "bushings.tbl/J1.bus", "bushings.tbl/J2.bus", "bushings.tbl/J4.bus",
        "springs.tbl/coil.spr", "mapping.yaml"]
    for pa, pb in zip(a, b):
        assert pa.read_bytes() == pb.read_bytes(), pa.name
    assert "TIMESTAMP      =  '2023/11/14,22:13:20'" in a[0].read_text()
    points = adams_car.read_hardpoints(tmp_path / "a")
    assert set(points) == set(s.hardpoints)
    for name, p in s.hardpoints.items():  # this config is in the ADAMS frame, left side
        assert points[name].symmetry == "left/right"
        assert points[name].position_mm == tuple(p)
    j1 = adams_car.read_bushing(tmp_path / "a" / "bushings.tbl" / "J1.bus")
    assert j1.stiffness["x"] == {"deflection": [-10.0, -5.0, 0.0, 5.0, 10.0],
                                 "load": [-3000.0, -1500.0, 0.0, 1500.0, 3000.0]}
    assert j1.stiffness["rz"]["load"][-1] == 16000.0  # 1600 N*mm/deg over +-10 deg
    back = adams_car.read_bushing_assemblies(sub_file(tmp_path / "a"))
    for name, p in preload.items():
        assert back[name]["left"] is back[name]["right"]  # one 'left/right' block
        assert back[name]["left"].definition == ".ACAR.forces.ac_bushing"
        assert back[name]["left"].property_file == f"mdids://a/bushings.tbl/{name}.bus"
        np.testing.assert_allclose(back[name]["left"].preload, p, atol=1e-6)
    # the strut load on the top mount
    assert back["J4"]["left"].preload[2] == pytest.approx(4824.36, abs=0.01)


def test_export_iso_frame_and_nonlinear_curve(tmp_path):
    from elastokin.mbs.design import design_state

    s = suspension_from_dict(read_yaml(WISHBONE)[0], "double_wishbone.yaml")
    adams_export.export_adams(s, tmp_path, design_state(s).bushing_preload, range_mm=5.0,
                              range_deg=40.0)
    points = adams_car.read_hardpoints(tmp_path)
    assert points["lca_front"].position_mm == (-200.0, -350.0, 150.0)  # ISO -> ADAMS, Y < 0
    bus = adams_car.read_bushing(tmp_path / "bushings.tbl" / "lca_bushing.bus")
    # the curve as given (+-30 deg), extended with its end slopes to the asked +-40 deg
    assert bus.stiffness["rz"] == {"deflection": [-40.0, -30.0, -10.0, 0.0, 10.0, 30.0, 40.0],
                                   "load": [-42500.0, -30000.0, -5000.0, 0.0, 5000.0, 30000.0,
                                            42500.0]}
    assert bus.stiffness["z"]["deflection"] == [-5.0, -2.5, 0.0, 2.5, 5.0]
    text = sub_file(tmp_path).read_text()
    assert "$   location 0.0 -350.0 150.0 mm" in text  # lca_pivot in the ADAMS frame


def test_export_needs_balanced_preloads(mcpherson):
    _, s, _ = mcpherson
    with pytest.raises(ConfigError, match="preloads must be solved first"):
        adams_export.export_adams(s, "/nonexistent")


def test_kc_channels(tmp_path):
    kc = tmp_path / "kc.csv"
    kc.write_text("# elastokin_version: 0.1.0\n"
                  "model,load_case,step,branch,pad_z_mm,wheel_travel_mm,toe_deg,camber_deg,"
                  "wheel_centre_x_mm,wheel_centre_y_mm,contact_patch_fy_N,spring_coil_force_N,"
                  "bushing_J1_rz_deg,extra\n"
                  "initial,parallel_travel,1,stroke,-1.0,-0.9,0.01,-0.02,0.5,780.0,-12.5,"
                  "4800.0,0.1,7\n")
    out = tmp_path / "kc_adams.csv"
    adams_kc.write_adams_kc_csv(kc, out, ISO)
    lines = out.read_text().splitlines()
    assert "# elastokin_version: 0.1.0" in lines
    assert any(ln.startswith("# channel units: pad_vertical_displacement mm, wheel_travel mm, "
                             "toe_angle deg, camber_angle deg") for ln in lines)
    header, row = [ln.split(",") for ln in lines if not ln.startswith("#")]
    assert header == ["model", "load_case", "step", "branch", "pad_vertical_displacement",
                      "wheel_travel", "toe_angle", "camber_angle", "wheel_center_x",
                      "wheel_center_y", "tire_force_y", "coil_spring_force",
                      "bushing_J1_rot_z", "extra"]
    # ISO config frame -> ADAMS frame: x and y change sign; everything else unchanged
    assert row == ["initial", "parallel_travel", "1", "stroke", "-1.0", "-0.9", "0.01",
                   "-0.02", "-0.5", "-780.0", "12.5", "4800.0", "0.1", "7"]
    adams_kc.write_adams_kc_csv(kc, out, ADAMS_FRAME)
    assert out.read_text().splitlines()[-1].split(",")[8:11] == ["0.5", "780.0", "-12.5"]


# ----------------------------------------------------------------------------------------------
# Round trip: export, import into a template that has lost its geometry and stiffness, same K&C


def test_round_trip_pseudo_mcpherson_same_steer_amplitude(tmp_path, mcpherson):
    data, s, preload = mcpherson
    adams_export.export_adams(s, tmp_path, preload)
    template = scrambled(data)
    cfg, warnings = adams_car.import_adams(template, tmp_path, tmp_path / "mapping.yaml")
    assert warnings == []
    back = suspension_from_dict(cfg, "imported.yaml")
    for name, p in s.hardpoints.items():
        np.testing.assert_array_equal(back.hardpoints[name], p)
    assert_same_bushings(s, back, np.linspace(-20.0, 20.0, 81))
    original = steer_amplitude(data, "original.yaml")
    assert steer_amplitude(template, "scrambled.yaml") != pytest.approx(original, abs=1e-3)
    assert steer_amplitude(cfg, "imported.yaml") == pytest.approx(original, abs=1e-6)
    assert original == pytest.approx(0.5188, abs=0.005)  # see test_cli's nominal regression


def test_round_trip_iso_frame_double_wishbone(tmp_path):
    from elastokin.mbs.design import design_state

    data = read_yaml(WISHBONE)[0]
    s = suspension_from_dict(data, "double_wishbone.yaml")
    adams_export.export_adams(s, tmp_path, design_state(s).bushing_preload)
    cfg, _ = adams_car.import_adams(scrambled(data), sub_file(tmp_path),
                                    tmp_path / "mapping.yaml")
    assert cfg["hardpoints"] == data["hardpoints"]  # ISO -> ADAMS -> ISO, exactly
    assert steer_amplitude(cfg, "imported.yaml") == pytest.approx(
        steer_amplitude(data, "original.yaml"), abs=1e-6)


# ----------------------------------------------------------------------------------------------
# Commands


def test_cli_export_then_import(tmp_path, case_path):
    runner = CliRunner()
    out = tmp_path / "adams"
    r = runner.invoke(main, ["export-adams", "--config", str(case_path), "--out", str(out)])
    assert r.exit_code == 0, r.output
    assert "wrote 6 files" in r.output
    assert sorted(p.relative_to(out).as_posix() for p in out.rglob("*") if p.is_file()) == [
        "bushings.tbl/J1.bus", "bushings.tbl/J2.bus", "bushings.tbl/J4.bus", "mapping.yaml",
        "springs.tbl/coil.spr",
        "subsystems.tbl/pseudo-McPherson_front_left_Meissonnier_et_al._2006.sub"]
    data = read_yaml(case_path)[0]
    moved = scrambled(data)
    moved["measurements"]["folder"] = "cmm"  # relative to the template
    (tmp_path / "tpl" / "cmm").mkdir(parents=True)
    (tmp_path / "tpl" / "cmm" / "assembly.igs").write_text("")
    template = tmp_path / "tpl" / "template.yaml"
    template.write_text(yaml.safe_dump(moved, sort_keys=False))
    new = tmp_path / "sub" / "new.yaml"
    r = runner.invoke(main, ["import-adams", "--hardpoints", str(out),
                             "--mapping", str(out / "mapping.yaml"), "--template",
                             str(template), "--bushing",
                             f"J4={ADAMS / 'bushing_mm_newton_deg.bus'}", "--out", str(new)])
    assert r.exit_code == 0, r.output
    cfg = read_yaml(new)[0]
    assert cfg["hardpoints"] == data["hardpoints"]
    assert cfg["connections"]["J1"]["stiffness"]["x"]["load"][-1] == 3000.0   # J1.bus
    assert cfg["connections"]["J4"]["stiffness"]["rz"]["load"][-1] == 50000.0  # --bushing
    # the CMM files of the template are still found from the new config's folder
    assert cfg["measurements"]["folder"] == "../tpl/cmm"
    assert (new.parent / cfg["measurements"]["folder"] / "assembly.igs").is_file()
    assert new.read_text().startswith("# elastokin config imported from ADAMS/Car files")


def test_cli_export_identified_with_kc(tmp_path, case_path):
    from elastokin.config.loading import load_suspension
    from elastokin.identification.geometric import identify

    kc = tmp_path / "kc.csv"
    kc.write_text("model,load_case,step,branch,toe_deg,wheel_centre_x_mm\n"
                  "identified,parallel_travel,1,stroke,0.25,1.5\n")
    out = tmp_path / "adams"
    r = CliRunner().invoke(main, ["export-adams", "--config", str(case_path), "--out",
                                  str(out), "--identified", "--kc", str(kc)])
    assert r.exit_code == 0, r.output
    ident = identify(load_suspension(case_path)).identified_config
    points = adams_car.read_hardpoints(out)
    for name, p in ident["hardpoints"].items():
        assert points[name].position_mm == pytest.approx(p, abs=1e-9)
    assert "(identified)" in (out / "bushings.tbl" / "J1.bus").read_text().splitlines()[0]
    assert (out / "kc_adams.csv").read_text().splitlines()[-2:] == [
        "model,load_case,step,branch,toe_angle,wheel_center_x",
        "identified,parallel_travel,1,stroke,0.25,1.5"]


def test_cli_errors_are_one_line(tmp_path, case_path):
    runner = CliRunner()
    r = runner.invoke(main, ["import-adams", "--hardpoints", str(SUB), "--mapping",
                             str(MAPPING), "--template", str(WISHBONE), "--bushing",
                             f"lca_bushing={ADAMS / 'malformed_non_monotonic.bus'}",
                             "--out", str(tmp_path / "x.yaml")])
    assert r.exit_code == 1
    assert r.output.count("\n") == 1 and "Traceback" not in r.output
    assert "malformed_non_monotonic.bus, line 58, block [FZ_CURVE]" in r.output
    assert not (tmp_path / "x.yaml").exists()
    r = runner.invoke(main, ["import-adams", "--hardpoints", str(SUB), "--mapping",
                             str(MAPPING), "--template", str(WISHBONE), "--bushing", "lca.bus",
                             "--out", str(tmp_path / "x.yaml")])
    assert r.exit_code == 1 and "expected NAME=FILE.bus" in r.output
    r = runner.invoke(main, ["export-adams", "--config", str(tmp_path / "none.yaml"), "--out",
                             str(tmp_path / "o")])
    assert r.exit_code == 1 and "cannot read config file" in r.output
