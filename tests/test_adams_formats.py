"""ADAMS/Car files as ADAMS/Car writes them (issue 16): the tolerant TeimOrbit reader, unit
names and systems, left/right pairs kept apart (hardpoints, bushing and spring assemblies), XML
bushing property files, Akima interpolation, and an export in the form ADAMS/Car opens (an
ADAMS/Car database with a subsystem file named after the template's hardpoints).

Test data: tests/data/adams/lr_form.cdb (a subsystem in Adams/Car's own left/right form with its
bushing property files, one of them XML) and lr_form_mapping.yaml."""

import math
import re
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
from elastokin.formats.adams import teimorbit
from elastokin.formats.adams.assemblies import read_bushing_assemblies, read_spring_assemblies
from elastokin.formats.adams.curves import akima, akima_deviation
from elastokin.formats.adams.mapping import read_mapping

DATA = Path(__file__).parent / "data"
ADAMS = DATA / "adams"
WISHBONE = DATA / "double_wishbone.yaml"
LR = ADAMS / "lr_form.cdb"
LR_SUB = LR / "subsystems.tbl" / "lr_wishbone.sub"
LR_MAPPING = ADAMS / "lr_form_mapping.yaml"
BUS = ADAMS / "bushing_mm_newton_deg.bus"
XML = LR / "bushings.tbl" / "uca_xml.xml"


# ----------------------------------------------------------------------------------------------
# The tolerant reader


def test_description_rows_free_text_repeated_keys_and_any_block_name():
    text = "\n".join([
        "[3D]",                                                                 # 1
        " Flow = 900.0   <- gallons per minute",                                # 2
        " Flow = 950.0",                                                        # 3
        "[PARAMETER]",                                                          # 4
        "{parameter_name symmetry type value}",                                 # 5
        " 'toe_angle'  'left/right'  'real'  0.25",                             # 6
        "  'static toe, deg'",                                                  # 7
        "  'a second description line'",                                        # 8
        " 'kinematic_flag'  'single'  'integer'  0",                            # 9
        "[ WALL CONTACT ]",                                                     # 10
        "{ depth  k }",                                                         # 11
        " -1.0  5E5   <- use this format for constant values",                  # 12
    ])
    f = teimorbit.parse_teimorbit(text, "t.hol")
    assert [b.name for b in f.blocks] == ["3D", "PARAMETER", "WALL CONTACT"]
    assert f.block("3D").entries["FLOW"].value == 950.0 and f.block("3D").entries["FLOW"].line == 3
    p = f.block("PARAMETER").tables[0]
    assert p.rows == [("toe_angle", "left/right", "real", 0.25),
                      ("kinematic_flag", "single", "integer", 0.0)]
    assert p.descriptions == {0: "static toe, deg a second description line"}
    wall = f.block("WALL CONTACT").tables[0]
    assert wall.rows == [(-1.0, 5.0e5)] and wall.notes == {0: "<- use this format for "
                                                               "constant values"}
    assert f.warnings == [
        "t.hol, line 2, block [3D]: FLOW: free text after the value ignored: "
        "'<- gallons per minute'",
        "t.hol, line 3, block [3D]: FLOW is given again (first at line 2): the last value is "
        "used",
        "t.hol, line 12, block [WALL CONTACT]: free text after the values of 1 row(s) of "
        "{depth k} ignored (lines 12): '<- use this format for constant values'"]


@pytest.mark.parametrize("units, factors", [
    ("Units = 'Imperial'", (304.8, 4.4482216152605, 1.0, 0.45359237, 1.0)),
    ("UNITS = 'mks'\n TIME = 'milliseconds'", (1000.0, 1.0, 1.0, 1.0, 1e-3)),
    ("LENGTH = 'inches'\n FORCE = 'Pound Force'\n ANGLE = 'Radians'\n TIME = 'seconds'",
     (25.4, 4.4482216152605, math.degrees(1.0), 1.0, 1.0)),
    ("LENGTH = 'feet'\n MASS = 'kilograms'\n TIME = 'hours'", (304.8, 1.0, 1.0, 1.0, 3600.0)),
])
def test_every_adams_unit_name_and_system(tmp_path, units, factors):
    p = tmp_path / "u.sub"
    p.write_text(f"[UNITS]\n {units}\n")
    u = teimorbit.read_teimorbit(p).units
    got = tuple(u.factor(q) for q in ("length", "force", "angle", "mass", "time"))
    assert got == pytest.approx(factors, rel=1e-12)


