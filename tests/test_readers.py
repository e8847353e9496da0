"""Every reader wraps its library: a bad file (truncated, binary, another encoding, bad numbers)
raises an ElastokinError whose one-line message names the file (and the line where known);
the CLI prints it as one ``elastokin: error:`` line and exits 1. Also the IGES unit-flag hint
of geometric identification."""

import random
import shutil
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from elastokin.cli.main import main
from elastokin.config.loading import load_suspension
from elastokin.errors import ConfigError, ElastokinError, MeasurementError
from elastokin.formats.adams.kc import write_adams_kc_csv
from elastokin.formats.adams.teimorbit import read_teimorbit
from elastokin.formats.cmm import read_points, write_points
from elastokin.formats.kc_test import read_kc_test
from elastokin.identification.geometric import identify

ROOT = Path(__file__).resolve().parents[1]
CASE = ROOT / "configs" / "pseudo_mcpherson.yaml"
MEASURED = ROOT / "configs" / "pseudo_mcpherson_measurements"
KC_TEST = ROOT / "configs" / "pseudo_mcpherson_kc_test"
BUS = ROOT / "tests" / "data" / "adams" / "bushing_mm_newton_deg.bus"
ISO = {"x": "forward", "y": "left", "z": "up"}
HEADER = "label,kind,x_mm,y_mm,z_mm,x2_mm,y2_mm,z2_mm\n"
#: bytes of a binary file: a header, NUL bytes, bytes that are not UTF-8
BINARY = b"\x7fELF\x02\x01\x01\x00\x00\x00" + bytes(range(256)) * 8


def raises(exc_type, fn, path, *fragments):
    """``fn(path)`` raises ``exc_type`` with a one-line message naming ``path`` and every
    fragment; returns the message."""
    with pytest.raises(exc_type) as err:
        fn(path)
    msg = str(err.value)
    assert str(path) in msg, msg
    assert "\n" not in msg, msg
    for f in fragments:
        assert f in msg, (f, msg)
    return msg


def cli_fails(*args, name: str) -> str:
    result = CliRunner().invoke(main, [str(a) for a in args])
    out = result.output.strip()
    assert result.exit_code == 1, result.output
    assert out.startswith("elastokin: error:") and "\n" not in out, out
    assert "Traceback" not in result.output and name in out, out
    return out


def iges_lines() -> list[str]:
    return (MEASURED / "front_arm.igs").read_text().splitlines(keepends=True)


# ------------------------------------------------------------------------------------ IGES


@pytest.mark.parametrize("keep", [7, 8, 20, 30, -1])
def test_truncated_iges(tmp_path, keep):
    """Cut after a whole line: before, 8-31 lines read through pyiges, then raised
    AttributeError ('Point' object has no attribute '_x') on the entities' coordinates."""
    path = tmp_path / "front_arm.igs"
    path.write_text("".join(iges_lines()[:keep]))
    raises(MeasurementError, read_points, path, "unreadable IGES file", "truncated")


def test_truncated_iges_mid_line(tmp_path):
    text = "".join(iges_lines())
    path = tmp_path / "cut.igs"
    for n in range(600, len(text) - 1, 97):
        path.write_text(text[:n])
        raises(MeasurementError, read_points, path, "unreadable IGES file")


def test_iges_entity_without_parameter_data(tmp_path):
    """The terminate line is there but the last entity's parameter lines are not: pyiges
    reads the file and leaves the entity without coordinates."""
    lines = [ln for ln in iges_lines() if not (ln[72] == "P" and ln[64:72].strip() == "15")]
    path = tmp_path / "front_arm.igs"
    path.write_text("".join(lines))
    raises(MeasurementError, read_points, path, "directory line 15", "no parameter data")


@pytest.mark.parametrize("content, fragments", [
    (BINARY, ["line 1", "binary data"]),
    (bytes(random.Random(7).randrange(1, 256) for _ in range(4000)), ["unreadable IGES"]),
    (b"not an iges file\n" * 5, ["no directory entries"]),
], ids=["binary", "random bytes", "text"])
def test_garbage_iges(tmp_path, content, fragments):
    path = tmp_path / "garbage.igs"
    path.write_bytes(content)
    raises(MeasurementError, read_points, path, *fragments)


