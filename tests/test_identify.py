"""Geometric identification end to end: measurement files, the virtual CMM, the identified
model against the synthetic truth, the paper's own check, and bad input."""

import copy
import json
import shutil

import numpy as np
import pytest
import yaml
from click.testing import CliRunner

from elastokin.cli.main import main
from elastokin.config.loading import load_suspension, read_yaml, suspension_from_dict
from elastokin.config.schema.suspension import ClearanceSpec
from elastokin.errors import MeasurementError
from elastokin.formats.cmm import read_points, write_points
from elastokin.physics.pose import clearance_bound_mm, pose_error_gain
from elastokin.studies.identification import identify_geometry as identify
from elastokin.synthetic.virtual_cmm import synthesize

from .conftest import CASE

MEASURED = CASE.parent / "pseudo_mcpherson_measurements"


@pytest.fixture(scope="module")
def ident(case):
    return identify(case)


@pytest.fixture(scope="module")
def truth():
    return yaml.safe_load((MEASURED / "truth.yaml").read_text())


def measured_copy(tmp_path, mutate_config=None):
    """The shipped config, its measurement folder and its K&C test folder copied to
    ``tmp_path``."""
    shutil.copytree(MEASURED, tmp_path / MEASURED.name)
    kc_test = CASE.parent / "pseudo_mcpherson_kc_test"
    shutil.copytree(kc_test, tmp_path / kc_test.name)
    data = read_yaml(CASE)[0]
    if mutate_config:
        mutate_config(data)
    path = tmp_path / CASE.name
    path.write_text(yaml.safe_dump(data))
    return path, tmp_path / MEASURED.name


# ------------------------------------------------------------------------------ files


def test_iges_and_csv_round_trip(tmp_path):
    pts = {"M1": [1.0, 2.0, 3.5], "M2": [-1000.0, 2.123456, 0.0], "J1": [0.1, 0.2, -0.3]}
    lines = {"J1.Z": [[0, 0, 0], [0, 0, 100.0]], "J1.X": [[0, 0, 0], [100.0, 0, 0.5]]}
    for ext in (".igs", ".csv"):
        write_points(tmp_path / f"p{ext}", pts, lines, "two lines\nof comment")
        back = read_points(tmp_path / f"p{ext}")
        assert back.order == ["M1", "M2", "J1"]
        for k, v in pts.items():
            np.testing.assert_allclose(back.points[k], v, atol=1e-6)
        for k, v in lines.items():
            np.testing.assert_allclose(back.lines[k], v, atol=1e-6)


def test_iges_units_transform_and_subscripts(tmp_path):
    """A user's IGES file: inches (unit flag 1), a transformation matrix (entity 124) and
    labels split into label + subscript, as CAD systems write them."""
    path = tmp_path / "user.igs"
    write_points(path, {"M": [1.0, 2.0, 3.0]}, {})
    text = path.read_text().splitlines()
    text = [ln.replace(",1.0,2,2HMM,", ",1.0,1,2HIN,") for ln in text]
    de = [i for i, ln in enumerate(text) if ln[72] == "D"]
    # point: transform pointer -> DE 3 (the matrix), subscript 7
    text[de[0]] = text[de[0]][:48] + f"{3:>8}" + text[de[0]][56:]
    text[de[1]] = text[de[1]][:64] + f"{7:>8}" + text[de[1]][72:]
    p_lines = [ln for ln in text if ln[72] == "P"]
    rest = [ln for ln in text if ln[72] in "ST"]
    g_lines = [ln for ln in text if ln[72] == "G"]
    # rotation of 90 deg about z and a shift of (10, 0, 0) inch
    d124 = [f"{124:>8}{2:>8}{0:>8}{1:>8}{0:>8}{0:>8}{0:>8}{0:>8}{'00010000':>8}D{3:>7}",
            f"{124:>8}{0:>8}{0:>8}{1:>8}{0:>8}{'':>8}{'':>8}{'':>8}{0:>8}D{4:>7}"]
    p124 = f"{'124,0.,-1.,0.,10.,1.,0.,0.,0.,0.,0.,1.,0.;':<64}{3:>8}P{2:>7}"
    text = ([rest[0]] + g_lines + [ln for ln in text if ln[72] == "D"] + d124 + p_lines
            + [p124] + [rest[-1]])
    path.write_text("\n".join(text) + "\n")
    back = read_points(path)
    np.testing.assert_allclose(back.points["M7"], np.array([10 - 2.0, 1.0, 3.0]) * 25.4,
                               atol=1e-9)


