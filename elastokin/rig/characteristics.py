"""Per-step columns of a sweep and the summary figures of a model (pure numpy on solved rig
steps; names, units and definitions in :mod:`elastokin.rig.channels`).

Frames and units: the config frame, mm, N, N*mm, deg. Signs (ISO 8855 / SAE J670 names):
toe positive toe-in; camber positive top outboard; wheel travel positive bump (wheel-centre z
relative to the design position); contact-patch forces are the forces the rig pad applies to
the tyre, config frame (Fz > 0 pushes the wheel up).
"""

from __future__ import annotations

import numpy as np

from elastokin.config.suspension import Suspension
from elastokin.physics.axle_sweeps import wheelbase_change_mm
from elastokin.physics.motion_ratio import motion_ratio, wheel_rate_from_springs
from elastokin.physics.states import StepState, WheelArrays
from elastokin.physics.steering_geometry import track_change_mm
from elastokin.physics.wheel import camber_deg, slope, toe_deg, windowed_slope
from elastokin.rig.axle_channels import iso_rotation
from elastokin.rig.channels import CHARACTERISTICS, GRADIENTS, STEERING_AXIS_COLUMNS
from elastokin.rig.item_channels import (
    bushing_columns,
    length_column,
    motion_ratio_column,
    spring_column,
    stop_column,
)
from elastokin.rig.steering import steering_axis_columns
from elastokin.rig.sweeps import Sweep, find_sweep, static_row_value


def wheel_columns(centre: np.ndarray, spin: np.ndarray, suspension: Suspension,
                  centre0: np.ndarray) -> dict[str, np.ndarray]:
    """The wheel's columns (kc.csv name -> array) from wheel-centre positions (n, 3) (mm) and
    outboard spin axes (n, 3), config frame; displacements from ``centre0``."""
    s = suspension
    return {
        "wheel_travel_mm": (centre - centre0) @ s.up,
        "wheel_centre_longitudinal_mm": (centre - centre0) @ s.forward,
        "wheel_centre_lateral_mm": (centre - centre0) @ s.left,
        "wheel_centre_x_mm": centre[:, 0],
        "wheel_centre_y_mm": centre[:, 1],
        "wheel_centre_z_mm": centre[:, 2],
        "toe_deg": toe_deg(spin, s.forward, s.outboard),
        "camber_deg": camber_deg(spin, s.forward, s.outboard, s.up),
    }


def wheel_column_tangents(states: list[StepState], suspension: Suspension,
                          static: StepState) -> dict[str, np.ndarray]:
    """Derivatives (n_steps, n_parameters) of the wheel's columns (:func:`wheel_columns`)
    with respect to the parameters of steps solved with sensitivities (``StepState
    .sensitivity``): central differences of the columns along each parameter's tangent of
    the wheel centre and spin axis, with a step small enough (at most 1e-6 of the unit spin
    axis and 1e-3 mm; the columns are linear in the centre) that they are linear over it to
    rounding. The displacements are changes from ``static`` (the model's static state,
    solved with the same sensitivities): its own derivative is part of theirs."""
    centre = np.array([st.wheel_centre_mm for st in states])
    spin = np.array([st.spin_axis for st in states])
    d_centre = np.array([st.sensitivity["wheel_centre_mm"] for st in states])  # (n, 3, p)
    d_spin = np.array([st.sensitivity["spin_axis"] for st in states])
    centre0, d_centre0 = static.wheel_centre_mm, static.sensitivity["wheel_centre_mm"]
    out: dict[str, list[np.ndarray]] = {}
    for j in range(d_centre.shape[2]):
        size = max(float(np.max(np.abs(d_spin[:, :, j]))),
                   1e-3 * float(np.max(np.abs(d_centre[:, :, j]))), 1e-300)
        h = 1e-6 / size
        plus, minus = (wheel_columns(centre + k * d_centre[:, :, j], spin + k * d_spin[:, :, j],
                                     suspension, centre0 + k * d_centre0[:, j])
                       for k in (h, -h))
        for name in plus:
            out.setdefault(name, []).append((plus[name] - minus[name]) / (2 * h))
    return {name: np.stack(cols, axis=1) for name, cols in out.items()}