def test_iges_not_ascii_names_the_line(tmp_path):
    lines = iges_lines()
    lines[1] = lines[1].replace("elastokin", "Prüfteil ", 1)
    path = tmp_path / "front_arm.igs"
    path.write_bytes("".join(lines).encode("latin-1"))
    raises(MeasurementError, read_points, path, "line 2", "not ASCII text")


def test_iges_malformed_records_name_line_and_columns(tmp_path):
    path = tmp_path / "front_arm.igs"
    lines = iges_lines()
    lines[9] = lines[9][:16] + "     x 0" + lines[9][24:]  # structure field of DE 3
    path.write_text("".join(lines))
    raises(MeasurementError, read_points, path, "line 10, columns 17-24", "not an integer")
    path.write_text("".join(iges_lines()) + "\n")  # a blank line after the terminate line
    raises(MeasurementError, read_points, path, "line 34", "not an IGES record")


def test_iges_non_finite_coordinate(tmp_path):
    lines = iges_lines()
    k = next(i for i, ln in enumerate(lines) if ln.startswith("116,273.192826"))
    lines[k] = lines[k].replace("273.192826", "1.0E999   ")
    path = tmp_path / "front_arm.igs"
    path.write_text("".join(lines))
    raises(MeasurementError, read_points, path, "not finite")


@pytest.mark.filterwarnings("ignore:overflow:RuntimeWarning")
def test_iges_random_damage_never_escapes(tmp_path):
    """Random damage to a valid file: either it still reads or a MeasurementError names it."""
    rng = random.Random(2006)
    text = "".join(iges_lines())
    path = tmp_path / "damaged.igs"
    for _ in range(300):
        s = list(text)
        for _ in range(rng.randint(1, 4)):
            i = rng.randrange(len(s))
            s[i:i + rng.randint(0, 1)] = rng.choice("0123456789,;.-+ EDHx\n\x00é")
        path.write_bytes("".join(s).encode("latin-1"))
        try:
            read_points(path)
        except MeasurementError as exc:
            assert str(path) in str(exc) and "\n" not in str(exc)


# ------------------------------------------------------------------------- CSV point files


@pytest.mark.parametrize("content, fragments", [
    ((HEADER + "Mé,point,1,2,3,,,\n").encode("latin-1"), ["line 2", "not UTF-8"]),
    (BINARY, ["line 1", "binary data"]),
    ((HEADER + "M1,point,1,2,3,,,\n").encode("utf-16"), ["UTF-16"]),
    ((HEADER + "M1,point,nan,2,3,,,\n").encode(), ["line 2", "column x_mm", "finite"]),
    ((HEADER + "M1,point,1,2,1e999,,,\n").encode(), ["line 2", "column z_mm", "finite"]),
    ((HEADER + "M1,point,1,5,2,3,,,\n").encode(), ["line 2", "9 cells", "decimal comma"]),
    ((HEADER + "M1,point,1,2,3,,," + "9" * 200_000 + "\n").encode(), ["unreadable CSV"]),
    (HEADER.replace(",", ";").encode(), ["line 1", "separated by ';'"]),
], ids=["latin-1", "binary", "utf-16", "nan", "overflow", "decimal comma", "huge field",
        "semicolons"])
def test_bad_csv_point_files(tmp_path, content, fragments):
    path = tmp_path / "front_arm.csv"
    path.write_bytes(content)
    raises(MeasurementError, read_points, path, *fragments)


def test_csv_point_file_with_byte_order_mark(tmp_path):
    path = tmp_path / "front_arm.csv"
    path.write_bytes(("\ufeff" + HEADER + "M1,point,1,2,3,,,\n").encode())
    np.testing.assert_array_equal(read_points(path).points["M1"], [1.0, 2.0, 3.0])


