"""K&C test files as sweeps and back: the test channels (per wheel, docs/kc_test_data.md)
converted to kc.csv columns in the config frame, so that every chart and summary treats the
test like a model (the model ``test``), and a sweep's columns as test channels (the synthetic
test data). Names and signs come from :mod:`elastokin.rig.channels`.

Branches are labelled as the rig sweeps them (parallel travel: ``approach`` down to rebound,
``stroke`` up to bump, ``return``; force sweeps: ``rise``, ``fall``, ``return``; vertical
force: ``approach``, ``rise``, ``fall``). Units mm, N, N*mm, deg.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from elastokin.config.suspension import Suspension
from elastokin.errors import MeasurementError
from elastokin.formats.kc_test import KCTest, read_kc_test
from elastokin.rig.channels import CHANNELS, LOAD_CASES, TEST_CHANNELS, Channel
from elastokin.rig.sweeps import Sweep

#: branch names as the rig sweeps each load case (see the module docstring)
BRANCHES = {
    "parallel_travel": ("approach", "stroke", "return"),
    "vertical_force": ("approach", "rise", "fall"),
}
FORCE_BRANCHES = ("rise", "fall", "return")


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
    if load_case == "parallel_travel" and slices:
        # the stroke is the first rising branch; what comes before it is the approach
        first_up = next((i for i, sl in enumerate(slices) if x[sl][-1] > x[sl][0]), 0)
        names = ("approach",) * first_up + ("stroke", "return", "return")
    # a turning point belongs to the branch it ends (as the model's sweeps label it) ...
    for i in reversed(range(len(slices))):
        labels[slices[i]] = names[min(i, len(names) - 1)]
    # ... except that the travel stroke starts at the rebound point
    if load_case == "parallel_travel" and names[0] == "approach":
        labels[slices[0].stop - 1] = "stroke"
    return labels.astype(str)


def to_sweep(test: KCTest, suspension: Suspension) -> Sweep:
    """A :class:`~elastokin.formats.kc_test.KCTest` as a sweep of the model ``test``
    (kc.csv names, config-frame signs)."""
    cols: dict[str, np.ndarray] = {"branch": branch_labels(test.load_case, test)}
    for name, values in test.channels.items():
        channel = TEST_CHANNELS.get(name)
        if channel is None or channel.name == "track_change_mm":
            continue
        cols[channel.name] = wheel_sign(channel, suspension) * np.asarray(values, float)
    return Sweep("test", test.load_case, cols)


def sweep_to_test_channels(sweep: Sweep, suspension: Suspension) -> dict[str, np.ndarray]:
    """A sweep's columns as K&C test channels: the load case's input first, then wheel travel
    (under forces), toe, camber and the wheel-centre displacements; per-wheel signs,
    elastokin units."""
    c = sweep.columns
    case = LOAD_CASES[sweep.load_case]
    names = [case.input] + (["wheel_travel_mm"] if case.name != "parallel_travel" else [])
    names += ["toe_deg", "camber_deg", "wheel_centre_longitudinal_mm",
              "wheel_centre_lateral_mm"]
    out = {}
    for name in names:
        ch = CHANNELS[name]
        out[ch.test] = wheel_sign(ch, suspension) * np.asarray(c[name], float)
    return out


def read_test_sweeps(suspension: Suspension) -> tuple[list[Sweep], list[str]]:
    """The config's ``kc_test`` files as sweeps (one per load case found) and the files read.
    A file named in ``kc_test.files`` must exist; otherwise ``<load case>.csv`` is read when
    present."""
    s = suspension
    spec = s.kc_test
    if spec is None:
        return [], []
    folder = Path(s.source).parent / spec.folder
    for case in spec.files:
        if case not in LOAD_CASES:
            raise MeasurementError(f"{s.source}: key 'kc_test.files.{case}': unknown load case "
                                   f"(expected one of {', '.join(LOAD_CASES)})")
    sweeps, files = [], []
    for case in LOAD_CASES:
        path = folder / spec.files.get(case, f"{case}.csv")
        if not path.exists():
            if case in spec.files:
                raise MeasurementError(f"{s.source}: key 'kc_test.files.{case}': file {path} "
                                       "does not exist")
            continue
        test = read_kc_test(path)
        if test.load_case != case:
            raise MeasurementError(f"{path}: holds load case '{test.load_case}', but the "
                                   f"config reads it as '{case}'")
        sweeps.append(to_sweep(test, s))
        files.append(str(path))
    if not sweeps:
        raise MeasurementError(f"{s.source}: key 'kc_test': no K&C test file in {folder} "
                               f"(expected <load case>.csv, e.g. parallel_travel.csv)")
    return sweeps, files
