"""The whole car on the rig from its two axles' results: the body-roll sweep of the table
(both axles rolled alike, each at its axle load) and the car's figures (names and
definitions: :mod:`elastokin.rig.vehicle_channels`; the mathematics:
:mod:`elastokin.physics.vehicle`).

The body is clamped to the rig's table and the axles share no part but the body: with the
table's motion given, each axle's equilibrium depends on that motion and its own pads only.
So the car on the table is its two axles solved under one body motion: the table's roll, with
heave and pitch free so that each axle carries its load (the axle's roll case, whose heave
beam holds its total vertical load). Nothing is approximated by taking them apart.

ISO 8855; mm, N, N*mm, deg.
"""

from __future__ import annotations

import numpy as np

from elastokin.config.vehicle import ROLES, CarData, Vehicle
from elastokin.errors import ModelError
from elastokin.physics import vehicle as car
from elastokin.physics.wheel import slope
from elastokin.rig.characteristics import determined
from elastokin.rig.paths import sweep_path
from elastokin.rig.sweeps import Sweep, find_sweep
from elastokin.rig.vehicle_channels import (
    AXLE_FIGURES,
    BODY_ROLL,
    CAR_CHARACTERISTICS,
    WHEEL_FIGURES,
)

#: the axle's own load case the table's body roll is (both axles run it alike)
ROLL_CASE = "roll_vertical_force"


def axle_in_car(summary: dict, config_side: str) -> dict:
    """An axle's figures in the car (summary.json ``models.<label>.front`` / ``.rear``
    before the understeer terms) from its model's summary (``ModelResult.summary()``, the
    config side's wheel first): the axle's figures of
    :data:`~elastokin.rig.vehicle_channels.AXLE_FIGURES`, its left wheel's of
    ``WHEEL_FIGURES`` and its lateral force steer (from the named compliances; None for a
    kinematic model)."""
    left = summary if config_side == "left" else summary.get("left", {})
    axle = summary.get("axle") or {}
    out = {k: axle.get(k) for k in AXLE_FIGURES}
    out.update({k: left.get(k) for k in WHEEL_FIGURES})
    named = axle.get("named_compliances")
    out["lateral_force_steer_deg_per_kN"] = None if not named else float(car.axle_steer_deg(
        named["lateral_force_toe_in_phase_left_deg_per_kN"],
        named["lateral_force_toe_in_phase_right_deg_per_kN"]))
    return out


def _known(*values) -> bool:
    return all(v is not None and np.isfinite(v) for v in values)


def _value(v) -> float:
    """A figure as a float, NaN for none."""
    return float("nan") if v is None else float(v)


