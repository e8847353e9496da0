"""``elastokin doe``: clearance sampling, sensitivity, determinism serial vs dask, failed
samples, resume, bad input."""

import copy
import json

import numpy as np
import pytest
import yaml
from click.testing import CliRunner
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from elastokin.cli.main import main
from elastokin.config.loading import read_yaml
from elastokin.errors import ConfigError, ElastokinError
from elastokin.rig.characteristics import steer_amplitude_deg
from elastokin.rig.load_cases import parallel_travel
from elastokin.studies import doe, doe_runner, doe_sampling, doe_statistics


def run_doe(config, out, *args):
    return CliRunner().invoke(main, ["doe", "--config", str(config), "--out", str(out),
                                     "--quiet", *args])


def write_config(tmp_path, case_path, name="case.yaml", edit=None):
    """The shipped config (CMM folder made absolute) written to tmp_path, optionally edited."""
    data = copy.deepcopy(read_yaml(case_path)[0])
    m = data["measurements"]
    m["folder"] = str((case_path.parent / m.get("folder", ".")).resolve())
    data.pop("kc_test", None)  # rig test data: not used by a DOE
    if edit is not None:
        edit(data)
    path = tmp_path / name
    path.write_text(yaml.safe_dump(data, sort_keys=False))
    return path


@pytest.fixture(scope="module")
def joints(case):
    return doe_sampling.clearance_joints(case)


# ---------------------------------------------------------------------------- sampling
def test_clearance_joints_of_the_case(case, joints):
    assert [j.name for j in joints] == ["J1", "J2", "J4", "J8", "J7"]
    assert [j.kind for j in joints] == ["disc"] * 3 + ["ball"] * 2
    for j in joints:  # dL_max = 13/2 - 12 + 12.5/2 etc. (config CHOICE comment)
        assert j.max_shift_mm == pytest.approx(0.75)


@settings(max_examples=60, deadline=None)
@given(u=arrays(np.float64, (5, 12), elements=st.floats(0.0, 1.0, exclude_max=True)))
def test_sampled_shifts_stay_in_the_clearance(case, joints, u):
    bushings = {b.name: b for b in case.bushings}
    comps = doe_sampling.shift_components(joints, u)
    for row in comps:
        shifts = doe_sampling.shifts_mm(joints, row)
        for j in joints:
            v = shifts[j.name]
            assert np.linalg.norm(v) <= j.max_shift_mm * (1 + 1e-12)
            if j.kind == "disc":  # in the plane normal to the housing axis
                assert abs(v @ bushings[j.name].frame[:, 2]) < 1e-12


def test_disc_and_ball_maps_are_uniform():
    # hand-checkable points: r = R sqrt(u1) and r = R u1^(1/3)
    assert doe_sampling.disc_components([0.25, 0.0], 2.0) == pytest.approx([1.0, 0.0])
    assert doe_sampling.disc_components([1.0, 0.25], 2.0) == pytest.approx([0.0, 2.0], abs=1e-12)
    assert doe_sampling.ball_components([0.125, 0.5, 0.0], 2.0) == pytest.approx([1.0, 0.0, 0.0],
                                                                        abs=1e-12)
    assert doe_sampling.ball_components([1.0, 0.0, 0.3], 2.0) == pytest.approx([0.0, 0.0, 2.0],
                                                                      abs=1e-12)
    # uniform in area / volume: a quarter of the disc's points, an eighth of the ball's,
    # within half the radius (binomial sd < 0.004 for 20000 points)
    u = np.random.default_rng(1).random((20000, 3))
    assert np.mean(np.linalg.norm(doe_sampling.disc_components(u[:, :2], 1.0), axis=1) < 0.5) == \
        pytest.approx(0.25, abs=0.015)
    b = doe_sampling.ball_components(u, 1.0)
    assert np.mean(np.linalg.norm(b, axis=1) < 0.5) == pytest.approx(0.125, abs=0.012)
    assert np.abs(b.mean(axis=0)).max() < 0.02  # no preferred direction


@pytest.mark.parametrize("method", doe_sampling.METHODS)
def test_unit_samples_depend_on_seed_only(method):
    a = doe_sampling.unit_samples(method, 16, 12, seed=7)
    assert a.shape == (16, 12) and np.all((a >= 0) & (a < 1))
    assert np.array_equal(a, doe_sampling.unit_samples(method, 16, 12, seed=7))
    assert not np.array_equal(a, doe_sampling.unit_samples(method, 16, 12, seed=8))
    if method == "lhs":  # one point in each of the 16 strata of every coordinate
        assert all(sorted(np.floor(a[:, i] * 16).astype(int)) == list(range(16))
                   for i in range(12))


