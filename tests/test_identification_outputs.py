"""What `elastokin identify` writes (issue 19, item 3): the paper's own equation numbers, joints
identified beyond their clearance dL_max flagged and warned about, and configs that keep the
model's label, the K&C test data and the references, so that `elastokin kc` on them compares
the identified model with the test as the case study does."""

from __future__ import annotations

import hashlib
import json

import numpy as np
import pytest
import yaml
from click.testing import CliRunner

from elastokin.cli.main import main
from elastokin.config.loading import load_suspension, relocated_folder
from elastokin.identification.geometric import JointResult
from elastokin.report.text import identification_table
from elastokin.studies.identification import identify_geometry
from elastokin.studies.kc_job import model_labels, select_models

from .conftest import CASE

RIG = CASE.parent / "rigs" / "travel_only.yaml"


@pytest.fixture(scope="module")
def ident(case):
    return identify_geometry(case)


@pytest.fixture(scope="module")
def identified(tmp_path_factory):
    """`elastokin identify` on the case study (about a second: no stiffness fit)."""
    out = tmp_path_factory.mktemp("identify") / "ident"
    result = CliRunner().invoke(main, ["identify", "--config", str(CASE), "--out", str(out)])
    assert result.exit_code == 0, result.output
    return out, result.output


def test_a_bushing_shift_counts_against_the_clearance_normal_to_its_axis():
    axis = np.array([0.0, 0.0, 1.0])
    along = JointResult("B", "bushing", np.zeros(3), np.array([0.0, 0.0, 2.0]),
                        max_shift_mm=0.75, housing_axis=axis)
    assert along.clearance_shift_mm == 0.0 and not along.exceeds_clearance
    across = JointResult("B", "bushing", np.zeros(3), np.array([0.6, 0.6, 2.0]),
                         max_shift_mm=0.75, housing_axis=axis)
    assert across.clearance_shift_mm == pytest.approx(0.6 * 2 ** 0.5)
    assert across.exceeds_clearance
    ball = JointResult("S", "spherical", np.zeros(3), np.array([0.0, 0.0, 0.7]),
                       max_shift_mm=0.75)
    assert ball.clearance_shift_mm == pytest.approx(0.7) and not ball.exceeds_clearance
    unbolted = JointResult("L", "link end", np.zeros(3), np.array([5.0, 0.0, 0.0]))
    assert not unbolted.exceeds_clearance


def test_shifts_beyond_dl_max_are_flagged_with_a_warning(ident):
    """On the case study J1 (0.784 mm across its axis) and J8 (0.765 mm) are identified
    beyond their 0.75 mm clearance: the as-built truth lies inside it, the rest is CMM
    noise (0.1 mm)."""
    truth = yaml.safe_load((CASE.parent / "pseudo_mcpherson_measurements" /
                            "truth.yaml").read_text())["clearance_shift_mm"]
    flagged = {n for n, j in ident.joints.items() if j.exceeds_clearance}
    assert flagged == {"J1", "J8"}
    for name in flagged:
        j = ident.joints[name]
        assert np.linalg.norm(truth[name]) <= j.max_shift_mm  # the truth is inside
        [warning] = [w for w in ident.all_warnings if f"joint '{name}'" in w]
        assert f"{j.clearance_shift_mm:.3f} mm" in warning and "dL_max = 0.750 mm" in warning
    d = ident.to_json()
    assert d["joints"]["J1"]["exceeds_clearance"] and not d["joints"]["J2"]["exceeds_clearance"]
    assert len(d["warnings"]) == 3  # the dropped mark and the two joints


def test_the_table_cites_the_papers_own_equation_numbers(ident):
    text = identification_table(ident)
    for ref in ("eqs. (8)-(10)", "eqs. (11)-(12)", "eq. (19)", "eq. (1)", "eqs. (22)-(23)",
                "eqs. (20), (26)", "Meissonnier et al. (2006)", "section 5"):
        assert ref in text, ref
    assert "method.md" not in text and "[7]" not in text
    rows: dict[str, str] = {}
    for ln in text.splitlines():
        if ln.startswith("  J"):
            rows.setdefault(ln.split()[0], ln)  # the joints table comes first
    assert rows["J1"].split()[6:8] == ["0.784", "!"] and "!" not in rows["J2"]


