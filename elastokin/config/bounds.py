"""Bounds on the work a config implies, checked by the schema before anything is allocated:
the number of rig steps of every load case (counted exactly as :mod:`elastokin.rig.paths`
builds the input paths), the size of a bushing curve, and the smallest angles that still
define a direction. The bounds are documented in the README ("Config reference").
"""

from __future__ import annotations

import math

from pydantic_core import PydanticCustomError

#: the most rig steps one load case may take (each step is a static solve)
MAX_STEPS_PER_LOAD_CASE = 100_000
#: the most points of a bushing force-deflection curve (``deflection`` and ``load`` each)
MAX_CURVE_POINTS = 10_000
#: a point's coordinates at most this far from the origin (mm; a car is a few metres long):
#: beyond, a typo that would make the geometry's arithmetic overflow or lose every digit
MAX_COORDINATE_MM = 1.0e6
#: the most solver steps per recorded rig step of the synthetic real suspension
MAX_SUBSTEPS = 100
#: the most beam elements on one segment of a beam part, and the most nodes it names
MAX_ELEMENTS_PER_SEGMENT = 200
MAX_BEAM_NODES = 100
#: a wheel spin axis at least this far from vertical, and a bushing's ``radial`` at least this
#: far from its ``axis`` (deg): closer, toe and camber or the bushing frame are undefined
MIN_AXIS_ANGLE_DEG = 1.0

#: pydantic error type of a refused step count; its context ``key`` is the key path
#: below the validated model that the message is about
TOO_MANY_STEPS = "too_many_steps"


def leg_steps(start: float, end: float, step: float) -> float:
    """Steps of one leg from ``start`` to ``end`` in steps no larger than ``step``, as
    :func:`elastokin.rig.paths.leg` takes them (a float: ``inf`` when it overflows)."""
    n = abs(end - start) / step - 1e-9
    if not math.isfinite(n):
        return math.inf
    return float(max(1, math.ceil(n)))


def travel_steps(rebound_mm: float, bump_mm: float, step_mm: float, unloading: bool) -> float:
    """Steps of a parallel-travel case: approach to rebound, stroke to bump, return."""
    n = leg_steps(0.0, rebound_mm, step_mm) + leg_steps(rebound_mm, bump_mm, step_mm)
    return n + leg_steps(bump_mm, rebound_mm, step_mm) if unloading else n


def vertical_force_steps(min_N: float, max_N: float, step_N: float,
                         wheel_load_N: float | None = None) -> float:
    """Steps of a vertical-force case: approach from the design wheel load to ``min_N``
    (one step when the wheel load is not known), rise to ``max_N``, fall to ``min_N``."""
    approach = 1.0 if wheel_load_N is None else leg_steps(wheel_load_N, min_N, step_N)
    return approach + 2.0 * leg_steps(min_N, max_N, step_N)


def sweep_steps(amplitude: float, step: float) -> float:
    """Steps of a force or torque sweep 0 -> +A -> -A -> 0 (the fall takes twice the rise's)."""
    return 4.0 * leg_steps(0.0, amplitude, step)


def count_text(count: float) -> str:
    """A step count for a message: ``360,000``; very large ones in exponent form."""
    if not math.isfinite(count):
        return "more than 1e308"
    return f"{count:,.0f}" if count < 1e15 else f"{count:.3g}"


def check_steps(count: float, key: str, step_text: str, detail: str = "") -> None:
    """Refuse a load case of more than :data:`MAX_STEPS_PER_LOAD_CASE` steps: a pydantic
    error of type :data:`TOO_MANY_STEPS` naming ``key`` (the step's key path) in its context.
    ``step_text`` is the step with its unit, ``detail`` what the steps cover."""
    if count <= MAX_STEPS_PER_LOAD_CASE:
        return
    over = f" {detail}" if detail else ""
    raise PydanticCustomError(
        TOO_MANY_STEPS,
        f"{step_text} gives {count_text(count)} steps{over}; at most "
        f"{MAX_STEPS_PER_LOAD_CASE:,} per load case".replace("{", "(").replace("}", ")"),
        {"key": key},
    )
