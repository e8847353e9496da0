"""Plausible ranges of the vehicle data a config types (wheelbase, CG height, the design
track, tyre radius and rate, steering ratio and travel, anti-roll bar rate, axle fractions):
a value outside its range is refused, with the unit slip that would explain it named
(``3.378 - in metres?``). Values inside are never judged. The ranges are wide on purpose
(from a go-kart to a heavy truck) and are documented in the README ("Limits").

Units: mm, N, N*mm, deg (those of the config).
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Plausible:
    """``low <= value <= high`` in ``unit``; ``slips``: (unit the value may have been typed
    in, factor from that unit to ``unit``)."""

    low: float
    high: float
    unit: str
    slips: tuple[tuple[str, float], ...]


#: a length in mm typed in another unit
LENGTH_SLIPS = (("metres", 1000.0), ("centimetres", 10.0), ("inches", 25.4))

#: the plausible range of each checked key (its last segment), see the module docstring
RANGES = {
    "wheelbase_mm": Plausible(500.0, 20_000.0, "mm", LENGTH_SLIPS),
    "cg_height_mm": Plausible(100.0, 3_000.0, "mm", LENGTH_SLIPS),
    "track_mm": Plausible(400.0, 4_000.0, "mm", LENGTH_SLIPS),
    "loaded_radius_mm": Plausible(100.0, 2_000.0, "mm", LENGTH_SLIPS),
    "tyre_rate_N_per_mm": Plausible(10.0, 20_000.0, "N/mm",
                                    (("N/m", 1e-3), ("kN/mm", 1000.0))),
    "ratio_mm_per_rev": Plausible(5.0, 500.0, "mm per steering-wheel turn",
                                  (("metres", 1000.0), ("centimetres", 10.0))),
    "limit_mm": Plausible(5.0, 500.0, "mm", LENGTH_SLIPS[:2]),
    "rate_Nmm_per_deg": Plausible(100.0, 1e8, "N*mm/deg", (("N*m/deg", 1000.0),)),
    # the mass one axle carries (the static-load analysis)
    "axle_mass_kg": Plausible(20.0, 30_000.0, "kg", (("N", 1.0 / 9.80665), ("tonnes", 1000.0))),
    # the whole vehicle's mass (a vehicle file)
    "mass_kg": Plausible(50.0, 60_000.0, "kg", (("N", 1.0 / 9.80665), ("tonnes", 1000.0))),
}


def implausible(key: str, value: float) -> str | None:
    """Why ``value`` of ``key`` (a key of :data:`RANGES`) is not plausible, or None: the
    range and the unit slips that would bring the value into it."""
    r = RANGES[key]
    if r.low <= value <= r.high:
        return None
    slips = [unit for unit, factor in r.slips if r.low <= value * factor <= r.high]
    hint = f" - in {' or '.join(slips)}?" if slips else ""
    return (f"{value:g}{hint} (expected {r.low:,g} ... {r.high:,g} {r.unit}, README "
            "'Limits')")


def fraction_problem(value: float) -> str | None:
    """Why ``value`` is not a fraction 0 ... 1 (a percentage named as such), or None."""
    if 0.0 <= value <= 1.0:
        return None
    hint = f" - a percentage? give {value / 100:g}" if 1.0 < value <= 100.0 else ""
    return f"{value:g}{hint} (a fraction: 0 ... 1)"


def plausible(value: float | None, info) -> float | None:
    """A pydantic field validator: ``value`` of the field ``info.field_name`` (a key of
    :data:`RANGES`) within its range (None passes)."""
    problem = None if value is None else implausible(info.field_name, value)
    if problem:
        raise ValueError(problem)
    return value


def fraction(value: float) -> float:
    """A pydantic field validator: a fraction 0 ... 1 (:func:`fraction_problem`)."""
    problem = fraction_problem(value)
    if problem:
        raise ValueError(problem)
    return value
