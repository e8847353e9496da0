"""K&C test files as sweeps and back: the test channels (per wheel, docs/kc_test_data.md)
converted to kc.csv columns in the config frame, so that every chart and summary treats the
test like a model (the model ``test``), and a sweep's columns as test channels (the synthetic
test data). Names and signs come from :mod:`elastokin.rig.channels`.

A file may hold one wheel (its sweep has :attr:`Sweep.side` "": the config side's wheel) or both
wheels of an axle (one sweep per wheel, ``side`` "left" / "right").

Branches are labelled as the rig sweeps them (parallel, opposite and single wheel travel:
``approach`` down to rebound, ``stroke`` up to bump, ``return``; force, roll and steering
sweeps: ``rise``, ``fall``, ``return``; vertical force: ``approach``, ``rise``, ``fall``; static
load: ``rise``). Units mm, N, N*mm, deg.
"""

from __future__ import annotations

import warnings

import numpy as np

from elastokin.config.confined import data_file, data_folder
from elastokin.config.suspension import Suspension
from elastokin.errors import MeasurementError
from elastokin.formats.kc_test import KCTest, read_kc_test
from elastokin.rig.channels import CHANNELS, LOAD_CASES, TEST_CHANNELS, Channel
from elastokin.rig.drives import why_not_run
from elastokin.rig.sweeps import Sweep

#: branch names as the rig sweeps each load case (see the module docstring)
TRAVEL_CASES = ("parallel_travel", "opposite_travel", "single_wheel_travel")
BRANCHES = {
    **{case: ("approach", "stroke", "return") for case in TRAVEL_CASES},
    "vertical_force": ("approach", "rise", "fall"),
}
FORCE_BRANCHES = ("rise", "fall", "return")


class KCTestWarning(UserWarning):
    """A K&C test file that is read but cannot be used (its load case never runs)."""


def wheel_sign(channel: Channel, suspension: Suspension) -> float:
    """Factor from a test channel's per-wheel sign to the config-frame sign of its kc.csv
    column (its own inverse)."""
    lateral = float(suspension.left @ suspension.outboard)  # +1 left wheel, -1 right wheel
    return {"lateral": lateral, "toe_in_torque": -lateral}.get(channel.test_sign, 1.0)


def branch_labels(load_case: str, test: KCTest) -> np.ndarray:
    """Each test row's branch label, as the rig's sweeps label them."""
    names = BRANCHES.get(load_case, FORCE_BRANCHES)
    x = test.input
    labels = np.empty(x.size, dtype=object)
    slices = list(test.branches)
    if load_case in TRAVEL_CASES and slices:
        # the stroke is the first rising branch; what comes before it is the approach
        first_up = next((i for i, sl in enumerate(slices) if x[sl][-1] > x[sl][0]), 0)
        names = ("approach",) * first_up + ("stroke", "return", "return")
    # a turning point belongs to the branch it ends (as the model's sweeps label it) ...
    for i in reversed(range(len(slices))):
        labels[slices[i]] = names[min(i, len(names) - 1)]
    # ... except that the travel stroke starts at the rebound point
    if load_case in TRAVEL_CASES and names[0] == "approach":
        labels[slices[0].stop - 1] = "stroke"
    return labels.astype(str)


def to_sweep(test: KCTest, suspension: Suspension, side: str = "") -> Sweep:
    """One wheel of a :class:`~elastokin.formats.kc_test.KCTest` as a sweep of the model
    ``test`` (kc.csv names, config-frame signs): ``side`` "" for a one-wheel file (the config
    side's wheel, :attr:`Sweep.side` ""), else the file's ``left`` or ``right`` wheel."""
    view = suspension.on_side(side) if side else suspension
    cols: dict[str, np.ndarray] = {"branch": branch_labels(test.load_case, test)}
    for name, values in test.wheel(side).items():
        channel = TEST_CHANNELS.get(name)
        if channel is None or channel.name == "track_change_mm":
            continue
        cols[channel.name] = wheel_sign(channel, view) * np.asarray(values, float)
    return Sweep("test", test.load_case, cols, side=side)


#: what the synthetic test files record besides the input, wheel travel (when it is not the
#: input), toe, camber and the wheel-centre displacements (kc.csv names)
MORE_CHANNELS = {"roll_vertical_force": ("roll_moment_Nmm",),
                 "steering": ("rack_travel_mm", "steer_angle_deg")}


def sweep_to_test_channels(sweep: Sweep, suspension: Suspension) -> dict[str, np.ndarray]:
    """A sweep's columns as one wheel's K&C test channels: the load case's input first, then
    wheel travel (when it is not the input), the case's :data:`MORE_CHANNELS`, toe, camber
    and the wheel-centre displacements; per-wheel signs of the sweep's wheel
    (:attr:`Sweep.side`, "" the config side's), elastokin units."""
    c = sweep.columns
    case = LOAD_CASES[sweep.load_case]
    view = suspension.on_side(sweep.side) if sweep.side else suspension
    names = [case.input] + (["wheel_travel_mm"] if case.input != "wheel_travel_mm" else [])
    names += [*MORE_CHANNELS.get(case.name, ()), "toe_deg", "camber_deg",
              "wheel_centre_longitudinal_mm", "wheel_centre_lateral_mm"]
    out = {}
    for name in names:
        ch = CHANNELS[name]
        out[ch.test] = wheel_sign(ch, view) * np.asarray(c[name], float)
    return out