@pytest.mark.parametrize("units, words", [
    ("LENGTH = 'furlong'", "unknown length unit 'furlong'"),
    ("UNITS = 'martian'", "unknown unit system 'martian'"),
])
def test_broken_units_are_still_errors(tmp_path, units, words):
    p = tmp_path / "u.sub"
    p.write_text(f"[UNITS]\n {units}\n")
    with pytest.raises(ConfigError, match=re.escape(f"u.sub, line 2, block [UNITS]: {words}")):
        teimorbit.read_teimorbit(p)


def test_unknown_unit_kind_is_warned_about(tmp_path):
    p = tmp_path / "u.sub"
    p.write_text("[UNITS]\n CURRENT = 'ampere'\n LENGTH = 'meter'\n")
    f = teimorbit.read_teimorbit(p)
    assert f.units.length == "meter"
    assert f.warnings == [f"{p}, line 2, block [UNITS]: CURRENT = 'ampere': not a unit "
                          "elastokin converts (LENGTH, FORCE, ANGLE, MASS, TIME): ignored"]


def test_windows_1252_only_in_comments_is_read(tmp_path):
    p = tmp_path / "w.pdc"
    p.write_bytes(b"[BLADES]\n$ blades at N/360\xb0\n{ degrees radius }\n 0.0 0.35\n")
    f = teimorbit.read_teimorbit(p)
    assert f.block("BLADES").tables[0].rows == [(0.0, 0.35)]
    assert "read as Windows-1252" in f.warnings[0] and "line 2" in f.warnings[0]
    p.write_bytes(b"[BLADES]\n Name = 'caf\xe9'\n")
    with pytest.raises(ConfigError, match="line 2: not a text file"):
        teimorbit.read_teimorbit(p)


# ----------------------------------------------------------------------------------------------
# Left/right pairs as Adams/Car writes them


def test_asymmetric_hardpoint_rows_are_kept_apart():
    points = adams_car.read_hardpoints(LR_SUB)
    tie = points["tierod_outer"]
    assert tie.symmetry == "asymmetric"
    np.testing.assert_array_equal(tie.at("left"), [131.0, -701.0, 211.0])
    np.testing.assert_array_equal(tie.at("right"), [133.0, 702.0, 212.0])  # not the mirror
    np.testing.assert_array_equal(points["lca_front"].at("right"), [-202.0, 351.0, 151.0])


def test_left_and_right_assembly_blocks_are_kept_apart():
    bushings = read_bushing_assemblies(LR_SUB)
    left, right = bushings["lca_front"]["left"], bushings["lca_front"]["right"]
    assert left.preload.tolist() == [0.0, 0.0, -120.0, 0.0, 0.0, 1500.0]
    assert right.preload.tolist() == [0.0, 0.0, -240.0, 0.0, 0.0, 3000.0]
    assert right.property_file.endswith("lca_front_right.bus")
    assert bushings["uca_front"]["left"] is bushings["uca_front"]["right"]
    springs = read_spring_assemblies(LR_SUB)
    assert springs["ride_spring"]["left"].values["USER_VALUE"] == 189.5
    assert springs["ride_spring"]["right"].values["USER_VALUE"] == 2000.0


