"""ADAMS/Car files as a user gets them wrong, or receives them from a supplier (docs/adams.md):
every one ends in one line naming the file, the line and the block or key and what is
expected, never a traceback, never a silently wrong model, never the text of a file that is
not TeimOrbit."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest
import yaml
from click.testing import CliRunner

from elastokin.cli.main import main
from elastokin.config.loading import read_yaml
from elastokin.errors import ConfigError
from elastokin.formats.adams.car import import_adams, read_bushing, read_hardpoints
from elastokin.formats.adams.importing import subsystem_files
from elastokin.formats.adams.mapping import read_mapping

ADAMS = Path(__file__).parent / "data" / "adams"
WISHBONE = Path(__file__).parent / "data" / "double_wishbone.yaml"
SUB = (ADAMS / "double_wishbone.sub").read_text()
BUS = (ADAMS / "bushing_mm_newton_deg.bus").read_text()
ROW = " 'lca_front                   '  'left/right'      -202.0     -351.0      151.0"
UNITS = " LENGTH  =  'mm'"


def hardpoints_error(tmp_path: Path, content: str | bytes, *fragments: str) -> str:
    """``read_hardpoints`` of a .sub holding ``content`` fails with one line naming it and
    every fragment; returns the message."""
    path = tmp_path / "front.sub"
    path.write_bytes(content if isinstance(content, bytes) else content.encode())
    with pytest.raises(ConfigError) as exc:
        read_hardpoints(path)
    msg = str(exc.value)
    assert msg.startswith(str(path)) and "\n" not in msg, msg
    for f in fragments:
        assert f in msg, (f, msg)
    return msg


def line_of(text: str, fragment: str) -> int:
    return next(i for i, ln in enumerate(text.splitlines(), start=1) if fragment in ln)


# ----------------------------------------------------------------------------------------------
# Units


def test_unknown_length_unit(tmp_path):
    text = SUB.replace(UNITS, " LENGTH  =  'furlong'")
    hardpoints_error(tmp_path, text, f"line {line_of(text, 'furlong')}, block [UNITS]: "
                     "unknown length unit 'furlong' (known: ")


def test_units_block_in_metres_for_values_in_mm(tmp_path):
    """A supplier's file whose [UNITS] says meter while its values are mm: 351 m wide."""
    text = SUB.replace(UNITS, " LENGTH  =  'meter'")
    hardpoints_error(tmp_path, text, "hardpoint 'wheel_center' is at [-1000.0, -781000.0, "
                     "301000.0] mm, more than 20 m from the origin (LENGTH 'meter'): a wrong "
                     "[UNITS] block?", f"line {line_of(text, 'wheel_center')}")


def test_values_in_metres_without_units_block(tmp_path):
    start, end = SUB.index("$----------------------------------------------------------------"
                           "---------UNITS"), SUB.index("$-------------------------------------"
                                                       "----------------------------SUBSYSTEM_H")
    text = SUB[:start] + SUB[end:]
    rows = [ln for ln in text.splitlines() if "'left/right'     " in ln
            and "hardpoint" not in ln]
    for ln in rows:
        head, *xyz = ln.rsplit(None, 3)
        text = text.replace(ln, f"{head} " + " ".join(f"{float(v) / 1000:g}" for v in xyz))
    hardpoints_error(tmp_path, text, "every hardpoint lies within 10 mm of the origin (no "
                     "[UNITS] block: ADAMS/Car's default, mm): values in metres?")


# ----------------------------------------------------------------------------------------------
# Blocks, rows, keywords


def test_hardpoint_table_with_misspelled_columns(tmp_path):
    text = SUB.replace("x_value    y_value    z_value", "x    y    z")
    hardpoints_error(tmp_path, text, "no hardpoint table {hardpoint_name symmetry x_value "
                     "y_value z_value} in any block; found {hardpoint_name symmetry x y z} "
                     f"(line {line_of(text, '{hardpoint_name')})")


def test_bus_without_a_curve_block(tmp_path):
    path = tmp_path / "x.bus"
    path.write_text(BUS.replace("[FY_CURVE]", "[FY_CURVES]"))
    with pytest.raises(ConfigError, match=rf"^{path}: block \[FY_CURVE\] is missing$"):
        read_bushing(path)