def test_measurement_file_cannot_be_written(tmp_path):
    for ext in (".igs", ".csv"):
        raises(MeasurementError, lambda p: write_points(p, {"M1": [0.0, 0, 0]}),
               tmp_path / "missing" / f"m{ext}", "cannot write")


# ------------------------------------------------------------------------- K&C test files


@pytest.mark.parametrize("content, fragments", [
    (BINARY, ["line 1", "binary data", "K&C test CSV"]),
    (b"# load_case: lateral_force\n# caf\xe9\nlateral_force [N],toe [deg]\n",
     ["line 2", "not UTF-8"]),
    ("lateral_force [N],toe [deg]\n0,0\n".encode("utf-16"), ["UTF-16"]),
    (b"lateral_force [N],toe [deg]\n0,0\n1," + b"9" * 200_000 + b"\n",
     ["line 3", "unreadable CSV row"]),
], ids=["binary", "latin-1", "utf-16", "huge field"])
def test_bad_kc_test_files(tmp_path, content, fragments):
    path = tmp_path / "lateral_force.csv"
    path.write_bytes(content)
    raises(MeasurementError, read_kc_test, path, *fragments)


def test_binary_kc_test_file_on_the_cli(tmp_path):
    """``elastokin kc`` reads the test files first: one line, no traceback, nothing run."""
    shutil.copy(CASE, tmp_path / CASE.name)
    for folder in (MEASURED, KC_TEST):
        shutil.copytree(folder, tmp_path / folder.name)
    (tmp_path / KC_TEST.name / "lateral_force.csv").write_bytes(BINARY)
    cli_fails("kc", "--config", tmp_path / CASE.name, "--out", tmp_path / "out", "--quiet",
              name="lateral_force.csv")
    assert not (tmp_path / "out").exists()


# ------------------------------------------------------------------ kc.csv for ADAMS export


def test_binary_kc_csv_for_export_adams(tmp_path):
    """Before: UnicodeDecodeError from write_adams_kc_csv, a traceback on the console."""
    kc = tmp_path / "kc.csv"
    kc.write_bytes(BINARY)
    msg = cli_fails("export-adams", "--config", CASE, "--out", tmp_path / "x", "--kc", kc,
                    name="kc.csv")
    assert "line 1" in msg and "expected an elastokin kc.csv" in msg
    assert not (tmp_path / "x").exists()


KC_HEADER = "model,load_case,step,toe_deg,wheel_centre_x_mm\n"


@pytest.mark.parametrize("content, fragments", [
    ((KC_HEADER + "# caf\xe9\n").encode("latin-1"), ["line 2", "non-UTF-8"]),
    ((KC_HEADER + "m,lc,1,0.1,abc\n").encode(), ["data row 1", "wheel_centre_x_mm", "'abc'"]),
    ((KC_HEADER + "m,lc,1,0.1\n").encode(), ["line 2", "4 cells"]),
    ((KC_HEADER + "m,lc,1,0.1," + "9" * 200_000 + "\n").encode(), ["unreadable CSV"]),
], ids=["latin-1", "not a number", "short row", "huge field"])
def test_bad_kc_csv_for_adams(tmp_path, content, fragments):
    kc = tmp_path / "kc.csv"
    kc.write_bytes(content)
    raises(ConfigError, lambda p: write_adams_kc_csv(p, tmp_path / "out.csv", ISO), kc,
           *fragments)


def test_kc_adams_csv_cannot_be_written(tmp_path):
    kc = tmp_path / "kc.csv"
    kc.write_text(KC_HEADER + "m,lc,1,0.1,2.0\n")
    out = tmp_path / "missing" / "kc_adams.csv"
    raises(ConfigError, lambda p: write_adams_kc_csv(kc, p, ISO), out, "cannot write")


# ------------------------------------------------------------------------ TeimOrbit files


