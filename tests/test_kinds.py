"""The shipped axle kinds checked without trusting the model (issue 25): each result of the
solver against an independent solve written here (scipy, plain numpy).

- multi-link: toe and camber over travel from a loop-closure solve of the upright's pose (the
  five link lengths of the kinematic model and the wheel-centre height), 1e-6 deg;
- the HMMWV's rear double wishbone (tie rods to the body): the same loop closure on its arms'
  four distances and the tie rod, 1e-6 deg; its kinematic roll centre against the knuckle's
  velocity solved from the arms' pivot axes and the tie rod (the arm-line construction in
  3D), 0.01 mm;
- semi-trailing arm: the arm turns about its fixed pivot axis: toe and camber over travel from
  that one rotation, 1e-9 deg;
- solid axle with a Panhard rod: the kinematic roll centre where the rod's line crosses the
  plane midway between the contact points (the centre plane at design), every travel step
  against an independent pose solve of the axle, 0.1 mm; with a Watt's linkage: on the line
  through the drawbar's ball joint and the Watt's centre pivot, 0.1 mm;
- the resolved blocks: one shared part carrying both wheels, items on both sides.

Toe (toe-in +) and camber (top outboard +) of the left wheel from its outboard spin axis s in
the ISO frame: toe = atan2(s_x, s_y), camber = -asin(s_z) (ADAMS/Car's camber angle).
"""

from __future__ import annotations

import copy

import numpy as np
import pytest
from scipy.optimize import brentq, least_squares
from scipy.spatial.transform import Rotation

from elastokin.config.variants import kinematic
from elastokin.mbs.design import build_model
from elastokin.rig.load_cases import parallel_travel

from .axle_rigs import config, rig, suspension

#: a coarse parallel travel (the kinds' own ranges are wider; these keep the tests quick)
TRAVEL = {"rebound_mm": -60, "bump_mm": 60, "step_mm": 10}


def kinematic_travel(name: str, travel: dict = TRAVEL, newton_tolerance: float | None = None):
    """(the config mapping, its kinematic model's parallel-travel sweep of the left wheel),
    optionally with a tighter Newton tolerance (relative; the config's ``solver``)."""
    d = config(name)
    d["rig"] = rig(parallel_travel=travel)
    if newton_tolerance is not None:
        d["solver"]["newton_tolerance"] = newton_tolerance
    s = kinematic(suspension(d, name))
    return d, parallel_travel(build_model(s), "kinematic")


def point(d: dict, name: str) -> np.ndarray:
    return np.asarray(d["hardpoints"][name], float)


def toe_camber_deg(spin: np.ndarray) -> tuple[float, float]:
    """Of the left wheel (ISO frame), from its outboard spin axis."""
    return float(np.degrees(np.arctan2(spin[0], spin[1]))), \
        float(-np.degrees(np.arcsin(spin[2])))


def wheel_centre(sweep, k: int) -> np.ndarray:
    return np.array([sweep.columns[f"wheel_centre_{a}_mm"][k] for a in "xyz"])


# ------------------------------------------------------------------------- multi-link
#: (chassis point, upright point) of each of the five distances that hold the upright: the
#: upper A-arm's two (its revolute axis through both chassis points), the lateral, trailing
#: and toe links
MULTILINK_LINKS = [("uca_front", "uca_outer"), ("uca_rear", "uca_outer"),
                   ("lateral_inner", "lateral_outer"), ("trailing_front", "trailing_rear"),
                   ("toe_link_inner", "toe_link_outer")]


def upright_pose(d: dict, z_mm: float, start: np.ndarray,
                 links: list[tuple[str, str]] = MULTILINK_LINKS) -> np.ndarray:
    """The upright's pose (rotation vector, rad; wheel-centre displacement, mm) at which the
    five link lengths (``links``: chassis point, upright point) are those of the design and
    the wheel centre is at height ``z_mm``."""
    c0 = point(d, "wheel_centre")
    links = [(point(d, a), point(d, b) - c0, np.linalg.norm(point(d, b) - point(d, a)))
             for a, b in links]

    def residual(x):
        R = Rotation.from_rotvec(x[:3]).as_matrix()
        out = [np.linalg.norm(c0 + x[3:] + R @ local - fixed) - length
               for fixed, local, length in links]
        return np.array(out + [c0[2] + x[5] - z_mm])

    fit = least_squares(residual, start, method="lm", xtol=1e-15, ftol=1e-15, gtol=1e-15)
    assert np.max(np.abs(fit.fun)) < 1e-9
    return fit.x


