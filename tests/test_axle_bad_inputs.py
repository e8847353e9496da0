"""Bad axle input ends in one clear line naming the key (issue 18, correctness 7): a mirror
plane that cuts a part, a shared part declared on both sides, an anti-roll bar whose drop link
does not reach the wheel, a steering input beyond the rack's travel. On the shipped double
wishbone axle and the steering trapezoid of tests/data; one case through ``elastokin kc``."""

import pytest
import yaml
from click.testing import CliRunner

from elastokin.cli import main
from elastokin.errors import ConfigError
from elastokin.rig.drives import steering_drive

from .axle_rigs import config, suspension


def _error(data: dict) -> str:
    with pytest.raises(ConfigError) as info:
        suspension(data, "axle.yaml")
    message = str(info.value)
    assert "\n" not in message and message.startswith("axle.yaml: key '")
    return message


def _edit(path: str, value):
    def edit(d):
        *keys, last = path.split(".")
        for k in keys:
            d = d.setdefault(k, {})
        d[last] = value
    return edit


def _drop_link_to(part: str):
    return _edit("connections.arb_drop_link.parts", ["arb", part])


def _no_drop_link(d):
    del d["connections"]["arb_drop_link"]


CASES = [
    # the centre plane cuts a part: a lower-arm pivot, the bar's mount beyond y = 0
    ("arm_across_centre_plane", _edit("hardpoints.lca_pivot", [0.0, -5.0, 0.0]),
     "connections.lca_bushing", ["cuts part 'lower_arm'", "axle.shared"]),
    ("bar_mount_across_centre_plane", _edit("hardpoints.arb_mount", [-330.0, -20.0, 120.0]),
     "connections.arb_bushing", ["cuts part 'arb'", "y = -20 mm"]),
    # a shared part declared on both sides: its other-side copy as a part, a point of its
    # connection moved on the other side, listed twice
    ("shared_part_copy_declared", _edit("parts.rack_right", {}), "parts.rack_right",
     ["shared part", "declared once"]),
    ("shared_point_on_other_side",
     _edit("axle.other_side", {"hardpoints": {"rack_centre": [-250.0, 0.0, 60.0]}}),
     "axle.other_side.hardpoints.rack_centre", ["declared once", "other side"]),
    ("shared_listed_twice", _edit("axle.shared", ["rack", "rack"]), "axle.shared[1]",
     ["listed twice"]),
    ("name_of_a_mirrored_copy", _edit("parts.arb_right", {}), "parts.arb_right",
     ["mirrored copy of part 'arb'", "rename"]),
    # the bar's drop link does not reach the wheel
    ("bar_without_drop_link", _no_drop_link, "axle.anti_roll_bar.part",
     ["no drop link", "lower_arm", "'arb_bushing' to body"]),
    ("drop_link_to_the_body", _drop_link_to("body"), "axle.anti_roll_bar.part",
     ["no drop link", "'arb_drop_link' to body"]),
    ("drop_link_to_the_shared_rack", _drop_link_to("rack"), "axle.anti_roll_bar.part",
     ["no drop link", "'arb_drop_link' to rack"]),
    # an other-side stiffness override whose curve is not a law
    ("other_side_curve_not_increasing",
     _edit("axle.other_side", {"connections": {"lca_bushing": {"stiffness": {
         "x": {"deflection": [-1.0, 0.0, 1.0], "load": [0.0, 0.0, 1.0]}}}}}),
     "axle.other_side.connections.lca_bushing.stiffness.x", ["increasing"]),
]


