"""Units of TeimOrbit files (the ADAMS text format): Adams' unit names, unit systems, and which
table columns and keys hold which quantity.

Pure Python. Every factor converts a value in an ADAMS unit to elastokin's unit of the same
dimension: mm, N, deg, kg, s (derived quantities are products: N*mm, N*s/mm, ...). Names are
matched case-insensitively, with spaces or hyphens read as ``_`` and a plural read as its
singular (``'seconds'`` is ``'second'``, ``'inches'`` is ``'inch'``). A ``[UNITS]`` block may
name a whole unit system (``Units = 'Imperial'``, as Adams Drill writes) instead of, or before,
single units. Conventions: ``docs/adams.md``.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

__all__ = [
    "COLUMN_QUANTITIES",
    "DIMENSIONS",
    "KEY_QUANTITIES",
    "QUANTITY_UNITS",
    "UNIT_FACTORS",
    "UNIT_SYSTEMS",
    "Units",
    "damping_quantity",
    "unit_factor",
    "unit_key",
]

_LBF = 4.4482216152605  # N (exact by definition of the pound-force)
_RAD = 180.0 / math.pi

#: ADAMS unit names (lower case; spaces read as ``_``) and their factor to the elastokin unit of
#: each base dimension: mm, N, deg, kg, s
UNIT_FACTORS: dict[str, dict[str, float]] = {
    "length": {
        "mm": 1.0, "millimeter": 1.0, "millimetre": 1.0, "cm": 10.0, "centimeter": 10.0,
        "centimetre": 10.0, "meter": 1000.0, "metre": 1000.0, "m": 1000.0, "km": 1.0e6,
        "kilometer": 1.0e6, "kilometre": 1.0e6, "inch": 25.4, "in": 25.4, "foot": 304.8,
        "feet": 304.8, "ft": 304.8, "mile": 1609344.0, "micrometer": 1.0e-3, "micron": 1.0e-3,
    },
    "force": {
        "newton": 1.0, "n": 1.0, "kilo_newton": 1000.0, "kilonewton": 1000.0, "knewton": 1000.0,
        "kn": 1000.0, "millinewton": 1.0e-3, "centinewton": 1.0e-2, "dyne": 1.0e-5,
        "pound_force": _LBF, "lbf": _LBF, "kpound_force": 1000.0 * _LBF, "kip": 1000.0 * _LBF,
        "ounce_force": _LBF / 16.0, "ozf": _LBF / 16.0, "kilogram_force": 9.80665,
        "kg_force": 9.80665, "kgf": 9.80665, "gram_force": 9.80665e-3,
    },
    "angle": {
        "degrees": 1.0, "degree": 1.0, "deg": 1.0,
        "radians": _RAD, "radian": _RAD, "rad": _RAD,
    },
    "mass": {
        "kg": 1.0, "kilogram": 1.0, "gram": 1.0e-3, "g": 1.0e-3, "tonne": 1000.0,
        "megagram": 1000.0, "pound_mass": 0.45359237, "lbm": 0.45359237,
        "kpound_mass": 453.59237, "ounce_mass": 0.45359237 / 16.0, "slug": _LBF / 0.3048,
    },
    "time": {
        "second": 1.0, "sec": 1.0, "s": 1.0, "millisecond": 1.0e-3, "msec": 1.0e-3,
        "ms": 1.0e-3, "microsecond": 1.0e-6, "minute": 60.0, "min": 60.0, "hour": 3600.0,
        "hr": 3600.0, "h": 3600.0,
    },
}

DIMENSIONS = ("length", "force", "angle", "mass", "time")

#: unit systems a ``[UNITS]`` block may name (``Units = 'Imperial'``): Adams Drill's two and
#: Adams View's four, each as (length, force, angle, mass, time)
UNIT_SYSTEMS: dict[str, tuple[str, str, str, str, str]] = {
    "imperial": ("foot", "pound_force", "degrees", "pound_mass", "second"),
    "metric": ("meter", "newton", "degrees", "kg", "second"),
    "mmks": ("mm", "newton", "degrees", "kg", "second"),
    "mks": ("meter", "newton", "degrees", "kg", "second"),
    "cgs": ("cm", "dyne", "degrees", "gram", "second"),
    "ips": ("inch", "pound_force", "degrees", "pound_mass", "second"),
}

#: derived quantities: exponents of (length, force, angle, mass, time) and the elastokin unit
QUANTITY_UNITS: dict[str, tuple[tuple[int, int, int, int, int], str]] = {
    "length": ((1, 0, 0, 0, 0), "mm"),
    "force": ((0, 1, 0, 0, 0), "N"),
    "angle": ((0, 0, 1, 0, 0), "deg"),
    "mass": ((0, 0, 0, 1, 0), "kg"),
    "time": ((0, 0, 0, 0, 1), "s"),
    "torque": ((1, 1, 0, 0, 0), "N*mm"),
    "velocity": ((1, 0, 0, 0, -1), "mm/s"),
    "angular_velocity": ((0, 0, 1, 0, -1), "deg/s"),
    "damping": ((-1, 1, 0, 0, 1), "N*s/mm"),
    "rotational_damping": ((1, 1, -1, 0, 1), "N*mm*s/deg"),
    "stiffness": ((-1, 1, 0, 0, 0), "N/mm"),
    "rotational_stiffness": ((1, 1, -1, 0, 0), "N*mm/deg"),
}

#: table columns of a known quantity (lower-case names), converted on reading
COLUMN_QUANTITIES: dict[str, str] = {
    "disp": "length", "force": "force", "rot": "angle", "torque": "torque",
    "x_value": "length", "y_value": "length", "z_value": "length",
    "radius": "length", "width": "length", "vel": "velocity", "velocity": "velocity",
}

#: ``KEY = value`` entries of a known quantity (upper-case names), converted on reading;
#: keys of the ``[DAMPING]`` block are classified by :func:`damping_quantity`
KEY_QUANTITIES: dict[str, str] = {
    **{f"T_PRELOAD_{a}": "force" for a in "XYZ"},
    **{f"R_PRELOAD_{a}": "torque" for a in "XYZ"},
    **{f"T_OFFSET_{a}": "length" for a in "XYZ"},
    **{f"R_OFFSET_{a}": "angle" for a in "XYZ"},
    "GEOMETRY_LENGTH": "length", "GEOMETRY_RADIUS": "length", "FREE_LENGTH": "length",
}


def damping_quantity(key: str) -> str | None:
    """Translational damping (FX.., CX.., TRANS..) or rotational (TX.., CTX.., ROT..)."""
    k = key.upper()
    if re.match(r"^(F[XYZ]|C[XYZ]|TRANS)", k):
        return "damping"
    if re.match(r"^(T[XYZ]|CT[XYZ]|ROT)", k):
        return "rotational_damping"
    return None


def unit_key(name: str) -> str:
    """A unit name as looked up: lower case, spaces and hyphens read as ``_``."""
    return re.sub(r"[\s-]+", "_", str(name).strip().lower())


def unit_factor(dimension: str, name: str) -> float | None:
    """Factor of the ADAMS unit ``name`` of ``dimension`` to elastokin's unit (None: unknown).
    A plural is read as its singular (``seconds``, ``inches``, ``meters``)."""
    table = UNIT_FACTORS[dimension]
    k = unit_key(name)
    for candidate in (k, k[:-1] if k.endswith("s") else None,
                      k[:-2] if k.endswith("es") else None):
        if candidate and candidate in table:
            return table[candidate]
    return None


@dataclass(frozen=True)
class Units:
    """The ``[UNITS]`` of a TeimOrbit file (ADAMS names as written in the file)."""

    length: str = "mm"
    force: str = "newton"
    angle: str = "degrees"
    mass: str = "kg"
    time: str = "second"

    def factor(self, quantity: str) -> float:
        """Multiplier from this file's unit of ``quantity`` to elastokin's."""
        exponents, _ = QUANTITY_UNITS[quantity]
        f = 1.0
        for dim, e in zip(DIMENSIONS, exponents):
            if e:
                f *= unit_factor(dim, getattr(self, dim)) ** e
        return f

    @classmethod
    def system(cls, name: str) -> Units | None:
        """The units of a named system (``Imperial``, ``Metric``, ``MMKS``...); None: unknown."""
        found = UNIT_SYSTEMS.get(unit_key(name))
        return None if found is None else cls(*found)
