"""Steering axis per rig step (elastokin.steering_axis, kc columns caster_deg,
kingpin_inclination_deg, scrub_radius_mm, caster_trail_mm): known axes, the McPherson's
virtual-kingpin construction, the summary at the static state, signs, NaN with a reason."""

import copy
import csv
import json
import warnings
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from elastokin.cli.main import main
from elastokin.config.loading import load_suspension, read_yaml, suspension_from_dict
from elastokin.config.variants import kinematic as kinematic_variant
from elastokin.mbs.design import build_model, design_state
from elastokin.mbs.model import ModelOptions
from elastokin.physics import steering_geometry as ch
from elastokin.physics.states import PartPoses, StepState
from elastokin.physics.steering_axis import _null_spaces, steering_axes_from_poses
from elastokin.rig.channels import STEERING_AXIS_COLUMNS
from elastokin.rig.load_cases import parallel_travel, static_equilibrium
from elastokin.rig.pad import run_pad
from elastokin.rig.steering import (
    SteeringAxisWarning,
    steering_axis_columns,
    steering_skeleton,
)
from elastokin.studies.kc_job import ModelResult

ROOT = Path(__file__).parent.parent
DW = Path(__file__).parent / "data" / "double_wishbone.yaml"
MCPHERSON = ROOT / "configs" / "pseudo_mcpherson.yaml"


def _unit(v):
    v = np.asarray(v, float)
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def _design_step(s) -> StepState:
    """The design position as a step: every part at its design pose."""
    poses = PartPoses({p: np.eye(3) for p in s.parts}, {p: np.zeros(3) for p in s.parts},
                      {p: np.zeros(3) for p in s.parts})
    w = s.wheel
    return StepState(w.centre_mm, w.spin_axis, np.eye(3), w.contact_patch_mm, np.zeros(3), {},
                     {}, {}, poses)


def _design_values(s) -> dict[str, float]:
    return {k: float(v[0]) for k, v in steering_axis_columns([_design_step(s)], s).items()}


def _expected(s, point, direction, centre, spin) -> dict[str, np.ndarray]:
    """The four characteristics of a known axis (characteristics.py, same conventions)."""
    contact = ch.contact_point(centre, spin, s.wheel.loaded_radius_mm, s.up)
    return {
        "caster_deg": ch.caster_deg(direction, s.forward, s.up),
        "kingpin_inclination_deg": ch.kingpin_inclination_deg(direction, s.outboard, s.up),
        "scrub_radius_mm": ch.scrub_radius_mm(point, direction, contact, spin, s.forward,
                                              s.outboard, s.up),
        "caster_trail_mm": ch.caster_trail_mm(point, direction, contact, spin, s.forward,
                                              s.outboard, s.up),
    }


def _line_errors(axes, p, q):
    """Angle (deg) between each step's axis and the line p-q, and the largest distance (mm)
    of p and q from the axis."""
    d = _unit(q - p)
    angle = np.degrees(np.arcsin(np.clip(np.linalg.norm(np.cross(axes.direction, d), axis=1),
                                         0, 1)))
    dist = [np.linalg.norm(np.cross(x - axes.point, axes.direction), axis=1) for x in (p, q)]
    return angle, np.maximum(*dist)


def _moved(states, part, point):
    return np.array([st.poses.moved(part, point) for st in states])


# ---------------------------------------------------------------- a hand-checkable axis


def test_double_wishbone_design_axis_by_hand():
    """Design position: the axis is the line through the ball joints lca_outer (0, 720, 130)
    and uca_outer (10, 660, 460) (ISO frame, left wheel, contact point (0, 780, 0)): leaning
    10 mm forward and 60 mm inboard over 330 mm, meeting the ground at
    x = -10 * 130 / 330, y = 720 + 60 * 130 / 330."""
    v = _design_values(load_suspension(DW))
    assert v["caster_deg"] == pytest.approx(-np.degrees(np.arctan(10 / 330)), abs=1e-9)
    assert v["kingpin_inclination_deg"] == pytest.approx(np.degrees(np.arctan(60 / 330)),
                                                         abs=1e-9)
    assert v["scrub_radius_mm"] == pytest.approx(780 - (720 + 60 * 130 / 330), abs=1e-9)
    assert v["caster_trail_mm"] == pytest.approx(-10 * 130 / 330, abs=1e-9)


