"""Models against K&C test data: the error of a model's sweep against a test sweep, and the
rig that runs a test's load cases.

Errors compare **changes from the static state** (each curve's value at input 0 on its first
branch through 0), so that a static alignment offset does not hide the characteristic: for
every test point, the model's curve of the same branch is interpolated at the test input; the
RMS is over the test points inside the model's input range. Units of the columns compared
(mm, deg).
"""

from __future__ import annotations

import numpy as np
from pydantic import ValidationError

from elastokin.config.schema.rig import RigSpec
from elastokin.errors import MeasurementError
from elastokin.rig.channels import ERRORS, LOAD_CASES
from elastokin.rig.sweeps import Sweep, branch_names, find_sweep


def rig_for_test(test: list[Sweep], rig: RigSpec) -> RigSpec:
    """A rig that runs the load cases of the ``test`` sweeps over their input ranges (to the
    nearest whole step), at the step sizes of ``rig`` (its defaults where ``rig`` leaves a
    case out); load cases without test data are left out (parallel travel stays ``rig``'s).
    The stiffness fit runs this rig, whatever rig the report uses."""
    cases: dict[str, Sweep] = {}
    for sw in test:  # the first sweep of a load case: the config side's (read_test_sweeps)
        cases.setdefault(sw.load_case, sw)
    fields = {}
    for name, info in RigSpec.model_fields.items():
        base = getattr(rig, name) or info.default  # every case has a default spec
        sw = cases.get(name) if LOAD_CASES[name].corner else None
        if sw is None:
            fields[name] = getattr(rig, name) if name == "parallel_travel" else None
            continue
        x = np.asarray(sw.columns[LOAD_CASES[name].input], float)
        lo, hi = float(np.nanmin(x)), float(np.nanmax(x))

        def steps(v: float, h: float) -> float:  # to the nearest whole step
            return float(np.round(v / h) * h)

        if name == "parallel_travel":
            h = base.step_mm
            fields[name] = base.model_copy(update={
                "rebound_mm": min(-h, steps(lo, h)), "bump_mm": max(h, steps(hi, h)),
                "unloading": "return" in set(sw.columns["branch"])})
        elif name == "vertical_force":
            h = base.step_N
            fields[name] = base.model_copy(update={"min_N": max(h, steps(lo, h)),
                                                   "max_N": max(2 * h, steps(hi, h))})
        else:
            torque = name == "aligning_torque"
            h = base.step_Nmm if torque else base.step_N
            fields[name] = base.model_copy(update={
                "amplitude_Nmm" if torque else "amplitude_N": max(h, steps(max(-lo, hi), h))})
    # validated again: the test's input ranges must give a rig within the step bounds
    data = {k: (v.model_dump() if v is not None else None) for k, v in fields.items()}
    try:
        return RigSpec.model_validate(data)
    except ValidationError as err:
        problem = err.errors()[0]
        where = ".".join(str(p) for p in problem["loc"])
        raise MeasurementError(f"K&C test data: the rig that runs them ({where}): "
                               f"{problem['msg'].removeprefix('Value error, ')}") from None


def travel_stroke_note(models: dict[str, list[Sweep]], test: list[Sweep]) -> str | None:
    """A warning when the models' parallel-travel stroke differs from the test's by more than
    one step (steer amplitudes are then over different strokes), else None."""
    t = next((sw for sw in test if sw.load_case == "parallel_travel"), None)
    if t is None:
        return None
    tx = t.stroke("wheel_travel_mm")
    for label, sweeps in models.items():
        m = next((sw for sw in sweeps if sw.load_case == "parallel_travel"), None)
        if m is None:
            continue
        mx = m.stroke("wheel_travel_mm")
        step = float(np.median(np.abs(np.diff(mx)))) if mx.size > 1 else 0.0
        if abs(mx.min() - tx.min()) > step + 1e-9 or abs(mx.max() - tx.max()) > step + 1e-9:
            return (f"the test's travel stroke ({tx.min():.0f} to {tx.max():.0f} mm) differs "
                    f"from the rig's (model '{label}': {mx.min():.0f} to {mx.max():.0f} mm): "
                    "steer amplitudes are over different strokes; the errors use the test "
                    "points inside the model's stroke")
    return None


