"""Nothing an axle's user types is silently lost or wrong (issue 24, items 3, 7 and 10): the
mistakes a user makes in an axle config and in two-wheel K&C test files, each refused with one
line naming the file and the key (or column), or warned about and left out; never a
traceback, never a result from a value that cannot be meant. On the shipped double wishbone
axle, the case study's K&C test files and the small axles of tests/data; no solve except the
one command-line case."""

from __future__ import annotations

import copy
import shutil
import warnings
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
import yaml
from click.testing import CliRunner

from elastokin.cli import main
from elastokin.config.loading import load_suspension, load_suspension_with_rig, read_yaml
from elastokin.errors import ConfigError, ElastokinError, MeasurementError
from elastokin.formats.kc_test import read_kc_test, write_kc_test
from elastokin.formats.kc_test_sweeps import KCTestWarning, read_test_sweeps
from elastokin.rig.drives import RigWarning, check_rig, steering_drive
from elastokin.studies.kc_job import run_kc

from .axle_rigs import config, suspension
from .conftest import CASE
from .kc_files import sweep

KC_TEST = CASE.parent / "pseudo_mcpherson_kc_test"


def _error(data: dict, name: str = "axle.yaml") -> str:
    with pytest.raises(ElastokinError) as info:
        suspension(data, name)
    message = str(info.value)
    assert "\n" not in message and message.startswith(f"{name}: key '"), message
    return message


def test_the_other_sides_points_in_the_adams_frame():
    """x rearward, y right: the right wheel's points have y > 0; typed with the left wheel's
    sign they are refused, typed right they are taken."""
    d = config("swing_axle.yaml")
    turn = np.diag([-1.0, -1.0, 1.0])
    d["hardpoints"] = {k: (turn @ v).tolist() for k, v in d["hardpoints"].items()}
    d["frame"] = {"x": "rearward", "y": "right", "z": "up"}
    d["wheel"]["spin_axis"] = [0, -1, 0]
    d["connections"]["pivot"]["axis"] = [-1, 0, 0]
    d["axle"] = {"other_side": {"hardpoints": {"pivot": [0.0, -100.0, 250.0]}}}
    assert "is not on the right side" in _error(d)
    d["axle"]["other_side"]["hardpoints"]["pivot"] = [0.0, 101.0, 250.0]
    s = suspension(d)
    assert s.hardpoints["pivot_right"].tolist() == [0.0, 101.0, 250.0]


@pytest.mark.parametrize("number", ["1.0e+400", "-2.5e+309", "9" * 5000])
def test_a_number_too_large_is_named_by_its_key(tmp_path, number):
    """A hardpoint value beyond a float: its key path and line (a 5000-digit integer was a
    traceback of Python's integer parser)."""
    text = (CASE.parent.parent / "configs" / "double_wishbone_axle.yaml").read_text()
    text = text.replace("  lca_outer: [-36.0, 787.0, -118.0]",
                        f"  lca_outer: [{number}, 787.0, -118.0]", 1)
    path = tmp_path / "axle.yaml"
    path.write_text(text)
    with pytest.raises(ConfigError, match=r"axle\.yaml: line \d+: key 'hardpoints\.lca_outer"
                       r"\[0\]': the number .* is too large"):
        load_suspension(path)


# ------------------------------------------------------------------------------ the rig
def test_a_steering_amplitude_from_a_rig_file_is_the_rig_files(tmp_path):
    rig = tmp_path / "lock.yaml"
    rig.write_text("steering: {amplitude_deg: 700.0}\n")
    s = load_suspension_with_rig(CASE.parent / "double_wishbone_axle.yaml", rig)
    with pytest.raises(ConfigError, match=rf"^{rig} \(rig file\): key 'steering\."
                       r"amplitude_deg': 700 deg takes the rack beyond its travel limit"):
        steering_drive(s, s.rig.steering)