#: the same five distances on a double wishbone whose tie rod goes to the body (the HMMWV's
#: rear): each arm's two (its revolute axis through both chassis points) and the tie rod
DOUBLE_WISHBONE_LINKS = [("lca_front", "lca_outer"), ("lca_rear", "lca_outer"),
                         ("uca_front", "uca_outer"), ("uca_rear", "uca_outer"),
                         ("tierod_inner", "tierod_outer")]


@pytest.mark.parametrize("name, links", [
    ("multilink_axle.yaml", MULTILINK_LINKS),
    ("double_wishbone_rear_axle.yaml", DOUBLE_WISHBONE_LINKS)],
    ids=["multilink", "double_wishbone_rear"])
def test_toe_and_camber_from_a_loop_closure(name, links):
    d, sweep = kinematic_travel(name)
    pose = np.zeros(6)
    toe, camber = [], []
    for k in range(sweep.steps):
        pose = upright_pose(d, wheel_centre(sweep, k)[2], pose, links)
        spin = Rotation.from_rotvec(pose[:3]).as_matrix() @ np.array([0.0, 1.0, 0.0])
        t, c = toe_camber_deg(spin)
        toe.append(t)
        camber.append(c)
    travel = sweep.columns["wheel_travel_mm"]
    assert np.ptp(travel) > 100.0 and np.ptp(toe) > 0.1 and np.ptp(camber) > 1.0  # it moves
    np.testing.assert_allclose(sweep.columns["toe_deg"], toe, rtol=0, atol=1e-6)
    np.testing.assert_allclose(sweep.columns["camber_deg"], camber, rtol=0, atol=1e-6)


def cross_matrix(r: np.ndarray) -> np.ndarray:
    """The matrix of ``r x .``."""
    return np.array([[0.0, -r[2], r[1]], [r[2], 0.0, -r[0]], [-r[1], r[0], 0.0]])


def test_double_wishbone_rear_roll_centre_from_the_knuckles_velocity():
    """The HMMWV's rear (ideal joints): the kinematic roll centre against the arm-line
    construction in 3D. Its upper arm's axis is 0.8 deg off the x axis, so the planar
    construction of tests/test_axle_roll_centre.py is not exact (its front-view arm lines put
    the roll centre at 398.8 mm, 7.7 mm low); here the knuckle's velocity at design is solved
    from the hardpoints: each ball joint moves as its arm turns about the pivot axis through
    its chassis points, the tie rod keeps its length, the wheel centre rises at unit rate (8
    linear equations: the knuckle's 6, the arms' 2 rates). The contact point's front-view
    velocity then gives the line to the centre plane. 0.01 mm: the model's roll centre is a
    central difference along its 1 mm steps (measured 1.2e-4 mm)."""
    d, sweep = kinematic_travel("double_wishbone_rear_axle.yaml",
                                {"rebound_mm": -4, "bump_mm": 4, "step_mm": 1})
    c = point(d, "wheel_centre")
    A, b = np.zeros((8, 8)), np.zeros(8)  # unknowns: w (rad/mm), v_c (mm/mm), arm rates
    for row, (front, rear, ball) in enumerate([("lca_front", "lca_rear", "lca_outer"),
                                               ("uca_front", "uca_rear", "uca_outer")]):
        axis = point(d, front) - point(d, rear)
        axis /= np.linalg.norm(axis)
        rows = slice(3 * row, 3 * row + 3)
        A[rows, :3] = -cross_matrix(point(d, ball) - c)  # w x (B - c)
        A[rows, 3:6] = np.eye(3)
        A[rows, 6 + row] = -np.cross(axis, point(d, ball) - point(d, rear))
    tie_rod = point(d, "tierod_outer") - point(d, "tierod_inner")
    A[6, :3] = -tie_rod @ cross_matrix(point(d, "tierod_outer") - c)
    A[6, 3:6] = tie_rod
    A[7, 5], b[7] = 1.0, 1.0
    x = np.linalg.solve(A, b)
    arm = np.array([0.0, 0.0, -d["wheel"]["loaded_radius_mm"]])  # wheel centre -> contact
    v = x[3:6] + np.cross(x[:3], arm)
    hand = (c + arm)[1] * v[1] / v[2]  # the line normal to (v_y, v_z) meets y = 0
    k = np.flatnonzero((sweep.columns["pad_z_mm"] == 0.0)
                       & (sweep.columns["branch"] == "stroke"))[0]
    assert sweep.columns["roll_centre_height_mm"][k] == pytest.approx(hand, abs=0.01)
    assert sweep.columns["roll_centre_lateral_mm"][k] == pytest.approx(0.0, abs=1e-6)


