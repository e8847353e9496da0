"""The 3D view (issue 26): the scene's geometry, the kinematic figures it draws (checked
against a hand construction), the parts' poses recorded per step (checked against the wheel
columns), a config with errors drawn as far as it resolves, ``elastokin view``, and the page
in headless Chromium with the network cut (drawn, the slider moves the wheel, no error, no
request)."""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pytest
import yaml
from click.testing import CliRunner

from elastokin.cli.main import main
from elastokin.config.draft import draft_from_dict, draft_of, draft_suspension
from elastokin.config.loading import load_suspension, load_suspension_with_rig, read_yaml
from elastokin.config.variants import with_hardpoints
from elastokin.identification.overlay import magnification
from elastokin.physics.states import PartPoses, PoseSeries
from elastokin.rig.scene import build_scene
from elastokin.rig.scene_motion import design_frames, frame_steps

from .browser import Browser, chromium_path
from .conftest import ROOT

CORNER = ROOT / "tests" / "data" / "double_wishbone.yaml"
AXLE = ROOT / "configs" / "double_wishbone_axle.yaml"
TRAVEL = ROOT / "configs" / "rigs" / "travel_only.yaml"


# ------------------------------------------------------------------------------ geometry
def test_scene_of_a_corner_by_hand():
    scene = build_scene(draft_of(load_suspension(CORNER)))
    parts = {p.name: p for p in scene.parts}
    assert {lab.split(" ")[0] for lab in parts["lower_arm"].labels} == {
        "lca_pivot", "lca_outer", "spring_lower"}
    assert len(parts["lower_arm"].edges) == 3 and len(parts["lower_arm"].triangles) == 1
    assert len(parts["upper_arm"].edges) == 1 and not parts["upper_arm"].triangles
    assert len(parts["knuckle"].points_mm) == 4 and len(parts["knuckle"].triangles) == 4
    assert len(parts["rack"].points_mm) == 1  # the rack joint and the tie rod's end coincide
    assert {lab.split(" ")[0] for lab in scene.ground_labels} == {
        "lca_pivot", "uca_front", "rack_end", "spring_upper"}
    assert set(scene.loose_labels) == {"lca_front", "lca_rear", "uca_rear"}  # axes only
    kinds = sorted(i.kind for i in scene.items)
    assert kinds == ["bushing", "link", "rack", "revolute", "spherical", "spherical", "spring"]
    assert len({p.colour for p in scene.parts}) == len(scene.parts)
    (w,) = scene.wheels
    np.testing.assert_allclose(w.contact_patch_mm, [0.0, 780.0, 0.0])


def _intersect(p, q, r, s):
    """The point where the line p-q meets the line r-s (2D)."""
    a = np.array([q - p, r - s]).T
    t = np.linalg.solve(a, r - p)
    return p + t[0] * (q - p)


def test_design_instant_centre_and_roll_centre_by_hand():
    """Arms pivoting about axes along x, ball joints and wheel centre in one transverse
    plane: the front-view velocities there are a rotation about x, so the instant centre is
    where the arm lines meet (the classic construction), whatever the tie rod does; the roll
    centre (a corner: with its mirror image) is where the line from the contact point
    through it meets the centre plane."""
    s = load_suspension(CORNER)
    s = with_hardpoints(s, {"uca_outer": np.array([0.0, 660.0, 460.0])})
    frames = design_frames(build_scene(draft_of(s)), s)
    ic = _intersect(np.array([350.0, 150.0]), np.array([720.0, 130.0]),
                    np.array([430.0, 470.0]), np.array([660.0, 460.0]))
    np.testing.assert_allclose(frames.instant_centre_mm["left"][0], [0.0, *ic], atol=1e-6)
    contact = np.array([780.0, 0.0])
    z0 = contact[1] + (0.0 - contact[0]) * (ic[1] - contact[1]) / (ic[0] - contact[0])
    np.testing.assert_allclose(frames.roll_centre_mm[0], [0.0, 0.0, z0], atol=1e-6)
    # the steering axis passes through both ball joints (springs locked, rack released)
    a, b = frames.steering_axis_mm["left"][0]
    for joint in ([0.0, 720.0, 130.0], [0.0, 660.0, 460.0]):
        d = np.cross(b - a, np.asarray(joint) - a) / np.linalg.norm(b - a)
        assert np.linalg.norm(d) < 1e-6