def test_repeated_assembly_of_one_side_warns_and_keeps_the_last():
    f = teimorbit.parse_teimorbit("[BUSHING_ASSEMBLY]\n USAGE = 'a'\n SYMMETRY = 'left'\n"
                                  " T_PRELOAD_X = 1\n[BUSHING_ASSEMBLY]\n USAGE = 'a'\n"
                                  " SYMMETRY = 'left/right'\n T_PRELOAD_X = 2\n", "r.sub")
    out = read_bushing_assemblies(f)
    assert out["a"]["left"].preload[0] == 2.0 == out["a"]["right"].preload[0]
    assert f.warnings == ["r.sub, line 5, block [BUSHING_ASSEMBLY]: USAGE 'a' (left) is given "
                          "again (first at line 1): the last block is used"]
    bad = teimorbit.parse_teimorbit("[BUSHING_ASSEMBLY]\n USAGE = 'a'\n SYMMETRY = 'both'\n",
                                    "r.sub")
    with pytest.raises(ConfigError, match=r"r.sub, line 3, block \[BUSHING_ASSEMBLY\]: USAGE "
                                          r"'a': SYMMETRY 'both'"):
        read_bushing_assemblies(bad)


@pytest.mark.parametrize("side", ["left", "right"])
def test_import_of_a_left_right_database_takes_each_side(tmp_path, side):
    """The mapping names the bushing by its ADAMS usage: its property file is the one of the
    side's [BUSHING_ASSEMBLY], found in the database that holds the subsystem."""
    template = read_yaml(WISHBONE)[0]
    mapping = tmp_path / "m.yaml"
    mapping.write_text(LR_MAPPING.read_text() + f"side: {side}\n")
    cfg, warnings = adams_car.import_adams(template, LR, mapping)
    tie = cfg["hardpoints"]["tierod_outer"]  # ISO frame
    assert tie == ([-131.0, 701.0, 211.0] if side == "left" else [-133.0, -702.0, 212.0])
    load = cfg["connections"]["lca_bushing"]["stiffness"]["x"]["load"]
    assert load[-1] == (12000.0 if side == "left" else 24000.0)
    assert (side == "right") == any("takes the right point" in w for w in warnings)


# ----------------------------------------------------------------------------------------------
# XML bushing property files


def test_xml_bushing_reads_as_the_bus_file():
    xml, bus = adams_car.read_bushing(XML), adams_car.read_bushing(BUS)
    assert xml.stiffness == bus.stiffness  # meter / newton / radians -> mm, N, N*mm, deg
    assert xml.units.length == "meter" and xml.damping["FX_DAMPING"] == (1.5, "N*s/mm")
    assert xml.damping["TZ_DAMPING"] == (pytest.approx(20.0), "N*mm*s/deg")


def test_xml_linear_rate_and_rotation_names(tmp_path):
    text = XML.read_text()
    text = text.replace('name="rz"', 'name="az"')
    text = re.sub(r'(<ConnectorDirectionComponent name="x".*?type=)"spline"',
                  r'\1"linear"', text, count=1, flags=re.S)
    text = text.replace('rate="0"', 'rate="2500"', 1)  # N/m
    p = tmp_path / "lin.xml"
    p.write_text(text)
    props = adams_car.read_bushing(p)
    assert props.stiffness["x"] == 2.5  # N/mm
    assert props.laws()[0](4.0) == pytest.approx(10.0)
    assert props.stiffness["rz"] == adams_car.read_bushing(BUS).stiffness["rz"]


@pytest.mark.parametrize("change, words", [
    (lambda t: t.replace('name="y"', 'name="q"'), 'name="q">, line'),
    (lambda t: t.replace("0.005 4000.0", "0.005 -4000.0", 1), "force -4000 N does not increase"),
    (lambda t: t.replace("</afc:Document>", ""), "not well-formed XML"),
    (lambda t: t.replace('current="meter"', 'current="cubit"'), "unknown length unit 'cubit'"),
    (lambda t: t.replace("0.005 4000.0", "0.005 4000.0 1", 1), "expected one 'deflection "
                                                                  "load' pair"),
])
def test_broken_xml_names_file_element_and_line(tmp_path, change, words):
    p = tmp_path / "bad.xml"
    p.write_text(change(XML.read_text()))
    with pytest.raises(ConfigError) as exc:
        adams_car.read_bushing(p)
    msg = str(exc.value)
    assert msg.startswith(str(p)) and words in msg and "line" in msg and "\n" not in msg


