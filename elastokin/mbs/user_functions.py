"""Exudyn user functions of a model: bushing laws and rig input paths, written in closed form
(hinge functions) so that Exudyn converts them to symbolic functions evaluated at C++ speed
(:func:`exudyn.advancedUtilities.CreateSymbolicUserFunction`). Units mm, N, N*mm; rotations
in rad inside Exudyn, deg in the bushing laws."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from exudyn.advancedUtilities import CreateSymbolicUserFunction

from elastokin.mbs.exudyn_api import exu

#: deg per rad as the user functions multiply Exudyn's rotations (rad) into the laws' deg
DEG_PER_RAD = 57.29577951308232


def path_hinges(ts: np.ndarray, values: np.ndarray) -> list[tuple[float, float, list]]:
    """Each column of the piecewise-linear path ``values`` (n+1, k) over ``ts`` (n+1,) as
    (c, k0, [(t_i, dk_i)]) with v(t) = c + k0*t + sum dk_i*max(t - t_i, 0); hinges whose
    slope change is negligible are dropped."""
    ts = np.asarray(ts, float)
    values = np.asarray(values, float).reshape(ts.size, -1)
    out = []
    for v in values.T:
        slopes = np.diff(v) / np.diff(ts)
        k0 = float(slopes[0])
        tol = 1e-12 * max(1.0, float(np.max(np.abs(slopes))))
        hinges = [(float(ts[i]), float(slopes[i] - slopes[i - 1]))
                  for i in range(1, slopes.size) if abs(slopes[i] - slopes[i - 1]) > tol]
        out.append((float(v[0] - k0 * ts[0]), k0, hinges))
    return out


def make_path_function(ts: np.ndarray, values: np.ndarray, kind: str, symbolic: bool):
    """A rig input path as an Exudyn user function of load time t: ``kind`` "load" gives a
    ``loadVectorUserFunction`` (3 values), "offset" a generic joint ``offsetUserFunction``
    (6 values). Written with hinge functions so that it converts to a symbolic function."""
    columns = path_hinges(ts, values)
    maxf = max_function(symbolic)

    def value(i, t):
        c, k0, hinges = columns[i]
        out = c + k0 * t
        for ti, dk in hinges:
            out = out + dk * maxf(t - ti, 0.0)
        return out

    if kind == "offset":
        def offset(mbs, t, itemNumber, offsetUserFunctionParameters):
            return [value(0, t), value(1, t), value(2, t), value(3, t), value(4, t),
                    value(5, t)]
        return offset

    def load(mbs, t, loadVector):
        return [value(0, t), value(1, t), value(2, t)]
    return load


def _max(a, b):
    return a if a > b else b


def max_function(symbolic: bool):
    """max(a, b) for a user function: Exudyn's symbolic max, or Python's comparison."""
    return exu.symbolic.max if symbolic else _max


def attach_user_function(model, obj: int, parameter: str, function, symbolic: bool,
                         keep: list | None = None) -> None:
    """Set ``function`` as the user function ``parameter`` of object ``obj``; symbolic: as
    Exudyn's symbolic function, its expression tree kept in ``keep`` (default: with the
    model's bushing laws, for the model's life; a rig path's with the current solve's,
    ``model.keep_alive``), which it must outlive."""
    if symbolic:
        function = CreateSymbolicUserFunction(model.mbs, function, parameter, obj)
        (model.bushing_functions if keep is None else keep).append(function)
    model.mbs.SetObjectParameter(obj, parameter, function)


def make_bushing_function(laws: Sequence, initial_deflection: Sequence, symbolic: bool):
    """The bushing's 6 loads (N, N*mm) as an Exudyn ``springForceTorqueUserFunction``.

    Deflection in the bushing frame: displacement (mm) and Tait-Bryan rotation (rad, converted
    to deg), plus the initial deflection; each direction's law is written in closed form (hinge
    functions, times a polynomial for a progressive law; see :mod:`elastokin.physics.laws`), so the
    same closure is converted to a symbolic function.
    """
    # plain numbers, or symbolic variables of a parametric bushing (mbs.bushings)
    u0 = [x if isinstance(x, exu.symbolic.Real) else float(x) for x in initial_deflection]
    maxf = max_function(symbolic)

    def evaluate(i, v):
        return laws[i].expression(v, maxf)

    def bushing_loads(mbs, t, itemNumber, displacement, rotation, velocity, angularVelocity,
                      stiffness, damping, rotJ0, rotJ1, offset):
        return [evaluate(0, displacement[0] + u0[0]),
                evaluate(1, displacement[1] + u0[1]),
                evaluate(2, displacement[2] + u0[2]),
                evaluate(3, rotation[0] * DEG_PER_RAD + u0[3]),
                evaluate(4, rotation[1] * DEG_PER_RAD + u0[4]),
                evaluate(5, rotation[2] * DEG_PER_RAD + u0[5])]

    return bushing_loads