@pytest.mark.parametrize("kinematic", [False, True])
def test_double_wishbone_axis_through_ball_joints_at_every_step(kinematic):
    """Double wishbone, spring on the lower arm: with the spring locked and the rack moved
    the knuckle turns about the line through its two ball joints, at every step of the
    travel sweep, compliant (bushings deflected) or kinematic. Both sides use the same solved
    poses, so the agreement is to rounding."""
    s = load_suspension(DW)
    model = build_model(kinematic_variant(s) if kinematic else s, ModelOptions(), design_state(s))
    z = np.linspace(-60.0, 60.0, 25)
    states = run_pad(model, pad_z_mm=z)
    centre = np.array([st.wheel_centre_mm for st in states])
    axes = steering_axes_from_poses(steering_skeleton(s), [st.poses for st in states], centre)
    assert axes.reason is None
    lower = _moved(states, "knuckle", s.hardpoints["lca_outer"])
    upper = _moved(states, "knuckle", s.hardpoints["uca_outer"])
    angle, dist = _line_errors(axes, lower, upper)
    assert angle.max() < 1e-9 and dist.max() < 1e-9
    spin = np.array([st.spin_axis for st in states])
    expected = _expected(s, lower, _unit(upper - lower), centre, spin)
    got = steering_axis_columns(states, s)
    for name in STEERING_AXIS_COLUMNS:
        np.testing.assert_allclose(got[name], expected[name], atol=1e-9, err_msg=name)
    # the axis does move with travel (the test is not trivially at the design position)
    assert np.ptp(got["kingpin_inclination_deg"]) > 0.3


# ------------------------------------------------------------ McPherson: virtual kingpin


def _virtual_kingpin(top, arms):
    """The classic construction in 3D: the line through the strut top mount ``top`` that
    meets both lower-arm lines (inner, outer); a true lower ball joint or the 'virtual' one
    of two arms. Each arm line and ``top`` span a plane; the axis is their intersection."""
    n = [np.cross(inner - top, outer - inner) for inner, outer in arms]
    d = _unit(np.cross(n[0], n[1]))
    return np.where(d[..., 2:] < 0, -d, d)


def test_mcpherson_matches_virtual_kingpin_construction():
    """Kinematic pseudo-McPherson: the screw axis equals the virtual-kingpin line (through the
    top mount J4, meeting the arm lines J1-J8 and J2-J7) at the design position and at every
    step of the travel sweep. Tolerance 1e-6 deg / 1e-6 mm: the construction uses the
    knuckle's ball-joint points, the screw axis the arms' own markers, which coincide only to
    the Newton tolerance of the static solve (1e-6 absolute residual)."""
    s = load_suspension(MCPHERSON)
    h = s.hardpoints
    # design position, from the hardpoints alone
    d0 = _virtual_kingpin(h["J4"], [(h["J1"], h["J8"]), (h["J2"], h["J7"])])
    design = _design_values(s)
    expected = _expected(s, h["J4"], d0, s.wheel.centre_mm, s.wheel.spin_axis)
    for name in STEERING_AXIS_COLUMNS:  # rounding: 1e-9 deg, 1e-7 mm (lever arms ~1 m)
        tol = 1e-9 if name.endswith("_deg") else 1e-7
        assert design[name] == pytest.approx(float(expected[name]), abs=tol), name
    # about 7.5 deg caster, as the config's comment on its frame says
    assert 7.0 < design["caster_deg"] < 8.0 and 12 < design["kingpin_inclination_deg"] < 16
    # every step of the kinematic travel sweep, and its row at the design pad height
    model = build_model(kinematic_variant(s), ModelOptions(), design_state(s))
    sweep = parallel_travel(model, "initial_kinematic")
    c = sweep.columns
    row = np.flatnonzero((c["pad_z_mm"] == 0) & (c["branch"] == "stroke"))[0]
    for name in STEERING_AXIS_COLUMNS:
        assert c[name][row] == pytest.approx(design[name], abs=1e-6), name
    z = np.r_[np.linspace(-5.0, -90.0, 18), np.linspace(-80.0, 90.0, 18)]
    states = run_pad(model, pad_z_mm=z)
    centre = np.array([st.wheel_centre_mm for st in states])
    axes = steering_axes_from_poses(steering_skeleton(s), [st.poses for st in states], centre)
    j7, j8 = _moved(states, "knuckle", h["J7"]), _moved(states, "knuckle", h["J8"])
    d = _virtual_kingpin(h["J4"], [(h["J1"], j8), (h["J2"], j7)])
    angle, dist = _line_errors(axes, np.broadcast_to(h["J4"], j7.shape), h["J4"] + 100 * d)
    assert angle.max() < 1e-6 and dist.max() < 1e-6
    assert np.ptp(c["caster_deg"]) > 1.0  # the axis moves over the stroke


