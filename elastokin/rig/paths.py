"""The rig's input paths (pure numpy): equal steps between turning points, with the branch
label of every step. Units of the input (mm, N, N*mm)."""

from __future__ import annotations

import numpy as np


def leg(start: float, end: float, step: float) -> np.ndarray:
    """Equal steps no larger than ``step`` from ``start`` (excluded) to ``end`` (included)."""
    n = max(1, int(np.ceil(abs(end - start) / step - 1e-9)))
    return np.linspace(start, end, n + 1)[1:]


def labelled(legs: list[np.ndarray], names: tuple[str, ...]) -> tuple[np.ndarray, np.ndarray]:
    """The legs joined, and each step's branch label (the name of its leg)."""
    branch = np.concatenate([[b] * x.size for b, x in zip(names, legs)])
    return np.concatenate(legs), branch


def travel_path(rebound_mm: float, bump_mm: float, step_mm: float, unloading: bool,
                approach_step_mm: float | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Prescribed contact-patch travel (mm) and branch labels for a parallel-travel case:
    from the design position (0) down to ``rebound_mm`` (``approach``, in steps of
    ``approach_step_mm``, default ``step_mm``), up to ``bump_mm`` (``stroke``, loading) and,
    with ``unloading``, back down to ``rebound_mm`` (``return``), in steps no larger than
    ``step_mm``. The stroke starts at the rebound point (the approach's last step)."""
    legs = [leg(0.0, rebound_mm, approach_step_mm or step_mm),
            leg(rebound_mm, bump_mm, step_mm)]
    if unloading:
        legs.append(leg(bump_mm, rebound_mm, step_mm))
    z, branch = labelled(legs, ("approach", "stroke", "return"))
    branch[legs[0].size - 1] = "stroke"
    return z, branch


def sweep_path(amplitude: float, step: float) -> tuple[np.ndarray, np.ndarray]:
    """0 -> +amplitude -> -amplitude -> 0 in steps no larger than ``step``, with branch labels
    ``rise``, ``fall`` and ``return`` (loading and unloading, as a rig records them)."""
    rise = leg(0.0, amplitude, step)
    # twice the rise's steps, so that both branches pass the same force values
    fall = np.linspace(amplitude, -amplitude, 2 * rise.size + 1)[1:]
    return labelled([rise, fall, leg(-amplitude, 0.0, step)], ("rise", "fall", "return"))


def vertical_force_path(wheel_load_N: float, min_N: float, max_N: float,
                        step_N: float) -> tuple[np.ndarray, np.ndarray]:
    """From the design wheel load down to ``min_N`` (approach), up to ``max_N`` (rise) and
    back to ``min_N`` (fall)."""
    legs = [leg(wheel_load_N, min_N, step_N), leg(min_N, max_N, step_N),
            leg(max_N, min_N, step_N)]
    return labelled(legs, ("approach", "rise", "fall"))