def test_pose_series_by_hand():
    quarter = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])  # 90 deg about z
    steps = [PartPoses({"arm": np.eye(3)}, {"arm": np.zeros(3)}, {"arm": np.array([1.0, 0, 0])}),
             PartPoses({"arm": quarter}, {"arm": np.array([0.0, 0.0, 5.0])},
                       {"arm": np.array([1.0, 0, 0])})]
    series = PoseSeries.stack(steps)
    assert series.steps == 2
    np.testing.assert_allclose(series.at(1).moved("arm", [2.0, 0.0, 0.0]), [1.0, 1.0, 5.0])
    R, t = series.transforms("arm", [0, 1])
    np.testing.assert_allclose(R[1] @ [2.0, 0.0, 0.0] + t[1], [1.0, 1.0, 5.0])
    R, t = series.transforms("body", [0, 1])  # the ground does not move
    np.testing.assert_allclose(R[1], np.eye(3)) and np.testing.assert_allclose(t, 0.0)
    nodes = np.arange(6.0).reshape(2, 3)  # a beam part's node line: stacked per step
    steps[1].node_mm["beam"], steps[1].node_rotation["beam"] = nodes, np.stack([quarter] * 2)
    steps[0].node_mm["beam"], steps[0].node_rotation["beam"] = nodes * 0, np.stack([np.eye(3)] * 2)
    series = PoseSeries.stack(steps)
    assert series.node_mm["beam"].shape == (2, 2, 3)
    np.testing.assert_allclose(series.at(1).node_mm["beam"], nodes)
    np.testing.assert_allclose(series.at(1).node_rotation["beam"][1], quarter)


def test_frame_steps_keep_the_branch_ends():
    branch = np.array(["approach"] * 5 + ["stroke"] * 100 + ["return"] * 50)
    steps = frame_steps(branch, 21)
    assert {0, 4, 5, 104, 105, 154} <= set(steps.tolist())
    assert len(steps) <= 21 + 6 and np.all(np.diff(steps) > 0)
    np.testing.assert_array_equal(frame_steps(branch[:10], 21), np.arange(10))


def test_magnification_is_round():
    assert magnification(0.8) == 50.0 and magnification(0.03) == 2000.0
    assert magnification(100.0) == 1.0 and magnification(0.0) == 1.0


# ------------------------------------------------------------------------------ drafts
def test_a_config_with_errors_resolves_as_far_as_it_can():
    data = read_yaml(CORNER)[0]
    data["hardpoints"]["lca_outer"] = [0.0, 720.0]  # two numbers
    data["springs"]["coil"]["rate_N_per_mm"] = -30.0
    data["wheels"] = {}  # an unknown key
    data["connections"]["tie_rod"]["at"] = ["rack_end", "nowhere"]
    d = draft_from_dict(data, "dw.yaml")
    assert d.suspension is None and len(d.errors) == 5, d.errors
    assert any("key 'hardpoints.lca_outer" in e for e in d.errors)
    assert any("springs.coil.rate_N_per_mm" in e for e in d.errors)
    assert any("unknown top-level key 'wheels' (did you mean 'wheel'?)" in e for e in d.errors)
    assert any("key 'connections.tie_rod.at': hardpoint 'nowhere'" in e for e in d.errors)
    assert any("key 'connections.lower_ball.at': hardpoint 'lca_outer'" in e for e in d.errors)
    assert {j.name for j in d.joints} == {"upper_pivot", "upper_ball", "steering"}
    assert [b.name for b in d.bushings] == ["lca_bushing"] and not d.links and not d.springs
    assert list(d.wheels) == ["left"]
    scene = build_scene(d)
    assert scene.errors == d.errors and "knuckle" in scene.part_names
    frames = design_frames(scene, d.suspension)  # nothing kinematic without the whole
    assert frames.frames == 1 and not frames.steering_axis_mm


def test_a_valid_config_is_its_whole_suspension(tmp_path):
    d = draft_suspension(AXLE)
    s = load_suspension(AXLE)
    assert d.errors == () and d.suspension is not None
    assert [j.name for j in d.joints] == [j.name for j in s.joints] and set(d.wheels) == {
        "left", "right"}
    data = read_yaml(AXLE)[0]
    data["axle"]["steering"]["rack"] = "tie_rod"  # an error across sections: the axle's
    d = draft_from_dict(data, "axle.yaml")
    assert len(d.errors) == 1 and "axle.steering.rack" in d.errors[0]
    assert list(d.wheels) == ["left"] and d.joints  # the corner as it resolves
    bad = tmp_path / "bad.yaml"
    bad.write_text("elastokin: 1\nhardpoints: [1, 2\n")
    d = draft_suspension(bad)
    assert len(d.errors) == 1 and "line" in d.errors[0] and not d.parts


