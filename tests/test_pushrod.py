"""The push-rod axle with rockers and a heave spring (configs/fsae_pushrod_axle.yaml, issue 25),
checked without trusting the model:

- the rocker's motion ratio: at every step of parallel travel the pose of the corner is solved
  here from the wheel-centre height alone (the upright on its five distances, the wishbone's
  angle from its ball joint, the rocker's from the push rod's length), and the ratio of the
  coil-over's, the damper's and the heave spring's compression to the wheel travel is the
  virtual-work ratio of that pose (instantaneous: the upright's velocity, the wishbone's
  rotation rate, the push rod's force direction, the rocker's pivot axis, the spring's line),
  against the model's motion-ratio channels to 0.1 % (measured 2.4e-4: the channel's
  differences over 2.5 mm steps, one-sided at the travel's ends); the lengths to 1e-6 mm;
- the heave spring: parallel travel loads it, opposite travel does not (its motion ratio at
  design zero, its force even in the travel: both to solver tolerance), and its rate shows
  in the wheel rate and the ride rate as rate x ratio^2 / 2 per wheel;
- items joining the two sides of an axle: resolved once, refused on a corner or when they
  join only the other side's parts;
- ADAMS/Car: the real subsystem's hardpoints are the config's (import-adams), export and
  import give them back to the bit, with ADAMS/Car's names.

The config's frame is ADAMS/Car's (x rearward, y right, z up): the left corner has y < 0.
"""

from __future__ import annotations

import copy
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import brentq, least_squares
from scipy.spatial.transform import Rotation

from elastokin.config.variants import ModelVariant
from elastokin.errors import ConfigError
from elastokin.mbs.design import build_model
from elastokin.physics.axle_sweeps import ride_rate_N_per_mm
from elastokin.rig.drives import drives
from elastokin.rig.load_cases import parallel_travel, run_drive_sides
from elastokin.studies.kc_job import load_cases

from .axle_rigs import config, rig, suspension

NAME = "fsae_pushrod_axle.yaml"
MIRROR = np.diag([1.0, -1.0, 1.0])
#: the upright's five distances (chassis or rack point, upright point); the rack is held
UPRIGHT_LINKS = [("lca_front", "lca_outer"), ("lca_rear", "lca_outer"),
                 ("uca_front", "uca_outer"), ("uca_rear", "uca_outer"),
                 ("tierod_inner", "tierod_outer")]


def point(d: dict, name: str) -> np.ndarray:
    return np.asarray(d["hardpoints"][name], float)


def unit(v: np.ndarray) -> np.ndarray:
    return v / np.linalg.norm(v)


def turned(p: np.ndarray, centre: np.ndarray, axis: np.ndarray, angle: float) -> np.ndarray:
    return centre + Rotation.from_rotvec(angle * axis).apply(p - centre)


def upright_pose(d: dict, z_mm: float, start: np.ndarray) -> np.ndarray:
    """(rotation vector, rad; wheel-centre displacement, mm) of the upright with its five
    distances those of the design and the wheel centre at height ``z_mm``."""
    c0 = point(d, "wheel_centre")
    links = [(point(d, a), point(d, b) - c0, np.linalg.norm(point(d, b) - point(d, a)))
             for a, b in UPRIGHT_LINKS]

    def residual(x):
        R = Rotation.from_rotvec(x[:3]).as_matrix()
        return [*(np.linalg.norm(c0 + x[3:] + R @ q - f) - n for f, q, n in links),
                c0[2] + x[5] - z_mm]

    fit = least_squares(residual, start, method="lm", xtol=1e-15, ftol=1e-15, gtol=1e-15)
    assert np.max(np.abs(fit.fun)) < 1e-9
    return fit.x


