"""The hardpoint sensitivity table (``elastokin sensitivity``): the exact effect of every
hardpoint coordinate, per mm, on the summary characteristics, ranked; ADAMS Insight's
effects table, from one model run with derivatives (:mod:`elastokin.studies.design_runs`)
instead of a design of experiments.

Every coordinate (x, y, z, config frame) of every hardpoint the suspension uses is a design
variable; on an axle both sides' points move together (mirrored), as a designer moves a
pickup of a symmetric axle. Units: the characteristic's own unit per mm.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from elastokin.config.design_variables import DesignVariable, design_suspension
from elastokin.config.frozen import plain_data
from elastokin.config.suspension import Suspension
from elastokin.errors import ConfigError
from elastokin.studies.design_runs import DesignRun, run_design

#: the characteristics of the table, in this order (those a model gives: an axle's, with
#: steering and vehicle data, more)
TABLE_CHARACTERISTICS = (
    "bump_steer_deg_per_m", "bump_steer_at_design_deg_per_m", "bump_camber_deg_per_m",
    "caster_deg", "kingpin_inclination_deg", "scrub_radius_mm", "caster_trail_mm",
    "wheel_rate_N_per_mm", "axle.roll_centre_height_mm", "axle.axle_roll_steer_deg_per_deg",
    "axle.roll_camber_left_deg_per_deg", "axle.roll_stiffness_Nmm_per_deg",
    "axle.percent_anti_dive", "axle.percent_anti_lift_traction", "axle.percent_anti_squat",
    "axle.percent_ackermann_lock", "axle.steering_ratio_centre")
#: the load cases the table needs (and the compliance matrix of a compliant model)
TABLE_LOAD_CASES = ("parallel_travel", "vertical_force", "roll_vertical_force", "steering")


@dataclass
class SensitivityTable:
    """Effects (per mm) of every hardpoint coordinate on each characteristic: ``effects``
    (variables, characteristics), the model's values of the characteristics, the model
    label, time, and the coordinates left out."""

    variables: list[DesignVariable]
    characteristics: list[str]
    values: np.ndarray
    effects: np.ndarray
    label: str
    seconds: float = 0.0
    run: DesignRun | None = field(default=None, repr=False)
    #: coordinates the config does not let move: (name, why)
    skipped: list[tuple[str, str]] = field(default_factory=list)

    def ranked(self, characteristic: str) -> list[tuple[DesignVariable, float]]:
        """The variables by the size of their effect on ``characteristic``, largest first."""
        j = self.characteristics.index(characteristic)
        order = np.argsort(-np.abs(self.effects[:, j]), kind="stable")
        return [(self.variables[i], float(self.effects[i, j])) for i in order]


def used_hardpoints(suspension: Suspension) -> list[str]:
    """The hardpoints some connection, spring, stop, the wheel or the axle refers to, in the
    config's order."""
    raw = plain_data(suspension.raw)
    names = set(raw["hardpoints"])
    used: set[str] = set()

    def visit(value):
        if isinstance(value, str) and value in names:
            used.add(value)
        elif isinstance(value, dict):
            for v in value.values():
                visit(v)
        elif isinstance(value, list):
            for v in value:
                visit(v)

    for key in ("connections", "springs", "stops", "wheel", "axle", "parts"):
        visit(raw.get(key))
    return [n for n in raw["hardpoints"] if n in used]


def hardpoint_variables(suspension: Suspension
                        ) -> tuple[list[DesignVariable], list[tuple[str, str]]]:
    """Every coordinate of every used hardpoint as a design variable (both sides), and the
    coordinates the config does not let move, with the reason (e.g. the anti-roll bar's
    centre off the vehicle's centre plane)."""
    out, skipped = [], []
    for name in used_hardpoints(suspension):
        for axis in range(3):
            v = DesignVariable("hardpoint", name, axis)
            try:
                design_suspension(suspension, [v], [v.value(suspension.raw) + 0.01])
            except ConfigError as exc:
                skipped.append((v.name, str(exc)))
                continue
            out.append(v)
    return out, skipped


def sensitivity_table(suspension: Suspension, label: str = "initial",
                      progress: Callable[[str], None] = lambda msg: None
                      ) -> SensitivityTable:
    """The table of ``suspension``'s model ``label`` (``initial`` or ``initial_kinematic``)
    on the load cases of its rig that the characteristics need."""
    t0 = time.perf_counter()
    variables, skipped = hardpoint_variables(suspension)
    rig = suspension.rig
    rig = rig.model_copy(update={name: None for name in type(rig).model_fields
                                 if name != "parallel_travel" and name not in TABLE_LOAD_CASES})
    x0 = np.array([v.value(suspension.raw) for v in variables])
    progress(f"model '{label}' with the derivatives of {len(variables)} hardpoint "
             "coordinates")
    run = run_design(suspension, variables, x0, (label,), rig)
    summary, tangents = run.summary[label], run.summary_tangents[label]
    names = [c for c in TABLE_CHARACTERISTICS if c in summary and c in tangents
             and np.all(np.isfinite(tangents[c]))]
    effects = np.column_stack([tangents[c] for c in names]) if names else \
        np.zeros((len(variables), 0))
    return SensitivityTable(variables, names, np.array([summary[c] for c in names]), effects,
                            label, time.perf_counter() - t0, run, skipped)
