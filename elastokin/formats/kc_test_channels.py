"""The channels, units and load cases of K&C test files (``docs/kc_test_data.md``) and the
layout of a file's header: a file holds one wheel (channels named as in the channel table:
``toe``) or both wheels of an axle (per-wheel channels suffixed with the side: ``toe_left``,
``toe_right``; per-axle channels such as ``roll_angle`` once). Pure functions on names; the
reader and the writer (:mod:`elastokin.formats.kc_test`) turn their ``ValueError`` into a
:class:`~elastokin.errors.MeasurementError` naming the file.

Units: every channel is converted to the elastokin unit of its quantity (mm, N, N*mm, deg,
``-`` for a fraction).
"""

from __future__ import annotations

import math
import re
from collections.abc import Sequence
from dataclasses import dataclass

from elastokin.rig.channels import CHANNEL_LIST, LOAD_CASE_LIST

__all__ = ["CHANNELS", "LOAD_CASES", "SIDES", "UNITS", "Channel", "LoadCase", "check_layout",
           "column_side", "input_columns"]

#: accepted units per quantity and their factor to the elastokin unit (the first entry)
UNITS: dict[str, dict[str, float]] = {
    "length": {"mm": 1.0, "cm": 10.0, "m": 1000.0},
    "force": {"N": 1.0, "kN": 1000.0},
    "torque": {"N*mm": 1.0, "N*m": 1000.0, "kN*m": 1.0e6},
    "angle": {"deg": 1.0, "rad": 180.0 / math.pi},
    "fraction": {"-": 1.0, "%": 0.01},
}

#: the wheel sides a channel name may end with
SIDES = ("left", "right")
#: other ways of naming a wheel side: refused in a channel's suffix (one axle per file, its
#: wheels named ``_left`` and ``_right``) instead of being taken for an unknown channel
_OTHER_SIDE = re.compile(r"(?:(?:front|rear)_)?(?:left|right|l|r|lh|rh|lf|rf|lr|rr|fl|fr|rl|"
                         r"nearside|offside|inner|outer|inside|outside|centre|center|middle|"
                         r"both)")


@dataclass(frozen=True)
class Channel:
    """A known test-file channel (from the channel table, :mod:`elastokin.rig.channels`): its
    quantity (a key of :data:`UNITS`), its per-wheel sign convention and whether it has one
    value for the whole axle (``per_axle``: never suffixed with a side)."""

    name: str
    quantity: str
    meaning: str
    per_axle: bool = False

    @property
    def unit(self) -> str:
        """The elastokin unit values are converted to."""
        return next(iter(UNITS[self.quantity]))


#: known channels by name
CHANNELS: dict[str, Channel] = {c.test: Channel(c.test, c.quantity, c.test_meaning, c.per_axle)
                                 for c in CHANNEL_LIST if c.test}
#: known channels, longest name first (a side suffix is looked for after the longest match)
_KNOWN = sorted(CHANNELS, key=len, reverse=True)


@dataclass(frozen=True)
class LoadCase:
    """A load case: its input channel (the file's first column) and the measured channels it
    must have; ``corner``: a single corner's case (else an axle's only)."""

    name: str
    input: str
    required: tuple[str, ...]
    meaning: str
    corner: bool = True


#: supported load cases by name (a corner's and an axle's)
LOAD_CASES: dict[str, LoadCase] = {c.name: LoadCase(c.name, c.test_input, c.test_required,
                                                   c.meaning, c.corner)
                                   for c in LOAD_CASE_LIST}


def column_side(name: str) -> tuple[str, str]:
    """(channel, side) of a normalised column name: ``toe_left`` -> (``toe``, ``left``); a
    known channel or an unknown name -> (name, ""). Raises ``ValueError`` (the reason) for a
    known channel with another side spelling (``toe_lh``), a side in front (``left_toe``) or
    a side on a per-axle channel (``roll_angle_left``)."""
    if name in CHANNELS:
        return name, ""
    for base in _KNOWN:
        if name.startswith(base + "_"):
            side = name[len(base) + 1:]
            if not re.fullmatch(_OTHER_SIDE, side):
                continue
            if CHANNELS[base].per_axle:
                raise ValueError(f"'{base}' has one value for the axle: name it '{base}', "
                                 "without a side")
            if side not in SIDES:
                raise ValueError(f"unknown side '{side}' (a per-wheel channel ends in _left or "
                                 f"_right, e.g. '{base}_left')")
            return base, side
        if name.endswith("_" + base):
            side = name[:-len(base) - 1]
            if re.fullmatch(_OTHER_SIDE, side):
                raise ValueError(f"put the side after the channel: '{base}_{side}' (sides: "
                                 "left, right)")
    return name, ""


def input_columns(load_case: str, names: Sequence[str]) -> list[str]:
    """The columns among ``names`` that hold the load case's input channel (one; two when a
    per-wheel input is given for both wheels)."""
    case = LOAD_CASES[load_case]
    return [n for n in names if _base(n) == case.input]


def _base(name: str) -> str:
    try:
        return column_side(name)[0]
    except ValueError:
        return name


def _shown(name: str, side: str = "") -> str:
    """A channel as a header cell in elastokin units, e.g. ``'toe_left [deg]'``."""
    unit = CHANNELS[name].unit if name in CHANNELS else ""
    return f"'{name}{'_' + side if side else ''} [{unit}]'"


def check_layout(load_case: str, names: Sequence[str], shown: Sequence[str]) -> tuple[str, ...]:
    """The wheel sides of a file (``()``: one wheel, unnamed; else those its per-wheel channels
    are suffixed with, in file order) from its column names (normalised, file order;
    ``shown``: the cells as written, for messages). Raises ``ValueError`` (the reason, naming
    the column) when a per-wheel channel lacks a side among suffixed ones, a per-wheel channel
    is given for one side and not the other, the first column is not the load case's input or
    a required channel is missing."""
    case = LOAD_CASES[load_case]
    columns = [column_side(n) for n in names]
    sides = tuple(dict.fromkeys(side for _, side in columns if side))
    if sides:
        for k, (base, side) in enumerate(columns):
            if not side and base in CHANNELS and not CHANNELS[base].per_axle:
                raise ValueError(f"column {k + 1} '{shown[k]}': a per-wheel channel without a "
                                 f"side, in a file whose channels name their wheel: "
                                 f"{' or '.join(_shown(base, s) for s in SIDES)}")
        given = {(base, side) for base, side in columns if side}
        for base, side in columns:
            for other in sides:
                if side and (base, other) not in given:
                    raise ValueError(f"channel {_shown(base, other)} is missing: the file has "
                                     f"{_shown(base, side)} (a file with both wheels gives "
                                     "every per-wheel channel for each)")
    first = columns[0][0]
    if first != case.input:
        wanted = _shown(case.input) if CHANNELS[case.input].per_axle or not sides else \
            " or ".join(_shown(case.input, s) for s in sides)
        raise ValueError(f"load case '{load_case}' needs its input channel {wanted} as the "
                         f"first column; the first column is '{shown[0]}'")
    missing = [_shown(c, side) for side in (sides or ("",)) for c in case.required
               if (c, side) not in columns]
    if missing:
        raise ValueError(f"load case '{load_case}' needs channel(s) {', '.join(missing)}; the "
                         f"file has {', '.join(shown)}")
    return sides
