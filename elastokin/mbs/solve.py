"""Quasi-static solves of a :class:`~elastokin.mbs.model.SuspensionModel` along the paths of
its attachments (supports and loads), from the design position.

Static "time" runs 0..1 over the steps; each attachment's path is a piecewise-linear function
of it (a constant, or a symbolic user function at C++ speed). One ``SolveStatic`` covers every
step (sensors record each in C++), or one per step for a model with ball-joint friction, whose
anchors slip between steps. Units mm, N, N*mm; config frame.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
from exudyn.advancedUtilities import CreateSymbolicUserFunction

from elastokin.errors import ModelError, SolverError
from elastokin.mbs import friction
from elastokin.mbs.assembly import free_parts, free_parts_message
from elastokin.mbs.contact import set_contact_path
from elastokin.mbs.exudyn_api import exu, exudyn_call
from elastokin.mbs.model import DEG, SuspensionModel
from elastokin.mbs.user_functions import make_path_function
from elastokin.physics.states import ModelState, PartPoses


def simulation_settings(model: SuspensionModel, steps: int):
    """Exudyn's static-solver settings from the config's ``solver`` section."""
    sv = model.suspension.solver
    ss = exu.SimulationSettings()
    ss.solution.file.write = False
    ss.solution.sensors.active = True  # internal storage only: every sensor has no file
    ss.solution.sensors.writePeriod = 0.0
    st = ss.staticSolver
    st.numberOfLoadSteps = steps
    st.useLoadFactor = False  # loads follow their user functions of t, not a load factor
    st.adaptiveStep = sv.adaptive_step
    st.verboseMode = 0
    st.stepInformation = 0
    st.newton.useModifiedNewton = sv.modified_newton
    st.newton.relativeTolerance = sv.newton_tolerance
    st.newton.absoluteTolerance = model.absolute_tolerance
    st.newton.maxIterations = sv.max_newton_iterations
    ss.linearSolver.solverType = exu.LinearSolverType.EigenDense
    # work Exudyn does for nothing here (issue 28, item 6; the Newton iterates, hence every
    # result, bit for bit the same): more than one pass of the discontinuous iteration (no
    # item of a frictionless model acts after a Newton step). (The loads' Jacobian is not
    # nothing: a force at a point of a turning part has one; leaving it out changed the force
    # cases at 1e-7.)
    if model.options.discontinuous_iterations is not None:
        st.discontinuous.maxIterations = model.options.discontinuous_iterations
    elif not model.friction:
        st.discontinuous.maxIterations = 1
    return ss


def set_path(model: SuspensionModel, kind: str, item: int, ts: np.ndarray,
             values: np.ndarray) -> None:
    """Make an input follow the piecewise-linear path ``values`` (n+1, k) over load time
    ``ts``: a constant when it is constant, otherwise a user function of t (``kind``:
    "offset" of a support's generic joint, or "load")."""
    mbs = model.mbs
    set_param = mbs.SetObjectParameter if kind == "offset" else mbs.SetLoadParameter
    uf_name = "offsetUserFunction" if kind == "offset" else "loadVectorUserFunction"
    const = np.allclose(values, values[0], rtol=0.0, atol=0.0)
    if const and kind != "offset":
        set_param(item, uf_name, 0)
        set_param(item, "loadVector", values[0].tolist())
        return
    symbolic = model.options.user_functions == "symbolic"
    fn = make_path_function(ts, values, kind, symbolic=symbolic)
    if symbolic:
        fn = CreateSymbolicUserFunction(mbs, fn, uf_name, item)
        model.keep_alive.append(fn)
    set_param(item, uf_name, fn)


def _refined(model, inputs, steps: int, substeps: int) -> dict[str, np.ndarray]:
    """Every path subdivided linearly into ``substeps`` steps per step; loads start at their
    first value, supports at offset 0 (the design position)."""
    out = {}
    for name, v in inputs.items():
        start = np.zeros((1, v.shape[1])) if name in model.supports else v[:1]
        path = np.vstack([start, v])
        s = np.linspace(0.0, steps, steps * substeps + 1)
        out[name] = np.array([np.interp(s, np.arange(steps + 1), c) for c in path.T]).T[1:]
    return out


def solve_path(model: SuspensionModel, inputs: Mapping[str, np.ndarray], what: str,
               settle: Mapping[str, np.ndarray] | None = None, solve_per_step: bool = False,
               substeps: int | None = None) -> list[ModelState]:
    """Solve a sequence of quasi-static steps from the design position.

    inputs: attachment name -> its values per step: a support's offset (n, 6) (mm, rad; the
        support is active in this solve), a load's vector (n, 3) (N or N*mm). Loads without
        values are zero, supports without values inactive.
    settle: with ball-joint friction, the rig starts from the settled suspension: a first
        step with the supports at offset 0 and these load values (others zero), friction
        released, then every ball joint at rest there; that step is not returned.
    solve_per_step: one ``SolveStatic`` per step (the slow, straightforward way, kept for
        benchmarks); a model with friction always solves per step.
    substeps: solver steps per returned step (default: the model's, from its friction spec).
    Raises :class:`SolverError` naming the step that did not converge.
    """
    inputs = {k: np.atleast_2d(np.asarray(v, float)) for k, v in inputs.items()}
    unknown = sorted(set(inputs) - set(model.supports) - set(model.loads))
    if unknown or not inputs:
        raise ModelError(f"solve_path: give values for attachments of the model (unknown: "
                         f"{', '.join(unknown) or 'none given'})")
    n = len(next(iter(inputs.values())))
    substeps = model.substeps if substeps is None else int(substeps)
    if substeps > 1:
        states = solve_path(model, _refined(model, inputs, n, substeps), what, settle,
                            solve_per_step, substeps=1)
        return states[substeps - 1::substeps]
    settling = bool(model.friction)
    if settling:
        solve_per_step = True
        friction.reset(model)
        first = {name: (np.zeros((1, v.shape[1])) if name in model.supports else
                        np.asarray((settle or {}).get(name, np.zeros(v.shape[1])),
                                   float).reshape(1, -1)) for name, v in inputs.items()}
        inputs = {name: np.vstack([first[name], v]) for name, v in inputs.items()}
        n += 1
    ts = np.linspace(0.0, 1.0, n + 1)
    applied = set_attachment_paths(model, inputs, ts, n)
    if model.load_recorder is not None:
        model.load_recorder.update()  # sensors of attachments added since the last solve
    data, loads = _solve_steps(model, ts, n, what, solve_per_step, settling)
    states = model_states(model, data, loads, applied)
    return states[1:] if settling else states


def set_attachment_paths(model: SuspensionModel, inputs, ts: np.ndarray, n: int) -> dict:
    """Every attachment's path over ``ts``: every path starts from the design state at t = 0
    (support offset 0, loads at the first step's value). Returns the loads' values per step."""
    model.keep_alive.clear()
    applied = {}
    for name, e in model.loads.items():
        v = inputs.get(name, np.zeros((n, 3)))
        if e["kind"] == "contact":  # a force at the tyre's contact point (mbs.contact)
            set_contact_path(model, name, ts, np.vstack([v[:1], v]))
        else:
            set_path(model, "load", e["load"], ts, np.vstack([v[:1], v]))
        applied[name] = v
    for name, e in model.supports.items():
        active = name in inputs or name in model.locks
        if name in inputs:
            set_path(model, "offset", e["object"], ts, np.vstack([np.zeros((1, 6)),
                                                                  inputs[name]]))
        elif active:  # a lock: held at its offset from the design position on
            set_path(model, "offset", e["object"], ts,
                     np.vstack([np.zeros((1, 6)), np.tile(model.locks[name], (n, 1))]))
        model.mbs.SetObjectParameter(e["object"], "activeConnector", active)
    return applied


def _solve_steps(model: SuspensionModel, ts: np.ndarray, n: int, what: str,
                 solve_per_step: bool, settling: bool) -> list[dict]:
    mbs = model.mbs
    initial = exu.ConfigurationType.Initial
    q0 = mbs.systemData.GetODE2Coordinates(initial)
    mbs.systemData.SetODE2Coordinates(q0, exu.ConfigurationType.Current)
    mbs.Assemble()
    ss = simulation_settings(model, n)
    label = f"{model.suspension.source}: {what}"

    def solve() -> tuple[bool, str]:
        try:
            return exudyn_call(lambda: mbs.SolveStatic(ss), label) is not False, ""
        except SolverError as exc:
            return False, f" (Exudyn: {str(exc).removeprefix(label + ': ')})"

    if not solve_per_step:
        ok, detail = solve()
        data, loads = recorded_arrays(model, ts)
        rows = range(len(data[f"part:{model.wheel_part}:R"]))
    else:
        ss.staticSolver.numberOfLoadSteps = 1
        ss.staticSolver.loadStepDuration = 1.0 / n
        rows, ok, detail = [], True, ""
        try:
            for k in range(n):
                ss.staticSolver.loadStepStart = ts[k]
                ok, detail = _solve_one_step(model, solve, settling and k == 0)
                if not ok:
                    break
                rows.append(recorded(model, ts[k:k + 2])[-1])
                mbs.systemData.SetODE2Coordinates(mbs.systemData.GetODE2Coordinates(),
                                                  initial)
        finally:
            mbs.systemData.SetODE2Coordinates(q0, initial)
    if not ok or len(rows) < n:
        free = free_parts(model, simulation_settings(model, 1))  # a singular Jacobian?
        if free:
            raise ModelError(free_parts_message(model, free))
        sv = model.suspension.solver
        raise SolverError(
            f"{label}: static solve did not converge after step {len(rows)} of {n} "
            f"(Newton tolerance {sv.newton_tolerance:g}, at most {sv.max_newton_iterations} "
            f"iterations){detail}; check the geometry and the loads, or the solver settings")
    if solve_per_step:  # the rows as arrays over the steps
        data = {k: np.array([row[k] for row in rows]) for k in rows[0] if k != "loads"}
        loads = None if rows[0]["loads"] is None else [row["loads"] for row in rows]
    return data, loads


def _solve_one_step(model: SuspensionModel, solve, settle: bool) -> tuple[bool, str]:
    if settle:  # friction released, then at rest where it settled
        friction.set_active(model, False)
        ok, detail = solve()
        friction.set_active(model, True)
        if ok:
            friction.at_rest(model)
        return ok, detail
    for _ in range(friction.FRICTION_ITERATIONS):
        ok, detail = solve()
        # friction: re-solve the step until no anchor has to slip further
        if not ok or not model.friction or friction.slip(model) < friction.FRICTION_TOLERANCE:
            return ok, detail
    return False, (f" (ball-joint friction: anchors still slipping after "
                   f"{friction.FRICTION_ITERATIONS} re-solves)")


def recorded(model: SuspensionModel, ts: np.ndarray) -> list[dict[str, np.ndarray]]:
    """Sensor values at the load-step times ``ts[1:]`` that were reached (adaptive sub-steps
    skipped), one dict of arrays per step (and its ``loads``)."""
    picked, loads = recorded_arrays(model, ts)
    n = len(picked[f"part:{model.wheel_part}:R"])
    rows = [{k: v[i] for k, v in picked.items()} for i in range(n)]
    for i, row in enumerate(rows):
        row["loads"] = None if loads is None else loads[i]
    return rows


def recorded_arrays(model: SuspensionModel, ts: np.ndarray
                    ) -> tuple[dict[str, np.ndarray], list | None]:
    """Sensor values at the load-step times ``ts[1:]`` that were reached (adaptive sub-steps
    skipped), as arrays (steps, k) by sensor key (bushings combined), and each step's load
    table (None without a load recorder)."""
    data = {k: np.asarray(model.mbs.GetSensorStoredData(v)) for k, v in model.sensors.items()}
    t = data[f"part:{model.wheel_part}:R"][:, 0]
    # each load step's last record (an adaptive step records its sub-steps too), up to the
    # first step not reached
    hit = np.abs(t[:, None] - ts[None, 1:]) < 1e-9
    found = hit.any(axis=0)
    reached = found.size if found.all() else int(np.argmin(found))
    idx = (t.size - 1 - np.argmax(hit[::-1, :reached], axis=0)).astype(int)
    loads = None
    if model.load_recorder is not None and idx.size:  # from the sensors as stored
        table = model.load_recorder.tables(data, idx)
        loads = [table.step(i) for i in range(idx.size)]
    picked = combined_sensors({k: v[idx, 1:] for k, v in data.items()
                               if not k.startswith("load:")}, model)
    return picked, loads


def combined_sensors(data: dict[str, np.ndarray], model: SuspensionModel
                     ) -> dict[str, np.ndarray]:
    """Sensor values (steps, k) with each bushing's deflection (mm and deg) and load in one
    6-vector per step (bushings whose sensors were not read are left out), and each beam
    part's node positions (steps, m, 3) and rotations from their design frames (steps, m, 3,
    3) in one array each (``beam:<part>:node_x``, ``beam:<part>:node_R``)."""
    for name in model.bushings:
        if f"bushing:{name}:d" not in data:
            continue
        data[f"bushing:{name}:u"] = np.concatenate(
            [data.pop(f"bushing:{name}:d"), data.pop(f"bushing:{name}:r") / DEG], axis=1)
        data[f"bushing:{name}:load"] = np.concatenate(
            [data.pop(f"bushing:{name}:f"), data.pop(f"bushing:{name}:t")], axis=1)
    for part, line in model.node_lines.items():
        if f"part:node:{line[0]}:R" not in data:
            continue
        design = np.array([model.beams[part].frames[n] for n in line])
        R = np.stack([data.pop(f"part:node:{n}:R") for n in line], axis=1)
        R = R.reshape(len(R), len(line), 3, 3)  # (not -1: a run that reached no step has 0)
        data[f"beam:{part}:node_R"] = R @ np.swapaxes(design, 1, 2)
        data[f"beam:{part}:node_x"] = np.stack([data.pop(f"part:node:{n}:disp")
                                                for n in line], axis=1)
    return data


def model_states(model: SuspensionModel, data: dict[str, np.ndarray], loads: list | None,
                 applied: dict[str, np.ndarray]) -> list[ModelState]:
    """The model's state at every step (bushings without values left out) from its sensors'
    values as arrays (steps, k) (:func:`recorded_arrays`), each step's load table and the
    loads applied (steps, 3); the keys are sorted out once, not per step."""
    n = len(data[f"part:{model.wheel_part}:R"])
    springs = [(name, (-data[f"spring:{name}"][:, 0]).tolist()) for name in model.springs]
    scalars = [(f"stop:{name}", np.abs(data[f"stop:{name}"][:, 0]).tolist())
               for name in model.stops]
    # spring and damper lengths (mm) between their points
    scalars += [(f"{k}_length:{n}", data[f"{k}_length:{n}"][:, 0].tolist())
                for k, items in (("spring", model.springs), ("damper", model.dampers))
                for n in items]
    if model.anti_roll_bar is not None:
        scalars += [("arb:twist_deg", (data["arb:r"][:, 2] / DEG).tolist()),
                    ("arb:torque_Nmm", data["arb:t"][:, 2].tolist())]
    bushings = [(name, data[f"bushing:{name}:u"], data[f"bushing:{name}:load"],
                 e.get("ideal") is None) for name, e in model.bushings.items()
                if f"bushing:{name}:u" in data]
    nan = np.full(6, np.nan)
    rotation = [(p, data[f"part:{p}:R"].reshape(-1, 3, 3)) for p in model.pose_refs]
    displacement = [(p, data[f"part:{p}:disp"]) for p in model.pose_refs]
    supports = [(name, data[f"support:{name}"]) for name in model.supports]
    points = [(k.removeprefix("point:"), v) for k, v in data.items() if k.startswith("point:")]
    nodes = [(part, data[f"beam:{part}:node_x"], data[f"beam:{part}:node_R"])
             for part in model.node_lines if f"beam:{part}:node_x" in data]
    out = []
    for i in range(n):
        defl = {name: u[i] + model.initial_deflection[name] if own else u[i]
                for name, u, _, own in bushings}
        load = {name: f[i] if own else nan.copy() for name, _, f, own in bushings}
        poses = PartPoses({p: r[i] for p, r in rotation}, {p: d[i] for p, d in displacement},
                          model.pose_refs)
        for part, x, R in nodes:  # combined_sensors: rotations from the design frames
            poses.node_mm[part], poses.node_rotation[part] = x[i], R[i]
        out.append(ModelState(poses, {name: v[i] for name, v in springs}, defl, load,
                              {name: v[i] for name, v in supports},
                              {k: v[i] for k, v in applied.items()},
                              {name: v[i] for name, v in points},
                              scalars={k: v[i] for k, v in scalars},
                              loads=None if loads is None else loads[i]))
    return out


def state_arrays(model: SuspensionModel, data: dict[str, np.ndarray],
                 applied: dict[str, np.ndarray]) -> dict[str, object]:
    """:func:`model_states` as arrays over the steps: from sensor values (steps, k) (bushings
    combined, :func:`combined_sensors`) and the loads applied (steps, 3), the fields of a
    :class:`~elastokin.physics.states.ModelState` as arrays over the steps (``poses``: per
    part (rotation (n, 3, 3), displacement (n, 3)))."""
    scalars = {f"stop:{n}": np.abs(data[f"stop:{n}"][:, 0]) for n in model.stops}
    scalars.update({f"{k}_length:{n}": data[f"{k}_length:{n}"][:, 0]
                    for k, items in (("spring", model.springs), ("damper", model.dampers))
                    for n in items})
    if model.anti_roll_bar is not None:
        scalars["arb:twist_deg"] = data["arb:r"][:, 2] / DEG
        scalars["arb:torque_Nmm"] = data["arb:t"][:, 2]
    defl, load = {}, {}
    for name, e in model.bushings.items():
        if f"bushing:{name}:u" not in data:
            continue
        u = data[f"bushing:{name}:u"]
        if e.get("ideal") is None:
            defl[name], load[name] = u + model.initial_deflection[name], \
                data[f"bushing:{name}:load"]
        else:
            defl[name], load[name] = u, np.full(u.shape, np.nan)
    return {
        "spring_force_N": {n: -data[f"spring:{n}"][:, 0] for n in model.springs},
        "bushing_deflection": defl, "bushing_load": load, "scalars": scalars,
        "poses": {n: (data[f"part:{n}:R"].reshape(-1, 3, 3), data[f"part:{n}:disp"])
                  for n in model.pose_refs},
        "reference_mm": model.pose_refs,
        "support_force_N": {n: data[f"support:{n}"] for n in model.supports},
        "points": {k.removeprefix("point:"): v for k, v in data.items()
                   if k.startswith("point:")},
        "applied": applied,
    }