# ------------------------------------------------------------------------- semi-trailing arm
def test_semi_trailing_arm_turns_about_its_pivot_axis():
    """At each step the one rotation about the pivot axis (arm_chassis_inner ->
    arm_chassis_outer) that puts the wheel centre at the model's height gives the model's
    toe and camber (1e-9 deg) and the wheel centre's other coordinates (1e-8 mm). The Newton
    tolerance is tightened from the config's 1e-8 to 1e-10 (relative): at 1e-8 the joints are
    met to 2e-7 mm and toe agrees to 1.6e-8 deg; at 1e-10 to 1.5e-9 mm and 1.1e-10 deg."""
    d, sweep = kinematic_travel("semi_trailing_arm_axle.yaml", newton_tolerance=1e-10)
    inner, outer = point(d, "arm_chassis_inner"), point(d, "arm_chassis_outer")
    axis = (outer - inner) / np.linalg.norm(outer - inner)
    c0 = point(d, "wheel_centre")

    def turned(theta, p):
        return inner + Rotation.from_rotvec(theta * axis).apply(p - inner)

    for k in range(sweep.steps):
        c = wheel_centre(sweep, k)
        theta = brentq(lambda t, z=c[2]: turned(t, c0)[2] - z, -0.5, 0.5, xtol=1e-15,
                       rtol=1e-15)
        np.testing.assert_allclose(turned(theta, c0), c, rtol=0, atol=1e-8)
        spin = Rotation.from_rotvec(theta * axis).apply([0.0, 1.0, 0.0])
        toe, camber = toe_camber_deg(spin)
        assert sweep.columns["toe_deg"][k] == pytest.approx(toe, abs=1e-9)
        assert sweep.columns["camber_deg"][k] == pytest.approx(camber, abs=1e-9)
    assert np.ptp(sweep.columns["toe_deg"]) > 1.0  # the inclined axis steers the wheel


# ------------------------------------------------------------------------- solid axles
def panhard_pose(d: dict, pad_mm: float, start: np.ndarray) -> np.ndarray:
    """(roll about x, rad; lateral and vertical shift, mm) of the planar-guided axle with both
    contact points ``pad_mm`` above their design height and the Panhard rod's length kept."""
    r = d["wheel"]["loaded_radius_mm"]
    patch = [point(d, "wheel_centre") - [0.0, 0.0, r]]
    patch.append(patch[0] * [1.0, -1.0, 1.0])
    chassis, axle_end = point(d, "panhard_chassis"), point(d, "panhard_axle")
    length = np.linalg.norm(axle_end - chassis)

    def residual(x):
        R = Rotation.from_rotvec([x[0], 0.0, 0.0])
        moved = [R.apply(p) + [0.0, x[1], x[2]] for p in (*patch, axle_end)]
        return [moved[0][2] - patch[0][2] - pad_mm, moved[1][2] - patch[1][2] - pad_mm,
                np.linalg.norm(moved[2] - chassis) - length]

    fit = least_squares(residual, start, method="lm", xtol=1e-15, ftol=1e-15, gtol=1e-15)
    assert np.max(np.abs(fit.fun)) < 1e-9
    return fit.x