def test_a_rig_files_step_too_fine_for_the_configs_wheel_load_is_the_rig_files(tmp_path):
    """The step count of the vertical-force approach depends on the config's wheel load: the
    rig file's key is named, not the config's rig section (which the rig file replaced)."""
    d = config("double_wishbone_axle.yaml")
    d["design"]["wheel_load_N"] = 45000.0
    cfg, rig = tmp_path / "axle.yaml", tmp_path / "fine.yaml"
    cfg.write_text(yaml.safe_dump(d))
    rig.write_text("vertical_force: {min_N: 1000, max_N: 7500, step_N: 0.2}\n")
    with pytest.raises(ConfigError, match=rf"^{rig} \(rig file\): key 'vertical_force\."
                       r"step_N': 0\.2 N gives 285,000 steps from design\.wheel_load_N 45000"):
        load_suspension_with_rig(cfg, rig)


def test_a_load_case_given_that_cannot_run_is_warned_about():
    """A steering sweep typed for an axle without steering, an axle case on a corner: said
    once (the K&C job leaves them out), not silently dropped; defaults say nothing."""
    d = config("swing_axle.yaml")
    d["rig"]["steering"] = {"step_deg": 5.0}
    with pytest.warns(RigWarning, match=r"key 'rig\.steering': given, but the axle has no "
                      r"steering"):
        check_rig(suspension(d, "swing.yaml"))
    del d["axle"]
    d["rig"]["steering"] = None
    d["rig"]["roll_vertical_force"] = {"amplitude_deg": 1.0}
    with pytest.warns(RigWarning, match=r"'rig\.roll_vertical_force': given, but an axle load "
                      r"case, and the config is one corner"):
        check_rig(suspension(d, "swing.yaml"))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        check_rig(suspension(config("double_wishbone_axle.yaml")))


# ------------------------------------------------------------------- two-wheel test files
def _case_study(tmp_path: Path, files: dict[str, str], axle: bool = True, **rig) -> Path:
    """The case study without CMM data, its K&C test folder holding ``files`` (name -> text,
    or the shipped file's name), as a config file in ``tmp_path``."""
    folder = tmp_path / "kc"
    folder.mkdir()
    for name, text in files.items():
        if text == "shipped":
            shutil.copy(KC_TEST / name, folder / name)
        else:
            (folder / name).write_text(text)
    d = copy.deepcopy(read_yaml(CASE)[0])
    del d["measurements"]
    if not axle:
        del d["axle"]
    d["kc_test"] = {"folder": "kc", **({} if axle else {
        "stiffness_identification": {"enabled": False}})}
    d["rig"] = {**d.get("rig", {}), **rig}
    path = tmp_path / "case.yaml"
    path.write_text(yaml.safe_dump(d, sort_keys=False))
    return path


def _steering_file() -> str:
    swa = sweep(300.0, 6)
    lines = ["steering_wheel_angle [deg],toe_left [deg],toe_right [deg]"]
    lines += [f"{a:.3f},{0.01 * a:.5f},{-0.01 * a:.5f}" for a in swa]
    return "\n".join(lines) + "\n"


def test_a_steering_test_on_an_axle_without_steering_is_left_out_with_a_warning(tmp_path):
    path = _case_study(tmp_path, {"parallel_travel.csv": "shipped",
                                  "steering.csv": _steering_file()})
    with pytest.warns(KCTestWarning, match=r"steering\.csv: K&C test of steering ignored: no "
                      r"load case of .*case\.yaml can use it \(the axle has no steering"):
        sweeps, files = read_test_sweeps(load_suspension(path))
    assert {sw.load_case for sw in sweeps} == {"parallel_travel"}
    assert len(files) == 2  # both were read (a bad file still fails)


def test_a_roll_test_on_a_corner_alone_is_an_error_naming_the_folder(tmp_path):
    path = _case_study(tmp_path, {"roll_vertical_force.csv": "shipped"}, axle=False)
    with pytest.warns(KCTestWarning), pytest.raises(MeasurementError, match=(
            rf"key 'kc_test': no K&C test file in {tmp_path / 'kc'} that this config's load "
            r"cases can use \(.*roll_vertical_force\.csv: an axle load case, and the config "
            r"is one corner")):
        read_test_sweeps(load_suspension(path))