# ----------------------------------------------------------------------------------------------
# Akima interpolation


def test_akima_spline_and_its_distance_to_the_piecewise_linear_law():
    x = np.array([0.0, 1.0, 2.0, 3.0, 4.0, 5.0])
    assert akima(x, x**2, [2.5]) == pytest.approx([6.25])       # exact on a parabola
    np.testing.assert_allclose(akima(x, 3 * x, [0.3, 4.9]), [0.9, 14.7])  # straight: a line
    assert akima_deviation(x, 3 * x)[0] == pytest.approx(0.0, abs=1e-12)
    props = adams_car.read_bushing(BUS)
    dev, at = props.akima["rz"]
    assert dev > 0 and -30.0 < at < 30.0
    assert "differs from elastokin's piecewise-linear law by up to" in props.interpolation_note()


# ----------------------------------------------------------------------------------------------
# The export in the form ADAMS/Car opens


@pytest.fixture(scope="module")
def wishbone():
    from elastokin.mbs.design import design_state

    s = suspension_from_dict(read_yaml(WISHBONE)[0], "double_wishbone.yaml")
    return s, design_state(s)


def test_export_with_the_template_names_and_form(tmp_path, wishbone):
    s, state = wishbone
    mapping = tmp_path / "m.yaml"
    mapping.write_text(LR_MAPPING.read_text().replace(
        "  tierod_outer: tierod_outer", "  tierod_outer: hpr_tierod_outer") + yaml.safe_dump(
        {"subsystem": {"template": "_double_wishbone", "minor_role": "rear"}}))
    files = adams_export.export_adams(
        s, tmp_path / "front.cdb", state.bushing_preload, spring_force=state.spring_force_N,
        mapping=read_mapping(mapping), timestamp="2024/01/02,03:04:05")
    sub = tmp_path / "front.cdb" / "subsystems.tbl" / "generic_double_wishbone_front_left.sub"
    assert sub in files and (tmp_path / "front.cdb" / "bushings.tbl" / "lca_front.bus") in files
    text = sub.read_text()
    # titles at column 1, keys indented by one space, the real header fields
    for line in text.splitlines():
        assert line[:1] in ("$", "[", "(", "{", " "), line
        if line.lstrip().startswith(("[", "(", "{")):
            assert not line.startswith(" "), line
    f = teimorbit.read_teimorbit(sub)
    assert f.block("MDI_HEADER").value("FILE_TYPE") == "sub"
    head = f.block("SUBSYSTEM_HEADER")
    assert (head.value("TEMPLATE_NAME"), head.value("MAJOR_ROLE"), head.value("MINOR_ROLE"),
            head.value("TIMESTAMP")) == (
        "mdids://acar_shared/templates.tbl/_double_wishbone.tpl", "suspension", "rear",
        "2024/01/02,03:04:05")
    points = adams_car.read_hardpoints(sub)
    assert {"wheel_center", "tierod_inner", "lca_front"} <= set(points)
    assert "wheel_centre" not in points and "rack_end" not in points
    # tierod_outer is written as the right point of its pair: the stored left one is its mirror
    assert points["tierod_outer"].position_mm == (130.0, 700.0, 210.0)
    assert points["tierod_outer"].at("right").tolist() == [130.0, -700.0, 210.0]
    (b,) = read_bushing_assemblies(f).values()
    a = b["left"]
    assert (a.definition, a.usage, a.symmetry, a.property_file) == (
        ".ACAR.forces.ac_bushing", "lca_front", "left/right",
        "mdids://front/bushings.tbl/lca_front.bus")
    spring = read_spring_assemblies(f)["ride_spring"]["left"]
    assert spring.property_file == "mdids://front/springs.tbl/ride_spring.spr"
    assert spring.values["USER_VALUE"] == pytest.approx(state.spring_force_N["coil"], abs=1e-6)
    spr = teimorbit.read_teimorbit(tmp_path / "front.cdb" / "springs.tbl" / "ride_spring.spr")
    coil = s.springs[0]
    assert spr.block("SPRING_DATA").value("FREE_LENGTH") == pytest.approx(
        coil.installed_length_mm + state.spring_force_N["coil"] / coil.rate_N_per_mm)