def test_panhard_roll_centre_where_the_rod_crosses_the_axle_centre_plane():
    """Along parallel travel: the rod's line (chassis end fixed, axle end moved with the axle
    solved here) crosses the plane midway between the contact points at the roll centre; at
    design that is the vehicle centre plane, at the wheel centres' height (the rod is level
    there: 347 mm above the ground)."""
    d, sweep = kinematic_travel("solid_axle_panhard.yaml")
    r = d["wheel"]["loaded_radius_mm"]
    patch = point(d, "wheel_centre") - [0.0, 0.0, r]
    chassis, axle_end = point(d, "panhard_chassis"), point(d, "panhard_axle")
    pose = np.zeros(3)
    for k in range(sweep.steps):
        pose = panhard_pose(d, sweep.columns["pad_z_mm"][k], pose)
        R = Rotation.from_rotvec([pose[0], 0.0, 0.0])
        shift = np.array([0.0, pose[1], pose[2]])
        ends = [chassis, R.apply(axle_end) + shift]
        patches = [R.apply(p) + shift for p in (patch, patch * [1.0, -1.0, 1.0])]
        mid_y = 0.5 * (patches[0][1] + patches[1][1])
        t = (mid_y - ends[0][1]) / (ends[1][1] - ends[0][1])
        crossing = ends[0] + t * (ends[1] - ends[0])
        height = crossing[2] - 0.5 * (patches[0][2] + patches[1][2])
        assert sweep.columns["roll_centre_height_mm"][k] == pytest.approx(height, abs=0.1)
        assert sweep.columns["roll_centre_lateral_mm"][k] == pytest.approx(mid_y, abs=0.1)
    at_design = np.flatnonzero((sweep.columns["pad_z_mm"] == 0.0)
                               & (sweep.columns["branch"] == "stroke"))[0]
    assert sweep.columns["roll_centre_height_mm"][at_design] == pytest.approx(r, abs=0.1)
    assert np.ptp(sweep.columns["roll_centre_lateral_mm"]) > 1.0  # the rod's arc shifts it


def test_watt_roll_centre_on_the_drawbar_to_pivot_line():
    """At design the tube rolls about the line through the drawbar's ball joint and the
    Watt's centre pivot (the two points of the tube held sideways); the roll centre is where
    that line crosses the contact points' transverse plane."""
    d, sweep = kinematic_travel("solid_axle_watt.yaml")
    ball, pivot = point(d, "drawbar_front"), point(d, "watt_pivot")
    patch = point(d, "wheel_centre") - [0.0, 0.0, d["wheel"]["loaded_radius_mm"]]
    t = (patch[0] - ball[0]) / (pivot[0] - ball[0])
    hand = ball[2] + t * (pivot[2] - ball[2]) - patch[2]
    assert hand == pytest.approx(347.0 + 100.0 + 50.0 * 1905.0 / 2105.0)
    k = np.flatnonzero((sweep.columns["pad_z_mm"] == 0.0)
                       & (sweep.columns["branch"] == "stroke"))[0]
    assert sweep.columns["roll_centre_height_mm"][k] == pytest.approx(hand, abs=0.1)
    assert sweep.columns["roll_centre_lateral_mm"][k] == pytest.approx(0.0, abs=0.1)
    # the Watt's linkage keeps the tube from shifting sideways in heave: 0.03 mm over +-60 mm
    # (a Panhard rod of the same span, 1028 mm, would shift it 60^2 / 2056 = 1.75 mm)
    assert np.max(np.abs(sweep.columns["wheel_centre_lateral_mm"])) < 0.1


def test_a_shared_part_carries_both_wheels_and_items_on_both_sides():
    d = config("solid_axle_panhard.yaml")
    s = suspension(d, "panhard.yaml")
    assert {w.part for w in s.wheels.values()} == {"axle"}
    np.testing.assert_array_equal(s.wheels["right"].centre_mm, [0.0, -732.5, 0.0])
    springs = {sp.name: sp for sp in s.springs}
    assert set(springs) == {"coil", "coil_right"}
    assert springs["coil_right"].parts == ("body", "axle")
    np.testing.assert_array_equal(springs["coil_right"].seats_mm[0], [0.0, -514.2, 347.6])
    assert {st.name for st in s.stops} == {"bump_stop", "bump_stop_right", "rebound_stop",
                                           "rebound_stop_right"}
    # kept once: the guide and the Panhard rod's bushings; mirrored: the bar halves' joints
    assert [b.name for b in s.bushings] == ["panhard_chassis_bushing", "panhard_axle_bushing"]
    assert sorted(j.name for j in s.joints) == ["arb_bearing", "arb_bearing_right",
                                                "arb_slider", "arb_slider_right",
                                                "axle_guide"]
    assert s.axle.balance_springs == ("coil", "coil_right")
    # the wheels move together (summary.json axle.dependent, the report's make-up); not on
    # an independent axle, whose wheels the held steering rack and the anti-roll bar join
    from elastokin.report.files import axle_data
    from elastokin.report.html.axle import make_up_rows

    assert axle_data(s)["dependent"]
    assert ["wheel motion", "independent"] not in make_up_rows(axle_data(s))
    dw = suspension(config("double_wishbone_axle.yaml"), "dw.yaml")
    assert not axle_data(dw)["dependent"]
    assert ["wheel motion", "independent"] in make_up_rows(axle_data(dw))