# ------------------------------------------------------------- summary = static state


def _csv_rows(path):
    with open(path) as fh:
        return list(csv.DictReader(line for line in fh if not line.startswith("#")))


def test_summary_is_the_travel_zero_row_and_the_static_state(tmp_path):
    out = tmp_path / "dw"
    result = CliRunner().invoke(main, ["kc", "--config", str(DW), "--out", str(out), "--quiet"])
    assert result.exit_code == 0, result.output
    summary = json.loads((out / "summary.json").read_text())
    rows = _csv_rows(out / "kc.csv")
    for label in ("initial", "initial_kinematic"):
        zero = [r for r in rows if r["model"] == label and r["load_case"] == "parallel_travel"
                and r["branch"] == "stroke" and float(r["pad_z_mm"]) == 0.0]
        assert len(zero) == 1
        for name in STEERING_AXIS_COLUMNS:
            assert summary["models"][label][name] == pytest.approx(float(zero[0][name]),
                                                                   abs=1e-9), (label, name)
    # ... and that row is the static equilibrium under the design wheel load (force control)
    s = load_suspension(DW)
    static = static_equilibrium(build_model(s, ModelOptions(), design_state(s))).state
    assert static.pad_force_N[2] == pytest.approx(s.design.wheel_load_N)
    at_static = steering_axis_columns([static], s)
    for name in STEERING_AXIS_COLUMNS:
        assert summary["models"]["initial"][name] == pytest.approx(float(at_static[name][0]),
                                                                   abs=1e-6), name


def test_summary_without_steering_columns_is_none():
    """Test data (no steering-axis channels) and a sweep without the zero pad height."""
    from elastokin.rig.sweeps import Sweep

    sw = Sweep("test", "parallel_travel", {"branch": np.array(["stroke"] * 3),
                                           "pad_z_mm": np.array([1.0, 2.0, 3.0]),
                                           "toe_deg": np.zeros(3),
                                           "wheel_travel_mm": np.array([1.0, 2.0, 3.0]),
                                           "caster_deg": np.ones(3)})
    out = ModelResult("test", False, [sw], {}).summary()
    assert all(out[name] is None for name in STEERING_AXIS_COLUMNS)


# ---------------------------------------------------------------------------- signs


def _dw_variant(change) -> dict[str, float]:
    data = copy.deepcopy(read_yaml(DW)[0])
    change(data)
    return _design_values(suspension_from_dict(data, "dw.yaml"))


def _set(data, name, index, value):
    data["hardpoints"][name][index] = value


def test_signs_caster_and_trail():
    """Upper ball joint 30 mm behind the lower one (x forward): the axis top leans rearward,
    positive caster, and the axis meets the ground ahead of the contact point, positive
    trail; 30 mm ahead: both negative."""
    rear = _dw_variant(lambda d: _set(d, "uca_outer", 0, -30.0))
    front = _dw_variant(lambda d: _set(d, "uca_outer", 0, 30.0))
    assert rear["caster_deg"] == pytest.approx(np.degrees(np.arctan(30 / 330)), abs=1e-9)
    assert rear["caster_trail_mm"] == pytest.approx(30 * 130 / 330, abs=1e-9)
    assert front["caster_deg"] < 0 and front["caster_trail_mm"] < 0