def axle_test_channels(sweeps: list[Sweep], suspension: Suspension) -> dict[str, np.ndarray]:
    """One load case's sweeps of both wheels as the channels of a two-wheel K&C test file:
    per-wheel channels suffixed with the side (``toe_left``, ``toe_right``, side by side),
    per-axle ones once. The input first: of a per-wheel input the driven wheel's (the config
    side's, unless it is held while the other moves: single wheel travel)."""
    per_side = {sw.side: sweep_to_test_channels(sw, suspension) for sw in sweeps}
    names = list(per_side[sweeps[0].side])
    ranges = {side: float(np.ptp(ch[names[0]])) for side, ch in per_side.items()}
    largest = max(ranges.values())
    sides = sorted(per_side, key=lambda side: ranges[side] < 0.5 * largest)  # stable
    out = {}
    for name in names:
        if TEST_CHANNELS[name].per_axle:
            out[name] = per_side[sides[0]][name]
        else:
            out.update({f"{name}_{side}": per_side[side][name] for side in sides})
    return out


def side_sweeps(sweeps: list[Sweep], side: str, suspension: Suspension) -> list[Sweep]:
    """The sweeps of one wheel (a one-wheel file's, side "", are the config side's)."""
    return [sw for sw in sweeps if (sw.side or suspension.side) == side]


def _wheels_of(test: KCTest, suspension: Suspension) -> list[str]:
    """The wheels of a test file the suspension has ("" for a one-wheel file), config side
    first."""
    if not test.sides:
        return [""]
    sides = [side for side in suspension.sides if side in test.sides]
    if not sides:
        raise MeasurementError(f"{test.source}: holds the {' and '.join(test.sides)} wheel, "
                               f"and {suspension.source} describes the {suspension.side} "
                               "corner only")
    return sides


def read_test_sweeps(suspension: Suspension) -> tuple[list[Sweep], list[str]]:
    """The config's ``kc_test`` files as sweeps and the files read: per load case found, one
    sweep per wheel the file holds and the suspension has (:attr:`Sweep.side` "" for a
    one-wheel file: the config side's), the config side's sweeps first. A file named in
    ``kc_test.files`` must exist; otherwise ``<load case>.csv`` is read when present. A file
    whose load case no model of the suspension can run (:func:`~elastokin.rig.drives
    .why_not_run`: a roll test on a corner, a steering test on an axle without steering) is
    read, then left out with a :class:`KCTestWarning` naming it, as is one whose load case
    the rig leaves out (unless the stiffness fit runs it); when every file is, an error."""
    s = suspension
    spec = s.kc_test
    if spec is None:
        return [], []
    folder = data_folder(s, "kc_test")
    for case in spec.files:
        if case not in LOAD_CASES:
            raise MeasurementError(f"{s.source}: key 'kc_test.files.{case}': unknown load case "
                                   f"(expected one of {', '.join(LOAD_CASES)})")
    # the stiffness fit runs the test's corner cases whatever the rig (kc_job.fits_stiffness)
    fitted = spec.stiffness_identification.enabled and bool(s.bushings) and not s.kinematic
    sweeps, files, unused = [], [], []
    for case in LOAD_CASES:
        # inside the config's folders, links followed (the folder may come from anyone)
        key = f"kc_test.files.{case}" if case in spec.files else "kc_test.folder"
        path = data_file(s, "kc_test", spec.files.get(case, f"{case}.csv"), key)
        if not path.exists():
            if case in spec.files:
                raise MeasurementError(f"{s.source}: key 'kc_test.files.{case}': file {path} "
                                       "does not exist")
            continue
        test = read_kc_test(path)
        if test.load_case != case:
            raise MeasurementError(f"{path}: holds load case '{test.load_case}', but the "
                                   f"config reads it as '{case}'")
        files.append(str(path))
        why = why_not_run(s, case, fitted)
        if why is not None:  # read (a bad file still fails), then left out with a word
            unused.append(f"{path}: {why}")
            warnings.warn(KCTestWarning(f"{path}: K&C test of {case} ignored: no load case "
                                        f"of {s.source} can use it ({why})"), stacklevel=2)
            continue
        sweeps += [to_sweep(test, s, side) for side in _wheels_of(test, s)]
    if unused and not sweeps:
        raise MeasurementError(f"{s.source}: key 'kc_test': no K&C test file in {folder} that "
                               f"this config's load cases can use ({'; '.join(unused)})")
    if not sweeps:
        raise MeasurementError(f"{s.source}: key 'kc_test': no K&C test file in {folder} "
                               f"(expected <load case>.csv, e.g. parallel_travel.csv)")
    mine = [(sw.side or s.side) == s.side for sw in sweeps]
    return ([sw for sw, m in zip(sweeps, mine) if m]
            + [sw for sw, m in zip(sweeps, mine) if not m]), files