def _segments(sweep: Sweep, x: str, y: str):
    """(branch, x, y) per branch in step order, the approach left out."""
    br = sweep.columns["branch"]
    for name in branch_names(br):
        if name == "approach":
            continue
        keep = br == name
        yield name, sweep.columns[x][keep], sweep.columns[y][keep]


def static_value(sweep: Sweep, x: str, y: str) -> float:
    """y at x = 0 on the first branch that passes 0, or starts one step from it (a rig
    sweep's first step is already loaded); else the first row. The errors and the charts of a
    force case measure every curve from this value."""
    xs, ys = sweep.columns[x], sweep.columns[y]
    br = sweep.columns["branch"]
    for name in branch_names(br):
        keep = br == name
        xb, yb = xs[keep], ys[keep]
        if xb.size < 2:
            continue
        step = 1.01 * float(np.median(np.abs(np.diff(xb))))
        if xb.min() - step <= 0.0 <= xb.max() + step:
            order = np.argsort(xb)
            return float(np.interp(0.0, xb[order], yb[order]))
    return float(ys[0])


def residual_points(model: Sweep, test: Sweep, x: str, y: str, clamp: bool = False
                    ) -> list[tuple[str, np.ndarray, np.ndarray]] | None:
    """(branch, test input, model - test change from the static state) per branch of the
    test, in test-point order (see the module docstring); None when a column is missing.
    Test points outside the model's input range are left out, or with ``clamp`` compared
    with the model's end value."""
    for sw in (model, test):
        if x not in sw.columns or y not in sw.columns:
            return None
    y0m, y0t = static_value(model, x, y), static_value(test, x, y)
    model_branches = {name: (xb, yb) for name, xb, yb in _segments(model, x, y)}
    out = []
    for name, xt, yt in _segments(test, x, y):
        if name not in model_branches:
            continue
        xm, ym = model_branches[name]
        order = np.argsort(xm)
        xm, ym = xm[order], ym[order]
        inside = np.ones(xt.size, bool) if clamp else (xt >= xm[0]) & (xt <= xm[-1])
        out.append((name, xt[inside],
                    (np.interp(xt[inside], xm, ym) - y0m) - (yt[inside] - y0t)))
    return out


def curve_residuals(model: Sweep, test: Sweep, x: str, y: str,
                    clamp: bool = False) -> np.ndarray | None:
    """(model - test) changes from the static state at the test points, branch by branch
    (:func:`residual_points`), in test-point order; None when a column is missing."""
    points = residual_points(model, test, x, y, clamp)
    if points is None:
        return None
    return np.concatenate([r for _, _, r in points]) if points else np.empty(0)


def curve_error_rms(model: Sweep, test: Sweep, x: str, y: str) -> float | None:
    """RMS of (model - test) changes from the static state, branch by branch (see the module
    docstring); None when a column is missing or no test point lies in the model's range."""
    r = curve_residuals(model, test, x, y)
    return float(np.sqrt(np.mean(r ** 2))) if r is not None and r.size else None


def model_errors(model_sweeps: list[Sweep], test_sweeps: list[Sweep]) -> dict[str, float | None]:
    """The errors of one model against the test on one wheel
    (:data:`elastokin.rig.channels.ERRORS`)."""
    out = {}
    for name, e in ERRORS.items():
        m, t = find_sweep(model_sweeps, e.load_case), find_sweep(test_sweeps, e.load_case)
        out[name] = None if m is None or t is None else curve_error_rms(m, t, e.x, e.y)
    return out


def errors_by_side(model_sweeps: dict[str, list[Sweep]], test_sweeps: dict[str, list[Sweep]],
                   side: str) -> dict:
    """The errors of one model against the test on every wheel the test has (sweeps by
    side): the config ``side``'s as :func:`model_errors` gives them, each other wheel's
    under its side's name (``{"right": {metric: RMS}}``) when the model has that wheel."""
    out: dict = model_errors(model_sweeps.get(side, []), test_sweeps.get(side, []))
    for other, sweeps in test_sweeps.items():
        if other != side and sweeps and model_sweeps.get(other):
            out[other] = model_errors(model_sweeps[other], sweeps)
    return out