def test_signs_kingpin_inclination_and_scrub():
    """Upper ball joint inboard of the lower one: positive KPI; outboard: negative. Axis
    meeting the ground inboard of the contact point: positive scrub radius; wheel moved
    inboard (contact point inboard of the axis' ground point): negative."""
    base = _dw_variant(lambda d: None)
    assert base["kingpin_inclination_deg"] > 0 and base["scrub_radius_mm"] > 0
    out = _dw_variant(lambda d: _set(d, "uca_outer", 1, 760.0))
    assert out["kingpin_inclination_deg"] == pytest.approx(-np.degrees(np.arctan(40 / 330)),
                                                           abs=1e-9)

    inboard = _dw_variant(lambda d: _set(d, "wheel_centre", 1, 700.0))
    assert inboard["scrub_radius_mm"] == pytest.approx(700 - (720 + 60 * 130 / 330), abs=1e-9)


def _mirror(data, sx, sy, frame, side):
    """The same physical suspension in another config frame or on the other side."""
    d = copy.deepcopy(data)
    flip = np.array([sx, sy, 1.0])
    d["hardpoints"] = {k: (np.asarray(v, float) * flip).tolist()
                       for k, v in d["hardpoints"].items()}
    d["frame"], d["side"] = frame, side
    d["wheel"]["spin_axis"] = (np.asarray(d["wheel"]["spin_axis"], float) * flip).tolist()
    d["connections"]["lca_bushing"]["radial"] = (np.asarray(
        d["connections"]["lca_bushing"]["radial"], float) * flip).tolist()
    d["connections"]["steering"]["axis"] = (np.asarray(
        d["connections"]["steering"]["axis"], float) * flip).tolist()
    return d


@pytest.mark.parametrize("sx, sy, frame, side", [
    (-1.0, -1.0, {"x": "rearward", "y": "right", "z": "up"}, "left"),  # ADAMS/Car frame
    (1.0, -1.0, {"x": "forward", "y": "left", "z": "up"}, "right"),  # the right wheel
])
def test_signs_do_not_depend_on_frame_or_side(sx, sy, frame, side):
    data = read_yaml(DW)[0]
    base = _design_values(suspension_from_dict(copy.deepcopy(data), "dw.yaml"))
    other = _design_values(suspension_from_dict(_mirror(data, sx, sy, frame, side), "m.yaml"))
    for name in STEERING_AXIS_COLUMNS:
        assert other[name] == pytest.approx(base[name], abs=1e-9), name


def test_mcpherson_signs_in_the_adams_frame():
    """The shipped McPherson (x rearward, y right, left wheel): J4 behind and inboard of the
    lower arms' ends, so positive caster and KPI, and the axis meets the ground ahead of the
    contact point (positive trail)."""
    v = _design_values(load_suspension(MCPHERSON))
    assert v["caster_deg"] > 0 and v["kingpin_inclination_deg"] > 0
    assert v["caster_trail_mm"] > 0


# ------------------------------------------------------------------ undefined: NaN


def _nan_with_warning(s, match):
    with pytest.warns(SteeringAxisWarning, match=match):
        v = _design_values(s)
    assert all(np.isnan(v[name]) for name in STEERING_AXIS_COLUMNS)


def test_no_steering_element_gives_nan():
    """McPherson with a second link on the knuckle: which one steers is not defined."""
    data = copy.deepcopy(read_yaml(MCPHERSON)[0])
    data["connections"]["extra_link"] = {"type": "link", "parts": ["body", "knuckle"],
                                         "at": ["J3", "J9"]}
    _nan_with_warning(suspension_from_dict(data, "m.yaml"), "steering input")


