"""Flexible beam parts as a config building block (a part's ``beam:`` section): resolution,
mirroring on an axle (a beam on each side, or one shared beam across the car), connections
at nodes, and every bad input named by its key. No solver but for the assembly check."""

from __future__ import annotations

import copy
from pathlib import Path

import numpy as np
import pytest

from elastokin.config.loading import read_yaml, suspension_from_dict
from elastokin.config.variants import rigid_beams
from elastokin.errors import ConfigError, ModelError

TWIST_BEAM = Path(__file__).resolve().parents[1] / "configs" / "twist_beam_axle.yaml"
MIRROR = np.diag([1.0, -1.0, 1.0])


def config() -> dict:
    return copy.deepcopy(read_yaml(TWIST_BEAM)[0])


def load(data: dict):
    return suspension_from_dict(data, "beam.yaml")


def beam_section(data: dict) -> dict:
    return data["parts"]["cross_beam"]["beam"]


def test_a_shared_beam_is_one_piece_across_the_car():
    s = load(config())
    (b,) = s.beams
    assert b.part == "cross_beam" and not b.rigid
    assert b.node_names == ("beam_end_right", "beam_centre", "beam_end")
    assert np.allclose(b.nodes_mm, [[270.0, -560.0, 25.0], [270.0, 0.0, 25.0],
                                    [270.0, 560.0, 25.0]])
    assert b.length_mm == pytest.approx(1120.0)
    # one straight beam: x along it (to the left), z up, y = z x x rearward; the shear centre
    # 42.13 mm above the node line on both halves
    for R in b.frames:
        assert np.allclose(R, [[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    assert np.allclose(b.shear_centre_mm, [[0.0, 0.0, 42.13]] * 2)
    assert b.section.GJ_Nmm2 == 1.283e9 and b.elements_per_segment == 4
    assert "cross_beam_right" not in s.parts  # declared once


def test_a_beam_on_each_side_is_mirrored():
    """A beam that is not shared: the other side's copy at the mirrored nodes, its section
    axes right-handed again and its shear centre the mirror image of this side's."""
    data = config()
    data["hardpoints"]["beam_inner"] = [270.0, 150.0, 25.0]
    data["hardpoints"]["beam_outer"] = [300.0, 560.0, 40.0]
    beam = beam_section(data)
    beam["nodes"] = ["beam_inner", "beam_end", "beam_outer"]
    beam["section"]["shear_centre_mm"] = [10.0, 42.0]
    data["axle"]["shared"] = []
    data["connections"]["beam_mount"] = {"type": "spherical", "parts": ["body", "cross_beam"],
                                         "at": "beam_inner"}
    s = load(data)
    left, right = s.beams
    assert right.part == "cross_beam_right" and "cross_beam_right" in s.parts
    assert right.node_names == ("beam_inner_right", "beam_end_right", "beam_outer_right")
    assert np.allclose(right.nodes_mm, left.nodes_mm @ MIRROR)
    for RL, RR, eL, eR in zip(left.frames, right.frames, left.shear_centre_mm,
                              right.shear_centre_mm):
        assert np.linalg.det(RR) == pytest.approx(1.0)
        assert np.allclose(RR[:, 0], MIRROR @ RL[:, 0])  # along the mirrored segment
        assert np.allclose(RR[:, 2], MIRROR @ RL[:, 2])
        assert np.allclose(eR, MIRROR @ eL)  # the same physical point, mirrored
    # the kinked beam's segments have their own axes; the offset is (y, z) in them
    R0 = left.frames[0]
    assert np.allclose(left.shear_centre_mm[0], 10.0 * R0[:, 1] + 42.0 * R0[:, 2])


@pytest.mark.parametrize("change, key, words", [
    (lambda d: d["hardpoints"].update(beam_centre=[270.0, 10.0, 25.0]),
     "parts.cross_beam.beam.nodes", "first node on the vehicle centre plane"),
    (lambda d: beam_section(d).update(nodes=["beam_centre", "beam_tip"]),
     "parts.cross_beam.beam.nodes[1]", "hardpoint 'beam_tip' is not defined"),
    (lambda d: beam_section(d).update(nodes=["beam_centre", "beam_centre"]),
     "parts.cross_beam.beam.nodes", "listed twice"),
    (lambda d: beam_section(d)["section"].update(z_axis=[0.0, 1.0, 0.0]),
     "parts.cross_beam.beam.nodes", "section z axis runs along the segment"),
    (lambda d: beam_section(d)["section"].update(GJ_Nmm2=0.0),
     "parts.cross_beam.beam.section.GJ_Nmm2", "greater than 0"),
    (lambda d: beam_section(d).pop("elements_per_segment"),
     "parts.cross_beam.beam.elements_per_segment", "required key is missing"),
    (lambda d: d["connections"]["beam_weld"].update(at="wheel_centre"),
     "connections.beam_weld", "not one of the beam's nodes"),
    (lambda d: d["wheel"].update(part="cross_beam"),
     "wheel.part", "the wheel is carried by a rigid part"),
])
def test_bad_beam_inputs_name_the_key(change, key, words):
    data = config()
    change(data)
    with pytest.raises(ConfigError) as info:
        load(data)
    message = str(info.value)
    assert f"key '{key}'" in message and words in message, message


def test_a_shared_beams_nodes_stay_on_the_config_side():
    data = config()
    data["hardpoints"]["beam_back"] = [270.0, -20.0, 25.0]
    beam_section(data)["nodes"] = ["beam_centre", "beam_end", "beam_back"]
    with pytest.raises(ConfigError, match="'beam_back' is not"):
        load(data)


def test_identification_needs_rigid_parts():
    data = config()
    data["measurements"] = {"parts": {}, "assembly": {"file": "a.csv", "marks": {}}}
    with pytest.raises(ConfigError, match="key 'measurements'.*rigid parts"):
        load(data)
    data = config()
    data["motion"] = {"ground": {"file": "g.csv"}, "marks": {}, "positions": {
        f"p{k}": {"file": f"p{k}.csv"} for k in range(3)}}
    with pytest.raises(ConfigError, match="key 'motion'.*rigid parts"):
        load(data)
    data = config()
    data["kc_test"] = {"folder": "."}
    with pytest.raises(ConfigError, match="stiffness_identification.enabled"):
        load(data)


def test_the_rigid_variant_keeps_the_geometry():
    s = load(config())
    rigid = rigid_beams(s)
    assert [b.rigid for b in rigid.beams] == [True] and not s.beams[0].rigid
    assert np.array_equal(rigid.beams[0].nodes_mm, s.beams[0].nodes_mm)


def test_a_beam_that_can_move_without_deforming_is_refused():
    """The cross beam on ball joints at both ends spins about the line through them: the
    assembly check says so (the solve would be singular)."""
    from elastokin.mbs.design import check_assembly

    data = config()
    data["connections"]["beam_weld"]["type"] = "spherical"
    with pytest.raises(ModelError, match="beam part 'cross_beam' can move without deforming"):
        check_assembly(load(data))