@pytest.mark.parametrize("content, fragments", [
    (BINARY, ["line 1", "not a text file"]),
    (BUS.read_bytes().replace(b"[UNITS]", b"[UNITS]\x00", 1), ["binary"]),
    (b"[MDI_HEADER]\n" + "caf\xe9".encode("latin-1") + b"\n", ["line 2", "not UTF-8"]),
    (b"\x01\x02\x03" * 10_000 + b"\n[UNITS]\n", ["line 1", "its text is not shown"]),
], ids=["binary", "nul byte", "latin-1", "control characters"])
def test_bad_teimorbit_files(tmp_path, content, fragments):
    path = tmp_path / "bushing.bus"
    path.write_bytes(content)
    msg = raises(ConfigError, read_teimorbit, path, *fragments)
    assert len(msg) < 300, msg


def test_binary_bus_file_on_the_cli(tmp_path):
    adams = ROOT / "tests" / "data" / "adams"
    bus = tmp_path / "lca.bus"
    bus.write_bytes(BINARY)
    cli_fails("import-adams", "--hardpoints", adams / "double_wishbone.sub", "--mapping",
              adams / "double_wishbone_mapping.yaml", "--template",
              ROOT / "tests" / "data" / "double_wishbone.yaml", "--bushing",
              f"lca_bushing={bus}", "--out", tmp_path / "x.yaml", name="lca.bus")
    assert not (tmp_path / "x.yaml").exists()


# ------------------------------------------------------------------ IGES unit-flag hint


def measured_copy(tmp_path) -> Path:
    shutil.copy(CASE, tmp_path / CASE.name)
    shutil.copytree(MEASURED, tmp_path / MEASURED.name)
    return tmp_path / CASE.name


def set_unit_flag(path: Path, flag: str) -> None:
    """Rewrite the unit flag (and name) of a file written by write_iges, numbers unchanged."""
    text = path.read_text()
    new = text.replace(",1.0,2,2HMM,", flag)
    assert new != text and len(new) == len(text)
    path.write_text(new)


@pytest.mark.parametrize("file, flag, factor", [
    ("front_arm.igs", ",1.0,1,2HIN,", "1/25.4"),
    ("knuckle.igs", ",1.0,10,1HC,", "0.1"),
    ("body.igs", ",1.0,4,2HFT,", "1/304.8"),
])
def test_part_unit_flag_hint(tmp_path, file, flag, factor):
    config = measured_copy(tmp_path)
    set_unit_flag(tmp_path / MEASURED.name / file, flag)
    with pytest.raises(MeasurementError) as err:
        identify(load_suspension(config))
    msg = str(err.value)
    assert "assembly.igs" in msg and "match no ordering" in msg
    assert msg.endswith(f"; the marks fit after scaling by {factor}: check the unit flag of "
                        f"{tmp_path / MEASURED.name / file}"), msg


def test_assembly_unit_flag_hint(tmp_path):
    config = measured_copy(tmp_path)
    set_unit_flag(tmp_path / MEASURED.name / "assembly.igs", ",1.0,1,2HIN,")
    with pytest.raises(MeasurementError) as err:
        identify(load_suspension(config))
    assert str(err.value).endswith("every part's marks fit after scaling the assembled marks "
                                   "by 1/25.4: check the unit flag of "
                                   f"{tmp_path / MEASURED.name / 'assembly.igs'}")


def test_no_unit_hint_for_wrong_marks(tmp_path):
    """Two wrong assembled marks of one part: no unit factor fits, no hint."""
    config = measured_copy(tmp_path)
    path = tmp_path / MEASURED.name / "assembly.igs"
    pts = read_points(path)
    ra = [k for k in pts.order if k.startswith("RA")]
    pts.points[ra[0]] = pts.points[ra[0]] + [9.0, 0, 0]
    pts.points[ra[1]] = pts.points[ra[1]] + [0, 0, -11.0]
    write_points(path, pts.points, {})
    with pytest.raises(ElastokinError) as err:
        identify(load_suspension(config))
    assert "rear_arm" in str(err.value) and "unit flag" not in str(err.value)