@pytest.mark.parametrize("content", [b"", b"not an iges file\n" * 5, bytes(range(256)) * 4])
def test_unreadable_iges(tmp_path, content):
    path = tmp_path / "broken.igs"
    path.write_bytes(content)
    with pytest.raises(MeasurementError, match="broken.igs"):
        read_points(path)


def test_csv_errors_name_file_and_line(tmp_path):
    path = tmp_path / "m.csv"
    path.write_text("label,kind,x_mm,y_mm\nM1,point,1,2\n")
    with pytest.raises(MeasurementError, match=r"m\.csv.*z_mm"):
        read_points(path)
    path.write_text("label,kind,x_mm,y_mm,z_mm,x2_mm,y2_mm,z2_mm\nM1,point,1,two,3,,,\n")
    with pytest.raises(MeasurementError, match=r"m\.csv: line 2: column y_mm"):
        read_points(path)


def test_clearance_bound_matches_paper_eq1():
    c = ClearanceSpec(hole_mm=13.0, bolt_mm=12.0, inner_bore_mm=12.5)
    assert c.max_shift_mm == pytest.approx(clearance_bound_mm(13.0, 12.0, 12.5)) == 0.75


def test_pose_error_gain_at_the_centroid():
    """Noise on n marks moves their centroid by 1/sqrt(n) of it (the rotation does not)."""
    marks = np.array([[100.0, 0, 0], [-100, 0, 0], [0, 100, 0], [0, 0, 100]])
    assert pose_error_gain(marks, marks.mean(axis=0)) == pytest.approx(0.5, rel=1e-4)
    # far from a small layout the rotation error dominates
    assert pose_error_gain(marks, [2000.0, 0, 0]) > 5


# ------------------------------------------------------------------------ virtual CMM


def test_synthesize_regenerates_the_committed_files_byte_for_byte(tmp_path, case):
    written = synthesize(case, folder=tmp_path)
    assert len(written) == 13
    for path in written:
        assert path.read_bytes() == (MEASURED / path.name).read_bytes(), path.name


def test_synthetic_truth_is_physical(truth, case):
    """Shifts within dL_max, bushing shifts normal to the sleeve axis, one gross mark."""
    m = case.measurements
    for name, shift in truth["clearance_shift_mm"].items():
        assert np.linalg.norm(shift) <= m.joints[name].clearance.max_shift_mm + 1e-9
        b = next((b for b in case.bushings if b.name == name), None)
        if b is not None:
            assert abs(np.dot(shift, b.frame[:, 2])) < 1e-6
    lo, hi = m.synthetic.gross_error_mm
    assert lo <= np.linalg.norm(truth["gross_error"]["error_mm"]) <= hi


def test_iges_and_csv_files_hold_the_same_data():
    for igs in MEASURED.glob("*.igs"):
        a, b = read_points(igs), read_points(igs.with_suffix(".csv"))
        assert a.order == b.order and a.lines.keys() == b.lines.keys()
        for k in a.points:
            np.testing.assert_array_equal(a.points[k], b.points[k])


# --------------------------------------------------------------------- identification


def test_identified_joints_within_0_3_mm_of_the_truth(ident):
    # tolerance from the issue; the CMM puts 95 % of its points within 0.1 mm, and across 21
    # seeds of the virtual CMM the worst joint error was 0.10-0.21 mm (0.147 for the shipped
    # seed); without noise it is 0.005 mm (test below)
    errors = {n: j.error_vs_truth_mm for n, j in ident.joints.items()}
    assert all(e is not None for e in errors.values())
    assert max(errors.values()) <= 0.3, errors


def test_paper_check_joints_at_measured_locations(ident):
    """The paper's check (its section 5): the identified model's static equilibrium puts
    every joint where it was measured (solver tolerance 1e-8: deviations of 1e-8 mm)."""
    assert ident.verification_max_deviation_mm <= 0.05
    assert ident.verification_max_deviation_mm < 1e-5


def test_the_wrong_mark_is_found(ident, truth, case):
    g = truth["gross_error"]
    match = ident.poses[g["part"]].match
    assert case.measurements.parts[g["part"]].marks[match.dropped_mark] == g["mark"]
    others = [p for p in ident.poses if p != g["part"]]
    assert all(ident.poses[p].match.dropped_mark is None for p in others)
    assert any(g["part"] in w and "dropped" in w for w in ident.warnings)