def steer_sign(side: str) -> float:
    """Steer angle (+ turning the wheel left) per toe change (+ toe-in) of ``side``'s wheel."""
    return -1.0 if side == "left" else 1.0


def characteristics(states: list[StepState] | WheelArrays, suspension: Suspension,
                    static: StepState, steering_rows: np.ndarray | None = None
                    ) -> dict[str, np.ndarray]:
    """Per-step columns (kc.csv name -> array) from solved rig steps of the wheel the
    suspension is seen from (a list, or their :class:`~elastokin.physics.states.WheelArrays`);
    every change (wheel travel, wheel-centre displacements, track and wheelbase change, steer
    angle) from ``static``, the model's own static state under the design wheel load
    (:func:`elastokin.rig.load_cases.static_states`), not from the config's design position:
    a model that does not rest exactly there (bushing preloads not balanced, a kinematic
    model with the compliant model's spring preload) reads zero at its own rest.
    ``steering_rows``: the steps whose steering-axis columns are computed (default all; the
    others NaN)."""
    s = suspension
    a = WheelArrays.of(states)
    pad = a.pad_force_N
    cols = wheel_columns(a.wheel_centre_mm, a.spin_axis, s, static.wheel_centre_mm)
    cols.update({
        "contact_patch_fx_N": pad[:, 0],
        "contact_patch_fy_N": pad[:, 1],
        "contact_patch_fz_N": pad[:, 2],
    })
    # the contact point: the wheel's lowest point (StepState.contact_patch_mm)
    patch = a.contact_patch_mm
    position = s.axle.vehicle.position if s.axle is not None and s.axle.vehicle is not None \
        else "front"
    cols["track_change_mm"] = track_change_mm(patch, static.contact_patch_mm, s.outboard)
    T = iso_rotation(s)
    cols["wheelbase_change_mm"] = wheelbase_change_mm(patch @ T.T, T @ static.contact_patch_mm,
                                                      position)
    # steer angle: toe change from the static state, + turning the wheel to the left
    toe0 = toe_deg(static.spin_axis, s.forward, s.outboard)
    cols["steer_angle_deg"] = (cols["toe_deg"] - toe0) * steer_sign(s.side)
    recorded = a.poses is not None if isinstance(states, WheelArrays) else \
        states[0].poses is not None
    if recorded:  # models that record the wheel part only: none
        cols.update(_steering_columns(states, a, s, steering_rows))
    mine = own_items(s)
    for name, force in a.spring_force_N.items():
        if mine(name):
            cols[spring_column(name)] = force
    for name, u in a.bushing_deflection.items():
        if mine(name):
            for i, col in enumerate(bushing_columns(name)):
                cols[col] = u[:, i]
    both = both_wheels(s)
    for key, value in a.scalars.items():
        if key.startswith("stop:") and mine(key[5:]):
            cols[stop_column(key[5:])] = value
        kind, _, name = key.partition("_length:")
        if name and (mine(name) or name in both):
            cols[length_column(kind, name)] = value
    return cols


def both_wheels(suspension: Suspension) -> set[str]:
    """The springs and dampers of an axle that both wheels move (kept once: joining the two
    sides, e.g. a heave spring, or among shared parts and the ground): their lengths and
    motion ratios are in both wheels' sweeps (each ratio per that wheel's travel)."""
    axle = suspension.axle
    if axle is None:
        return set()
    fixed = set(axle.shared) | {suspension.ground}
    return {it.name for it in (*suspension.springs, *suspension.dampers)
            if it.name in axle.across or set(it.parts) <= fixed}