def rocker_state(d: dict, z_mm: float, start: np.ndarray):
    """The corner at wheel-centre height ``z_mm``, solved here: (upright pose, the rocker's
    points moved, the rocker's rate and axis, per unit wheel travel)."""
    pose = upright_pose(d, z_mm, start)
    c0, R = point(d, "wheel_centre"), Rotation.from_rotvec(pose[:3]).as_matrix()
    c = c0 + pose[3:]
    moved = {b: c + R @ (point(d, b) - c0) for _, b in UPRIGHT_LINKS}
    # the upright's velocity: every distance kept, the wheel centre rising at 1 mm per mm
    rows, rhs = [], []
    for a, b in UPRIGHT_LINKS:
        e = moved[b] - point(d, a)
        rows.append(np.r_[np.cross(moved[b] - c, e), e])  # e . (v + w x r) = 0
        rhs.append(0.0)
    rows.append([0, 0, 0, 0, 0, 1.0])
    rhs.append(1.0)
    w, v = np.split(np.linalg.solve(np.array(rows), np.array(rhs)), 2)
    # the lower wishbone: its angle about its pivot axis from the ball joint, its rate
    f, a = point(d, "lca_front"), unit(point(d, "lca_rear") - point(d, "lca_front"))
    e0, e1 = point(d, "lca_outer") - f, moved["lca_outer"] - f
    e0, e1 = e0 - (e0 @ a) * a, e1 - (e1 @ a) * a
    angle = np.arctan2(a @ np.cross(e0, e1), e0 @ e1)
    lever = np.cross(a, moved["lca_outer"] - f)
    rate = lever @ (v + np.cross(w, moved["lca_outer"] - c)) / (lever @ lever)
    p = turned(point(d, "pushrod_arm"), f, a, angle)
    v_p = rate * np.cross(a, p - f)
    # the rocker: its angle from the push rod's length, its rate from the rod's direction
    pivot = point(d, "rocker_pivot")
    axis = unit(pivot - point(d, "rocker_axis"))
    length = np.linalg.norm(point(d, "pushrod_rocker") - point(d, "pushrod_arm"))
    theta = brentq(lambda t: np.linalg.norm(
        turned(point(d, "pushrod_rocker"), pivot, axis, t) - p) - length, -0.6, 0.6,
        xtol=1e-15, rtol=1e-15)
    r = turned(point(d, "pushrod_rocker"), pivot, axis, theta)
    n = unit(r - p)  # the push rod's force on the rocker acts along it
    omega = (n @ v_p) / (n @ np.cross(axis, r - pivot))
    points = {k: turned(point(d, k), pivot, axis, theta)
              for k in ("damper_rocker", "heave_rocker")}
    return pose, points, omega, axis, pivot


def virtual_work_ratios(d: dict, points, omega, axis, pivot) -> dict[str, float]:
    """The compression of the coil-over (and damper) and of the heave spring per wheel
    travel, both wheels rising together (the other rocker the mirror of this one)."""
    def speed(q):
        return omega * np.cross(axis, q - pivot)

    s = unit(points["damper_rocker"] - point(d, "damper_chassis"))
    h = points["heave_rocker"]
    across = unit(h - MIRROR @ h)
    return {"coil": -s @ speed(points["damper_rocker"]),
            "heave": -across @ (speed(h) - MIRROR @ speed(h))}


def test_motion_ratio_is_the_virtual_work_ratio_of_the_rocker_geometry():
    d = config(NAME)
    d["rig"] = rig(parallel_travel={"rebound_mm": -25, "bump_mm": 25, "step_mm": 2.5})
    sweep = parallel_travel(build_model(suspension(d, NAME)), "m")
    col = sweep.columns
    pose = np.zeros(6)
    for k in range(sweep.steps):
        pose, points, omega, axis, pivot = rocker_state(d, col["wheel_centre_z_mm"][k], pose)
        ratio = virtual_work_ratios(d, points, omega, axis, pivot)
        coil = np.linalg.norm(points["damper_rocker"] - point(d, "damper_chassis"))
        heave = np.linalg.norm(points["heave_rocker"] - MIRROR @ points["heave_rocker"])
        assert col["spring_coil_length_mm"][k] == pytest.approx(coil, abs=1e-6)
        assert col["damper_shock_length_mm"][k] == pytest.approx(coil, abs=1e-6)
        assert col["spring_heave_length_mm"][k] == pytest.approx(heave, abs=1e-6)
        for name, got in (("coil", col["spring_coil_motion_ratio"][k]),
                          ("coil", col["damper_shock_motion_ratio"][k]),
                          ("heave", col["spring_heave_motion_ratio"][k])):
            assert got == pytest.approx(ratio[name], rel=1e-3), (k, name)
    # the rocker makes the coil-over progressive: 0.59 at full rebound, 0.66 in full bump
    mr = sweep.stroke("spring_coil_motion_ratio")
    assert 0.58 < mr[0] < 0.60 and 0.65 < mr[-1] < 0.67


