"""Design to targets: design variables as overrides, targets files (errors naming file and
key), the optimiser (a known optimum found, a case it cannot meet stopped with what binds,
six points and three targets checked by a plain `elastokin kc` of the written config), the
optimised config written in place, and the sensitivity table against a full re-run."""

import json

import numpy as np
import pytest
from click.testing import CliRunner

from elastokin.cli.main import main
from elastokin.config.design_variables import DesignVariable, design_suspension, rack_points
from elastokin.config.loading import load_suspension, load_suspension_with_rig
from elastokin.errors import ConfigError
from elastokin.formats.config_edit import check_written, edited_config
from elastokin.formats.targets import load_targets
from elastokin.studies.design_job import run_optimize

from .conftest import ROOT

DW = ROOT / "configs" / "double_wishbone_axle.yaml"
CASE = ROOT / "configs" / "pseudo_mcpherson.yaml"
FINE_TRAVEL = ("parallel_travel: {rebound_mm: -1, bump_mm: 1, step_mm: 0.25, unloading: false}"
               "\nvertical_force: null\n")


def write(path, text: str):
    path.write_text(text)
    return path


def zero_bump_steer_height(hp: dict) -> float:
    """The tie rod's inner height at which the double wishbone has no bump steer at its
    design position, from its instant motion alone (no elastokin): the knuckle's twist when
    the arms turn about their pivot axes, the wheel does not turn about the vertical (no
    toe change: the spin axis is horizontal) and the wheel centre rises at unit speed; the
    tie rod then must not change length, i.e. the outer end's velocity is normal to it (in
    the front view: the tie rod in line with the arms' pole)."""
    P = {k: np.asarray(v, float) for k, v in hp.items()}

    def cross_matrix(r):  # cross_matrix(r) @ w == np.cross(w, r)
        return np.array([[0, r[2], -r[1]], [-r[2], 0, r[0]], [r[1], -r[0], 0]])

    lower = (P["lca_front"] - P["lca_rear"]) / np.linalg.norm(P["lca_front"] - P["lca_rear"])
    upper = (P["uca_front"] - P["uca_rear"]) / np.linalg.norm(P["uca_front"] - P["uca_rear"])
    A, b = np.zeros((8, 8)), np.zeros(8)  # unknowns: v (3), w (3), lower and upper arm rates
    for rows, ball, axis, pivot, col in ((slice(0, 3), P["lca_outer"], lower, P["lca_pivot"], 6),
                                         (slice(3, 6), P["uca_outer"], upper, P["uca_pivot"], 7)):
        A[rows, 0:3] = np.eye(3)
        A[rows, 3:6] = cross_matrix(ball)
        A[rows, col] = -np.cross(axis, ball - pivot)
    A[6, 5] = 1.0
    A[7, 2], A[7, 3:6], b[7] = 1.0, cross_matrix(P["wheel_centre"])[2], 1.0
    z = np.linalg.solve(A, b)
    T, inner = P["tierod_outer"], P["tierod_inner"]
    vT = z[0:3] + np.cross(z[3:6], T)
    return float(T[2] + (vT[0] * (T[0] - inner[0]) + vT[1] * (T[1] - inner[1])) / vT[2])


def test_known_optimum_tie_rod_height(tmp_path):
    """The tie-rod inner height zeroing bump steer at design, from 20 mm off, to 0.01 mm of
    the instant-centre construction (kinematic model, steering locked, both sides)."""
    rig = write(tmp_path / "rig.yaml", FINE_TRAVEL)
    s = load_suspension_with_rig(DW, rig)
    optimum = zero_bump_steer_height(s.hardpoints)
    start = design_suspension(s, [DesignVariable("hardpoint", "tierod_inner", 2)],
                              [optimum + 20.0])
    targets = write(tmp_path / "t.yaml", """
elastokin_targets: 1
model: initial_kinematic
variables:
  - {hardpoint: tierod_inner, axis: z, within_mm: 40}
characteristics:
  bump_steer_at_design_deg_per_m: {target: 0.0, tolerance: 0.001}
""")
    result = run_optimize(start, targets)
    assert result.met, result.binding
    assert abs(result.best.values[0] - optimum) < 0.01
    assert result.model_runs <= 10


