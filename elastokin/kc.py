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

from .config import Suspension, TravelSpec
from .geometry import camber_deg, slope, toe_deg
from .model import StepState, SuspensionModel

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


def travel_path(spec: TravelSpec) -> tuple[np.ndarray, np.ndarray]:
    """Prescribed contact-patch travel (mm) and branch labels for a parallel-travel case:
    from the design position (0) down to ``rebound_mm``, then up to ``bump_mm``, in steps no
    larger than ``step_mm``."""
    lo, hi, step = spec.rebound_mm, spec.bump_mm, spec.step_mm
    n_in = max(1, int(np.ceil(abs(lo) / step - 1e-9)))
    approach = np.linspace(0.0, lo, n_in + 1)[1:]
    n = max(1, int(np.ceil((hi - lo) / step - 1e-9)))
    stroke = np.linspace(lo, hi, n + 1)[1:]
    z = np.r_[approach, stroke]
    branch = np.array(["approach"] * approach.size + ["stroke"] * stroke.size)
    branch[approach.size - 1] = "stroke"  # the stroke starts at the rebound point
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
        "wheel_centre_x_mm": centre[:, 0],
        "wheel_centre_y_mm": centre[:, 1],
        "wheel_centre_z_mm": centre[:, 2],
        "toe_deg": toe_deg(spin, s.forward, s.outboard),
        "camber_deg": camber_deg(spin, s.forward, s.outboard, s.up),
        "contact_patch_fx_N": pad[:, 0],
        "contact_patch_fy_N": pad[:, 1],
        "contact_patch_fz_N": pad[:, 2],
    }
    for name in states[0].spring_force_N:
        cols[f"spring_{name}_force_N"] = np.array([st.spring_force_N[name] for st in states])
    units = ("mm", "mm", "mm", "deg", "deg", "deg")
    for name in states[0].bushing_deflection:
        u = np.array([st.bushing_deflection[name] for st in states])
        for i, (d, unit) in enumerate(zip(("x", "y", "z", "rx", "ry", "rz"), units)):
            cols[f"bushing_{name}_{d}_{unit}"] = u[:, i]
    return cols


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

    def summary(self) -> dict:
        travel = next(sw for sw in self.sweeps if sw.load_case == "parallel_travel")
        return {"steer_amplitude_deg": steer_amplitude_deg(travel),
                "bump_steer_deg_per_m": bump_steer_deg_per_m(travel),
                "kinematic": self.kinematic}


def static_equilibrium(model: SuspensionModel) -> StaticResult:
    """Solve the design load case: the wheel load applied at the contact patch, free patch."""
    s = model.suspension
    w = s.design.wheel_load_N
    state = model.run(pad_loads=[s.up * w], what="static equilibrium under the wheel load")[-1]
    forces = model.forces_on_part(s.wheel.part)
    residual = float(np.linalg.norm(sum(forces.values())))
    return StaticResult(state, w, bushing_table(state, s), residual)