def test_identified_shift_is_the_clearance_shift(ident, truth):
    """For a bushing the shift (identified inner sleeve - housing centre) is the as-built
    clearance shift; noise of the two measurements bounds the difference."""
    for name, shift in truth["clearance_shift_mm"].items():
        if ident.joints[name].kind == "bushing":
            assert np.linalg.norm(ident.joints[name].shift_mm - shift) < 0.3


def test_identified_deflections_match_the_paper_table3_order(ident):
    """J4 carries the wheel load axially: its identified deflection is the largest (7.4 mm
    here, 7.01 mm in the paper's Table 3)."""
    assert ident.joints["J4"].deflection[2] == pytest.approx(7.42, abs=0.05)


def test_noise_free_identification_is_exact(tmp_path, case_dict):
    data = read_yaml(CASE)[0]
    data["measurements"]["folder"] = str(tmp_path)
    data["measurements"]["synthetic"]["noise_mm"] = 0.0
    s = suspension_from_dict(data, str(tmp_path / "c.yaml"))
    synthesize(s)
    result = identify(s)
    # 0.020 mm measured (J1; J2 and J4 0.003 mm): the identification holds the bushings in
    # their ideal joints, the as-built also carries moments in them (J2 1.0 N*m, J4 0.6 N*m)
    # and so shares the lower arms' load a little differently; it was 0.005 mm before issue
    # 24, the wheel load then acting 0.5 mm off the tyre's lowest point in the as-built
    assert max(j.error_vs_truth_mm for j in result.joints.values()) < 0.03


def test_csv_files_identify_like_iges(tmp_path, ident):
    def to_csv(d):
        m = d["measurements"]
        for p in m["parts"].values():
            p["file"] = p["file"].replace(".igs", ".csv")
        m["assembly"]["file"] = m["assembly"]["file"].replace(".igs", ".csv")

    path, _ = measured_copy(tmp_path, to_csv)
    from elastokin.config.loading import load_suspension

    other = identify(load_suspension(path))
    for n, j in ident.joints.items():
        np.testing.assert_allclose(other.joints[n].identified_mm, j.identified_mm, atol=1e-9)


# ------------------------------------------------------------------------------- CLI


def run(*args):
    return CliRunner().invoke(main, [*map(str, args)])


@pytest.mark.slow
def test_identify_cli_contract_and_identified_config_runs(tmp_path, case_path, case_kc):
    out = tmp_path / "ident"
    result = run("identify", "--config", case_path, "--out", out)
    assert result.exit_code == 0, result.output
    d = json.loads((out / "identification.json").read_text())
    for p, v in d["parts"].items():
        assert isinstance(v["residual_rms_mm"], float), p
        assert v["dropped_mark"] is None or isinstance(v["dropped_mark"], int)
    for n, j in d["joints"].items():
        assert len(j["shift_mm"]) == 3 and isinstance(j["error_vs_truth_mm"], float), n
    assert isinstance(d["verification_max_deviation_mm"], float)
    assert d["config_sha256"] and d["exudyn_version"]
    assert "Verification" in (out / "identification.txt").read_text()
    # the identified config is a config: kc runs it and gets the kc job's identified model
    # (the steer amplitude: the config's parallel travel alone, the other load cases off; the
    # kc job runs every load case on the identified model: case_kc)
    rig = tmp_path / "travel.yaml"
    rig.write_text(yaml.safe_dump({**{case: None for case in yaml.safe_load(
        (CASE.parent / "rigs" / "travel_only.yaml").read_text())},
        "parallel_travel": read_yaml(CASE)[0]["rig"]["parallel_travel"]}))
    kc_out = tmp_path / "kc"
    result = run("kc", "--config", out / "identified.yaml", "--out", kc_out, "--quiet",
                 "--models", "identified,identified_kinematic",  # the fit: test_kc_test
                 "--data", CASE.parent, "--rig", rig)  # the test data beside the config
    assert result.exit_code == 0, result.output
    # ... and so is initial.yaml, whose spring seats sit off its strut axis (the housing
    # centre moved J4): its kinematic model used to diverge (issue 15); the stiffness fit
    # belongs to the identified model (switched off in initial.yaml)
    result = run("kc", "--config", out / "initial.yaml", "--out", tmp_path / "kc_initial",
                 "--quiet", "--data", CASE.parent, "--rig", rig)
    assert result.exit_code == 0, result.output
    initial = json.loads((tmp_path / "kc_initial" / "summary.json").read_text())["models"]
    assert list(initial) == ["test", "initial", "initial_kinematic"]
    kc_meas = case_kc  # `elastokin kc` on the config with its measurements
    a = json.loads((kc_out / "summary.json").read_text())["models"]["identified"]
    b = json.loads((kc_meas / "summary.json").read_text())["models"]["identified"]
    # the written config rounds coordinates to 9 significant digits: 1e-6 deg
    assert a["steer_amplitude_deg"] == pytest.approx(b["steer_amplitude_deg"], abs=1e-6)
    assert (kc_meas / "identification.json").exists()


