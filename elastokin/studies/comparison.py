"""Models against K&C test data: the test files as sweeps, and the error of each model.

The test files (``docs/kc_test_data.md``, per-wheel signs) become :class:`~elastokin.kc.Sweep`
objects of the model ``test`` with the column names and signs of ``kc.csv`` (config frame:
lateral + to the vehicle's left, aligning torque about +up), so every chart and summary treats
them like a model. Branches are labelled as the rig sweeps them (parallel travel: ``approach``
down to rebound, ``stroke`` up to bump, ``return``; force sweeps: ``rise``, ``fall``,
``return``; vertical force: ``approach``, ``rise``, ``fall``).

Errors (model against test) compare **changes from the static state** (each curve's value at
input 0 on its first branch through 0), so that a static alignment offset does not hide the
characteristic: for every test point, the model's curve of the same branch is interpolated at
the test input; the RMS is over the test points inside the model's input range.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from elastokin.config.schema import RigSpec
from elastokin.config.suspension import Suspension
from elastokin.errors import MeasurementError
from elastokin.formats.kc_test import LOAD_CASES
from elastokin.rig.load_cases import Sweep

#: test channel -> kc column (per-wheel sign -> config-frame sign applied in to_sweep)
_COLUMNS = {
    "wheel_travel": "wheel_travel_mm",
    "toe": "toe_deg",
    "camber": "camber_deg",
    "wheel_centre_longitudinal": "wheel_centre_longitudinal_mm",
    "wheel_centre_lateral": "wheel_centre_lateral_mm",
    "vertical_force": "vertical_force_N",
    "lateral_force": "lateral_force_N",
    "longitudinal_force": "longitudinal_force_N",
    "aligning_torque": "aligning_torque_Nmm",
}
#: branch names as the rig sweeps each load case (see the module docstring)
_BRANCHES = {
    "parallel_travel": ("approach", "stroke", "return"),
    "vertical_force": ("approach", "rise", "fall"),
}
_FORCE_BRANCHES = ("rise", "fall", "return")

#: the rig input (x) column of each load case, kc.csv name (the test format's input channel)
INPUT_COLUMNS = {name: _COLUMNS[case.input] for name, case in LOAD_CASES.items()}
#: the errors of the contract: name -> (load case, x column, y column)
ERRORS = {
    "steer_vs_travel_rms_deg": ("parallel_travel", "wheel_travel_mm", "toe_deg"),
    "steer_vs_lateral_force_rms_deg": ("lateral_force", "lateral_force_N", "toe_deg"),
    "longitudinal_displacement_rms_mm": ("longitudinal_force_patch", "longitudinal_force_N",
                                         "wheel_centre_longitudinal_mm"),
}


def rig_for_test(test: list[Sweep], rig: RigSpec) -> RigSpec:
    """A rig that runs the load cases of the ``test`` sweeps over their input ranges (to the
    nearest whole step), at the step sizes of ``rig`` (its defaults where ``rig`` leaves a
    case out); load cases without test data are left out (parallel travel stays ``rig``'s).
    The stiffness fit runs this rig, whatever rig the report uses."""
    cases = {sw.load_case: sw for sw in test}
    fields = {}
    for name, info in RigSpec.model_fields.items():
        base = getattr(rig, name) or info.default  # every case has a default spec
        sw = cases.get(name)
        if sw is None:
            fields[name] = getattr(rig, name) if name == "parallel_travel" else None
            continue
        x = np.asarray(sw.columns[INPUT_COLUMNS[name]], float)
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
    return RigSpec(**fields)


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


def _branch_labels(load_case: str, test) -> np.ndarray:
    names = _BRANCHES.get(load_case, _FORCE_BRANCHES)
    x = test.input
    labels = np.empty(x.size, dtype=object)
    slices = list(test.branches)
    if load_case == "parallel_travel" and slices:
        # the stroke is the first rising branch; what comes before it is the approach
        first_up = next((i for i, sl in enumerate(slices) if x[sl][-1] > x[sl][0]), 0)
        names = ("approach",) * first_up + ("stroke", "return", "return")
    # a turning point belongs to the branch it ends (as the model's sweeps label it) ...
    for i in reversed(range(len(slices))):
        labels[slices[i]] = names[min(i, len(names) - 1)]
    # ... except that the travel stroke starts at the rebound point
    if load_case == "parallel_travel" and names[0] == "approach":
        labels[slices[0].stop - 1] = "stroke"
    return labels.astype(str)


def to_sweep(test, suspension: Suspension) -> Sweep:
    """A :class:`~elastokin.testdata.KCTest` as a sweep of the model ``test`` (kc.csv names,
    config-frame signs)."""
    s = suspension
    lateral_sign = float(s.left @ s.outboard)
    cols: dict[str, np.ndarray] = {"branch": _branch_labels(test.load_case, test)}
    for name, values in test.channels.items():
        col = _COLUMNS.get(name)
        if col is None:
            continue
        v = np.asarray(values, float)
        if name in ("wheel_centre_lateral", "lateral_force"):
            v = lateral_sign * v
        elif name == "aligning_torque":
            v = -lateral_sign * v
        cols[col] = v
    return Sweep("test", test.load_case, cols)


def read_test_sweeps(suspension: Suspension) -> tuple[list[Sweep], list[str]]:
    """The config's ``kc_test`` files as sweeps (one per load case found) and the files read.
    A file named in ``kc_test.files`` must exist; otherwise ``<load case>.csv`` is read when
    present."""
    from elastokin.formats.kc_test import read_kc_test

    s = suspension
    spec = s.kc_test
    if spec is None:
        return [], []
    folder = Path(s.source).parent / spec.folder
    for case in spec.files:
        if case not in LOAD_CASES:
            raise MeasurementError(f"{s.source}: key 'kc_test.files.{case}': unknown load case "
                                   f"(expected one of {', '.join(LOAD_CASES)})")
    sweeps, files = [], []
    for case in LOAD_CASES:
        path = folder / spec.files.get(case, f"{case}.csv")
        if not path.exists():
            if case in spec.files:
                raise MeasurementError(f"{s.source}: key 'kc_test.files.{case}': file {path} "
                                       "does not exist")
            continue
        test = read_kc_test(path)
        if test.load_case != case:
            raise MeasurementError(f"{path}: holds load case '{test.load_case}', but the "
                                   f"config reads it as '{case}'")
        sweeps.append(to_sweep(test, s))
        files.append(str(path))
    if not sweeps:
        raise MeasurementError(f"{s.source}: key 'kc_test': no K&C test file in {folder} "
                               f"(expected <load case>.csv, e.g. parallel_travel.csv)")
    return sweeps, files


def _segments(sweep: Sweep, x: str, y: str):
    """(branch, x, y) per branch in step order, the approach left out."""
    br = sweep.columns["branch"]
    for name in dict.fromkeys(br):
        if name == "approach":
            continue
        keep = br == name
        yield name, sweep.columns[x][keep], sweep.columns[y][keep]


def _static_value(sweep: Sweep, x: str, y: str) -> float:
    """y at x = 0 on the first branch that passes 0, or starts one step from it (a rig
    sweep's first step is already loaded); else the first row."""
    xs, ys = sweep.columns[x], sweep.columns[y]
    br = sweep.columns["branch"]
    for name in dict.fromkeys(br):
        keep = br == name
        xb, yb = xs[keep], ys[keep]
        if xb.size < 2:
            continue
        step = 1.01 * float(np.median(np.abs(np.diff(xb))))
        if xb.min() - step <= 0.0 <= xb.max() + step:
            order = np.argsort(xb)
            return float(np.interp(0.0, xb[order], yb[order]))
    return float(ys[0])


def curve_residuals(model: Sweep, test: Sweep, x: str, y: str,
                    clamp: bool = False) -> np.ndarray | None:
    """(model - test) changes from the static state at the test points, branch by branch
    (see the module docstring), in test-point order; None when a column is missing.
    Test points outside the model's input range are left out, or with ``clamp`` compared
    with the model's end value (a residual vector of fixed length, for fitting)."""
    for sw in (model, test):
        if x not in sw.columns or y not in sw.columns:
            return None
    y0m, y0t = _static_value(model, x, y), _static_value(test, x, y)
    model_branches = {name: (xb, yb) for name, xb, yb in _segments(model, x, y)}
    residuals = []
    for name, xt, yt in _segments(test, x, y):
        if name not in model_branches:
            continue
        xm, ym = model_branches[name]
        order = np.argsort(xm)
        xm, ym = xm[order], ym[order]
        inside = np.ones(xt.size, bool) if clamp else (xt >= xm[0]) & (xt <= xm[-1])
        residuals.append((np.interp(xt[inside], xm, ym) - y0m) - (yt[inside] - y0t))
    return np.concatenate(residuals) if residuals else np.empty(0)


def curve_error_rms(model: Sweep, test: Sweep, x: str, y: str) -> float | None:
    """RMS of (model - test) changes from the static state, branch by branch (see the module
    docstring); None when a column is missing or no test point lies in the model's range."""
    r = curve_residuals(model, test, x, y)
    return float(np.sqrt(np.mean(r ** 2))) if r is not None and r.size else None


def model_errors(model_sweeps: list[Sweep], test_sweeps: list[Sweep]) -> dict[str, float | None]:
    """The contract's errors of one model against the test (:data:`ERRORS`)."""
    out = {}
    for name, (case, x, y) in ERRORS.items():
        m = next((sw for sw in model_sweeps if sw.load_case == case), None)
        t = next((sw for sw in test_sweeps if sw.load_case == case), None)
        out[name] = None if m is None or t is None else curve_error_rms(m, t, x, y)
    return out