def car_figures(front: dict, rear: dict, data: CarData, roll: Sweep | None = None
                ) -> dict[str, dict]:
    """The car's figures (``car``) and each axle's with its understeer terms (``front``,
    ``rear``), from the axles' figures (:func:`axle_in_car`), the vehicle's data and the
    table's body-roll sweep (:func:`body_roll_sweep`; None: no table figure). A figure whose
    inputs are missing is None."""
    axles = {"front": dict(front), "rear": dict(rear)}
    out = dict.fromkeys(CAR_CHARACTERISTICS)
    kf, kr = front["roll_stiffness_Nmm_per_deg"], rear["roll_stiffness_Nmm_per_deg"]
    if _known(kf, kr):
        out["roll_stiffness_Nmm_per_deg"] = kf + kr
        out["roll_stiffness_front_percent"] = 100.0 * float(
            car.roll_stiffness_distribution(kf, kr))
        out["roll_stiffness_rear_percent"] = 100.0 - out["roll_stiffness_front_percent"]
    a, L, h = data.cg_behind_front_axle_mm, data.wheelbase_mm, data.cg_height_mm
    for suffix in ("", "_force_based"):
        hf, hr = (x[f"roll_centre_height{suffix}_mm"] for x in (front, rear))
        if not _known(hf, hr):
            continue
        axis = car.roll_axis(hf, hr, L, a, h)
        out[f"roll_axis_height_under_cg{suffix}_mm"] = axis.height_under_cg_mm
        out[f"roll_axis_inclination{suffix}_deg"] = axis.inclination_deg
        if not suffix:
            out["roll_moment_arm_mm"] = axis.moment_arm_mm
    weight = {role: data.weight_N(role) for role in ROLES}
    if _known(out["roll_moment_arm_mm"], out["roll_stiffness_Nmm_per_deg"]):
        out["roll_gradient_deg_per_g"] = float(car.roll_gradient_deg_per_g(
            sum(weight.values()), out["roll_moment_arm_mm"], out["roll_stiffness_Nmm_per_deg"]))
    # each axle's terms of the understeer gradient (NaN, then None, where a rate is missing)
    grad = _value(out["roll_gradient_deg_per_g"])
    s = [_value(axles[role]["lateral_force_steer_deg_per_kN"]) / 1000.0 for role in ROLES]
    e = [_value(axles[role]["axle_roll_steer_deg_per_deg"]) for role in ROLES]
    terms = {"understeer_compliance_steer_deg_per_g": car.compliance_steer_terms_deg_per_g(
                 *s, weight["front"], weight["rear"]),
             "understeer_roll_steer_deg_per_g": car.roll_steer_terms_deg_per_g(*e, grad)}
    for key, (term_front, term_rear) in terms.items():
        axles["front"][key], axles["rear"][key] = float(term_front), float(term_rear)
        out[key] = float(term_front + term_rear)
    out["understeer_suspension_deg_per_g"] = sum(out[k] for k in terms)
    if roll is not None:
        keep = roll.columns["branch"] != "approach"
        out["roll_stiffness_table_Nmm_per_deg"] = slope(
            roll.columns["body_roll_deg"][keep], roll.columns["roll_moment_total_Nmm"][keep],
            what=f"model '{roll.model}': the car's roll stiffness on the table")
    return {"front": _figures(axles["front"]), "rear": _figures(axles["rear"]),
            "car": _figures(out)}


def _figures(values: dict) -> dict:
    """Figures as summary.json holds them: None for not determined (NaN)."""
    return {k: determined(v) if isinstance(v, (float, int)) and not isinstance(v, bool)
            else v for k, v in values.items()}


def body_roll_sweep(label: str, by_role: dict[str, dict[str, list[Sweep]]],
                    vehicle: Vehicle) -> Sweep | None:
    """The table's body roll (load case ``body_roll``) of the car model ``label``: each
    axle's roll case (its sweeps by side, ``by_role``) under the vehicle's body roll, the
    roll moments of both axles and their sum, the body's heave and pitch (from each axle's
    mean wheel travel) and each axle's steer angle, per step of the table's roll. None when
    an axle did not run its roll case."""
    spec = vehicle.body_roll
    phi, branch = sweep_path(spec.amplitude_deg, spec.step_deg)
    cols: dict[str, np.ndarray] = {"branch": branch, "body_roll_deg": phi}
    travel = {}
    for role in ROLES:
        s = vehicle.axle(role)
        if s.rig.roll_vertical_force != spec:  # built by config.vehicle: cannot happen
            raise ModelError(f"{s.source}: the {role} axle does not run the vehicle's body "
                             f"roll ({s.rig.roll_vertical_force} against {spec})")
        wheels = {side: find_sweep(sweeps, ROLL_CASE) for side, sweeps in by_role[role].items()}
        if any(sw is None for sw in wheels.values()):
            return None
        if any(sw.steps != phi.size for sw in wheels.values()):
            raise ModelError(f"{s.source}: the {role} axle's roll case has "
                             f"{wheels['left'].steps} steps, the table's {phi.size}")
        cols[f"roll_moment_{role}_Nmm"] = np.asarray(wheels["left"].columns["roll_moment_Nmm"])
        travel[role] = np.mean([sw.columns["wheel_travel_mm"] for sw in wheels.values()],
                               axis=0)
        cols[f"steer_{role}_deg"] = np.mean([sw.columns["steer_angle_deg"]
                                             for sw in wheels.values()], axis=0)
    cols["roll_moment_total_Nmm"] = cols["roll_moment_front_Nmm"] + cols["roll_moment_rear_Nmm"]
    d = vehicle.data
    cols["body_heave_mm"], cols["body_pitch_deg"] = car.body_heave_pitch(
        travel["front"], travel["rear"], d.wheelbase_mm, d.cg_behind_front_axle_mm)
    return Sweep(label, BODY_ROLL, cols, side="")

