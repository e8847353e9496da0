"""The loads of a model's load cases as the rig reports them: loads.csv's columns (names,
units and frames from :mod:`elastokin.rig.channels`), each element's peak per load case
(summary.json ``models.<label>.loads``) and the loads each ground (body, subframe) pickup
receives, with its worst case (``models.<label>.pickups``).

Config frame; N, N*mm, mm. Conventions: :mod:`elastokin.physics.loads`.
"""

from __future__ import annotations

import numpy as np

from elastokin.physics.loads import (
    FORCE,
    FORCE_LOCAL,
    MOMENT,
    MOMENT_LOCAL,
    ground_loads,
    peak_step,
)
from elastokin.physics.states import LoadItem, LoadTable
from elastokin.rig.item_channels import LOAD_COMPONENTS, load_column
from elastokin.rig.sweeps import Sweep

#: the elements whose loads a body pickup receives (not the rig's contact patches, not the
#: model's idle-spin springs)
PICKUP_KINDS = ("joint", "rack", "bushing", "link", "spring", "stop", "steering_gear",
                "support", "other")


def item_columns(item: LoadItem) -> list[tuple[str, int, int]]:
    """(loads.csv column, quantity, component) of an element: force and moment in the body
    frame and in its own (``local``); a link, spring or stop: its force in the body frame and
    along its line (``fz`` local); a ball joint: no moments."""
    if item.two_point:
        return [*((load_column(item.name, c, "body"), FORCE, i)
                  for i, c in enumerate(LOAD_COMPONENTS[:3])),
                (load_column(item.name, "fz", "local"), FORCE_LOCAL, 2)]
    comps = LOAD_COMPONENTS if item.moments else LOAD_COMPONENTS[:3]
    out = []
    for frame, (qf, qm) in (("body", (FORCE, MOMENT)), ("local", (FORCE_LOCAL, MOMENT_LOCAL))):
        out += [(load_column(item.name, c, frame), qf if c[0] == "f" else qm, "xyz".index(c[1]))
                for c in comps]
    return out


def load_columns(table: LoadTable) -> dict[str, np.ndarray]:
    """loads.csv's columns of a sweep's loads (column -> values per step)."""
    return {col: table.values[:, k, q, i] for k, item in enumerate(table.items)
            for col, q, i in item_columns(item)}


def load_peaks(sweeps: list[Sweep]) -> dict[str, dict]:
    """Every element's largest force and moment magnitude per load case, with the step
    (1-based, as kc.csv and loads.csv number them): ``{element: {"kind", "parts",
    "load_cases": {case: {"force_N", "force_step", "moment_Nmm", "moment_step"}}}}``."""
    out: dict[str, dict] = {}
    for sw in sweeps:
        if sw.loads is None:
            continue
        v = sw.loads.values
        for k, item in enumerate(sw.loads.items):
            entry = out.setdefault(item.name, {"kind": item.kind, "parts": list(item.parts),
                                               "load_cases": {}})
            i, f = peak_step(np.linalg.norm(v[:, k, FORCE], axis=1))
            peak = {"force_N": f, "force_step": i + 1}
            if item.moments:
                j, m = peak_step(np.linalg.norm(v[:, k, MOMENT], axis=1))
                peak.update(moment_Nmm=m, moment_step=j + 1)
            entry["load_cases"][sw.load_case] = peak
    return out


def load_summary(sweeps: list[Sweep]) -> dict[str, dict]:
    """summary.json's ``loads`` (:func:`load_peaks`) and ``pickups`` (:func:`pickup_loads`)
    of a model's sweeps; empty when no loads were recorded (test data)."""
    peaks = load_peaks(sweeps)
    return {"loads": peaks, "pickups": pickup_loads(sweeps)} if peaks else {}


def pickup_loads(sweeps: list[Sweep]) -> dict[str, dict]:
    """The load each ground pickup receives (body frame): per pickup its position (mm, on the
    ground), the element's kind, the largest force magnitude of every load case and the worst
    case (the largest of all) with its step, force and moment vectors (about the pickup)."""
    out: dict[str, dict] = {}
    for sw in sweeps:
        if sw.loads is None:
            continue
        for name, v in ground_loads(sw.loads, sw.loads.ground, PICKUP_KINDS).items():
            item = sw.loads.items[sw.loads.names().index(name)]
            i, f = peak_step(np.linalg.norm(v[:, 0], axis=1))
            entry = out.setdefault(name, {"kind": item.kind, "moments": item.moments,
                                          "point_mm": v[0, 2].tolist(), "load_cases": {},
                                          "worst": None})
            entry["load_cases"][sw.load_case] = f
            if entry["worst"] is None or f > entry["worst"]["force_N"]:
                entry["worst"] = {"load_case": sw.load_case, "step": i + 1, "force_N": f,
                                  "force_vector_N": v[i, 0].tolist(),
                                  "moment_vector_Nmm": v[i, 1].tolist()}
    return out
