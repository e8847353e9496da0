"""Helpers of the axle tests against the real solver: configs read from tests/data as
mappings, a rig with only the named load cases, and every load case of a suspension run on
its built model (Exudyn), the sweeps by (load case, side)."""

from __future__ import annotations

import copy
from pathlib import Path

from elastokin.config.loading import read_yaml, suspension_from_dict
from elastokin.mbs.design import build_model
from elastokin.rig.drives import drives
from elastokin.rig.load_cases import run_drive_sides

DATA = Path(__file__).parent / "data"
ALL_CASES = ("parallel_travel", "vertical_force", "lateral_force", "longitudinal_force_patch",
             "longitudinal_force_centre", "aligning_torque", "opposite_travel",
             "single_wheel_travel", "roll_vertical_force", "steering", "static_load",
             "lateral_force_anti_phase")


def config(name: str) -> dict:
    """A fresh, mutable copy of the mapping of ``tests/data/<name>`` (or ``configs/``)."""
    path = DATA / name
    if not path.exists():
        path = DATA.parents[1] / "configs" / name
    return copy.deepcopy(read_yaml(path)[0])


def rig(**cases) -> dict:
    """A rig section running only ``cases`` (name -> spec; parallel travel always runs)."""
    out = {case: None for case in ALL_CASES if case != "parallel_travel"}
    out.update(cases)
    return out


def suspension(data: dict, name: str = "axle_test.yaml"):
    return suspension_from_dict(data, name)


def run_cases(s) -> dict:
    """Every load case of ``s``'s rig on its model: {(load case, side): Sweep}."""
    model = build_model(s)
    return {(d.load_case, sw.side): sw for d in drives(s, kinematic=s.kinematic)
            for sw in run_drive_sides(model, "m", d)}