def test_hardpoint_given_twice(tmp_path):
    text = SUB.replace(ROW, ROW + "\n" + ROW.replace("-202.0", "-210.0"))
    line = line_of(text, "lca_front")
    hardpoints_error(tmp_path, text, f"line {line + 1}, block [HARDPOINT]: hardpoint "
                     f"'lca_front' is given twice (first at line {line})")


def test_hardpoint_given_twice_in_another_case(tmp_path):
    """Names are looked up case-insensitively: LCA_FRONT beside lca_front would be one of the
    two, silently."""
    text = SUB.replace(ROW, ROW + "\n" + ROW.replace("lca_front", "LCA_FRONT"))
    line = line_of(text, "lca_front")
    hardpoints_error(tmp_path, text, f"line {line + 1}", "hardpoint 'LCA_FRONT' is 'lca_front' "
                     f"(line {line}) again: ADAMS/Car hardpoint names are case-insensitive")


@pytest.mark.parametrize("old, new, words", [
    ("'left/right'", "'both'      ", "hardpoint 'lca_front': symmetry 'both', expected one of "
                                     "left/right, single, left, right"),
    ("-351.0", "-35l.0", "row 'lca_front': column y_value of {hardpoint_name symmetry x_value "
                         "y_value z_value}: '-35l.0' is not a number"),
], ids=["wrong symmetry keyword", "not a number"])
def test_bad_hardpoint_row(tmp_path, old, new, words):
    text = SUB.replace(ROW, ROW.replace(old, new))
    hardpoints_error(tmp_path, text, f"line {line_of(text, 'lca_front')}, block [HARDPOINT]: "
                     f"{words}")


@pytest.mark.parametrize("old, new, words", [
    ("SYMMETRY  =  'left/right'", "SYMMETRY  =  'mirror'",
     "USAGE 'lca_bushing': SYMMETRY 'mirror', expected one of left/right"),
    (" USAGE  =  'lca_bushing'\n", "", "USAGE = 'name' is missing"),
], ids=["wrong symmetry keyword", "no usage"])
def test_bad_bushing_assembly(tmp_path, old, new, words):
    db = database(tmp_path, SUB.replace(old, new))
    sub = db / "subsystems.tbl" / "front.sub"
    block = line_of(sub.read_text(), "[BUSHING_ASSEMBLY]")
    line = line_of(sub.read_text(), new.strip() or "[BUSHING_ASSEMBLY]")
    with pytest.raises(ConfigError) as exc:
        import_adams(read_yaml(WISHBONE)[0], db, db / "mapping.yaml")
    assert str(exc.value).startswith(f"{sub}, line {line if new else block}, block "
                                      f"[BUSHING_ASSEMBLY]: {words}"), str(exc.value)


# ----------------------------------------------------------------------------------------------
# Not a TeimOrbit file at all


@pytest.mark.parametrize("content, fragments", [
    (b"", ["empty file: no [BLOCK] (expected a TeimOrbit file)"]),
    (b"$ only a comment\n$-----------HARDPOINT\n", ["only $ comments: no [BLOCK]"]),
    (b"\x89PNG\r\n\x1a\n\x00\x00\x00\rIHDR" + bytes(range(256)),
     ["not a text file (byte 8 is binary"]),
    ("[MDI_HEADER]\n FILE_TYPE = 'sub'\n".encode("utf-16"), ["UTF-16 text; expected a TeimOrbit "
                                                            "text file in UTF-8", "save it"]),
    (b"<html><body>password=TOP-SECRET-7f3a</body></html>\n",
     ["line 1: a line that is neither a $ comment nor a [BLOCK] header comes before the first "
      "[BLOCK] header", "(its text is not shown)"]),
    (b"[section]\npassword = TOP-SECRET-7f3a\n", ["no hardpoint table"]),
], ids=["empty", "comments only", "binary", "utf-16", "html page", "ini file"])
def test_files_that_are_not_teimorbit(tmp_path, content, fragments):
    msg = hardpoints_error(tmp_path, content, *fragments)
    assert "TOP-SECRET" not in msg and "PNG" not in msg


# ----------------------------------------------------------------------------------------------
# A database and its references


