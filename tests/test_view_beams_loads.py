"""The 3D view's flexible beams and loads: the twist beam drawn through the nodes the model
solved (read back from Exudyn apart from the recording), its band twisting both ways in
opposite travel by the factor the legend states; the body pickups' and contact patches'
arrows at the loads of every frame (against loads.csv in tests/test_loads.py); and both as
the page's script draws them in headless Chromium."""

from __future__ import annotations

import numpy as np
import pytest

from elastokin.config.loading import read_yaml, suspension_from_dict
from elastokin.config.variants import ModelVariant
from elastokin.mbs.design import build_model
from elastokin.physics.beams import mean_rotation, node_line, twist_deg
from elastokin.rig.drives import drives
from elastokin.rig.load_cases import run_drive_sides
from elastokin.rig.scene_motion import frame_steps

from .browser import Browser, chromium_path
from .conftest import ROOT

TWIST_BEAM = ROOT / "configs" / "twist_beam_axle.yaml"
OFF = ("vertical_force", "lateral_force", "longitudinal_force_patch",
       "longitudinal_force_centre", "aligning_torque", "single_wheel_travel",
       "roll_vertical_force", "steering", "static_load", "lateral_force_anti_phase")


@pytest.fixture(scope="module")
def opposite():
    """The twist beam's model and a short opposite travel (+-40 mm in 10 mm steps)."""
    data = read_yaml(TWIST_BEAM)[0]
    data["rig"] = {**{k: None for k in OFF},
                   "parallel_travel": {"rebound_mm": -10, "bump_mm": 10, "step_mm": 10,
                                       "unloading": False},
                   "opposite_travel": {"rebound_mm": -40, "bump_mm": 40, "step_mm": 10,
                                       "unloading": False}}
    s = suspension_from_dict(data, str(TWIST_BEAM))
    model = build_model(ModelVariant(s.label, s))
    drive = next(d for d in drives(s) if d.load_case == "opposite_travel")
    sweeps = run_drive_sides(model, s.label, drive)
    return s, model, sweeps


def _node_line_from_exudyn(model, s) -> np.ndarray:
    """The beam's node-line nodes as Exudyn has them now, found by their reference
    positions (the design node line), not through the model's recording."""
    from elastokin.mbs.exudyn_api import exu

    mbs = model.mbs
    beam = s.beams[0]
    design, _ = node_line(beam.nodes_mm, beam.elements_per_segment)
    ovt, ref = exu.OutputVariableType, exu.ConfigurationType.Reference
    nodes = [n for n in range(mbs.systemData.NumberOfNodes())
             if mbs.GetNode(n)["name"].startswith(f"beam:{beam.part}:")]
    at = np.array([mbs.GetNodeOutput(n, ovt.Position, configuration=ref) for n in nodes])
    found = [nodes[int(np.argmin(np.linalg.norm(at - x, axis=1)))] for x in design]
    assert np.allclose(at[[nodes.index(n) for n in found]], design, atol=1e-9)
    return np.array([mbs.GetNodeOutput(n, ovt.Position) for n in found])


def test_the_beam_drawn_is_the_models(opposite):
    """The page's beam at the last frame (the last step) is where Exudyn has the nodes
    after the solve; the band twists one way at one end and the other way at the other,
    by the stated factor times the nodes' own twist."""
    from elastokin.report.view3d import build_view, model_view

    s, model, sweeps = opposite
    view = model_view(s.label, s, {"opposite_travel": sweeps})
    _, data = build_view([view])
    case = data["models"][s.label]["data"]["opposite_travel"]
    k = len(case["steps"])
    assert case["steps"][-1] == sweeps[0].steps - 1
    line = np.array(case["beam"]["cross_beam"]["line"]).reshape(k, -1, 3)
    np.testing.assert_allclose(line[-1], _node_line_from_exudyn(model, s), atol=0.006)
    factor = data["twist_factor"]
    R = sweeps[0].poses.node_rotation["cross_beam"]
    assert factor == 5.0 and 3.0 < twist_deg(R).max() * factor <= 30.0
    # the band's turn about the beam (y) from its design direction, at each end
    edge = np.array(case["beam"]["cross_beam"]["edge"]).reshape(k, -1, 3)
    band = edge - line
    turn = np.degrees(np.arctan2(band[..., 0], band[..., 2]))  # from z towards x
    top = int(np.argmax(np.abs(sweeps[0].columns["wheel_travel_mm"][case["steps"]])))
    ends = turn[top, [0, -1]]
    assert ends[0] * ends[1] < 0 and np.all(np.abs(ends) > 5.0)
    rel = np.swapaxes(mean_rotation(R[case["steps"][top]]), 0, 1) @ R[case["steps"][top]]
    true = np.degrees(np.arctan2(rel[:, 0, 2], rel[:, 2, 2]))[[0, -1]]
    np.testing.assert_allclose(ends, factor * true, rtol=0.05)  # small angles: linear
    assert np.abs(line[top] - line[0]).max() > 10.0  # the beam moves with the arms


