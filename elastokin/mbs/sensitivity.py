"""Exact sensitivities of a model's static steps to the laws of its parametric bushings.

At every converged static step the residual vanishes, R(y, p) = 0, with y the coordinates q
(every part: displacement mm, Tait-Bryan angles rad) and the Lagrange multipliers of the
joints. Its derivative with respect to a parameter p of the bushing laws is
``dy/dp = -(dR/dy)^-1 dR/dp``: one solve of the step's linear system per step, no re-solve of
the path. Here:

- ``dR/dy``: central differences of Exudyn's residual in every coordinate (its Newton
  Jacobian leaves out the geometric stiffness of loaded joints: measured on the case study up
  to 0.2 % of the largest entry, which left the sensitivities 0.1-1 % off; forward
  differences left them up to 1e-4 off, central ones 1e-5 at worst); coordinates of parts
  that no equation couples are perturbed together (a colouring of the parts over the
  connectors and joints between them), so a step costs two residuals per coordinate direction
  and colour class (24 on the case study), not two per coordinate. The multipliers' columns
  are the transpose of the joints' rows (the residual is linear in the multipliers).
- ``dR/dp``: forward differences of the residual at the recorded states with the laws at
  ``p + step`` (:class:`LawVariation`; parametric bushings change their laws without a
  rebuild, :class:`~elastokin.mbs.bushings.ParametricLaws`); variations of bushings on
  different parts are evaluated together.

The derivatives of the recorded points and part rotations follow from dq/dp through the
parts' Tait-Bryan (``Rxyz``) rotation. Units: mm, rad inside; per unit of each parameter.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from elastokin.errors import ModelError
from elastokin.mbs.exudyn_api import exu, exudyn_call
from elastokin.mbs.model import SuspensionModel
from elastokin.mbs.solve import simulation_settings, solve_path
from elastokin.physics.states import ModelState, StateSensitivity

#: central-difference step of the parts' coordinates (mm and rad), times max(1, |q|)
COORDINATE_STEP = 1e-5
#: objects whose equations on each part depend on that part's coordinates only: a spherical
#: joint's reaction on a part depends on its own rotation (and the multipliers), nothing else
SEPARABLE = ("JointSpherical",)


@dataclass(frozen=True)
class LawVariation:
    """One parameter as a change of parametric bushing laws: per bushing that the parameter
    changes, its six laws at ``p + step`` (``step`` in the parameter's unit, negative for a
    backward difference at an upper bound)."""

    laws: Mapping[str, Sequence]
    step: float

    @property
    def bushings(self) -> list[str]:
        """The bushings the parameter changes."""
        return list(self.laws)


def rxyz_matrix(theta: np.ndarray) -> np.ndarray:
    """Rotation matrix (..., 3, 3) of Tait-Bryan angles (..., 3) (rad) as Exudyn's ``Rxyz``
    nodes use them: ``Rx(t0) @ Ry(t1) @ Rz(t2)`` (local -> global), multiplied out."""
    theta = np.asarray(theta, float)
    (c0, c1, c2), (s0, s1, s2) = np.moveaxis(np.cos(theta), -1, 0), \
        np.moveaxis(np.sin(theta), -1, 0)
    R = np.empty(theta.shape[:-1] + (3, 3))
    R[..., 0, 0], R[..., 0, 1], R[..., 0, 2] = c1 * c2, -c1 * s2, s1
    R[..., 1, 0] = c0 * s2 + s0 * s1 * c2
    R[..., 1, 1] = c0 * c2 - s0 * s1 * s2
    R[..., 1, 2] = -s0 * c1
    R[..., 2, 0] = s0 * s2 - c0 * s1 * c2
    R[..., 2, 1] = s0 * c2 + c0 * s1 * s2
    R[..., 2, 2] = c0 * c1
    return R


def rxyz_derivatives(theta: np.ndarray) -> np.ndarray:
    """(..., 3, 3, 3): d R / d theta_k of :func:`rxyz_matrix` (last index k)."""
    return _rxyz(np.asarray(theta, float))[1]


def _rxyz(theta):
    c, s = np.cos(theta), np.sin(theta)
    zero, one = np.zeros_like(c[..., 0]), np.ones_like(c[..., 0])

    def mat(rows):
        return np.stack([np.stack(r, axis=-1) for r in rows], axis=-2)

    rx = mat([[one, zero, zero], [zero, c[..., 0], -s[..., 0]], [zero, s[..., 0], c[..., 0]]])
    ry = mat([[c[..., 1], zero, s[..., 1]], [zero, one, zero], [-s[..., 1], zero, c[..., 1]]])
    rz = mat([[c[..., 2], -s[..., 2], zero], [s[..., 2], c[..., 2], zero], [zero, zero, one]])
    drx = mat([[zero, zero, zero], [zero, -s[..., 0], -c[..., 0]],
               [zero, c[..., 0], -s[..., 0]]])
    dry = mat([[-s[..., 1], zero, c[..., 1]], [zero, zero, zero],
               [-c[..., 1], zero, -s[..., 1]]])
    drz = mat([[-s[..., 2], -c[..., 2], zero], [c[..., 2], -s[..., 2], zero],
               [zero, zero, zero]])
    d = np.stack([drx @ ry @ rz, rx @ dry @ rz, rx @ ry @ drz], axis=-1)
    return rx @ ry @ rz, d


def part_coordinates(model: SuspensionModel) -> dict[str, np.ndarray]:
    """Each moving part's (and rig body's) 6 indices in the ODE2 coordinate vector."""
    mbs = model.mbs
    nodes = {**model.node, **model.rig_nodes}
    return {p: mbs.GetNodeODE2Index(n) + np.arange(6) for p, n in nodes.items()}


def row_dependencies(model: SuspensionModel) -> list[tuple[np.ndarray, set[str]]]:
    """The residual's rows in groups, each with the parts whose coordinates they depend on:
    a part's equations (ODE2 rows) depend on its own coordinates and those of every part a
    connector or joint joins it to, but for :data:`SEPARABLE` joints; a joint's equations
    (algebraic rows, after the ODE2 rows) on the parts it joins."""
    mbs, sd = model.mbs, model.mbs.systemData
    bodies = {**model.body, **model.rig_bodies}
    part_of = {int(b): p for p, b in bodies.items()}
    coords = part_coordinates(model)
    reach = {p: {p} for p in bodies}
    out = []
    n2 = sd.ODE2Size()
    for i in range(sd.NumberOfObjects()):
        obj = mbs.GetObject(i)
        if "markerNumbers" not in obj:
            continue
        parts = {part_of.get(int(mbs.GetMarker(m).get("bodyNumber", -1)))
                 for m in obj["markerNumbers"]} - {None}
        ae = np.asarray(sd.GetObjectLTGAE(i), int)
        if ae.size:
            out.append((n2 + ae, parts))
        if obj["objectType"] not in SEPARABLE:
            for p in parts:
                reach[p] |= parts
    return [(coords[p], reach[p]) for p in bodies] + out


def colour_classes(rows: list[tuple[np.ndarray, set[str]]], parts: Sequence[str]
                   ) -> list[list[str]]:
    """Parts in classes whose coordinates can be perturbed together: no row depends on two
    parts of one class (greedy colouring, parts in the given order)."""
    moved = {p: {i for i, (_, deps) in enumerate(rows) if p in deps} for p in parts}
    classes: list[list[str]] = []
    for p in parts:
        for cls in classes:
            if all(not (moved[p] & moved[q]) for q in cls):
                cls.append(p)
                break
        else:
            classes.append([p])
    return classes


class Recorder:
    """Every solved (sub-)step's time, coordinates and multipliers (a post-step function)."""

    def __init__(self):
        self.rows: list[tuple[float, np.ndarray, np.ndarray]] = []

    def __call__(self, mbs, t):
        sd = mbs.systemData
        self.rows.append((float(t), np.array(sd.GetODE2Coordinates()),
                          np.array(sd.GetAECoordinates())))
        return True

    def at(self, times: np.ndarray) -> list[tuple[float, np.ndarray, np.ndarray]]:
        t = np.array([r[0] for r in self.rows])
        return [self.rows[int(np.flatnonzero(np.abs(t - tk) < 1e-9)[-1])] for tk in times]