def test_a_test_of_a_case_the_rig_leaves_out_is_warned_about(tmp_path):
    """Static load is off by default: its test file would be read and never compared."""
    x = np.linspace(0.0, 1.0, 6)
    text = "load_fraction [-],toe_left [deg],toe_right [deg]\n" + "".join(
        f"{v:.2f},{0.1 * v:.3f},{0.2 * v:.3f}\n" for v in x)
    path = _case_study(tmp_path, {"parallel_travel.csv": "shipped", "static_load.csv": text})
    with pytest.warns(KCTestWarning, match=r"static_load ignored: .*the rig leaves the load "
                      r"case out \(.*key 'rig\.static_load' is null\)"):
        read_test_sweeps(load_suspension(path))


def test_a_fit_without_a_corner_case_is_an_error_naming_the_test_folder(tmp_path):
    """The stiffness fit runs the corner's load cases: with only an axle case in the test
    data it was a numpy traceback after every model had run; now one error first."""
    path = _case_study(tmp_path, {"roll_vertical_force.csv": "shipped"})
    with pytest.raises(ConfigError, match=(
            r"key 'kc_test\.stiffness_identification': the stiffness fit runs the corner load "
            rf"cases .* the K&C test files in {tmp_path / 'kc'} hold none for the left wheel "
            r"\(they hold: roll_vertical_force\)")):
        run_kc(load_suspension(path))


def test_a_corner_with_only_an_axle_test_ends_in_one_line(tmp_path):
    path = _case_study(tmp_path, {"roll_vertical_force.csv": "shipped"}, axle=False)
    result = CliRunner().invoke(main, ["kc", "--config", str(path), "--out",
                                       str(tmp_path / "res"), "--quiet"])
    assert result.exit_code == 1
    errors = [ln for ln in result.output.splitlines() if "error" in ln]
    assert len(errors) == 1 and "roll_vertical_force.csv" in errors[0], result.output
    assert "Traceback" not in result.output and not (tmp_path / "res").exists()


def test_the_other_wheels_input_held_constant_is_refused(tmp_path):
    """Lateral force in phase drives both wheels: a right-wheel input column of zeros is a
    wrong column, not a sweep (single wheel travel's held wheel may be constant)."""
    f = sweep(2000.0, 5)
    p = write_kc_test(tmp_path / "lateral_force.csv", "lateral_force", {
        "lateral_force_left": f, "lateral_force_right": 0.0 * f, "toe_left": 1e-5 * f,
        "toe_right": 1e-5 * f})
    with pytest.raises(MeasurementError, match=r"column 'lateral_force_right \[N\]': the "
                       r"input of this wheel is constant \(0\) while 'lateral_force_left \[N\]'"
                       r" sweeps"):
        read_kc_test(p)
    t = sweep(50.0, 5)
    p = write_kc_test(tmp_path / "single_wheel_travel.csv", "single_wheel_travel", {
        "wheel_travel_left": t, "wheel_travel_right": 0.0 * t, "toe_left": 1e-3 * t,
        "toe_right": 0.0 * t})
    assert read_kc_test(p).sides == ("left", "right")


def test_the_mirror_keeps_a_users_asymmetric_point_and_its_sign(tmp_path):
    """The accepted counterpart of the wrong-side case: a right point on the right side is
    the right corner's, mirrored points elsewhere."""
    d = config("double_wishbone_axle.yaml")
    d["axle"]["other_side"] = {"hardpoints": {"tierod_outer": [-176.0, -825.0, -16.0]}}
    s = suspension(d)
    assert s.hardpoints["tierod_outer_right"].tolist() == [-176.0, -825.0, -16.0]
    assert s.hardpoints["lca_outer_right"].tolist() == [-36.0, -787.0, -118.0]
    assert replace(s, rig_source="r.yaml").rig_key("steering") == \
        "r.yaml (rig file): key 'steering'"
