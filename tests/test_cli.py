"""``elastokin kc`` end to end: the summary.json contract, kc.csv, charts, and bad input."""

import csv
import hashlib
import json
from pathlib import Path

import pytest
import yaml
from click.testing import CliRunner

from elastokin.cli.main import main
from elastokin.config.loading import load_suspension


def run_kc(config, out):
    return CliRunner().invoke(main, ["kc", "--config", str(config), "--out", str(out),
                                     "--quiet"])


@pytest.fixture
def kc_out(case_kc):
    return case_kc


@pytest.mark.slow
def test_summary_contract(kc_out, case):
    s = json.loads((kc_out / "summary.json").read_text())
    assert isinstance(s["elastokin_version"], str) and isinstance(s["exudyn_version"], str)
    assert s["config_sha256"] == case.sha256 and len(s["config_sha256"]) == 64
    init, ident = s["models"]["initial"], s["models"]["identified"]
    assert set(ident) == set(init)
    for m in (init, ident):
        assert isinstance(m["steer_amplitude_deg"], float)
        assert isinstance(m["bump_steer_deg_per_m"], float)
    for j in ("J1", "J2", "J4"):
        b = s["static"]["bushings"][j]
        assert {"radial_mm", "axial_mm", "torsion_deg"} <= set(b)
    assert s["solver"]["identified"]["newton_relative_tolerance"] > 0
    # case-study regression on the committed synthetic CMM data (0.559 deg identified, 0.379
    # deg initial since issue 24 put the pad at the tyre's lowest point and the zero at the
    # model's own static state; 0.548 and 0.363 before): 0.005 deg is far above solver noise
    # (1e-7 deg) and below any change of geometry, data or stiffness worth noticing
    assert ident["steer_amplitude_deg"] == pytest.approx(0.5589, abs=0.005)
    assert init["steer_amplitude_deg"] == pytest.approx(0.3793, abs=0.005)


@pytest.mark.slow  # elastokin kc end to end (every load case)
def test_nominal_model_regression(case_dict, tmp_path):
    """Without measurements the config's own (Table 2) geometry is the initial model."""
    path = tmp_path / "nominal.yaml"
    path.write_text(yaml.safe_dump(case_dict))
    assert run_kc(path, tmp_path / "out").exit_code == 0
    s = json.loads((tmp_path / "out" / "summary.json").read_text())
    # the compliant steer amplitude of the nominal model (0.519 deg since issue 24's contact
    # point, 0.506 before; the kinematic one 0.548 deg, cross-checked in test_kinematics);
    # 0.005 deg as above
    assert s["models"]["initial"]["steer_amplitude_deg"] == pytest.approx(0.5188, abs=0.005)
    assert s["models"]["initial_kinematic"]["steer_amplitude_deg"] == pytest.approx(
        0.5479, abs=0.005)


@pytest.mark.slow
def test_kc_csv_long_format(kc_out):
    lines = (kc_out / "kc.csv").read_text().splitlines()
    assert lines[0].startswith("# elastokin_version")
    rows = list(csv.DictReader(line for line in lines if not line.startswith("#")))
    models = {r["model"] for r in rows}
    assert models == {"test", "initial", "identified", "identified_stiffness"}
    assert {r["side"] for r in rows} == {"left", "right"}  # the case study is an axle
    stroke = [r for r in rows if r["model"] == "initial" and r["branch"] == "stroke"
              and r["load_case"] == "parallel_travel" and r["side"] == "left"]
    assert len(stroke) == 181  # -90 .. +90 mm at 1 mm
    for col in ("wheel_travel_mm", "wheel_centre_x_mm", "wheel_centre_y_mm",
                "wheel_centre_z_mm", "toe_deg", "camber_deg", "contact_patch_fz_N",
                "spring_coil_force_N", "bushing_J4_z_mm", "bushing_J1_rz_deg"):
        assert col in rows[0]
    travel = [float(r["wheel_travel_mm"]) for r in stroke]
    assert travel[0] == pytest.approx(-90, abs=1.0) and travel[-1] == pytest.approx(90, abs=1)


@pytest.mark.slow
def test_charts_written(kc_out):
    assert (kc_out / "steer_vs_travel.png").stat().st_size > 1000
    assert not list(kc_out.glob("*.svg"))  # SVG only with --svg (test_charts)