def solve_path_with_sensitivities(model: SuspensionModel, inputs: Mapping[str, np.ndarray],
                                  what: str, variations: Sequence[LawVariation]
                                  ) -> list[ModelState]:
    """:func:`~elastokin.mbs.solve.solve_path`, each returned state carrying its
    ``sensitivity`` with respect to each of ``variations`` (module docstring). The model's
    parametric bushings are at their current laws (the point p). Friction is refused."""
    states, steps = recorded_solve(model, inputs, what)
    if not variations:
        return states
    dy = _step_sensitivities(model, steps, variations, what)
    n2 = model.mbs.systemData.ODE2Size()
    q = np.array([step[1] for step in steps])
    for state, out in zip(states, _outputs(model, q, dy[:, :n2])):
        state.sensitivity = out
    return states


def recorded_solve(model: SuspensionModel, inputs: Mapping[str, np.ndarray], what: str
                   ) -> tuple[list[ModelState], list[tuple[float, np.ndarray, np.ndarray]]]:
    """:func:`~elastokin.mbs.solve.solve_path` and every returned step's converged (time,
    coordinates, multipliers), for sensitivities; a model with friction is refused."""
    if model.friction or model.substeps != 1:
        raise ModelError(f"{model.suspension.source}: sensitivities need a frictionless model")
    recorder = Recorder()
    model.mbs.SetPostStepUserFunction(recorder)
    try:
        states = solve_path(model, inputs, what)
    finally:
        model.mbs.SetPostStepUserFunction(0)
    return states, recorder.at(np.linspace(0.0, 1.0, len(states) + 1)[1:])