# ------------------------------------------------------------------------- compliance
#: the bushed kinds, and the push-rod axle (every joint ideal: its compliance is its springs'
#: through the rockers, the heave spring coupling the wheels)
BUSHED = ["multilink_axle.yaml", "semi_trailing_arm_axle.yaml", "solid_axle_panhard.yaml",
          "double_wishbone_rear_axle.yaml", "fsae_pushrod_axle.yaml"]


def force_based_roll_centre_mm(C: np.ndarray, d: dict) -> float:
    """ADAMS/Car's roll centre height (SVCROL) from a 12x12 compliance (ISO frame, left wheel
    first; mm and deg per N and N*mm): unit vertical forces, +1 at the left contact point and
    -1 at the right one (each a force and a moment at its wheel centre); the lines through the
    contact points normal to their (y, z) displacements meet at the roll centre; its height
    above the contact points."""
    centre = point(d, "wheel_centre")
    r = np.array([0.0, 0.0, -d["wheel"]["loaded_radius_mm"]])  # wheel centre -> contact point
    centres = [centre, centre * [1.0, -1.0, 1.0]]
    load = np.zeros(12)
    for i, sign in enumerate((1.0, -1.0)):
        f = sign * np.array([0.0, 0.0, 1.0])
        load[6 * i:6 * i + 6] = np.r_[f, np.cross(r, f)]
    u = C @ load
    rows, rhs = [], []
    for i in range(2):
        move = u[6 * i:6 * i + 3] + np.cross(np.radians(u[6 * i + 3:6 * i + 6]), r)
        p = centres[i] + r
        rows.append(move[1:])  # the line {q: move . (q - p) = 0} in the (y, z) plane
        rhs.append(move[1:] @ p[1:])
    y, z = np.linalg.solve(np.array(rows), np.array(rhs))
    return float(z - (centre + r)[2])


def reciprocity_error(C: np.ndarray) -> float:
    """The largest |C_ij - C_ji| relative to sqrt(C_ii C_jj), rotations in rad (pairs of a
    rigid direction, whose diagonal is ~0, left out)."""
    Cr = C.copy()
    Cr[[3, 4, 5, 9, 10, 11], :] = np.radians(Cr[[3, 4, 5, 9, 10, 11], :])
    scale = np.sqrt(np.outer(np.abs(np.diag(Cr)), np.abs(np.diag(Cr))))
    return float(np.max(np.divide(np.abs(Cr - Cr.T), scale, out=np.zeros_like(scale),
                                  where=scale > 1e-12 * scale.max())))