# ---------------------------------------------------------------------------- sensitivity
def test_statistics_hand_checked():
    s = doe_statistics.statistics([1.0, 2.0, 3.0, 4.0, None, float("nan")])
    assert s == {"mean": 2.5, "std": pytest.approx(np.sqrt(5 / 3)), "p05": pytest.approx(1.15),
                 "p95": pytest.approx(3.85), "min": 1.0, "max": 4.0, "n": 4}
    assert doe_statistics.statistics([2.0])["std"] is None
    assert doe_statistics.statistics([])["mean"] is None


def test_sensitivity_recovers_a_known_linear_ranking():
    """y = 3 a1 + 1 b1 + 0.5 b2 on independent inputs of equal variance: the joints' shares
    of the variance are 9 / 10.25 (A), 1.25 / 10.25 (B), 0 (C)."""
    rng = np.random.default_rng(3)
    X = rng.uniform(-1, 1, size=(4000, 5))  # a1 a2 b1 b2 c1
    groups = ["A", "A", "B", "B", "C"]
    y = 3 * X[:, 0] + X[:, 2] + 0.5 * X[:, 3]
    res = doe_statistics.joint_sensitivity(X, y, groups)
    assert res["method"] == "src" and res["r2"] == pytest.approx(1.0)
    assert res["joints"]["A"] == pytest.approx(9 / 10.25, abs=0.02)
    assert res["joints"]["B"] == pytest.approx(1.25 / 10.25, abs=0.02)
    assert res["joints"]["C"] == pytest.approx(0.0, abs=1e-12)
    # SRC of a noiseless linear function: b_i std(x_i) / std(y), exactly
    src = doe_statistics.standardised_regression(X, y).src
    expected = np.array([3, 0, 1, 0.5, 0]) * X.std(axis=0, ddof=1) / y.std(ddof=1)
    assert src == pytest.approx(expected, abs=1e-12)
    # too few samples for one regression on all 5 inputs: one regression per joint
    few = doe_statistics.joint_sensitivity(X[:6], y[:6], groups)
    assert few["method"] == "src_per_joint"
    assert max(few["joints"], key=few["joints"].get) == "A"
    assert doe_statistics.joint_sensitivity(X[:3], y[:3], groups)["joints"]["A"] is None


# ---------------------------------------------------------------------------- evaluation
def test_doe_travel_matches_the_kc_rig(case, case_design):
    """The DOE's travel (coarse unrecorded approach) gives kc's steer amplitude."""
    model = doe.as_built_model(case, {}, case_design)
    fast = doe.travel_sweep(model)
    assert fast.stroke("pad_z_mm").size == 181
    assert steer_amplitude_deg(fast) == pytest.approx(
        steer_amplitude_deg(parallel_travel(model, "kc")), abs=1e-8)


@pytest.mark.slow  # starts a dask LocalCluster of 2 worker processes (about 10 s)
def test_serial_and_local_cluster_give_identical_results(case_path, tmp_path):
    serial, dask = tmp_path / "serial", tmp_path / "dask"
    r1 = run_doe(case_path, serial, "--samples", "8", "--workers", "1")
    assert r1.exit_code == 0, r1.output
    r2 = run_doe(case_path, dask, "--samples", "8", "--workers", "2")
    assert r2.exit_code == 0, r2.output
    assert (serial / "doe.json").read_bytes() == (dask / "doe.json").read_bytes()
    assert "dask scheduler" in json.loads((dask / "doe_run.json").read_text())["executed_on"]
    d = json.loads((serial / "doe.json").read_text())
    assert (d["samples"], d["failed"], d["seed"]) == (8, 0, 0)
    assert set(d["steer_amplitude_deg"]) >= {"mean", "std", "p05", "p95"}
    assert set(d["sensitivity"]) == {"J1", "J2", "J4", "J7", "J8"}
    assert all(isinstance(v, float) for v in d["sensitivity"].values())
    # 0.75 mm of clearance spreads the 0.519 deg nominal steer amplitude by about 0.1 deg
    assert d["nominal"]["steer_amplitude_deg"] == pytest.approx(0.5188, abs=0.005)
    assert 0.01 < d["steer_amplitude_deg"]["std"] < 0.3
    assert d["solver"]["newton_relative_tolerance"] > 0 and len(d["config_sha256"]) == 64
    assert "wheel_rate_N_per_mm" in d["characteristics"]
    for name in ("doe_steer_amplitude", "doe_characteristics", "doe_sensitivity_tornado"):
        assert (serial / f"{name}.png").stat().st_size > 0  # SVG only with --svg
    lines = (serial / "samples.jsonl").read_text().splitlines()
    assert len(lines) == 9 and json.loads(lines[0])["seed"] == 0