def _outputs(model, q: np.ndarray, dq: np.ndarray) -> list[StateSensitivity]:
    """Derivatives of the recorded points and part rotations at every step from the steps'
    coordinates q (n, n2) and dq/dp (n, n2, n_p)."""
    coords = part_coordinates(model)
    rotation, points = {}, {}
    for part in {*model.pose_refs, *(p for p, _ in model.point_sensors.values())}:
        i = coords[part]
        dR = rxyz_derivatives(q[:, i[3:]])  # (n, 3, 3, 3)
        rotation[part] = np.einsum("nabk,nkp->nabp", dR, dq[:, i[3:]])
    for name, (part, local) in model.point_sensors.items():
        i = coords[part]
        points[name] = dq[:, i[:3]] + np.einsum("nabp,b->nap", rotation[part], local)
    return [StateSensitivity({k: v[j] for k, v in points.items()},
                             {p: rotation[p][j] for p in model.pose_refs})
            for j in range(q.shape[0])]


class Residual:
    """Exudyn's static residual at given states of ``model``, and the structure of its
    Jacobian: the perturbations of the forward differences (one per colour class and
    coordinate direction) and where each lands (rows, column)."""

    def __init__(self, model: SuspensionModel, n: int, what: str):
        self.model, self.mbs = model, model.mbs
        self.ss = simulation_settings(model, n)
        self.solver = exu.MainSolverStatic()
        exudyn_call(lambda: self.solver.InitializeSolver(self.mbs, self.ss), what)
        self.n2 = self.solver.GetODE2size()
        self.n = self.n2 + self.solver.GetAEsize()
        self.current = exu.ConfigurationType.Current
        self.coords = part_coordinates(model)
        self._structure = None

    @property
    def perturbed(self) -> list[np.ndarray]:
        """The coordinates of each perturbation (one per colour class and direction)."""
        return self.structure()[0]

    @property
    def scatter(self) -> np.ndarray:
        """(perturbation, row, column) of every Jacobian entry, as three rows."""
        return self.structure()[1]

    def structure(self) -> tuple[list[np.ndarray], np.ndarray]:
        if self._structure is None:  # made once, when a Jacobian is first asked for
            coords = self.coords
            rows = row_dependencies(self.model)
            perturbed, scatter = [], []
            for cls in colour_classes(rows, list(coords)):
                for k in range(6):
                    e = len(perturbed)
                    perturbed.append(np.array([coords[p][k] for p in cls]))
                    for p in cls:
                        for r, deps in rows:
                            if p in deps:
                                scatter += [(e, int(i), int(coords[p][k])) for i in r]
            self._structure = perturbed, np.array(scatter).T
        return self._structure

    def set_state(self, t: float, q: np.ndarray, lam: np.ndarray) -> None:
        sd = self.mbs.systemData
        sd.SetODE2Coordinates(q, self.current)
        sd.SetAECoordinates(lam, self.current)
        sd.SetTime(t, self.current)

    def residual(self) -> np.ndarray:
        self.solver.ComputeNewtonResidual(self.mbs, self.ss)
        return self.solver.GetSystemResidual()

    def jacobian(self) -> np.ndarray:
        self.solver.ComputeNewtonJacobian(self.mbs, self.ss)
        return self.solver.GetSystemJacobian()

    def close(self) -> None:
        self.solver.FinalizeSolver(self.mbs, self.ss)


def _step_sensitivities(model, steps, variations, what) -> np.ndarray:
    """(n_steps, n2 + n_ae, n_p): dy/dp at every recorded step."""
    res = Residual(model, len(steps), what)
    try:
        A, r0 = system_matrices(res, steps)
        B = _parameter_derivatives(res, model, steps, variations, r0)
    finally:
        res.close()
    return solve_tangents(A, B)