@pytest.mark.parametrize("name", BUSHED)
def test_compliance_is_reciprocal_and_the_force_based_roll_centre_kinematic(name):
    """On each bushed kind:

    - Maxwell-Betti: the 12x12 wheel-centre compliance (rotations in rad against torques in
      N*mm) is symmetric to 1e-3 of the diagonal's scale (central differences of a nonlinear
      model) on the rigid-bushing variant (every bushing its ideal joint; measured 8e-6
      multi-link, 2e-5 semi-trailing arm, 4e-6 Panhard, 3e-6 HMMWV rear) and on the bushed
      model with the bushings unloaded (a 1 N design wheel load, without the axle masses that
      fit the real one; 5e-7, 5e-6, 2.5e-4, 7.5e-7). Under the design load the bushed
      model's is not, in proportion to the load: a bushing's torque, each rotational law at
      the Tait-Bryan angles about the first part's axes, is not the gradient of an energy
      (README, bushings), so a bushing carrying a torque T0 adds a term of order T0 / K
      (measured at design: 3.9e-3 multi-link, 1.9e-2 semi-trailing arm, whose pivot bushing
      carries 2e6 N*mm against 1.5e8 N*mm/rad, 3.8e-3 HMMWV rear; bounded here by 5e-2);
    - on the rigid-bushing variant the force-based roll centre (computed here from its
      matrix, ADAMS/Car's construction) is the kinematic one of the same model (from its
      parallel travel) within 1 mm (measured 0.004 mm, HMMWV rear 0.0007 mm; the compliant
      models' own differ by 49 mm multi-link, 3.4 mm semi-trailing arm, 0.7 mm Panhard,
      12 mm HMMWV rear: the bushings). (Stiffening the bushings' held directions 1000 times
      instead converges to it too, 109.68 against 109.63 mm on the multi-link, but such laws
      stall Newton at its absolute tolerance on the semi-trailing arm and the Panhard axle.)

    The push-rod axle has no bushing (every joint ideal, as its source): its compliance is
    that of its springs through the rockers, symmetric under the design load too (2.3e-5;
    the heave spring couples the wheels: C[zL, zR] = C[zR, zL] = -8.85e-3 mm/N), and its
    force-based roll centre is the kinematic one (4.663 mm both, 0.0005 mm apart)."""
    from elastokin.rig.load_cases import wheel_compliance

    d = config(name)
    d["rig"] = rig(parallel_travel={"rebound_mm": -4, "bump_mm": 4, "step_mm": 2})
    s = suspension(d, name)
    assert reciprocity_error(wheel_compliance(build_model(s))) < (5e-2 if s.bushings else 1e-3)
    unloaded = copy.deepcopy(d)
    unloaded["design"]["wheel_load_N"] = 1.0
    unloaded["axle"].get("vehicle", {}).pop("axle_mass_kg", None)  # they fit the design load
    assert reciprocity_error(wheel_compliance(build_model(suspension(unloaded, name)))) < 1e-3
    rigid = build_model(kinematic(s))
    C = wheel_compliance(rigid)
    assert reciprocity_error(C) < 1e-3
    sweep = parallel_travel(rigid, "rigid_bushings")
    k = np.flatnonzero((sweep.columns["pad_z_mm"] == 0.0)
                       & (sweep.columns["branch"] == "stroke"))[0]
    assert force_based_roll_centre_mm(C, d) == pytest.approx(
        sweep.columns["roll_centre_height_mm"][k], abs=1.0)


def test_live_axle_pinion_torque_in_anti_squat():
    """A driven solid axle (vehicle.live_axle_ratio, ADAMS/Car's dependent suspension): the
    pinion torque T = Rl |F_l + F_r| / ratio, reacted by the housing, adds -T/t and +T/t to
    the wheel loads (ADAMS's SVCANA); ADAMS's formula evaluated here from the summary's 12x12
    matrix (ISO, left wheel first), for the left wheel and the right, then averaged."""
    from elastokin.config.variants import ModelVariant
    from elastokin.studies.kc_job import load_cases

    d = config("solid_axle_watt.yaml")
    d["rig"] = rig(parallel_travel={"rebound_mm": -4, "bump_mm": 4, "step_mm": 2})
    d["axle"]["vehicle"].update(drive="outboard", live_axle_ratio=4.0)
    v = d["axle"]["vehicle"]
    ax = load_cases(ModelVariant("m", suspension(d, "watt.yaml"))).summary()["axle"]
    C = np.array(ax["compliance_matrix_12x12"]["values"])
    rl, track = d["wheel"]["loaded_radius_mm"], 2.0 * point(d, "wheel_centre")[1]
    f = v["drive_fraction"] / 2.0  # the rear axle's share of a unit traction force, per wheel
    weight = v["cg_height_mm"] / (2.0 * v["wheelbase_mm"])
    torque = rl * 2.0 * f / 4.0
    loads = (weight - torque / track, weight + torque / track)
    percents = []
    for row in (2, 8):
        zf = f * (C[row, 0] - rl * C[row, 4] + C[row, 6] - rl * C[row, 10])
        zw = loads[0] * C[row, 2] + loads[1] * C[row, 8]
        percents.append(-100.0 * zf / zw)
    assert ax["percent_anti_squat"] == pytest.approx(np.mean(percents), rel=1e-12)
    without = dict(d, axle=dict(d["axle"], vehicle={k: x for k, x in v.items()
                                                     if k != "live_axle_ratio"}))
    plain = load_cases(ModelVariant("m", suspension(without, "watt.yaml"))).summary()["axle"]
    assert abs(plain["percent_anti_squat"] - ax["percent_anti_squat"]) > 0.1