# ------------------------------------------------------------------------------ the command
def test_view_of_a_config_with_errors(tmp_path):
    data = read_yaml(CORNER)[0]
    data["connections"]["tie_rod"]["at"] = ["rack_end", "nowhere"]
    config = tmp_path / "dw.yaml"
    config.write_text(yaml.safe_dump(data))
    out = tmp_path / "view.html"
    result = CliRunner().invoke(main, ["view", str(config), "--out", str(out)])
    assert result.exit_code == 1
    assert "hardpoint 'nowhere' is not defined" in result.output
    page = out.read_text()
    assert "1 error in the config" in page and "hardpoint &#x27;nowhere&#x27;" in page
    assert not re.search(r"<script[^>]+src=", page)  # plotly.js is in the page


def _page_data(page: str) -> dict:
    raw = re.search(r'<script type="application/json" id="ekv-data">(.*?)</script>', page,
                    re.S).group(1)
    return json.loads(raw.replace("<\\/", "</"))


def test_view_of_a_load_case_carries_the_solved_poses(tmp_path):
    """The page's poses (rotation vector, displacement of the reference point) put the wheel
    centre where the rig's columns say it is (a check of what the page carries)."""
    from scipy.spatial.transform import Rotation

    from elastokin.studies.view import load_case_sweeps

    out = tmp_path / "view.html"
    args = ["view", str(CORNER), "--load-case", "parallel_travel", "--rig", str(TRAVEL),
            "--out", str(out)]
    result = CliRunner().invoke(main, args)
    assert result.exit_code == 0, result.output
    data = _page_data(out.read_text())
    model = data["models"]["initial"]
    assert model["cases"] == ["parallel_travel", "design_position"]
    case = model["data"]["parallel_travel"]
    s = load_suspension_with_rig(CORNER, TRAVEL)
    (sweep,) = load_case_sweeps(s, "parallel_travel")
    k = model["parts"].index("knuckle")
    pose = np.array(case["pose"], float).reshape(len(case["steps"]), len(model["parts"]), 6)
    ref = np.array(model["ref"][k])
    R = Rotation.from_rotvec(pose[:, k, :3] * 1e-6).as_matrix()
    centre = (R @ (s.wheel.centre_mm - ref)) + ref + pose[:, k, 3:] * 0.01
    columns = np.array([sweep.columns[f"wheel_centre_{a}_mm"] for a in "xyz"]).T[case["steps"]]
    np.testing.assert_allclose(centre, columns, atol=0.02)  # rounding: 1e-6 rad, 0.01 mm
    bad = CliRunner().invoke(main, ["view", str(CORNER), "--load-case", "roll",
                                    "--out", str(tmp_path / "x.html")])
    assert bad.exit_code == 1 and "--load-case roll" in bad.output
    assert "parallel_travel, vertical_force" in bad.output


# ------------------------------------------------------------------------------ browser
READY = ("!!document.getElementById('ekv-plot') && "
         "document.getElementById('ekv-plot').getAttribute('data-ready') === '1'")
#: show only the selected model's wheels (every other trace hidden from the legend)
WHEELS_ONLY = ("(function(){var gd=document.getElementById('ekv-plot');gd.data.forEach("
               "function(t){if(t.name!=='wheels and tyres'&&t.visible!==false){t.visible="
               "'legendonly';}});gd.elastokinView.draw();return 1;})()")


def _slider(frame: int) -> str:
    return (f"(function(){{var s=document.getElementById('ekv-slider');s.value='{frame}';"
            "s.dispatchEvent(new Event('input'));return Number(s.max);})()")


def _case(name: str) -> str:
    return (f"(function(){{var s=document.getElementById('ekv-case');s.value='{name}';"
            "s.dispatchEvent(new Event('change'));return s.value;})()")


def _plot_box(b: Browser) -> dict:
    """The 3D scene's part of the plot (its left 80 %, the legend right of it), without
    the colour bar and the view buttons."""
    r = b.run("(function(){var r=document.getElementById('ekv-plot').getBoundingClientRect();"
              "return [r.left+window.scrollX,r.top+window.scrollY,r.width,r.height];})()")
    return {"x": r[0], "y": r[1] + 0.1 * r[3], "width": 0.8 * r[2], "height": 0.75 * r[3]}