def test_heave_spring_is_loaded_in_parallel_travel_not_in_opposite_travel():
    """At design the heave spring's motion ratio is 1.24 per wheel in parallel travel (both
    rockers pull it in) and 0 in opposite travel (one pulls as the other pushes), to solver
    tolerance; over opposite travel its force is even in the travel (the mirror image of +z
    is -z): it changes only to second order, 4 % of its parallel-travel force at 25 mm."""
    d = config(NAME)
    d["rig"] = rig(parallel_travel={"rebound_mm": -25, "bump_mm": 25, "step_mm": 5},
                   opposite_travel={"rebound_mm": -25, "bump_mm": 25, "step_mm": 5})
    s = suspension(d, NAME)
    model = build_model(s)
    sweeps = {dr.load_case: run_drive_sides(model, "m", dr)[0] for dr in drives(s)}
    rate = d["springs"]["heave"]["rate_N_per_mm"]

    def at(case, column, z):
        sw = sweeps[case]
        k = np.flatnonzero((sw.columns["pad_z_mm"] == z) & (sw.columns["branch"] == "stroke"))
        return sw.columns[column][k[0]]

    parallel = at("parallel_travel", "spring_heave_motion_ratio", 0.0)
    assert parallel == pytest.approx(1.24, abs=0.01)
    force = at("parallel_travel", "spring_heave_force_N", 25.0)
    assert abs(at("opposite_travel", "spring_heave_motion_ratio", 0.0)) < 1e-6
    up, down = (at("opposite_travel", "spring_heave_force_N", z) for z in (25.0, -25.0))
    assert up == pytest.approx(down, abs=1e-5)
    assert abs(up) < 0.05 * abs(force)
    assert at("opposite_travel", "spring_heave_force_N", 0.0) == pytest.approx(0.0, abs=1e-6)
    assert abs(force) > 0.9 * rate * parallel * 25.0  # k x MR x travel, the ratio falls


def test_heave_rate_shows_in_the_wheel_rate_and_ride_rate():
    """Doubling the heave spring's rate k adds k MR^2 / 2 to each wheel's rate (its
    compression MR per wheel, shared by the two wheels) and that wheel rate in series with
    the tyre to the ride rate: 0.2 %, over a vertical-force sweep of +-40 N about the design
    load (the wheel rate a least-squares slope; the heave spring carries no preload, so its
    lever's change adds nothing)."""
    d = config(NAME)
    d["rig"] = rig(parallel_travel={"rebound_mm": -2, "bump_mm": 2, "step_mm": 1},
                   vertical_force={"min_N": 620, "max_N": 700, "step_N": 10})
    stiff = copy.deepcopy(d)
    k = d["springs"]["heave"]["rate_N_per_mm"]
    stiff["springs"]["heave"]["rate_N_per_mm"] = 2.0 * k
    out = [load_cases(ModelVariant("m", suspension(x, NAME))).summary() for x in (d, stiff)]
    mr = out[0]["motion_ratios"]["spring_heave_motion_ratio"]
    added = 0.5 * k * mr ** 2
    tyre = d["wheel"]["tyre_rate_N_per_mm"]
    for side in ("left", "right"):
        wheel = [o if side == "left" else o[side] for o in out]
        assert wheel[1]["wheel_rate_N_per_mm"] - wheel[0]["wheel_rate_N_per_mm"] == \
            pytest.approx(added, rel=2e-3)
        assert wheel[1]["spring_wheel_rate_N_per_mm"] - wheel[0]["spring_wheel_rate_N_per_mm"] \
            == pytest.approx(added, rel=1e-9)
        ride = [o["axle"][f"ride_rate_{side}_N_per_mm"] for o in out]
        expected = ride_rate_N_per_mm(wheel[0]["wheel_rate_N_per_mm"] + added, tyre)
        assert ride[1] == pytest.approx(float(expected), rel=2e-3)
        assert ride[1] - ride[0] > 5.0  # the heave spring is most of the ride rate's change


# ------------------------------------------------------------------------- items across
def test_an_item_across_the_car_is_resolved_once_between_the_sides():
    s = suspension(config(NAME), NAME)
    heave = next(sp for sp in s.springs if sp.name == "heave")
    assert heave.parts == ("rocker", "rocker_right")
    np.testing.assert_array_equal(heave.seats_mm[1], MIRROR @ heave.seats_mm[0])
    assert [sp.name for sp in s.springs] == ["coil", "coil_right", "heave"]
    assert [dm.name for dm in s.dampers] == ["shock", "shock_right"]
    assert s.axle.across == ("heave",)
    # the corner alone has no other side: without the heave spring; the spring couples them
    from elastokin.config.variants import corner, side_couplings

    assert [sp.name for sp in corner(s).springs] == ["coil"]
    assert "'heave', joining the two sides" in side_couplings(s)