def test_unreachable_target_stops_with_the_best_point_and_what_binds(tmp_path):
    """A bump-steer target the tie rod cannot reach within 2 mm: the best point (the bound)
    is kept, the target missed and the variable at its bound are named."""
    rig = write(tmp_path / "rig.yaml", FINE_TRAVEL)
    s = load_suspension_with_rig(DW, rig)
    targets = write(tmp_path / "t.yaml", """
elastokin_targets: 1
model: initial_kinematic
variables:
  - {hardpoint: tierod_inner, axis: z, within_mm: 2}
characteristics:
  bump_steer_at_design_deg_per_m: {target: 0.0, tolerance: 0.01}
optimizer: {max_iterations: 6}
""")
    result = run_optimize(s, targets)
    assert not result.met
    assert result.best.values[0] == pytest.approx(56.0, abs=1e-6)  # 54 + 2: the upper bound
    text = " ".join(result.binding)
    assert "bump_steer_at_design_deg_per_m" in text and "tierod_inner.z at its upper bound" \
        in text


@pytest.mark.parametrize("body, key", [
    ("variables: []\ncharacteristics: {bump_steer_deg_per_m: {target: 0}}", "variables"),
    ("variables: [{hardpoint: nowhere, axis: z, within_mm: 5}]\n"
     "characteristics: {bump_steer_deg_per_m: {target: 0}}", "variables[0]"),
    ("variables: [{hardpoint: tierod_inner, within_mm: 5}]\n"
     "characteristics: {bump_steer_deg_per_m: {target: 0}}", "variables[0]"),
    ("variables: [{hardpoint: tierod_inner, axis: z, range_mm: [60, 90]}]\n"
     "characteristics: {bump_steer_deg_per_m: {target: 0}}", "variables[0]"),
    ("variables: [{spring: coil, preload_N: [0, 9000]}]\n"
     "characteristics: {bump_steer_deg_per_m: {target: 0}}", "variables[0]"),
    ("variables: [{hardpoint: tierod_inner, axis: z, within_mm: 5}]\n"
     "characteristics: {bump_steer_deg_per_m: {target: 0, tolerance: -1}}",
     "characteristics.bump_steer_deg_per_m.tolerance"),
    ("variables: [{hardpoint: tierod_inner, axis: z, within_mm: 5}]\n"
     "characteristics: {bump_steer_mm: {target: 0}}", "characteristics.bump_steer_mm"),
    ("variables: [{hardpoint: tierod_inner, axis: z, within_mm: 5}]\n"
     "curves: {c: {load_case: parallel_travel, x: wheel_travel_mm, y: toe_deg, "
     "points: {wheel_travel_mm: [0], toe_deg: [0]}, tolerance_mm: 0.1}}", "curves.c"),
    ("variables: [{hardpoint: tierod_inner, axis: z, within_mm: 5}]\n"
     "curves: {c: {load_case: lateral_force, x: lateral_force_N, y: toe_deg, "
     "points: {lateral_force_N: [0], toe_deg: [0]}}}\nmodel: initial_kinematic",
     "curves.c.load_case"),
    ("variables: [{hardpoint: tierod_inner, axis: z, within_mm: 5}]\n"
     "characteristics: {bump_steer_deg_per_m: {target: 0}}\n"
     "constraints: {link_lengths: {no_link: {range_mm: [1, 2]}}}",
     "constraints.link_lengths.no_link"),
])
def test_bad_targets_files_name_the_file_and_key(tmp_path, body, key):
    s = load_suspension(DW)
    path = write(tmp_path / "bad_targets.yaml", "elastokin_targets: 1\n" + body + "\n")
    with pytest.raises(ConfigError) as err:
        load_targets(path, s)
    assert "bad_targets.yaml" in str(err.value) and key in str(err.value), str(err.value)