def motion_ratio_columns(columns: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """The motion ratio of every spring and damper of a travel sweep's ``columns`` (their
    length columns against ``wheel_travel_mm``:
    :func:`elastokin.physics.motion_ratio.motion_ratio`)."""
    out = {}
    for name, length in columns.items():
        ratio = motion_ratio_column(name)
        if ratio is not None:
            out[ratio] = motion_ratio(columns["wheel_travel_mm"], length)
    return out


def _steering_columns(states, a: WheelArrays, s: Suspension, rows) -> dict[str, np.ndarray]:
    """The steering-axis columns at every step, or at ``rows`` only (NaN elsewhere)."""
    if rows is None:
        steps = states if not isinstance(states, WheelArrays) else \
            [a.step(i) for i in range(len(a))]
        return steering_axis_columns(steps, s)
    rows = np.asarray(rows, int)
    steps = [states[i] if not isinstance(states, WheelArrays) else a.step(i) for i in rows]
    some = steering_axis_columns(steps, s) if rows.size else {}
    out = {}
    for name in STEERING_AXIS_COLUMNS:
        out[name] = np.full(len(a), np.nan)
        if rows.size:
            out[name][rows] = some[name]
    return out


def own_items(suspension: Suspension):
    """Whether a spring, bushing or stop (by name) belongs to the sweep of the wheel the
    suspension is seen from: on an axle the other side's carry its suffix, the config side's
    and the shared ones do not."""
    axle = suspension.axle
    if axle is None:
        return lambda name: True
    if suspension.side == axle.sides[0]:
        return lambda name: not name.endswith(axle.suffix)
    return lambda name: name.endswith(axle.suffix)


def steer_amplitude_deg(sweep: Sweep) -> float:
    """Max - min toe over the measured stroke (deg)."""
    toe = sweep.stroke("toe_deg")
    return float(toe.max() - toe.min())


def bump_steer_deg_per_m(sweep: Sweep) -> float:
    """Toe change per wheel travel, least squares over exactly the symmetric bump-steer window
    of the stroke (deg/m; :func:`elastokin.physics.wheel.windowed_slope`); NaN, with a
    warning, when the window holds fewer than three distinct travel steps."""
    c = CHARACTERISTICS["bump_steer_deg_per_m"]
    return c.scale * windowed_slope(
        sweep.stroke(c.x), sweep.stroke(c.y), c.window[1], what=slope_subject(sweep, c),
        where=f"of wheel travel within +-{c.window[1]:g} mm on the stroke",
        remedy=finer(sweep, c.load_case))


def slope_subject(sweep: Sweep, c) -> str:
    """What a fitted characteristic ``c`` of ``sweep``'s model and wheel is, for a warning:
    ``model 'initial', right wheel: bump steer (bump_steer_deg_per_m)``."""
    wheel = f", {sweep.side} wheel" if sweep.side else ""
    return f"model '{sweep.model}'{wheel}: {c.label} ({c.name})"


def finer(sweep: Sweep, load_case: str) -> str:
    """The remedy for a slope from too few steps of ``sweep`` (a warning's words)."""
    if sweep.model == "test":
        return f"the K&C test file of {load_case} has too few steps there"
    return f"a finer step of the rig's {load_case} gives it"


def determined(value) -> float | None:
    """A summary figure as summary.json holds it: None when it is not determined (NaN)."""
    return None if value is None or not np.isfinite(value) else float(value)


def bump_steer_at_design_deg_per_m(sweep: Sweep) -> float | None:
    """Toe change per wheel travel at the static state (deg/m): the stroke's slope by
    central differences (``np.gradient`` on its uneven travel), read at wheel travel 0 as
    :func:`~elastokin.rig.sweeps.static_row_value` reads a column."""
    travel, toe = sweep.stroke("wheel_travel_mm"), sweep.stroke("toe_deg")
    if travel.size < 3:
        return None
    slope = np.gradient(toe, travel)
    stroke = Sweep(sweep.model, sweep.load_case, {
        "branch": np.full(travel.size, "stroke"), "wheel_travel_mm": travel, "slope": slope})
    value = static_row_value(stroke, "slope")
    return None if value is None else 1000.0 * value


def measured(sweep: Sweep, name: str) -> np.ndarray:
    """``name`` on the measured rows of a sweep: every branch but the ``approach`` from the
    design position to the start of the measured stroke (or to the first force)."""
    return sweep.columns[name][sweep.columns["branch"] != "approach"]


def summary_figures(sweeps: list[Sweep], kinematic: bool,
                    compliance: np.ndarray | None = None,
                    springs: dict[str, tuple[float, float]] | None = None) -> dict:
    """The summary figures of one model (None when the load case was not run, or a slope is
    not determined: :func:`elastokin.physics.wheel.slope`): steer amplitude, bump steer, the
    steering axis at the static state (the parallel-travel stroke at wheel travel 0: the
    design wheel load on the pad), every gradient of
    :data:`~elastokin.rig.channels.GRADIENTS` (over the measured rows, :func:`measured`), the
    compliance matrix, every spring's and damper's motion ratio at the static state and,
    with ``springs`` (:func:`spring_shares`), the wheel rate from the springs."""
    travel = find_sweep(sweeps, "parallel_travel")
    has_toe = travel is not None and "toe_deg" in travel.columns
    out = {"steer_amplitude_deg": steer_amplitude_deg(travel) if has_toe else None,
           "bump_steer_deg_per_m": determined(bump_steer_deg_per_m(travel)) if has_toe
           else None,
           "bump_steer_at_design_deg_per_m":
               determined(bump_steer_at_design_deg_per_m(travel)) if has_toe else None,
           "kinematic": kinematic}
    for name in STEERING_AXIS_COLUMNS:
        out[name] = static_row_value(travel, name) if travel is not None else None
    # every spring's and damper's motion ratio at the static state (parallel travel)
    out["motion_ratios"] = {} if travel is None else {
        name: static_row_value(travel, name) for name in travel.columns
        if name.endswith("_motion_ratio")}
    out["spring_wheel_rate_N_per_mm"] = springs_wheel_rate(out, springs or {})
    for name, g in GRADIENTS.items():
        sw = find_sweep(sweeps, g.load_case)
        ok = sw is not None and g.x in sw.columns and g.y in sw.columns
        out[name] = None if not ok else determined(g.scale * slope(
            measured(sw, g.x), measured(sw, g.y), what=slope_subject(sw, g),
            where=f"of {g.x} in the {g.load_case} sweep", remedy=finer(sw, g.load_case)))
    if compliance is not None:
        out["compliance_matrix"] = {
            "rows": "wheel-centre displacement x y z [mm], rotation x y z [deg]",
            "columns": "force x y z [N], torque x y z [N*mm] at the wheel centre",
            "frame": "config", "values": compliance.tolist()}
    return out


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


def spring_shares(suspension: Suspension) -> dict[str, tuple[float, float]]:
    """Every spring's (rate N/mm, share): the share of its rate a wheel takes in parallel
    travel, 1/2 for a spring both wheels compress (:func:`both_wheels`), else 1
    (:mod:`elastokin.physics.motion_ratio`)."""
    both = both_wheels(suspension)
    return {sp.name: (sp.rate_N_per_mm, 0.5 if sp.name in both else 1.0)
            for sp in suspension.springs}


def springs_wheel_rate(figures: dict, springs: dict[str, tuple[float, float]]
                       ) -> float | None:
    """The wheel rate from the springs of one wheel's summary ``figures`` (its springs'
    motion ratios at the static state; None without a ratio or a rate)."""
    ratios = figures.get("motion_ratios") or {}
    terms = [(rate, ratios.get(motion_ratio_column(length_column("spring", name))), share)
             for name, (rate, share) in springs.items()]
    terms = [t for t in terms if t[1] is not None]
    return determined(wheel_rate_from_springs(terms)) if terms else None