def database(tmp_path: Path, sub_text: str, bus_text: str = BUS) -> Path:
    """``db.cdb`` with the subsystem ``sub_text`` (its PROPERTY_FILE in this database) and
    the bushing file, and a mapping taking the bushing by usage."""
    db = tmp_path / "db.cdb"
    (db / "subsystems.tbl").mkdir(parents=True)
    (db / "bushings.tbl").mkdir()
    (db / "bushings.tbl" / "bushing_mm_newton_deg.bus").write_text(bus_text)
    (db / "subsystems.tbl" / "front.sub").write_text(sub_text)
    mapping = yaml.safe_load((ADAMS / "double_wishbone_mapping.yaml").read_text())
    mapping["bushings"] = {"lca_bushing": {"usage": "lca_bushing"}}
    (db / "mapping.yaml").write_text(yaml.safe_dump(mapping))
    return db


def test_bus_with_a_non_monotonic_curve_in_the_database(tmp_path):
    bus = BUS.replace("                    -5                 -4000",
                      "                   -12                 -4000")
    db = database(tmp_path, SUB, bus)
    path = db / "bushings.tbl" / "bushing_mm_newton_deg.bus"
    r = CliRunner().invoke(main, ["import-adams", "--hardpoints", str(db), "--mapping",
                                  str(db / "mapping.yaml"), "--template", str(WISHBONE),
                                  "--out", str(tmp_path / "new.yaml")])
    assert r.exit_code == 1 and r.output.count("\n") == 1 and "Traceback" not in r.output
    line = line_of(bus, "-10                -12000") + 1
    assert (f"{path}, line {line}, block [FX_CURVE]: deflection -12 mm does not "
            "increase on -10 mm (line") in r.output


@pytest.mark.parametrize("usage", ["mdids://db/assemblies.tbl/front.asy",
                                   "mdids://db/assemblies.tbl/other.asy"])
def test_assembly_naming_an_assembly(tmp_path, usage):
    """A recursive reference: an assembly naming itself, or another assembly."""
    db = database(tmp_path, SUB)
    (db / "assemblies.tbl").mkdir()
    asy = db / "assemblies.tbl" / "front.asy"
    asy.write_text(f"[MDI_HEADER]\n FILE_TYPE = 'asy'\n[SUBSYSTEM]\n USAGE = '{usage}'\n")
    shutil.copy(asy, db / "assemblies.tbl" / "other.asy")
    with pytest.raises(ConfigError, match=rf"^{asy}, line 4, block \[SUBSYSTEM\]: USAGE names "
                                          r"an assembly .*, not a subsystem file"):
        subsystem_files(read_mapping(db / "mapping.yaml"), assembly=asy)


def test_mdids_of_an_unknown_database_alias(tmp_path):
    db = database(tmp_path, SUB.replace("mdids://elastokin_tests/bushings.tbl/",
                                        "mdids://acar_shared/bushings.tbl/front_"))
    with pytest.raises(ConfigError, match=r"PROPERTY_FILE 'mdids://acar_shared/bushings.tbl/"
                                          r"front_bushing_mm_newton_deg.bus' does not exist .*"
                                          r"alias 'acar_shared' taken as the database that "
                                          r"holds front.sub: .*does not read .acar.cfg"):
        import_adams(read_yaml(WISHBONE)[0], db, db / "mapping.yaml")


def test_property_file_that_is_a_folder(tmp_path):
    db = database(tmp_path, SUB.replace("bushing_mm_newton_deg.bus'", "'"))
    with pytest.raises(ConfigError, match=r"PROPERTY_FILE 'mdids://elastokin_tests/bushings"
                                          r".tbl/' is a folder, not a file"):
        import_adams(read_yaml(WISHBONE)[0], db, db / "mapping.yaml")


def test_database_with_two_subsystems_and_no_name(tmp_path):
    db = database(tmp_path, SUB)
    shutil.copy(db / "subsystems.tbl" / "front.sub", db / "subsystems.tbl" / "rear.sub")
    with pytest.raises(ConfigError, match=r"subsystems.tbl holds one .sub file or the "
                                          r"mapping's subsystem \(found 2: front.sub, rear.sub\)"):
        import_adams(read_yaml(WISHBONE)[0], db, db / "mapping.yaml")