def test_frames_keep_the_pickup_peaks():
    branch = np.array(["stroke"] * 200)
    steps = frame_steps(branch, 21, keep=[77, 131])
    assert {0, 77, 131, 199} <= set(steps.tolist())


def test_the_arrows_are_the_pickup_loads(opposite):
    """Each pickup's arrow (force N at every frame) is the load the ground receives at that
    step; every pickup's worst case is its largest force over the frames, which hold the
    step where it peaks."""
    from elastokin.physics.loads import ground_loads
    from elastokin.report.view3d import build_view, model_view
    from elastokin.rig.loads import PICKUP_KINDS, pickup_loads

    s, _, sweeps = opposite
    view = model_view(s.label, s, {"opposite_travel": sweeps})
    _, data = build_view([view])
    model = data["models"][s.label]
    case = model["data"]["opposite_travel"]
    table = sweeps[0].loads
    expected = ground_loads(table, table.ground, PICKUP_KINDS)
    assert set(case["loads"]["pickup"]) == set(expected) == set(model["pickups"])
    for name, v in expected.items():
        drawn = np.array(case["loads"]["pickup"][name]).reshape(-1, 3)
        np.testing.assert_allclose(drawn, v[case["steps"], 0], atol=0.051)
        np.testing.assert_allclose(model["pickups"][name], v[0, 2], atol=0.006)
    summary = pickup_loads(sweeps)
    for w in model["worst"]:
        assert (w["case"], w["step"]) == (summary[w["pickup"]]["worst"]["load_case"],
                                          summary[w["pickup"]]["worst"]["step"])
    assert [w["force_N"] for w in model["worst"]] == sorted(
        [w["force_N"] for w in model["worst"]], reverse=True)
    lo, hi = view.scene.extent_mm()
    drawn = data["load_mm_per_N"] * max(w["force_N"] for w in model["worst"])
    assert 0.2 / 2.5 < drawn / np.max(hi - lo) <= 0.2  # a round scale: 1, 2, 5 x 10^k


READY = "document.getElementById('ekv-plot').getAttribute('data-ready') === '1'"
TRACES = """(function(){var gd=document.getElementById('ekv-plot'), V=gd.elastokinView.V, out={};
V.recipes.forEach(function(r,k){if(r&&(r.kind==='beam'||r.kind==='arrows')){
out[r.kind+':'+(r.what)]={x:gd.data[k].x,y:gd.data[k].y,z:gd.data[k].z};}});return out;})()"""


def test_the_page_draws_the_beam_and_the_arrows(opposite, tmp_path):
    """In headless Chromium (network cut): the beam's line at the slider's frames is the
    page's data and moves between them; a pickup's arrow runs from its point along the
    force times the stated scale; the worst-case picker goes to the step it names."""
    if chromium_path() is None:
        pytest.skip("headless Chromium is not installed (apt-get install chromium)")
    from elastokin.report.view3d import build_view, model_view, write_view_page

    s, _, sweeps = opposite
    view = model_view(s.label, s, {"opposite_travel": sweeps})
    view.frames = view.frames[1:] + view.frames[:1]  # the load case first
    _, data = build_view([view])
    case = data["models"][s.label]["data"]["opposite_travel"]
    k = len(case["steps"])
    page = write_view_page(tmp_path / "view.html", "twist beam", [view], [], [])
    with Browser(1100, 800, offline=True) as b:
        b.open(page.resolve().as_uri())
        b.wait_for(READY)
        drawn = []
        for frame in (0, k - 1):
            b.run(f"(function(){{var s=document.getElementById('ekv-slider');s.value='{frame}';"
                  "s.dispatchEvent(new Event('input'));return 1;})()")
            t = b.run(TRACES)
            line = np.array([t["beam:line"][a] for a in "xyz"], float).T
            expected = np.array(case["beam"]["cross_beam"]["line"]).reshape(k, -1, 3)[frame]
            np.testing.assert_allclose(line, expected, atol=1e-9)
            drawn.append(line)
            arrows = t["arrows:pickup"]
            recipe = next(r for r in data["recipes"] if r and r.get("what") == "pickup")
            name = recipe["names"][0]  # its first arrow
            base = np.array([arrows[a][0] for a in "xyz"])
            tip = np.array([arrows[a][1] for a in "xyz"])
            force = np.array(case["loads"]["pickup"][name]).reshape(k, 3)[frame]
            np.testing.assert_allclose(base, data["models"][s.label]["pickups"][name])
            np.testing.assert_allclose(tip - base, force * data["load_mm_per_N"], atol=1e-9)
        assert np.abs(drawn[1] - drawn[0]).max() > 10.0
        worst = data["models"][s.label]["worst"][0]
        b.run("(function(){var s=document.getElementById('ekv-worst');s.value='0';"
              "s.dispatchEvent(new Event('change'));return 1;})()")
        assert b.run("document.getElementById('ekv-slider').value") == str(worst["frame"])
        assert b.run("document.getElementById('ekv-case').value") == worst["case"]
        assert b.errors == []
