"""A sweep: one load case on one model, as per-step columns (kc.csv names with units, see
:mod:`elastokin.rig.channels`). Plain data: the test data are sweeps of the model ``test``."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from elastokin.physics.states import LoadTable, PoseSeries


@dataclass
class Sweep:
    """One load case on one model: per-step columns (name with unit -> array) in step order.

    ``branch`` labels each step: parallel travel ``approach`` (from the design position to the
    start of the measured stroke, not used for characteristics), ``stroke`` and ``return``;
    force sweeps ``rise``, ``fall``, ``return``; vertical force ``approach``, ``rise``, ``fall``.
    """

    model: str
    load_case: str
    columns: dict[str, np.ndarray] = field(default_factory=dict)
    #: with parameter sensitivities: d column / d parameter, (steps, parameters), for the
    #: wheel's columns (:func:`elastokin.rig.characteristics.wheel_column_tangents`)
    tangents: dict[str, np.ndarray] = field(default_factory=dict)
    #: the wheel's side ("": the config's own side, e.g. test data of a corner)
    side: str = ""
    #: the load of every element of the model at every step (the whole model's: carried by
    #: the config side's sweep only; None: not recorded, test data, results read back)
    loads: LoadTable | None = None
    #: every moving part's pose at every step (the whole model's, the same in each wheel's
    #: sweep; None: not recorded, e.g. test data or results read back from files)
    poses: PoseSeries | None = None

    def stroke(self, name: str) -> np.ndarray:
        return self.columns[name][self.columns["branch"] == "stroke"]

    @property
    def steps(self) -> int:
        return len(self.columns["branch"])


def branch_names(branch: np.ndarray) -> list[str]:
    """The branch labels of a sweep's steps in the order the branches first appear."""
    b = np.asarray(branch)
    if b.size == 0:
        return []
    starts = np.r_[0, np.flatnonzero(b[1:] != b[:-1]) + 1]
    return list(dict.fromkeys(b[starts].tolist()))


def find_sweep(sweeps: list[Sweep], load_case: str) -> Sweep | None:
    """The sweep of ``load_case`` among ``sweeps`` (None when it was not run)."""
    return next((sw for sw in sweeps if sw.load_case == load_case), None)


def static_row_value(sweep: Sweep, name: str) -> float | None:
    """``name`` at the static state of a parallel-travel sweep: wheel travel 0 on the
    measured stroke (wheel travel is the change from the model's own static state under the
    design wheel load: the pad carries that load there), interpolated linearly when no step
    lands on it. None when the column is missing, undefined there (NaN) or 0 is outside the
    stroke."""
    if name not in sweep.columns or "wheel_travel_mm" not in sweep.columns:
        return None
    z, y = sweep.stroke("wheel_travel_mm").astype(float), sweep.stroke(name).astype(float)
    hit = np.flatnonzero(z == 0.0)
    if hit.size:
        value = float(y[hit[0]])
    else:
        order = np.argsort(z)
        if z.size < 2 or not z[order[0]] < 0.0 < z[order[-1]]:
            return None
        value = float(np.interp(0.0, z[order], y[order]))
    return value if np.isfinite(value) else None


def static_rows(columns: dict[str, np.ndarray]) -> np.ndarray:
    """The rows :func:`static_row_value` reads in a parallel-travel sweep's columns (the
    stroke's step at wheel travel 0, or the two around it); empty when none."""
    if "wheel_travel_mm" not in columns:
        return np.zeros(0, int)
    stroke = np.flatnonzero(np.asarray(columns["branch"]) == "stroke")
    z = np.asarray(columns["wheel_travel_mm"], float)[stroke]
    hit = np.flatnonzero(z == 0.0)
    if hit.size:
        return stroke[hit[:1]]
    below, above = np.flatnonzero(z < 0.0), np.flatnonzero(z > 0.0)
    if not (below.size and above.size):
        return np.zeros(0, int)
    return np.unique(stroke[[below[np.argmax(z[below])], above[np.argmin(z[above])]]])