#: on the solid axle with a Panhard rod: items among the shared tube and the ground that
#: exist on both sides (axle.both_sides)
SOLID_AXLE_CASES = [
    ("both_sides_unknown", _edit("axle.both_sides", ["coil", "coil_spring"]),
     "axle.both_sides[1]", ["no connection, spring or stop 'coil_spring'"]),
    ("both_sides_twice", _edit("axle.both_sides", ["coil", "coil"]), "axle.both_sides[1]",
     ["listed twice"]),
    ("both_sides_corner_item", _edit("axle.both_sides", ["coil", "arb_bearing"]),
     "axle.both_sides[1]", ["corner part 'arb'", "both sides already"]),
    ("both_sides_on_centre_plane", _edit("axle.both_sides", ["coil", "axle_guide"]),
     "connections.axle_guide", ["axle.both_sides", "y = 0 mm", "left side"]),
]


@pytest.mark.parametrize(
    "name, edit, key, words",
    [("double_wishbone_axle.yaml", *c[1:]) for c in CASES]
    + [("solid_axle_panhard.yaml", *c[1:]) for c in SOLID_AXLE_CASES],
    ids=[c[0] for c in CASES + SOLID_AXLE_CASES])
def test_bad_axle_config(name, edit, key, words):
    d = config(name)
    edit(d)
    message = _error(d)
    assert message.startswith(f"axle.yaml: key '{key}':"), message
    for word in words:
        assert word in message, message


def unbalanced_trapezoid(travel_mm: float) -> dict:
    """The steering trapezoid with its rack held off centre (a design that is not balanced:
    the spring's preload is given)."""
    d = config("steering_trapezoid.yaml")
    d["design"] = {"wheel_load_N": 4000}
    d["springs"]["coil"]["preload_N"] = 4000.0
    d["connections"]["steering"]["travel_mm"] = travel_mm
    return d


def test_steering_amplitude_beyond_the_rack_travel():
    d = config("double_wishbone_axle.yaml")
    d["rig"]["steering"] = {"amplitude_deg": 700.0}
    s = suspension(d, "axle.yaml")
    with pytest.raises(ConfigError, match=r"^axle\.yaml: key 'rig\.steering\.amplitude_deg': "
                       r"700 deg takes the rack beyond its travel limit \(axle\.steering\."
                       r"limit_mm 87 mm: 626\.4 deg"):
        steering_drive(s, s.rig.steering)


def test_steering_from_a_rack_held_off_centre_stays_within_its_travel():
    """Held at 40 mm of its 60 mm travel, the rack has 20 mm of room each way (the pinion's
    sense may mirror the sweep): lock to lock is 20 mm, and 30 mm is refused."""
    s = suspension(unbalanced_trapezoid(40.0), "axle.yaml")
    drive = steering_drive(s, s.rig.steering)
    assert drive.rack_travel_mm.min() == pytest.approx(20.0)
    assert drive.rack_travel_mm.max() == pytest.approx(60.0)
    assert abs(drive.inputs).max() == pytest.approx(20.0 / 50.0 * 360.0)
    spec = s.rig.steering.model_copy(update={"amplitude_deg": 30.0 / 50.0 * 360.0})
    with pytest.raises(ConfigError, match=r"^axle\.yaml: key 'rig\.steering\.amplitude_deg': "
                       r"216 deg .*limit_mm 60 mm, the rack held at 40 mm: 144 deg"):
        steering_drive(s, spec)


def test_rack_held_beyond_its_travel():
    message = _error(unbalanced_trapezoid(70.0))
    assert message.startswith("axle.yaml: key 'connections.steering.travel_mm': 70 mm is "
                              "beyond the rack's travel limit axle.steering.limit_mm 60")


def test_one_line_through_the_command(tmp_path):
    d = config("double_wishbone_axle.yaml")
    _no_drop_link(d)
    path = tmp_path / "axle.yaml"
    path.write_text(yaml.safe_dump(d, sort_keys=False))
    result = CliRunner().invoke(main, ["kc", "--config", str(path), "--out",
                                       str(tmp_path / "res"), "--quiet"])
    assert result.exit_code == 1
    lines = result.output.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("elastokin: error: ")
    assert "key 'axle.anti_roll_bar.part'" in lines[0]
    assert not (tmp_path / "res").exists()