def _no_inner(d):
    del d["measurements"]["joints"]["J1"]["inner"]


def _corrupt(folder):
    (folder / "rear_arm.igs").write_bytes(b"\x00\xff garbage" * 50)


def _two_marks(folder):
    path = folder / "assembly.igs"
    pts = read_points(path)
    keep = {k: v for k, v in pts.points.items() if not k.startswith("RA")}
    keep.update([(k, v) for k, v in pts.points.items() if k.startswith("RA")][:2])
    write_points(path, keep, {})


def _two_wrong_marks(folder):
    path = folder / "assembly.igs"
    pts = read_points(path)
    ra = [k for k in pts.order if k.startswith("RA")]
    pts.points[ra[0]] = pts.points[ra[0]] + [9.0, 0, 0]
    pts.points[ra[1]] = pts.points[ra[1]] + [0, 0, -11.0]
    write_points(path, pts.points, {})


BAD = {
    "sleeve side not given": (_no_inner, None, ["J1", "inner", "body", "front_arm",
                                                "pseudo_mcpherson.yaml"]),
    "unreadable IGES": (None, _corrupt, ["rear_arm.igs", "unreadable IGES"]),
    "fewer than 3 marks": (None, _two_marks, ["assembly.igs", "rear_arm", "at least 3"]),
    "no permutation": (None, _two_wrong_marks, ["assembly.igs", "rear_arm", "match no"]),
}


@pytest.mark.parametrize("name", list(BAD))
@pytest.mark.parametrize("command", ["identify", "kc"])
def test_bad_measurements_one_clear_line_and_no_output(tmp_path, name, command):
    mutate_config, mutate_files, expected = BAD[name]
    path, folder = measured_copy(tmp_path, mutate_config)
    if mutate_files:
        mutate_files(folder)
    out = tmp_path / "out"
    result = run(command, "--config", path, "--out", out, "--quiet")
    assert result.exit_code == 1
    message = result.output.strip()
    assert message.startswith("elastokin: error: ") and "\n" not in message, message
    for word in expected:
        assert word in message, message
    assert not out.exists()


def test_marks_of_a_missing_part_file(tmp_path):
    path, folder = measured_copy(tmp_path)
    (folder / "knuckle.igs").unlink()
    result = run("identify", "--config", path, "--out", tmp_path / "out", "--quiet")
    assert result.exit_code == 1 and "knuckle.igs" in result.output


def test_measurements_must_cover_every_part(tmp_path, case_dict):
    data = copy.deepcopy(read_yaml(CASE)[0])
    del data["measurements"]["parts"]["strut_rod"]
    with pytest.raises(Exception, match="strut_rod"):
        identify(suspension_from_dict(data, str(CASE)))


def test_a_label_mapping_that_finds_nothing_names_the_label(tmp_path):
    """``labels`` maps a hardpoint to its label in the file: a label the file does not hold is
    named with the mapping, not as the hardpoint."""
    def relabel(data):
        data["measurements"]["parts"]["strut_rod"]["labels"] = {"spring_upper_seat": "SPRING_X"}

    path, _ = measured_copy(tmp_path, relabel)
    with pytest.raises(MeasurementError) as exc:
        identify(load_suspension(path))
    assert "strut_rod.igs: part 'strut_rod': no point labelled 'SPRING_X' (measurements.parts" \
           ".strut_rod.labels gives 'SPRING_X' for hardpoint 'spring_upper_seat')" in \
           str(exc.value)