def test_help_documents_every_option():
    out = CliRunner().invoke(main, ["kc", "--help"]).output
    for opt in ("--config", "--out", "--rig", "--quiet"):
        assert opt in out


def bad(case_dict, tmp_path, mutate, text=None):
    path = tmp_path / "bad.yaml"
    if text is None:
        mutate(case_dict)
        text = yaml.safe_dump(case_dict)
    path.write_text(text)
    out = tmp_path / "out"
    result = run_kc(path, out)
    return result, out


def _del(d, *keys):
    for k in keys[:-1]:
        d = d[k]
    del d[keys[-1]]


BAD_INPUTS = {
    "malformed yaml": (None, "name: [unclosed\n", ["bad.yaml", "line", "malformed YAML"]),
    "unknown connection type": (
        lambda d: d["connections"]["J8"].update(type="ball"), None,
        ["connections.J8", "ball"]),
    "undefined hardpoint": (
        lambda d: d["connections"]["J7"].update(at="J77"), None, ["J77", "hardpoints"]),
    "undefined part": (
        lambda d: d["connections"]["J7"].update(parts=["rear_arm", "hub"]), None,
        ["'hub'", "not defined"]),
    "zero axis": (
        lambda d: d["connections"]["J4"].update(radial=[0.0, 0.0, 0.0]), None,
        ["connections.J4.radial", "zero"]),
    "non-unit axis": (
        lambda d: d["wheel"].update(spin_axis=[0.0, -2.0, 0.0]), None,
        ["wheel.spin_axis", "unit vector"]),
    "under-constrained": (
        lambda d: _del(d, "connections", "tie_rod"), None, ["under-constrained", "knuckle"]),
    "over-constrained": (
        lambda d: d["connections"].update(
            extra={"type": "spherical", "parts": ["body", "knuckle"], "at": "J6"}), None,
        ["over-constrained"]),
    "no convergence": (
        lambda d: d["solver"].update(max_newton_iterations=1, newton_tolerance=1e-14), None,
        ["did not converge"]),
}


@pytest.mark.parametrize("case_name", list(BAD_INPUTS))
def test_bad_input_one_clear_line(case_dict, tmp_path, case_name):
    mutate, text, expected = BAD_INPUTS[case_name]
    result, out = bad(case_dict, tmp_path, mutate, text)
    assert result.exit_code == 1
    message = result.output.strip()
    assert message.startswith("elastokin: error: ") and "\n" not in message, message
    assert "Traceback" not in result.output
    for word in expected:
        assert word in message, message
    assert not out.exists()
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".out")]


@pytest.mark.slow  # elastokin kc end to end, twice
def test_failed_run_keeps_previous_results(case_dict, case_path, tmp_path):
    out, good = tmp_path / "out", tmp_path / "good.yaml"
    # the nominal model (no fit) on parallel travel only (configs/rigs/travel_only.yaml):
    # a quick run whose results the failed run must leave alone
    case_dict["rig"] = yaml.safe_load((case_path.parent / "rigs" / "travel_only.yaml")
                                      .read_text())
    good.write_text(yaml.safe_dump(case_dict))
    assert run_kc(good, out).exit_code == 0
    before = (out / "summary.json").read_text()
    case_dict["connections"]["J8"]["type"] = "ball"
    path = tmp_path / "bad.yaml"
    path.write_text(yaml.safe_dump(case_dict))
    assert run_kc(path, out).exit_code == 1
    assert (out / "summary.json").read_text() == before


def test_refuses_to_overwrite_a_foreign_folder(tmp_path, case_path):
    out = tmp_path / "mine"
    out.mkdir()
    (out / "notes.txt").write_text("keep me")
    result = run_kc(case_path, out)
    assert result.exit_code == 1 and "not empty" in result.output
    assert (out / "notes.txt").read_text() == "keep me"