def _huge_j8_clearance(data):
    # a 390 mm "clearance" at the J8 ball joint: some as-built samples cannot be assembled,
    # even by continuation from the nominal geometry (at 55 mm they all can now)
    data["measurements"]["joints"]["J8"]["clearance"] = {
        "hole_mm": 400.0, "bolt_mm": 10.0, "inner_bore_mm": 400.0}


@pytest.mark.slow  # a dask LocalCluster too
def test_failed_samples_are_recorded_and_reported(case_path, tmp_path):
    """A real failed solve (absurd clearance): recorded with its error, the study completes,
    exit code 3, serially and on a LocalCluster alike."""
    config = write_config(tmp_path, case_path, edit=_huge_j8_clearance)
    args = ["--samples", "8", "--load-cases", "travel"]
    r1 = run_doe(config, tmp_path / "serial", *args, "--workers", "1")
    r2 = run_doe(config, tmp_path / "dask", *args, "--workers", "2")
    for r in (r1, r2):
        assert r.exit_code == 3, r.output
        assert "samples failed" in r.output
    d = json.loads((tmp_path / "serial" / "doe.json").read_text())
    assert 0 < d["failed"] < 8 and d["completed"] == 8
    assert d["steer_amplitude_deg"]["n"] == 8 - d["failed"]
    assert all("did not converge" in f["error"] for f in d["failures"])
    assert (tmp_path / "serial" / "doe.json").read_bytes() == \
        (tmp_path / "dask" / "doe.json").read_bytes()


@pytest.mark.slow  # two DOE studies end to end
def test_resume_gives_the_fresh_result(case, case_path, tmp_path):
    args = ["--samples", "8", "--load-cases", "travel", "--workers", "1"]
    fresh = run_doe(case_path, tmp_path / "fresh", *args)
    assert fresh.exit_code == 0, fresh.output
    # an interrupted study: 4 of 8 samples saved, the 5th torn mid-write
    study = doe.make_study(case, 8, "lhs", 0, "travel")
    store = doe_runner.SampleStore(tmp_path / "resumed" / doe_runner.STORE, study.header())
    assert doe_runner.run_study(study, store, limit=4) == 4
    with open(store.path, "a") as fh:
        fh.write('{"sample": 4, "shifts_mm": {"J1": [0.1')
    resumed = CliRunner().invoke(main, ["doe", "--config", str(case_path), "--out",
                                        str(tmp_path / "resumed"), *args])
    assert resumed.exit_code == 0, resumed.output
    assert "resuming: 4 of 8" in resumed.output
    assert json.loads((tmp_path / "resumed" / "doe_run.json").read_text())[
        "samples_evaluated_this_run"] == 4
    assert (tmp_path / "resumed" / "doe.json").read_bytes() == \
        (tmp_path / "fresh" / "doe.json").read_bytes()
    # the same folder, another study: a clear error, unless --restart
    other = run_doe(case_path, tmp_path / "resumed", *args, "--seed", "1")
    assert other.exit_code == 1
    assert "holds samples of another study (seed 0 (now 1))" in other.output
    assert "Traceback" not in other.output


# ---------------------------------------------------------------------------- bad input
def test_bad_input_is_one_line(case_path, tmp_path):
    no_meas = write_config(tmp_path, case_path, "nomeas.yaml",
                           edit=lambda d: d.pop("measurements"))
    r = run_doe(no_meas, tmp_path / "a", "--samples", "4")
    assert r.exit_code == 1 and "nomeas.yaml: no 'measurements' section" in r.output
    assert len(r.output.strip().splitlines()) == 1

    def no_clearance(d):
        for jm in d["measurements"]["joints"].values():
            jm.pop("clearance", None)
    r = run_doe(write_config(tmp_path, case_path, "noclr.yaml", edit=no_clearance),
                tmp_path / "b", "--samples", "4")
    assert r.exit_code == 1 and "key 'measurements.joints': no joint has a 'clearance'" \
        in r.output
    r = run_doe(case_path, tmp_path / "c", "--samples", "0")
    assert r.exit_code == 1 and r.output.strip() == \
        "elastokin: error: --samples: must be at least 1, got 0"
    r = run_doe(case_path, tmp_path / "d", "--samples", "2", "--scheduler", "no-port")
    assert r.exit_code == 1 and r.output.startswith("elastokin: error: --scheduler no-port: "
                                                    "cannot connect")
    (tmp_path / "e").mkdir()
    (tmp_path / "e" / "notes.txt").write_text("mine")
    r = run_doe(case_path, tmp_path / "e", "--samples", "2")
    assert r.exit_code == 1 and "holds no elastokin DOE study" in r.output
    with pytest.raises(ConfigError, match="--method"):
        doe_sampling.unit_samples("grid", 4, 2, 0)
    with pytest.raises(ElastokinError, match="--load-cases"):
        doe.make_study(doe.suspension_from_dict(read_yaml(case_path)[0], str(case_path)), 2,
                       load_cases="everything")
