"""The roll motion of an axle at the velocity level (elastokin.physics.roll_motion), on a
hand-made skeleton: a tube guided by a planar joint (normal x) and a Panhard rod (a distance)
rolls about the point where the rod's line crosses the centre plane; held rigidly it cannot
roll, and without the rod its motion is not fixed by the two contact points: NaN, with the
reason."""

import numpy as np
import pytest

from elastokin.physics.instant_centres import kinematic_roll_centre
from elastokin.physics.joints import CONSTRAINED
from elastokin.physics.pose import frame_from_z
from elastokin.physics.roll_motion import roll_motion
from elastokin.physics.skeleton import SkeletonElement

ORIGIN = np.zeros(3)
GUIDE = SkeletonElement("joint", ("body", "axle"), (ORIGIN, ORIGIN),
                        frame_from_z(np.array([1.0, 0.0, 0.0])), CONSTRAINED["planar"])
#: the rod from the body (left) to the tube (right), 80 mm above the wheel centres
ROD = SkeletonElement("distance", ("body", "axle"), (np.array([-100.0, 500.0, 80.0]),
                                                    np.array([-100.0, -500.0, 80.0])))
FIXED = SkeletonElement("joint", ("body", "axle"), (ORIGIN, ORIGIN), np.eye(3),
                        CONSTRAINED["fixed"])
CONTACT = {"left": np.array([[0.0, 750.0, -300.0]]), "right": np.array([[0.0, -750.0, -300.0]])}


def motion(elements):
    return roll_motion("body", elements, {"axle": np.eye(3)[None]}, {"axle": ORIGIN[None]},
                       {"axle": ORIGIN}, {side: ("axle", p) for side, p in CONTACT.items()},
                       np.array([0.0, 0.0, 1.0]))


def test_the_tube_rolls_about_the_rods_crossing_of_the_centre_plane():
    m = motion([GUIDE, ROD])
    assert m.reason is None
    v = m.contact_velocity
    np.testing.assert_allclose([v["left"][0, 2], v["right"][0, 2]], [1.0, -1.0], atol=1e-12)
    rc = kinematic_roll_centre(CONTACT["left"], v["left"], CONTACT["right"], v["right"])
    assert rc.height_mm[0] == pytest.approx(380.0, abs=1e-9)  # 80 mm above the centres
    assert rc.lateral_mm[0] == pytest.approx(0.0, abs=1e-9)


@pytest.mark.parametrize("elements, reason", [
    ([FIXED], "do not let the axle roll"),
    ([GUIDE], "more than the two motions")], ids=["held", "no_rod"])
def test_no_roll_motion_is_nan_with_its_reason(elements, reason):
    m = motion(elements)
    assert reason in m.reason
    assert np.isnan(m.contact_velocity["left"]).all()
