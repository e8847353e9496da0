"""The targets of a design study evaluated at a design point: the optimiser's objective, its
constraints and their exact gradients, and a readable verdict per target.

- A target curve: the model's ``y`` interpolated at the target's ``x`` values on the sweep's
  widest measured branch (the stroke of a travel, the fall of a force sweep); changes from
  x = 0 when ``relative``. Its weighted mean square error (in units of its tolerance, or of
  y) is an objective term; with a tolerance, every point within it is a constraint.
- A target characteristic: its square error (in units of its tolerance, or of itself) times
  its weight in the objective, with a tolerance a constraint; a range, two constraints.
- Link lengths within a range and hardpoints out of keep-out boxes: constraints.

Constraints are ``g >= 0``: a band ``|e| <= tol`` (a tolerance, a range about its middle)
as ``1 - (e / tol)^2``. Derivatives: the rig's
tangents (``Sweep.tangents``, ``DesignRun.summary_tangents``) through the interpolation by
central differences (exact: it is piecewise linear), the geometry's through the variables'
twin suspensions.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from elastokin.config.schema.rig import RigSpec
from elastokin.config.suspension import Suspension
from elastokin.errors import ConfigError
from elastokin.formats.targets import Targets, characteristic_unit
from elastokin.rig.channels import CHARACTERISTICS
from elastokin.rig.sweeps import Sweep, branch_names
from elastokin.studies.design_runs import DesignRun

#: the load case each axle characteristic needs (the others: the compliance matrix)
AXLE_LOAD_CASES = {"roll_centre": "parallel_travel", "roll_stiffness": "roll_vertical_force",
                   "anti_roll_bar": "roll_vertical_force", "roll_": "roll_vertical_force",
                   "axle_roll": "roll_vertical_force", "steering": "steering",
                   "percent_ackermann": "steering", "ackermann": "steering",
                   "outside_turn": "steering", "max_steer": "steering",
                   "ride_rate": "vertical_force"}


def characteristic_load_case(name: str) -> str:
    """The load case a characteristic (a targets file's name) is computed from."""
    base = name.split(".")[-1]
    if name.startswith("axle."):
        if base == "roll_centre_height_force_based_mm":
            return "parallel_travel"
        return next((case for prefix, case in AXLE_LOAD_CASES.items()
                     if base.startswith(prefix)), "parallel_travel")
    return CHARACTERISTICS[base].load_case or "parallel_travel"


#: the characteristics computed from the compliance matrix (by name or prefix)
FROM_COMPLIANCE = ("axle.percent_anti", "axle.roll_centre_height_force_based_mm",
                   "axle.named_compliances", "compliance")


def needs_compliance(targets: Targets) -> bool:
    """Whether a target reads the compliance matrix (anti-dive, the force-based roll
    centre, the named compliances)."""
    return any(name.startswith(FROM_COMPLIANCE) for name in targets.spec.characteristics)


def target_rig(suspension: Suspension, targets: Targets) -> RigSpec:
    """The config's rig with only the load cases the targets need."""
    needed = {c.load_case for c in targets.spec.curves.values()}
    needed |= {characteristic_load_case(n) for n in targets.spec.characteristics}
    rig = suspension.rig
    off = {name: None for name in type(rig).model_fields
           if name != "parallel_travel" and name not in needed}
    return rig.model_copy(update=off)


@dataclass
class TargetRow:
    """One target's verdict: its name, kind (curve, characteristic, link, keep-out), the
    model's value (worst point of a curve), what is asked, whether it is met, and by how much
    it is missed (in its own unit; 0 when met)."""

    name: str
    kind: str
    value: float
    asked: str
    met: bool
    miss: float
    unit: str = ""


@dataclass
class TargetValues:
    """Every target at one design point: the objective and its gradient (per variable),
    the constraints ``g >= 0`` with their labels and Jacobian, and the verdicts."""

    objective: float
    gradient: np.ndarray
    constraints: np.ndarray
    jacobian: np.ndarray
    labels: list[str]
    rows: list[TargetRow] = field(default_factory=list)
    curves: dict[str, tuple[np.ndarray, np.ndarray]] = field(default_factory=dict)

    @property
    def met(self) -> bool:
        return all(r.met for r in self.rows)

    @property
    def violation(self) -> float:
        """The largest constraint violation (0 when every constraint holds)."""
        return float(max(0.0, -np.min(self.constraints))) if self.constraints.size else 0.0


def curve_branch(sweep: Sweep, x: str) -> np.ndarray:
    """The rows of the sweep's widest measured branch in ``x`` (the first of equals)."""
    branch = np.asarray(sweep.columns["branch"])
    best, rows = -1.0, np.flatnonzero(branch != "approach")
    for name in branch_names(branch):
        if name == "approach":
            continue
        r = np.flatnonzero(branch == name)
        xs = np.asarray(sweep.columns[x], float)[r]
        if r.size > 1 and np.ptp(xs) > best + 1e-9:
            best, rows = float(np.ptp(xs)), r
    return rows


def curve_values(sweep: Sweep, x: str, y: str, at: np.ndarray, relative: bool,
                 shift: np.ndarray | None = None) -> np.ndarray:
    """The model's ``y`` at ``at`` (x values) on the widest branch; with ``shift``
    (variables,) the columns moved along their tangents by it (central differences)."""
    rows = curve_branch(sweep, x)
    xs = np.asarray(sweep.columns[x], float)[rows]
    ys = np.asarray(sweep.columns[y], float)[rows]
    if shift is not None:
        xs = xs + sweep.tangents[x][rows] @ shift if x in sweep.tangents else xs
        ys = ys + sweep.tangents[y][rows] @ shift
    order = np.argsort(xs)
    xs, ys = xs[order], ys[order]
    out = np.interp(at, xs, ys, left=np.nan, right=np.nan)
    if relative:
        out = out - np.interp(0.0, xs, ys)
    return out


def target_values(run: DesignRun, targets: Targets, label: str,
                  derivatives: bool = True) -> TargetValues:
    """Every target of ``targets`` on model ``label`` of ``run`` (module docstring)."""
    spec = targets.spec
    n = run.values.size
    terms: list[tuple[float, np.ndarray]] = []  # objective residuals and their gradients
    cons: list[tuple[str, float, np.ndarray]] = []  # (label, g, dg)
    rows: list[TargetRow] = []
    curves = {}
    for name, c in spec.curves.items():
        sweep = run.sweep(label, c.load_case, c.side)
        at = np.asarray(c.points[c.x], float)
        want = np.asarray(c.points[c.y], float)
        got = curve_values(sweep, c.x, c.y, at, c.relative)
        if np.isnan(got).any():
            raise ValueError(f"{targets.source}: key 'curves.{name}.points': {c.x} values "
                             f"outside the model's {c.load_case} sweep")
        jac = np.zeros((at.size, n))
        if derivatives:
            for k in range(n):
                h = np.eye(n)[k] * 1e-6
                jac[:, k] = (curve_values(sweep, c.x, c.y, at, c.relative, h)
                             - curve_values(sweep, c.x, c.y, at, c.relative, -h)) / 2e-6
        curves[name] = (at, got)
        tol = c.tolerance
        scale = tol or 1.0
        w = np.sqrt(c.weight / at.size) / scale
        terms += [(w * (g - t), w * jac[i]) for i, (g, t) in enumerate(zip(got, want))]
        err = got - want
        worst = int(np.argmax(np.abs(err)))
        unit = c.y.rsplit("_", 1)[-1]
        if tol is not None:
            for i in range(at.size):
                cons.append(band(f"curve {name} at {c.x}={at[i]:g}", err[i], tol, jac[i]))
        miss = max(0.0, float(np.abs(err[worst])) - (tol or np.inf))
        rows.append(TargetRow(name, "curve", float(got[worst]),
                              f"{want[worst]:.4g} at {c.x} = {at[worst]:g}"
                              + (f" within {tol:g}" if tol else f" (weight {c.weight:g})"),
                              miss == 0.0, miss, unit))
    for name, t in spec.characteristics.items():
        value = run.summary[label].get(name)
        if value is None or not np.isfinite(value):
            why = ("its load case or vehicle data missing" if name not in run.summary[label]
                   else "not determined on this rig: a windowed slope needs at least 3 "
                   "distinct points in its window, a finer step of the load case gives it")
            raise ConfigError(f"{targets.source}: key 'characteristics.{name}': the model "
                              f"'{label}' does not give it ({why})")
        grad = run.summary_tangents[label][name] if derivatives else np.zeros(n)
        rows.append(_characteristic(name, t, value, grad, terms, cons))
    for name, lk in spec.constraints.link_lengths.items():
        rows.append(_link(run, name, lk, cons, derivatives))
    for i, box in enumerate(spec.constraints.keep_out):
        rows.append(_keep_out(run, i, box, cons, derivatives))
    r = np.array([t[0] for t in terms])
    J = np.array([t[1] for t in terms]).reshape(len(terms), n)
    g = np.array([c[1] for c in cons])
    G = np.array([c[2] for c in cons]).reshape(len(cons), n)
    return TargetValues(float(r @ r), 2.0 * J.T @ r, g, G, [c[0] for c in cons], rows, curves)


def band(label: str, error: float, half: float, grad: np.ndarray
         ) -> tuple[str, float, np.ndarray]:
    """A band |error| <= half as one smooth constraint ``1 - (error / half)^2 >= 0`` (a
    pair of linear ones, upper and lower, is degenerate for SLSQP's subproblem when the
    band is narrow against the start's miss)."""
    r = error / half
    return label, 1.0 - r * r, -2.0 * r * grad / half


def _characteristic(name, t, value, grad, terms, cons) -> TargetRow:
    unit = characteristic_unit(name)
    if t.range is not None:
        lo, hi = t.range
        cons.append(band(name, value - (lo + hi) / 2, (hi - lo) / 2, grad))
        miss = max(0.0, lo - value, value - hi)
        return TargetRow(name, "characteristic", value, f"in [{lo:g}, {hi:g}]", miss == 0.0,
                         miss, unit)
    scale = t.tolerance or 1.0
    w = np.sqrt(t.weight) / scale
    terms.append((w * (value - t.target), w * grad))
    if t.tolerance is not None:
        cons.append(band(name, value - t.target, t.tolerance, grad))
    miss = max(0.0, abs(value - t.target) - (t.tolerance or np.inf))
    asked = f"{t.target:g}" + (f" +- {t.tolerance:g}" if t.tolerance else
                              f" (weight {t.weight:g})")
    return TargetRow(name, "characteristic", value, asked, miss == 0.0, miss, unit)


def _points(suspension: Suspension, names) -> list[np.ndarray]:
    return [np.asarray(suspension.hardpoints[p], float) for p in names]


def _link_points(s: Suspension, name: str, lk) -> tuple[np.ndarray, np.ndarray]:
    if lk.between is not None:
        a, b = _points(s, lk.between)
        return a, b
    link = next(x for x in s.links if x.name == name)
    return np.asarray(link.points_mm[0]), np.asarray(link.points_mm[1])


def _geometry_gradient(run: DesignRun, fn, derivatives: bool) -> np.ndarray:
    """d fn(suspension) / d variables through the variables' twin suspensions."""
    out = np.zeros(run.values.size)
    if derivatives:
        for k, (plus, minus, h) in enumerate(run.variations):
            out[k] = (fn(plus) - fn(minus)) / (2 * h)
    return out


def _link(run: DesignRun, name: str, lk, cons, derivatives: bool) -> TargetRow:
    def length(s):
        a, b = _link_points(s, name, lk)
        return float(np.linalg.norm(b - a))

    value = length(run.suspension)
    grad = _geometry_gradient(run, length, derivatives)
    lo, hi = lk.range_mm
    cons.append(band(f"link {name} length", value - (lo + hi) / 2, (hi - lo) / 2, grad))
    miss = max(0.0, lo - value, value - hi)
    return TargetRow(f"link {name}", "link length", value, f"in [{lo:g}, {hi:g}]",
                     miss == 0.0, miss, "mm")


def _keep_out(run: DesignRun, i: int, box, cons, derivatives: bool) -> TargetRow:
    lo, hi = np.array(box.min_mm), np.array(box.max_mm)
    size = float(np.max(hi - lo))

    def outside(s):  # the largest signed distance outside a face (> 0: outside the box)
        p = np.asarray(s.hardpoints[box.hardpoint], float)
        return float(np.max(np.r_[lo - p, p - hi]))

    value = outside(run.suspension)
    grad = _geometry_gradient(run, outside, derivatives)
    cons.append((f"keep-out box {i} of {box.hardpoint}", value / size, grad / size))
    miss = max(0.0, -value)
    return TargetRow(f"{box.hardpoint} out of box {i}", "keep-out", value,
                     "outside the box (distance > 0)", miss == 0.0, miss, "mm")