def solve_tangents(A: np.ndarray, B: np.ndarray) -> np.ndarray:
    """dy/dp = -A^-1 B at every step (A (n_steps, N, N) = dR/dy, B (n_steps, N, n_p) =
    dR/dp), equilibrated: rows and columns of mixed units (N, N*mm, mm, rad)."""
    r = 1.0 / np.maximum(np.max(np.abs(A), axis=2, keepdims=True), 1e-300)
    c = 1.0 / np.maximum(np.max(np.abs(A * r), axis=1, keepdims=True), 1e-300)
    return -c.transpose(0, 2, 1) * np.linalg.solve(A * r * c, B * r)


def system_matrices(res: Residual, steps) -> tuple[np.ndarray, np.ndarray]:
    """dR/dy (n_steps, N, N) at every step and the residual there (n_steps, N): the
    coordinates' columns by central differences (the joints' rows with them); the
    multipliers' columns their transpose (the residual is C_q^T lam + ..., checked against
    Exudyn's Jacobian at the first step) with Exudyn's multiplier block."""
    n2, n = res.n2, res.n
    res.set_state(*steps[0])
    J0 = res.jacobian()
    q_all = np.array([q for _, q, _ in steps])
    h = COORDINATE_STEP * np.maximum(1.0, np.abs(q_all))  # (n_steps, n2)
    # every perturbation of a step: +h and -h on the coordinates of one colour class and
    # direction (rows 2e and 2e + 1)
    signs = np.zeros((2 * len(res.perturbed), n2))
    for e, cols in enumerate(res.perturbed):
        signs[2 * e, cols], signs[2 * e + 1, cols] = 1.0, -1.0
    r0 = np.empty((len(steps), n))
    R = np.empty((len(steps), signs.shape[0], n))
    sd, cur = res.mbs.systemData, res.current
    for i, (t, q, lam) in enumerate(steps):
        res.set_state(t, q, lam)
        r0[i] = res.residual()
        Ri = R[i]
        for k, y in enumerate(q + signs * h[i]):
            sd.SetODE2Coordinates(y, cur)
            Ri[k] = res.residual()
    e, row, col = res.scatter
    A = np.zeros((len(steps), n, n))
    A[:, row, col] = (R[:, 2 * e, row] - R[:, 2 * e + 1, row]) / (2.0 * h[:, col])
    if not np.allclose(J0[:n2, n2:], J0[n2:, :n2].T, rtol=0.0,
                       atol=1e-12 * np.max(np.abs(J0[:n2, n2:]), initial=1.0)):
        raise ModelError(f"{res.model.suspension.source}: sensitivities: a joint's reaction "
                         "is not the transpose of its constraint Jacobian (unsupported joint)")
    A[:, :n2, n2:] = A[:, n2:, :n2].transpose(0, 2, 1)
    A[:, n2:, n2:] = J0[n2:, n2:]
    return A, r0


def _parameter_derivatives(res: Residual, model, steps, variations, r0) -> np.ndarray:
    """(n_steps, N, n_p): dR/dp by forward differences of the residual at every step."""
    n2, coords = res.n2, res.coords
    base = model.bushing_law_values()
    out = np.zeros((len(steps), res.n, len(variations)))
    for group in _variation_groups(model, variations):
        model.set_bushing_laws({b: laws for j in group
                                for b, laws in variations[j].laws.items()})
        changed = np.empty((len(steps), n2))
        for i, (t, q, lam) in enumerate(steps):
            res.set_state(t, q, lam)
            changed[i] = res.residual()[:n2]
        model.apply_bushing_law_values(base)
        for j in group:
            rows = np.concatenate([coords[p] for p in _variation_parts(model, variations[j])])
            out[:, rows, j] = (changed[:, rows] - r0[:, rows]) / variations[j].step
    return out


def _variation_parts(model, variation: LawVariation) -> set[str]:
    parts = set()
    for name in variation.bushings:
        b = next(b for b in model.suspension.bushings if b.name == name)
        parts |= {p for p in b.parts if p in model.body}
    return parts


def _variation_groups(model, variations) -> list[list[int]]:
    """Variations evaluated together: none shares a bushing or a part with another."""
    groups: list[tuple[list[int], set, set]] = []
    for j, v in enumerate(variations):
        parts, names = _variation_parts(model, v), set(v.bushings)
        for members, used_parts, used_names in groups:
            if not (parts & used_parts) and not (names & used_names):
                members.append(j)
                used_parts |= parts
                used_names |= names
                break
        else:
            groups.append(([j], set(parts), set(names)))
    return [g[0] for g in groups]