def test_export_writes_an_asymmetric_pair_when_the_sides_differ(tmp_path, wishbone):
    s, state = wishbone
    mapping = tmp_path / "m.yaml"
    mapping.write_text(yaml.safe_dump({"elastokin_adams_mapping": 1, "hardpoints": {
        "lca_front": "hpl_arm", "lca_rear": "hpr_arm", "spring_upper": "hps_top"}}))
    adams_export.export_adams(s, tmp_path / "x.cdb", state.bushing_preload,
                              mapping=read_mapping(mapping))
    points = adams_car.read_hardpoints(tmp_path / "x.cdb")
    arm = points["arm"]
    assert arm.symmetry == "asymmetric"
    assert arm.at("left").tolist() == [-200.0, -350.0, 150.0]   # lca_front, ADAMS frame
    assert arm.at("right").tolist() == [200.0, -350.0, 150.0]   # lca_rear as written
    assert points["top"].symmetry == "single"
    back, _ = adams_car.import_adams(read_yaml(WISHBONE)[0], tmp_path / "x.cdb",
                                     tmp_path / "x.cdb" / "mapping.yaml")
    assert back["hardpoints"] == read_yaml(WISHBONE)[0]["hardpoints"]


def test_export_refuses_two_points_on_one_adams_hardpoint(tmp_path, wishbone):
    s, state = wishbone
    mapping = tmp_path / "m.yaml"
    mapping.write_text(yaml.safe_dump({"elastokin_adams_mapping": 1, "hardpoints": {
        "lca_front": "arm", "lca_rear": "arm"}}))
    with pytest.raises(ConfigError, match="hardpoints lca_front and lca_rear are both written "
                                          "as the left point of ADAMS hardpoint 'arm'"):
        adams_export.export_adams(s, tmp_path / "x.cdb", state.bushing_preload,
                                  mapping=read_mapping(mapping))


def test_cli_export_with_mapping_and_template(tmp_path):
    out = tmp_path / "front.cdb"
    r = CliRunner().invoke(main, [
        "export-adams", "--config", str(WISHBONE), "--out", str(out), "--mapping",
        str(LR_MAPPING), "--template-name", "mdids://acar_shared/templates.tbl/_dw.tpl",
        "--major-role", "suspension", "--minor-role", "front", "--database", "mine"])
    assert r.exit_code == 0, r.output
    assert "no template given" not in r.output
    sub = out / "subsystems.tbl" / "generic_double_wishbone_front_left.sub"
    f = teimorbit.read_teimorbit(sub)
    assert f.block("SUBSYSTEM_HEADER").value("TEMPLATE_NAME") == \
        "mdids://acar_shared/templates.tbl/_dw.tpl"
    assert read_bushing_assemblies(f)["lca_front"]["left"].property_file == \
        "mdids://mine/bushings.tbl/lca_front.bus"
    cfg, _ = adams_car.import_adams(read_yaml(WISHBONE)[0], out / "subsystems.tbl",
                                    out / "mapping.yaml")
    assert cfg["hardpoints"] == read_yaml(WISHBONE)[0]["hardpoints"]
    r = CliRunner().invoke(main, ["export-adams", "--config", str(WISHBONE), "--out",
                                  str(tmp_path / "plain.cdb")])
    assert r.exit_code == 0 and "elastokin: warning: no template given" in r.output