def _colour_pixels(img: np.ndarray, colour: str) -> int:
    rgb = np.array([int(colour[k:k + 2], 16) for k in (1, 3, 5)], float)
    return int((np.abs(img.astype(float) - rgb).max(axis=-1) < 12).sum())


def check_view(b: Browser, url: str, colours: list[str], case: str) -> None:
    """The page drawn (every part colour in the scene), the slider moving the wheels (two
    screenshots of the wheels alone differ, and only where a wheel is), no error, no
    request but the page."""
    b.open(url)
    b.run("document.getElementById('ekv-plot').scrollIntoView()")  # a report's view waits
    b.wait_for(READY)
    b.settle()
    box = _plot_box(b)
    img = b.screenshot(box)
    for colour in colours:
        assert _colour_pixels(img, colour) > 30, colour
    assert b.run(_case(case)) == case
    last = b.run(_slider(0))
    assert last > 5
    b.run(WHEELS_ONLY)
    b.settle()
    first = b.screenshot(box).astype(int)
    b.run(_slider(last))
    b.settle()
    moved = b.screenshot(box).astype(int)
    ink = (first.min(axis=-1) < 200) | (moved.min(axis=-1) < 200)  # a wheel's lines
    changed = np.abs(first - moved).max(axis=-1) > 40
    assert changed.sum() > 200 and (changed & ink).sum() > 0.9 * changed.sum()
    assert b.errors == []
    assert [u for u in b.requests if not u.startswith(("file:", "data:"))] == []


@pytest.fixture(scope="module")
def browser():
    if chromium_path() is None:
        pytest.skip("headless Chromium is not installed (apt-get install chromium)")
    with Browser(1280, 1000, offline=True) as b:
        yield b


def test_view_page_in_chromium_offline(browser, tmp_path):
    """``elastokin view --load-case``: drawn, animated, no error, no request."""
    out = tmp_path / "view.html"
    result = CliRunner().invoke(main, ["view", str(CORNER), "--load-case", "parallel_travel",
                                       "--rig", str(TRAVEL), "--out", str(out)])
    assert result.exit_code == 0, result.output
    # lower arm, upper arm, knuckle (the rack is one point)
    check_view(browser, out.resolve().as_uri(), ["#1f77b4", "#ff7f0e", "#9467bd"],
               "parallel_travel")


@pytest.mark.slow
def test_report_view_in_chromium_offline(browser, case_kc: Path, tmp_path):
    """The case study's report (every model, every load case): drawn, animated, offline;
    and the view of a config with errors: what resolved drawn, the errors listed."""
    check_view(browser, (case_kc / "report.html").resolve().as_uri(),
               ["#1f77b4", "#ff7f0e", "#2ca02c", "#9467bd"], "parallel_travel")
    data = read_yaml(AXLE)[0]
    data["springs"]["coil"]["seats"] = ["spring_upper", "nowhere"]
    config = tmp_path / "axle.yaml"
    config.write_text(yaml.safe_dump(data, sort_keys=False))  # the parts' order: colours
    out = tmp_path / "view.html"
    assert CliRunner().invoke(main, ["view", str(config), "--out", str(out)]).exit_code == 1
    browser.open(out.resolve().as_uri())
    browser.wait_for(READY)
    listed = browser.run("document.querySelector('.ekv-errors').textContent")
    assert "1 error in the config" in listed and "hardpoint 'nowhere'" in listed
    img = browser.screenshot(_plot_box(browser))
    assert _colour_pixels(img, "#1f77b4") > 30 and browser.errors == []


@pytest.mark.slow
def test_benchmark_quick_mode(tmp_path):
    """benchmarks/bench_view.py --quick: its JSON has every figure (the browser's when
    Chromium is installed)."""
    import subprocess
    import sys

    out = tmp_path / "bench.json"
    subprocess.run([sys.executable, str(ROOT / "benchmarks" / "bench_view.py"), "--quick",
                    "--out", str(out)], check=True, capture_output=True, timeout=600)
    r = json.loads(out.read_text())
    report = r["report"]
    assert report["bytes"] == report["plotly_js_bytes"] + report["view_data_bytes"] + \
        report["other_bytes"] and report["plotly_js_bytes"] > 1e6
    assert report["frames"] > 10 and report["models"] == ["initial", "initial_kinematic"]
    if chromium_path() is not None:
        load = report["load"]
        assert load["lazy"] and load["load_s"] > 0 and load["view_s"] > 0
        assert load["renderer_cpu_s"] > 0 and load["page_errors"] == []
    assert r["poses"]["with_poses_s"] > 0 and r["poses"]["ratio"] > 0
    assert r["beam_nodes"]["identical_columns"] and r["beam_nodes"]["nodes_recorded"] == 9
    assert r["beam_nodes"]["nodes_recorded_without"] == 0  # ModelOptions(beam_nodes=False)
    assert report["full_bundle"]["plotly_js_bytes"] > report["plotly_js_bytes"]
    assert list(r["view"]) == ["double_wishbone_axle"]