def test_design_variables_mirror_and_one_side():
    """On an axle the mirrored point follows (x, z alike, y the other way) unless the
    variable names one side; the rack's position moves the rack's points; a bushing scale
    multiplies its rates on both sides."""
    s = load_suspension(DW)
    p = np.asarray(s.hardpoints["tierod_inner"])
    both = design_suspension(s, [DesignVariable("hardpoint", "tierod_inner", 1)], [p[1] + 3])
    assert both.hardpoints["tierod_inner_right"][1] == pytest.approx(-(p[1] + 3))
    one = design_suspension(s, [DesignVariable("hardpoint", "tierod_inner", 2,
                                               side="config")], [p[2] + 3])
    assert one.hardpoints["tierod_inner"][2] == pytest.approx(p[2] + 3)
    assert one.hardpoints["tierod_inner_right"][2] == pytest.approx(p[2])
    other = design_suspension(s, [DesignVariable("hardpoint", "tierod_inner", 2,
                                                 side="other")], [p[2] - 4])
    assert other.hardpoints["tierod_inner"][2] == pytest.approx(p[2])
    assert other.hardpoints["tierod_inner_right"][2] == pytest.approx(p[2] - 4)
    assert rack_points(s.raw) == ["rack_centre", "tierod_inner"]
    rack = design_suspension(s, [DesignVariable("rack_position", "", 2)], [5.0])
    for name in ("rack_centre", "tierod_inner", "tierod_inner_right"):
        assert rack.hardpoints[name][2] == pytest.approx(s.hardpoints[name][2] + 5.0)
    soft = design_suspension(s, [DesignVariable("bushing_scale", "lca_bushing",
                                                directions=("x", "y"))], [0.5])
    for name in ("lca_bushing", "lca_bushing_right"):
        b = next(b for b in soft.bushings if b.name == name)
        assert [law.rate_at_zero for law in b.laws[:3]] == pytest.approx([10000, 10000, 3000])


def test_optimised_config_keeps_the_file_and_says_what_moved(tmp_path):
    """Hardpoints and a spring rate edited in the user's file (comments kept, the old value
    beside the new); a bushing scale, which cannot be edited in place, makes the mapping be
    written again; both read back as the optimised design."""
    s = load_suspension(DW)
    text = DW.read_text()
    moved = [DesignVariable("hardpoint", "tierod_inner", 2), DesignVariable("spring_rate",
                                                                           "coil")]
    out = edited_config(text, s, moved, [61.25, 180.0])
    check_written(out, "t.yaml", s, moved, [61.25, 180.0], 6)
    assert "tierod_inner: [-250.0, 448.0, 61.25]" in out
    assert "# was [-250.0, 448.0, 54.0] (elastokin optimize)" in out
    assert "rate_N_per_mm: 180.0" in out and "rate_N_per_mm was 167.062" in out
    assert len(out.splitlines()) == len(text.splitlines())  # every comment line kept
    scaled = [DesignVariable("bushing_scale", "lca_bushing")]
    again = edited_config(text, s, scaled, [0.8])
    check_written(again, "t.yaml", s, scaled, [0.8], 6)
    assert "lca_bushing.scale: 1.0 -> 0.8" in again


@pytest.mark.slow
def test_six_points_three_targets_checked_by_a_plain_kc(tmp_path):
    """Six hardpoints (both arms' chassis points, the tie rod's ends) moved to meet bump
    steer, bump camber and roll centre height at once on the compliant model; `elastokin kc`
    of the written config gives the same figures."""
    rig = write(tmp_path / "rig.yaml", "parallel_travel: {rebound_mm: -50, bump_mm: 50, "
                "step_mm: 25, unloading: false}\nvertical_force: null\n")
    # the shipped targets, SLSQP stopped when its objective (start: 1) changes by less than
    # 1e-5, not 1e-10: 17 model runs, not 35, every target then met with a third of its band
    # to spare (the default polishes the objective deep inside the bands); the check against
    # a plain kc does not depend on where it stops
    shipped = ROOT / "configs" / "targets" / "double_wishbone_six_points.yaml"
    targets = write(tmp_path / "targets.yaml",
                    shipped.read_text() + "optimizer: {tolerance: 1.0e-5}\n")
    out = tmp_path / "opt"
    r = CliRunner().invoke(main, ["optimize", "--config", str(DW), "--targets", str(targets),
                                  "--rig", str(rig), "--out", str(out), "--quiet"])
    assert r.exit_code == 0, r.output
    design = json.loads((out / "design.json").read_text())
    assert design["met"] and len(design["variables"]) == 6
    kc = tmp_path / "kc"
    r = CliRunner().invoke(main, ["kc", "--config", str(out / "double_wishbone_axle_optimised"
                                                        ".yaml"), "--rig", str(rig),
                                  "--models", "initial", "--out", str(kc), "--quiet"])
    assert r.exit_code == 0, r.output
    summary = json.loads((kc / "summary.json").read_text())["models"]["initial"]
    got = {t["target"]: t["model"] for t in design["targets_optimised"]}
    assert summary["bump_steer_deg_per_m"] == pytest.approx(got["bump_steer_deg_per_m"],
                                                            abs=1e-6)
    assert summary["bump_camber_deg_per_m"] == pytest.approx(got["bump_camber_deg_per_m"],
                                                             abs=1e-6)
    assert summary["axle"]["roll_centre_height_mm"] == pytest.approx(
        got["axle.roll_centre_height_mm"], abs=1e-6)