def _spring_on_rack(body_seat):
    data = copy.deepcopy(read_yaml(DW)[0])
    data["springs"]["coil"]["parts"] = ["body", "rack"]
    data["springs"]["coil"]["seats"] = [body_seat, "rack_end"]
    return suspension_from_dict(data, "dw.yaml")


def test_spring_that_does_not_lock_travel_gives_nan():
    """Double wishbone whose only spring acts on the rack. Across the rack axis, locking it
    holds neither travel nor steering: the knuckle keeps two degrees of freedom. Along the
    rack axis, it locks the steering: the one motion left is the travel, whose axis is NOT
    the steering axis. Both NaN, never the travel's axis."""
    _nan_with_warning(_spring_on_rack([-140.0, 330.0, 50.0]), "more than one degree")
    _nan_with_warning(_spring_on_rack([-140.0, 100.0, 200.0]), "does not move the steering")


def test_no_spring_gives_nan():
    data = copy.deepcopy(read_yaml(DW)[0])
    del data["springs"]
    data["design"] = {"wheel_load_N": 4000}
    _nan_with_warning(suspension_from_dict(data, "dw.yaml"), "no spring")


def test_null_space_fallback_for_dependent_rows():
    """Repeated constraint rows: the QR fast path hands the step to the SVD, same space."""
    rng = np.random.default_rng(1)
    A = rng.normal(size=(2, 4, 6))
    A[1, 3] = A[1, 0]  # step 1: one redundant row, nullity 3 instead of 2
    nullity = {}
    for idx, null in _null_spaces(A):
        assert np.abs(A[idx] @ null).max() < 1e-12
        assert np.allclose(np.swapaxes(null, 1, 2) @ null, np.eye(null.shape[2]))
        nullity.update({int(i): null.shape[2] for i in idx})
    assert nullity == {0: 2, 1: 3}


def test_compliant_steps_warn_nothing_on_the_shipped_case():
    """The shipped case has an axis at every step (no warning, no NaN)."""
    s = load_suspension(MCPHERSON)
    model = build_model(s, ModelOptions(), design_state(s))
    with warnings.catch_warnings():
        warnings.simplefilter("error", SteeringAxisWarning)
        z = np.r_[np.linspace(-10.0, -90.0, 9), np.linspace(-70.0, 90.0, 9)]
        states = run_pad(model, pad_z_mm=z)
        cols = steering_axis_columns(states, s)
    assert all(np.isfinite(cols[name]).all() for name in STEERING_AXIS_COLUMNS)


def test_compliant_mcpherson_under_braking_matches_deflected_construction():
    """Compliant pseudo-McPherson under +-2 kN at the contact patch (J1 deflects about 12 mm):
    the axis is the virtual-kingpin line of the deflected geometry, through the strut rod's
    top-mount point and meeting the lines from each arm's inner (bushing) point to the
    knuckle's ball joint. Same solved poses on both sides: 1e-7 deg / 1e-6 mm."""
    s = load_suspension(MCPHERSON)
    h = s.hardpoints
    model = build_model(s, ModelOptions(), design_state(s))
    force = np.linspace(-2000.0, 2000.0, 9)
    states = run_pad(model, pad_loads=s.up * s.design.wheel_load_N + force[:, None] * s.forward)
    centre = np.array([st.wheel_centre_mm for st in states])
    axes = steering_axes_from_poses(steering_skeleton(s), [st.poses for st in states], centre)
    top = _moved(states, "strut_rod", h["J4"])
    arms = [(_moved(states, "front_arm", h["J1"]), _moved(states, "knuckle", h["J8"])),
            (_moved(states, "rear_arm", h["J2"]), _moved(states, "knuckle", h["J7"]))]
    assert np.linalg.norm(arms[0][0] - h["J1"], axis=1).max() > 10.0  # really deflected
    d = _virtual_kingpin(top, arms)
    angle, dist = _line_errors(axes, top, top + 100 * d)
    assert angle.max() < 1e-7 and dist.max() < 1e-6
    caster = steering_axis_columns(states, s)["caster_deg"]
    assert np.ptp(caster) > 1.0  # braking compliance moves the axis
