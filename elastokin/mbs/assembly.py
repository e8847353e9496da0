"""What holds each part of a built model: the system Jacobian of the static solver at the
current configuration, and the parts that nothing holds (:func:`free_parts`), named with
their connections. A static solve whose Jacobian is singular fails as "did not converge";
:func:`elastokin.mbs.solve.solve_path` asks :func:`free_parts` first, so that a part hanging
on one ball joint is reported by name. Units mm, N, N*mm, rad (Exudyn's coordinates).
"""

from __future__ import annotations

import numpy as np

from elastokin.mbs.exudyn_api import exu, exudyn_call
from elastokin.mbs.model import SuspensionModel

#: a part is free when a motion its joints allow meets less stiffness than this fraction of
#: the largest stiffness on the part (N/mm, N*mm/rad mixed: a relative floor far below any
#: rubber rate, far above rounding)
FREE_TOLERANCE = 1e-12


def system_jacobian(model: SuspensionModel, settings, what: str) -> np.ndarray:
    """The static solver's Jacobian of ``model`` at its current configuration (ODE2
    coordinates first, then the constraints' algebraic equations), with the solver
    ``settings`` (:func:`elastokin.mbs.solve.simulation_settings`)."""
    mbs, src = model.mbs, model.suspension.source
    mbs.Assemble()
    solver = exu.MainSolverStatic()
    exudyn_call(lambda: solver.InitializeSolver(mbs, settings), f"{src}: {what}")
    exudyn_call(lambda: solver.ComputeNewtonJacobian(mbs, settings), f"{src}: {what}")
    return np.asarray(solver.GetSystemJacobian())


def free_parts(model: SuspensionModel, settings) -> list[tuple[str, int]]:
    """The parts that stay free with every other part held: (part, number of free
    directions). A part's motions that its constraints allow (the null space of its columns
    of the constraint rows) must meet stiffness (a bushing, a spring, a stop, a torsion
    spring holding an idle spin); a part hanging on one ball joint, or between two ball
    joints with nothing to stop it turning about their line, does not."""
    mbs = model.mbs
    jac = system_jacobian(model, settings, "assembly diagnostics")
    n2 = mbs.systemData.ODE2Size()
    stiffness, cq = jac[:n2, :n2], jac[n2:, :n2]
    out = []
    for part, node in model.node.items():
        i0 = mbs.GetNodeODE2Index(node)
        cols = slice(i0, i0 + 6)
        rows = cq[np.any(cq[:, cols] != 0.0, axis=1), cols]
        if rows.size:
            _, sv, vt = np.linalg.svd(rows)
            rank = int(np.sum(sv > 1e-9 * sv[0])) if sv.size and sv[0] > 0 else 0
            allowed = vt[rank:].T
        else:
            allowed = np.eye(6)
        if allowed.shape[1] == 0:
            continue
        k = stiffness[cols, cols]
        held = allowed.T @ k @ allowed
        scale = max(float(np.max(np.abs(k))), 1e-300)
        ev = np.linalg.svd(held, compute_uv=False)
        free = int(np.sum(ev <= FREE_TOLERANCE * scale))
        if free:
            out.append((part, free))
    return out


def free_parts_message(model: SuspensionModel, free: list[tuple[str, int]]) -> str:
    """One line naming the free parts (:func:`free_parts`) and their connections."""
    s = model.suspension
    items = [*s.joints, *s.links, *s.bushings, *s.springs, *s.stops, *s.dampers]
    parts = []
    for part, n in free:
        held = [c.name for c in items if part in c.parts]
        parts.append(f"'{part}' ({n} free direction{'s' * (n > 1)}; its connections: "
                     f"{', '.join(held) or 'none'})")
    return (f"{s.source}: the assembly cannot be solved: nothing holds part"
            f"{'s' * (len(parts) > 1)} {', '.join(parts)} with the parts around held (a part "
            "hanging on one ball joint, or turning freely between two, with no bushing or "
            "spring); connect it by a bushing or another joint, or remove it (a rod between "
            "two ball joints is a 'link' connection, not a part)")