def test_sensitivity_command_matches_a_full_rerun(tmp_path):
    """`elastokin sensitivity` on the case study: every used hardpoint coordinate ranked per
    characteristic in the CSV; the tie rod's inner height's effect on bump steer equals
    central differences of two full runs."""
    rig = write(tmp_path / "rig.yaml", "parallel_travel: {rebound_mm: -50, bump_mm: 50, "
                "step_mm: 10, unloading: false}\nvertical_force: null\n")
    out = tmp_path / "sens"
    r = CliRunner().invoke(main, ["sensitivity", "--config", str(CASE), "--rig", str(rig),
                                  "--out", str(out), "--quiet"])
    assert r.exit_code == 0, r.output
    doc = json.loads((out / "sensitivity.json").read_text())
    effects = doc["characteristics"]["bump_steer_deg_per_m"]["effects_per_mm"]
    assert len(effects) == 33  # 11 hardpoints, x y z
    from elastokin.cli.design import nominal_suspension
    from elastokin.studies.design_runs import run_design

    s = nominal_suspension(CASE, rig)
    v = [DesignVariable("hardpoint", "J3", 2)]
    z = v[0].value(s.raw)
    runs = [run_design(s, v, [z + d], ("initial",), derivatives=False) for d in (0.05, -0.05)]
    fd = (runs[0].summary["initial"]["bump_steer_deg_per_m"]
          - runs[1].summary["initial"]["bump_steer_deg_per_m"]) / 0.1
    assert effects["J3.z"] == pytest.approx(fd, rel=1e-4)
    rows = (out / "sensitivity.csv").read_text().splitlines()
    assert rows[0].startswith("# elastokin sensitivity")
    assert rows[2].startswith("bump_steer_deg_per_m,deg/m,") and rows[2].endswith(
        f",{max(effects, key=lambda k: abs(effects[k])).replace('.', ',')},"
        f"{max(effects.values(), key=abs):.10g}")  # rank 1: the largest effect
    assert (out / "hardpoint_effects.png").exists() and (out / "report.html").exists()


def test_flexible_beams_are_refused_by_name(tmp_path):
    """Design sensitivities take every part as rigid: the twist beam's flexible cross beam is
    named in one line (exit code 1, nothing written)."""
    out = tmp_path / "sens"
    r = CliRunner().invoke(main, ["sensitivity", "--config",
                                  str(ROOT / "configs" / "twist_beam_axle.yaml"), "--rig",
                                  str(ROOT / "configs" / "rigs" / "travel_only.yaml"),
                                  "--out", str(out), "--quiet"])
    assert r.exit_code == 1
    assert "flexible beam part(s) cross_beam" in r.output and "Traceback" not in r.output
    assert not out.exists()


def test_a_target_the_rig_cannot_determine_is_one_line(tmp_path):
    """A characteristic target that the rig leaves undetermined (bump steer from 3 points of
    travel, 50 mm apart: 2 in its +-50 mm window) stops with one line naming the targets
    file, the key and why, not a traceback (exit code 1, nothing written)."""
    rig = write(tmp_path / "rig.yaml", "parallel_travel: {rebound_mm: -50, bump_mm: 50, "
                "step_mm: 50, unloading: false}\nvertical_force: null\nlateral_force: null\n"
                "longitudinal_force_patch: null\nlongitudinal_force_centre: null\n"
                "aligning_torque: null\nopposite_travel: null\nsingle_wheel_travel: null\n"
                "roll_vertical_force: null\nsteering: null\nlateral_force_anti_phase: null\n")
    out = tmp_path / "opt"
    r = CliRunner().invoke(main, ["optimize", "--config", str(DW), "--targets",
                                  str(ROOT / "configs" / "targets"
                                      / "double_wishbone_six_points.yaml"),
                                  "--rig", str(rig), "--out", str(out), "--quiet"])
    assert r.exit_code == 1 and "Traceback" not in r.output, r.output
    assert "key 'characteristics.bump_steer_deg_per_m'" in r.output
    assert "not determined on this rig" in r.output
    assert not out.exists()