def test_identify_prints_the_warnings_and_writes_both_hashes(identified):
    out, printed = identified
    for joint in ("J1", "J8"):
        assert f"elastokin: warning: joint '{joint}'" in printed
    d = json.loads((out / "identification.json").read_text())
    assert d["config_sha256"] == hashlib.sha256(CASE.read_bytes()).hexdigest()
    assert "rig_sha256" in d and d["rig_sha256"] is None
    assert d["joints"]["J8"]["exceeds_clearance"]
    assert "joint 'J8'" in (out / "identification.txt").read_text()


def test_written_configs_keep_label_test_data_and_references(identified, case):
    out, _ = identified
    s = load_suspension(out / "identified.yaml")
    assert s.label == "identified" and s.measurements is None
    assert s.reference.steer_amplitude_deg == case.reference.steer_amplitude_deg
    # the test folder, relative to the written config, is the case study's
    assert (out / s.kc_test.folder).resolve() == (CASE.parent / case.kc_test.folder).resolve()
    assert model_labels(s) == ["identified", "identified_kinematic"]
    assert "identified_stiffness" in select_models(s, None)
    initial = load_suspension(out / "initial.yaml")
    assert initial.label == "initial" and initial.kc_test is not None
    assert "identified_stiffness" not in select_models(initial, None)  # the fit: identified


def test_kc_on_the_identified_config_overlays_the_test(identified, tmp_path):
    """`elastokin kc` on identified.yaml runs the model as 'identified', beside the test, with
    the reference of the identified model only (travel only: a second)."""
    out, _ = identified
    res = tmp_path / "kc"
    result = CliRunner().invoke(main, ["kc", "--config", str(out / "identified.yaml"),
                                       "--rig", str(RIG), "--out", str(res), "--models",
                                       "identified", "--data", str(CASE.parent)])
    assert result.exit_code == 0, result.output
    summary = json.loads((res / "summary.json").read_text())
    assert list(summary["models"]) == ["test", "identified"]
    assert summary["errors"]["identified"]["steer_vs_travel_rms_deg"] is not None
    assert "identified 0.45" in result.output and "initial 0.6" not in result.output
    assert summary["rig_sha256"] == hashlib.sha256(RIG.read_bytes()).hexdigest()
    assert summary["config_sha256"] == hashlib.sha256(
        (out / "identified.yaml").read_bytes()).hexdigest()


def test_a_data_folder_seen_from_a_config_written_elsewhere(tmp_path):
    """What identify and import-adams write for a config's CMM / K&C test folder: relative
    to the new config's folder, by hand; an absolute folder as given; absolute where the
    two folders share only the root."""
    (tmp_path / "cfg" / "test_data").mkdir(parents=True)
    assert relocated_folder("test_data", tmp_path / "cfg", tmp_path / "out" / "x") == \
        "../../cfg/test_data"
    assert relocated_folder(".", tmp_path / "cfg", tmp_path / "cfg" / "sub") == ".."
    assert relocated_folder("../cfg/test_data", tmp_path / "cfg", tmp_path) == "cfg/test_data"
    assert relocated_folder("/data/kc", tmp_path / "cfg", tmp_path) == "/data/kc"
    apart = relocated_folder("test_data", tmp_path / "cfg", "/")
    assert apart == (tmp_path / "cfg" / "test_data").resolve().as_posix()


@pytest.mark.parametrize("label, fit, expected", [
    ("test", False, "label of another model"),
    ("initial_kinematic", False, "label of another model"),
    ("identified stiffness", False, "should match pattern"),
    ("identified_stiffness", True, "stiffness_identification.enabled: false"),
])
def test_a_label_that_would_clash_is_refused(case, label, fit, expected):
    from elastokin.config.frozen import plain_data
    from elastokin.config.loading import suspension_from_dict
    from elastokin.errors import ConfigError

    data = {**plain_data(case.raw), "measurements": None, "label": label}
    data["kc_test"]["stiffness_identification"]["enabled"] = fit
    with pytest.raises(ConfigError, match="key 'label'") as err:
        suspension_from_dict(data, "c.yaml")
    assert expected in str(err.value)