def test_the_figure_is_valid_plotly():
    """Every trace and layout property of a view (with an identification overlay) is one
    plotly knows: the page is built without plotly's validation (it costs a quarter of a
    second), so it is checked here."""
    import plotly.graph_objects as go

    from elastokin.report.view3d import build_view, model_view
    from elastokin.studies.view import load_case_sweeps

    s = load_suspension_with_rig(CORNER, TRAVEL)
    travel = {"parallel_travel": load_case_sweeps(s, "parallel_travel")}
    views = [model_view("initial", s, travel), model_view("identified", s, {})]
    figure, data = build_view(views, case_overlay())
    go.Figure(figure)  # raises on an unknown property
    assert data["order"] == ["initial", "identified"] and len(data["ident"]) == 3
    assert len(data["recipes"]) == len(figure["data"])


def test_the_shipped_plotly_bundle():
    """The plotly.js the view embeds is the vendored gl3d partial bundle as
    scripts/vendor_plotly.py wrote it (size and SHA-256 of its manifest, the version in its
    header), of the same major version as the plotly Python package the figures are validated
    with, and safe inside a script element."""
    import hashlib

    from plotly.offline import get_plotlyjs

    from elastokin.report.view3d import plotly_js

    vendor = ROOT / "elastokin" / "report" / "vendor"
    manifest = json.loads((vendor / "plotly-gl3d.json").read_text())
    raw = (vendor / manifest["file"]).read_bytes()
    assert len(raw) == manifest["bytes"] and hashlib.sha256(raw).hexdigest() == manifest["sha256"]
    text = plotly_js()
    assert f"plotly.js (gl3d - minified) v{manifest['version']}" in text[:200]
    python_js = re.search(r"plotly\.js v(\d+)\.", get_plotlyjs()[:300]).group(1)
    assert manifest["version"].split(".")[0] == python_js
    assert "</script" not in text.lower() and (vendor / "LICENSE-plotly.js.txt").is_file()


def case_overlay():
    from elastokin.identification.geometric import identify
    from elastokin.identification.overlay import identification_overlay

    return identification_overlay(identify(load_suspension(ROOT / "configs" /
                                                           "pseudo_mcpherson.yaml")))


def test_identification_overlay_against_the_pose_fit():
    """The marks drawn (measured, in the vehicle frame through the ground part's pose, and
    fitted) are as far apart as the pose fit says (its RMS residual, in the CMM frame: a
    rigid change of frame keeps distances); the knuckle's dropped mark has no measured
    point; the shifts are the identification's."""
    from elastokin.identification.geometric import identify

    ident = identify(load_suspension(ROOT / "configs" / "pseudo_mcpherson.yaml"))
    o = case_overlay()
    assert len(o.mark_labels) == 4 * len(ident.poses)
    gap = np.linalg.norm(o.measured_mm - o.fitted_mm, axis=1)
    for k, (part, pose) in enumerate(ident.poses.items()):
        mine = gap[4 * k:4 * k + 4]
        assert o.mark_labels[4 * k].startswith(part)
        kept = mine[np.isfinite(mine)]
        np.testing.assert_allclose(np.sqrt(np.mean(kept ** 2)), pose.match.residual_rms_mm,
                                   rtol=1e-9)
    assert np.isnan(gap).sum() == 1 and "knuckle M2" in o.mark_labels[int(np.flatnonzero(
        np.isnan(gap))[0])]
    shifts = np.linalg.norm(o.identified_mm - o.initial_mm, axis=1)
    assert o.factor * shifts.max() <= 60.0 < 2.5 * o.factor * shifts.max()
    assert o.beyond_clearance == tuple(j.exceeds_clearance for j in ident.joints.values())
    assert o.joint_names == tuple(ident.joints) and any(o.beyond_clearance)
