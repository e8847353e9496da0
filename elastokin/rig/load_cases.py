"""The virtual K&C rig: load cases on a :class:`~elastokin.model.SuspensionModel`, per-step
characteristics and their summary figures.

Frames and units: the config frame, mm, N, N*mm, deg. Signs (ISO 8855 / SAE J670 names, see
:mod:`elastokin.geometry`): toe positive toe-in; camber positive top outboard; wheel travel
positive bump (wheel-centre z relative to the design position); contact-patch forces are the
forces the rig pad applies to the tyre, config frame (Fz > 0 pushes the wheel up).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from elastokin.config.schema import ForceSweepSpec, TorqueSweepSpec, TravelSpec, VerticalForceSpec
from elastokin.config.suspension import Suspension
from elastokin.mbs.model import StepState, SuspensionModel
from elastokin.physics.steering_axis import steering_axes_from_poses, steering_skeleton
from elastokin.physics.steering_geometry import (
    caster_deg,
    caster_trail_mm,
    contact_point,
    kingpin_inclination_deg,
    scrub_radius_mm,
)
from elastokin.physics.wheel import camber_deg, slope, toe_deg

#: half-width of the travel window over which bump steer is fitted (mm)
BUMP_STEER_WINDOW_MM = 50.0


@dataclass
class Sweep:
    """One load case on one model: per-step columns (name with unit -> array) in step order.

    ``branch`` labels each step: ``approach`` (from the design position to the start of the
    measured stroke, not used for characteristics) and ``stroke`` (the measured stroke).
    """

    model: str
    load_case: str
    columns: dict[str, np.ndarray] = field(default_factory=dict)

    def stroke(self, name: str) -> np.ndarray:
        return self.columns[name][self.columns["branch"] == "stroke"]

    @property
    def steps(self) -> int:
        return len(self.columns["branch"])


def _leg(start: float, end: float, step: float) -> np.ndarray:
    """Equal steps no larger than ``step`` from ``start`` (excluded) to ``end`` (included)."""
    n = max(1, int(np.ceil(abs(end - start) / step - 1e-9)))
    return np.linspace(start, end, n + 1)[1:]


def travel_path(spec: TravelSpec) -> tuple[np.ndarray, np.ndarray]:
    """Prescribed contact-patch travel (mm) and branch labels for a parallel-travel case:
    from the design position (0) down to ``rebound_mm`` (``approach``), up to ``bump_mm``
    (``stroke``, loading) and, with ``unloading``, back down to ``rebound_mm`` (``return``),
    in steps no larger than ``step_mm``."""
    lo, hi, step = spec.rebound_mm, spec.bump_mm, spec.step_mm
    legs = [_leg(0.0, lo, step), _leg(lo, hi, step)]
    if spec.unloading:
        legs.append(_leg(hi, lo, step))
    z = np.concatenate(legs)
    branch = np.concatenate([[b] * leg.size for b, leg in zip(("approach", "stroke", "return"),
                                                              legs)])
    branch[legs[0].size - 1] = "stroke"  # the stroke starts at the rebound point
    return z, branch


def characteristics(states: list[StepState], suspension: Suspension,
                    design: StepState | None = None) -> dict[str, np.ndarray]:
    """Per-step characteristics (column name with unit -> array) from solved steps."""
    s = suspension
    centre0 = s.wheel.centre_mm if design is None else design.wheel_centre_mm
    centre = np.array([st.wheel_centre_mm for st in states])
    spin = np.array([st.spin_axis for st in states])
    pad = np.array([st.pad_force_N for st in states])
    cols = {
        "wheel_travel_mm": (centre - centre0) @ s.up,
        "wheel_centre_longitudinal_mm": (centre - centre0) @ s.forward,
        "wheel_centre_lateral_mm": (centre - centre0) @ s.left,
        "wheel_centre_x_mm": centre[:, 0],
        "wheel_centre_y_mm": centre[:, 1],
        "wheel_centre_z_mm": centre[:, 2],
        "toe_deg": toe_deg(spin, s.forward, s.outboard),
        "camber_deg": camber_deg(spin, s.forward, s.outboard, s.up),
        "contact_patch_fx_N": pad[:, 0],
        "contact_patch_fy_N": pad[:, 1],
        "contact_patch_fz_N": pad[:, 2],
    }
    if states[0].poses is not None:  # models built with ModelOptions(part_poses=False): none
        cols.update(steering_axis_columns(states, s))
    for name in states[0].spring_force_N:
        cols[f"spring_{name}_force_N"] = np.array([st.spring_force_N[name] for st in states])
    units = ("mm", "mm", "mm", "deg", "deg", "deg")
    for name in states[0].bushing_deflection:
        u = np.array([st.bushing_deflection[name] for st in states])
        for i, (d, unit) in enumerate(zip(("x", "y", "z", "rx", "ry", "rz"), units)):
            cols[f"bushing_{name}_{d}_{unit}"] = u[:, i]
    return cols


#: steering-axis columns of kc.csv and the summary (docs/characteristics.md)
STEERING_AXIS_COLUMNS = ("caster_deg", "kingpin_inclination_deg", "scrub_radius_mm",
                         "caster_trail_mm")


class SteeringAxisWarning(UserWarning):
    """The steering axis is undefined at some steps (NaN columns); the message says why."""


def steering_axis_columns(states: list[StepState], suspension: Suspension) -> dict[str,
                                                                                  np.ndarray]:
    """Caster (deg), kingpin inclination (deg), scrub radius (mm) and caster trail (mm) per
    step: the steering axis is the wheel part's instantaneous screw axis under a small steering
    input with the springs locked (:mod:`elastokin.steering_axis`), the ground plane the plane
    normal to ``up`` through the contact point of the wheel (loaded radius below the centre in
    the wheel plane). NaN where the axis is undefined, with a :class:`SteeringAxisWarning`."""
    s = suspension
    centre = np.array([st.wheel_centre_mm for st in states])
    spin = np.array([st.spin_axis for st in states])
    axes = steering_axes_from_poses(steering_skeleton(s), [st.poses for st in states], centre)
    d, p = axes.direction.copy(), axes.point
    d[np.abs(d @ s.up) < 1e-9] = np.nan  # a horizontal axis has no caster or ground point
    if axes.reason is not None or np.isnan(d).any():
        import warnings

        bad = int(np.isnan(d).any(axis=1).sum())
        warnings.warn(SteeringAxisWarning(
            f"{s.source}: steering axis undefined at {bad} of {len(states)} steps (NaN "
            f"caster, kingpin inclination, scrub radius, caster trail): "
            f"{axes.reason or 'horizontal axis'}"), stacklevel=2)
    contact = contact_point(centre, spin, s.wheel.loaded_radius_mm, s.up)
    return {
        "caster_deg": caster_deg(d, s.forward, s.up),
        "kingpin_inclination_deg": kingpin_inclination_deg(d, s.outboard, s.up),
        "scrub_radius_mm": scrub_radius_mm(p, d, contact, spin, s.forward, s.outboard, s.up),
        "caster_trail_mm": caster_trail_mm(p, d, contact, spin, s.forward, s.outboard, s.up),
    }


def static_row_value(sweep: Sweep, name: str) -> float | None:
    """``name`` at the static state of a parallel-travel sweep: the rig pad at the design
    height (``pad_z_mm`` = 0) on the measured stroke, interpolated linearly when no step lands
    on it. With a balanced design (``design.balance_spring``) the pad carries the design
    wheel load there, i.e. this is the static equilibrium under the design wheel load. None
    when the column is missing, undefined there (NaN) or 0 is outside the stroke."""
    if name not in sweep.columns or "pad_z_mm" not in sweep.columns:
        return None
    z, y = sweep.stroke("pad_z_mm").astype(float), sweep.stroke(name).astype(float)
    hit = np.flatnonzero(z == 0.0)
    if hit.size:
        value = float(y[hit[0]])
    else:
        order = np.argsort(z)
        if z.size < 2 or not z[order[0]] < 0.0 < z[order[-1]]:
            return None
        value = float(np.interp(0.0, z[order], y[order]))
    return value if np.isfinite(value) else None


def parallel_travel(model: SuspensionModel, label: str, spec: TravelSpec | None = None) -> Sweep:
    """Displacement-controlled parallel wheel travel (both wheels of an axle move together;
    here the one wheel of the model), steering locked, at the design wheel load."""
    s = model.suspension
    spec = spec or s.rig.parallel_travel
    z, branch = travel_path(spec)
    states = model.run(pad_z_mm=z, what=f"model '{label}', parallel travel")
    cols = {"branch": branch, "pad_z_mm": z}
    cols.update(characteristics(states, s))
    return Sweep(label, "parallel_travel", cols)


def sweep_path(amplitude: float, step: float) -> tuple[np.ndarray, np.ndarray]:
    """0 -> +amplitude -> -amplitude -> 0 in steps no larger than ``step``, with branch labels
    ``rise``, ``fall`` and ``return`` (loading and unloading, as a rig records them)."""
    rise = _leg(0.0, amplitude, step)
    # twice the rise's steps, so that both branches pass the same force values
    fall = np.linspace(amplitude, -amplitude, 2 * rise.size + 1)[1:]
    segments = [rise, fall, _leg(-amplitude, 0.0, step)]
    branch = np.concatenate([[b] * seg.size for b, seg in zip(("rise", "fall", "return"),
                                                              segments)])
    return np.concatenate(segments), branch


#: force-controlled load cases: input column, where the load acts, and its direction
#: (ISO 8855 vehicle axes: forward, left, up; forces and torques on the tyre / wheel)
FORCE_CASES = {
    "lateral_force": ("lateral_force_N", "patch", "left"),
    "longitudinal_force_patch": ("longitudinal_force_N", "patch", "forward"),
    "longitudinal_force_centre": ("longitudinal_force_N", "centre", "forward"),
    "aligning_torque": ("aligning_torque_Nmm", "torque", "up"),
}


def force_sweep(model: SuspensionModel, label: str, case: str,
                spec: ForceSweepSpec | TorqueSweepSpec | None = None) -> Sweep:
    """A force (or aligning torque) swept 0 -> +A -> -A -> 0 at the design wheel load, the
    contact patch free (force control); steering locked."""
    s = model.suspension
    column, where, direction = FORCE_CASES[case]
    spec = spec or getattr(s.rig, case)
    if isinstance(spec, TorqueSweepSpec):
        values, branch = sweep_path(spec.amplitude_Nmm, spec.step_Nmm)
    else:
        values, branch = sweep_path(spec.amplitude_N, spec.step_N)
    axis = getattr(s, direction)
    n = values.size
    pad = np.tile(s.up * s.design.wheel_load_N, (n, 1))
    centre = np.zeros((n, 6))
    if where == "patch":
        pad = pad + values[:, None] * axis
    elif where == "centre":
        centre[:, :3] = values[:, None] * axis
    else:
        centre[:, 3:] = values[:, None] * axis
    states = model.run(pad_loads=pad, centre_loads=centre, what=f"model '{label}', {case}")
    cols = {"branch": branch, column: values}
    cols.update(characteristics(states, s))
    return Sweep(label, case, cols)


def vertical_force(model: SuspensionModel, label: str,
                   spec: VerticalForceSpec | None = None) -> Sweep:
    """Vertical force at the contact patch (force control, patch free): from the design wheel
    load down to ``min_N`` (approach), up to ``max_N`` (rise) and back to ``min_N`` (fall)."""
    s = model.suspension
    spec = spec or s.rig.vertical_force
    w, step = s.design.wheel_load_N, spec.step_N
    legs = [_leg(w, spec.min_N, step), _leg(spec.min_N, spec.max_N, step),
            _leg(spec.max_N, spec.min_N, step)]
    fz = np.concatenate(legs)
    branch = np.concatenate([[b] * x.size for b, x in zip(("approach", "rise", "fall"), legs)])
    states = model.run(pad_loads=fz[:, None] * s.up, what=f"model '{label}', vertical force")
    cols = {"branch": branch, "vertical_force_N": fz}
    cols.update(characteristics(states, s))
    return Sweep(label, "vertical_force", cols)


def run_load_cases(model: SuspensionModel, label: str) -> list[Sweep]:
    """Every load case of the config's ``rig`` (parallel travel first). A kinematic model
    runs the vertical cases only: without bushings its answer to a lateral or longitudinal
    load is rigid-body statics, not compliance."""
    rig = model.suspension.rig
    sweeps = [parallel_travel(model, label)]
    if rig.vertical_force is not None:
        sweeps.append(vertical_force(model, label))
    if not model.options.kinematic:
        sweeps += [force_sweep(model, label, case) for case in FORCE_CASES
                   if getattr(rig, case) is not None]
    return sweeps


def compliance_matrix(model: SuspensionModel, force_step_N: float = 10.0,
                      torque_step_Nmm: float = 1000.0) -> np.ndarray:
    """6x6 compliance of the wheel centre at the static equilibrium under the design wheel
    load (patch free), by central differences: columns = force x, y, z (N) and torque x, y, z
    (N*mm) at the wheel centre, rows = wheel-centre displacement x, y, z (mm) and rotation
    vector x, y, z (deg); config frame."""
    s = model.suspension
    steps = [np.zeros(6)]
    for k in range(6):
        h = np.zeros(6)
        h[k] = force_step_N if k < 3 else torque_step_Nmm
        steps += [h, -h]
    centre = np.array(steps)
    pad = np.tile(s.up * s.design.wheel_load_N, (len(steps), 1))
    states = model.run(pad_loads=pad, centre_loads=centre, what="compliance matrix")
    R0, x0 = states[0].wheel_rotation, states[0].wheel_centre_mm
    from scipy.spatial.transform import Rotation

    def response(st):
        rot = Rotation.from_matrix(st.wheel_rotation @ R0.T).as_rotvec(degrees=True)
        return np.r_[st.wheel_centre_mm - x0, rot]

    C = np.empty((6, 6))
    for k in range(6):
        h = centre[1 + 2 * k, k]
        C[:, k] = (response(states[1 + 2 * k]) - response(states[2 + 2 * k])) / (2 * h)
    return C


def steer_amplitude_deg(sweep: Sweep) -> float:
    """Max - min toe over the measured stroke (deg)."""
    toe = sweep.stroke("toe_deg")
    return float(toe.max() - toe.min())


def bump_steer_deg_per_m(sweep: Sweep, window_mm: float = BUMP_STEER_WINDOW_MM) -> float:
    """Toe change per wheel travel, least squares over |travel| <= window (deg/m)."""
    return 1000.0 * slope(sweep.stroke("wheel_travel_mm"), sweep.stroke("toe_deg"),
                          (-window_mm, window_mm))


def bushing_table(state: StepState, suspension: Suspension) -> dict[str, dict[str, float]]:
    """Each bushing's deflection and load in its own frame (z axial, x main radial), laid out
    as the reference paper's Table 3: radial = in-plane deflection magnitude, axial = z,
    torsion = rotation about z, conical = tilt of the axis."""
    table = {}
    for b in suspension.bushings:
        u = state.bushing_deflection[b.name]
        f = state.bushing_load[b.name]
        table[b.name] = {
            "radial_mm": float(np.hypot(u[0], u[1])),
            "axial_mm": float(u[2]),
            "torsion_deg": float(u[5]),
            "conical_deg": float(np.hypot(u[3], u[4])),
            "deflection_mm_deg": [float(x) for x in u],
            "radial_force_N": float(np.hypot(f[0], f[1])),
            "axial_force_N": float(f[2]),
            "torsion_torque_Nmm": float(f[5]),
            "load_N_Nmm": [float(x) for x in f],
        }
    return table


#: gradient name -> (load case, x column, y column, scale): least squares over the whole sweep
GRADIENTS = {
    "bump_camber_deg_per_m": ("parallel_travel", "wheel_travel_mm", "camber_deg", 1000.0),
    "wheel_rate_N_per_mm": ("vertical_force", "wheel_travel_mm", "vertical_force_N", 1.0),
    "lateral_compliance_steer_deg_per_kN": ("lateral_force", "lateral_force_N", "toe_deg",
                                            1000.0),
    "lateral_compliance_camber_deg_per_kN": ("lateral_force", "lateral_force_N",
                                             "camber_deg", 1000.0),
    "lateral_compliance_mm_per_kN": ("lateral_force", "lateral_force_N",
                                     "wheel_centre_lateral_mm", 1000.0),
    "longitudinal_compliance_mm_per_kN": ("longitudinal_force_patch", "longitudinal_force_N",
                                          "wheel_centre_longitudinal_mm", 1000.0),
    "longitudinal_compliance_steer_deg_per_kN": ("longitudinal_force_patch",
                                                 "longitudinal_force_N", "toe_deg", 1000.0),
    "traction_compliance_mm_per_kN": ("longitudinal_force_centre", "longitudinal_force_N",
                                      "wheel_centre_longitudinal_mm", 1000.0),
    "traction_compliance_steer_deg_per_kN": ("longitudinal_force_centre",
                                             "longitudinal_force_N", "toe_deg", 1000.0),
    "aligning_torque_compliance_steer_deg_per_kNm": ("aligning_torque", "aligning_torque_Nmm",
                                                     "toe_deg", 1.0e6),
}


@dataclass
class StaticResult:
    """The static equilibrium under the design wheel load (force control at the patch)."""

    state: StepState
    wheel_load_N: float
    bushings: dict[str, dict[str, float]]
    wheel_assembly_force_residual_N: float


@dataclass
class ModelResult:
    """Everything the vertical K&C run produced for one model."""

    label: str
    kinematic: bool
    sweeps: list[Sweep]
    solver: dict
    compliance: np.ndarray | None = None  # see compliance_matrix

    def sweep(self, load_case: str) -> Sweep | None:
        return next((sw for sw in self.sweeps if sw.load_case == load_case), None)

    def summary(self) -> dict:
        """Summary figures (None when the load case was not run); definitions in
        :data:`GRADIENTS` and the README."""
        travel = self.sweep("parallel_travel")
        has_toe = travel is not None and "toe_deg" in travel.columns
        out = {"steer_amplitude_deg": steer_amplitude_deg(travel) if has_toe else None,
               "bump_steer_deg_per_m": bump_steer_deg_per_m(travel) if has_toe else None,
               "kinematic": self.kinematic}
        # steering axis at the static state (design pad height, design wheel load)
        for name in STEERING_AXIS_COLUMNS:
            out[name] = static_row_value(travel, name) if travel is not None else None
        for name, (case, x, y, scale) in GRADIENTS.items():
            sw = self.sweep(case)
            ok = sw is not None and x in sw.columns and y in sw.columns
            out[name] = scale * slope(sw.columns[x], sw.columns[y]) if ok else None
        if self.compliance is not None:
            out["compliance_matrix"] = {
                "rows": "wheel-centre displacement x y z [mm], rotation x y z [deg]",
                "columns": "force x y z [N], torque x y z [N*mm] at the wheel centre",
                "frame": "config", "values": self.compliance.tolist()}
        return out


def static_equilibrium(model: SuspensionModel) -> StaticResult:
    """Solve the design load case: the wheel load applied at the contact patch, free patch."""
    s = model.suspension
    w = s.design.wheel_load_N
    state = model.run(pad_loads=[s.up * w], what="static equilibrium under the wheel load")[-1]
    forces = model.forces_on_part(s.wheel.part)
    residual = float(np.linalg.norm(sum(forces.values())))
    return StaticResult(state, w, bushing_table(state, s), residual)