@pytest.mark.parametrize("edit, key, words", [
    (lambda d: d.pop("axle"), "springs.heave.parts",
     "is the other side's copy of 'rocker': an item joining the two sides needs an 'axle:'"),
    (lambda d: d["springs"]["heave"].update(parts=["rocker_right", "rocker_right"]),
     "springs.heave.parts", "connects part 'rocker_right' to itself"),
    (lambda d: d["springs"]["heave"].update(parts=["body", "rocker_right"]),
     "springs.heave.parts", "joins only the other side's parts"),
    (lambda d: d["springs"]["heave"].update(seats=["heave_rocker", "damper_rocker"]),
     "springs.heave", "is not on the right side of the vehicle centre plane"),
    (lambda d: d["wheel"].update(part="upright_right"), "wheel.part",
     "only a connection, spring, damper or stop joining the two sides may name it"),
    (lambda d: d["dampers"]["shock"].update(points=["damper_rocker", "damper_rocker"]),
     "dampers.shock.points", "the two points of a damper coincide"),
    (lambda d: d["dampers"].update(coil=d["dampers"]["shock"]), "dampers.coil",
     "the name 'coil' is taken by key 'springs.coil'"),
])
def test_bad_items_across_and_dampers(edit, key, words):
    d = config(NAME)
    edit(d)
    with pytest.raises(ConfigError) as err:
        suspension(d, "fsae.yaml")
    message = str(err.value)
    assert message.startswith(f"fsae.yaml: key '{key}':"), message
    assert words in message, message


# ------------------------------------------------------------------------- ADAMS/Car
CONFIGS = Path(__file__).resolve().parents[1] / "configs"
MAPPING = CONFIGS / "adams" / "fsae_pushrod_mapping.yaml"
REAL = Path(__file__).resolve().parents[2] / "shared" / "adams_real" / \
    "zbingf_fsae_front_susp_sub" / "fsae_front_susp.sub"


@pytest.mark.skipif(not REAL.is_file(), reason="../shared/adams_real is absent")
def test_the_hardpoints_are_what_import_adams_reads_from_the_real_subsystem():
    from elastokin.formats.adams.car import import_adams

    d = config(NAME)
    cfg, warnings = import_adams(copy.deepcopy(d), REAL, MAPPING)
    assert cfg["hardpoints"] == d["hardpoints"]
    assert any("rack_centre, heave_rocker" in w for w in warnings)  # the CHOICES, kept


def test_adams_round_trip_with_the_real_names(tmp_path):
    """Export with the mapping file (the real subsystem's names, template, roles and usages),
    import back onto a template whose every hardpoint moved: the hardpoints to the bit, the
    axle section, springs and dampers unchanged; the coil-over a left/right spring, the heave
    spring a single one, the damper a left/right damper with its property file."""
    from elastokin.formats.adams import car as adams_car
    from elastokin.formats.adams.assemblies import read_assemblies, read_spring_assemblies
    from elastokin.formats.adams.export import export_adams
    from elastokin.formats.adams.importing import import_adams_axle, subsystem_files
    from elastokin.formats.adams.mapping import read_mapping
    from elastokin.formats.adams.teimorbit import read_teimorbit
    from elastokin.mbs.design import design_state

    from .suspension_checks import scrambled

    d = config(NAME)
    s = suspension(d, NAME)
    state = design_state(s)
    db = tmp_path / "fsae_2012.cdb"
    export_adams(s, db, state.bushing_preload, spring_force=state.spring_force_N,
                 mapping=read_mapping(MAPPING), timestamp="2024/01/01,00:00:00")
    sub = db / "subsystems.tbl" / "fsae_front_susp.sub"
    head = read_teimorbit(sub).block("SUBSYSTEM_HEADER")
    assert head.value("TEMPLATE_NAME") == "mdids://fsae_2012/templates.tbl/_fsae_frontsusp.tpl"
    points = adams_car.read_hardpoints(sub)
    assert points["BC_center"].position_mm == (-359.6, -254.0, 434.6)
    assert points["heave_rocker"].symmetry == "left/right"
    springs = read_spring_assemblies(sub)
    assert set(springs["ride_spring"]) == {"left", "right"}
    assert set(springs["heave_spring"]) == {"single"}
    damper = read_assemblies(sub, "DAMPER_ASSEMBLY")["ride_damper"]
    assert set(damper) == {"left", "right"}
    assert damper["left"].property_file == "mdids://fsae_2012/dampers.tbl/ride_damper.dpr"
    (table,) = read_teimorbit(db / "dampers.tbl" / "ride_damper.dpr").block("CURVE").tables
    np.testing.assert_allclose(np.array(table.rows)[:, 1], 2.0 * np.array(table.rows)[:, 0])
    mapping = read_mapping(db / "mapping.yaml")
    cfg, warnings, _ = import_adams_axle(scrambled(d), subsystem_files(mapping, db),
                                         db / "mapping.yaml")
    assert warnings == []
    assert cfg["hardpoints"] == d["hardpoints"]
    for key in ("axle", "springs", "dampers", "connections"):
        assert cfg[key] == d[key], key