def test_rig_file_replaces_the_configs_load_cases(case_dict, tmp_path, case_path):
    """``--rig configs/rigs/travel_only.yaml``: travel only, +-50 mm in 2 mm steps, no
    unloading; the rig file and its own hash are in summary.json and kc.csv, the config's hash
    is the config file's."""
    config = tmp_path / "nominal.yaml"
    config.write_text(yaml.safe_dump(case_dict))
    rig = case_path.parent / "rigs" / "travel_only.yaml"
    out = tmp_path / "out"
    result = CliRunner().invoke(main, ["kc", "--config", str(config), "--rig", str(rig),
                                       "--out", str(out), "--quiet"])
    assert result.exit_code == 0, result.output
    s = json.loads((out / "summary.json").read_text())
    assert s["rig_file"] == str(rig)
    plain = load_suspension(config)
    assert s["config_sha256"] == plain.sha256 == hashlib.sha256(config.read_bytes()).hexdigest()
    assert s["rig_sha256"] == hashlib.sha256(rig.read_bytes()).hexdigest()
    lines = (out / "kc.csv").read_text().splitlines()
    assert f"# rig_file: {rig}" in lines and f"# rig_sha256: {s['rig_sha256']}" in lines
    assert f"# config_sha256: {s['config_sha256']}" in lines
    rows = list(csv.DictReader(line for line in lines if not line.startswith("#")))
    assert {r["load_case"] for r in rows} == {"parallel_travel"}
    stroke = [float(r["wheel_travel_mm"]) for r in rows
              if r["model"] == "initial" and r["branch"] == "stroke" and r["side"] == "left"]
    assert len(stroke) == 51 and stroke[0] == pytest.approx(-50, abs=1.0)
    assert not [r for r in rows if r["branch"] == "return"]


@pytest.mark.parametrize("text, expected", [
    ("lateral_force: {amplitude_N: -5}\n", ["rig.yaml (rig file)", "lateral_force.amplitude_N",
                                           "greater than 0"]),
    ("rig: {lateral_forse: null}\n", ["rig.yaml (rig file)", "lateral_forse"]),
    ("- 1\n", ["rig.yaml", "mapping", "rig file"]),
])
def test_bad_rig_file_one_clear_line(case_dict, tmp_path, text, expected):
    config, rig = tmp_path / "nominal.yaml", tmp_path / "rig.yaml"
    config.write_text(yaml.safe_dump(case_dict))
    rig.write_text(text)
    result = CliRunner().invoke(main, ["kc", "--config", str(config), "--rig", str(rig),
                                       "--out", str(tmp_path / "out"), "--quiet"])
    message = result.output.strip()
    assert result.exit_code == 1 and message.startswith("elastokin: error: ")
    assert "\n" not in message and "Traceback" not in message
    for word in expected:
        assert word in message, message


def test_models_option_runs_only_the_models_asked_for(tmp_path):
    """--models: the double wishbone yields initial and initial_kinematic; asking for one
    runs that one only; an unknown name is refused, listing what the config yields."""
    dw = Path(__file__).parent / "data" / "double_wishbone.yaml"
    result = CliRunner().invoke(main, ["kc", "--config", str(dw), "--models", "initial",
                                       "--out", str(tmp_path / "out"), "--quiet"])
    assert result.exit_code == 0, result.output
    s = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert set(s["models"]) == {"initial"}
    bad = CliRunner().invoke(main, ["kc", "--config", str(dw), "--models", "nope",
                                    "--out", str(tmp_path / "bad"), "--quiet"])
    assert bad.exit_code == 1 and "unknown model nope" in bad.output
    assert "initial, initial_kinematic" in bad.output


def test_runs_finishing_at_once_into_one_folder_replace_it_in_turn(tmp_path):
    """Threads that finish at once into one results folder (as two `elastokin kc` processes
    may): every run succeeds and the folder holds one run's complete results. Without the
    move lock about 6 % of such runs failed with 'Directory not empty' or 'No such file'."""
    import threading

    from elastokin.cli.common import Output

    errors = []

    def run(out: Path, tag: str) -> None:
        try:
            with Output(out) as tmp:
                (tmp / "summary.json").write_text(tag)
                (tmp / "kc.csv").write_text(tag * 100)
        except Exception as exc:  # noqa: BLE001 - every failure is the test's finding
            errors.append(repr(exc))

    for k in range(40):
        out = tmp_path / f"res{k}"
        threads = [threading.Thread(target=run, args=(out, str(i))) for i in range(3)]
        for t in threads:
            t.start()
        for t in threads:
            t.join()
        tag = (out / "summary.json").read_text()
        assert (out / "kc.csv").read_text() == tag * 100  # one run's, complete
    assert errors == []
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(f"res{k}" for k in range(40))
