"""The columns named after an item of a suspension (a spring's force, length and motion
ratio, a damper's length and motion ratio, a stop's force, a bushing's deflection, an element's
load in loads.csv): their names and the fields of their channel, the rest of the channel table
being :mod:`elastokin.rig.channels`'s. Units mm, N, N*mm, deg; the unit is the name's suffix.
"""

from __future__ import annotations

import re

#: loads.csv: force x y z (N), moment x y z (N*mm) in each frame (docs/characteristics.md)
LOAD_COMPONENTS = ("fx", "fy", "fz", "mx", "my", "mz")
LOAD_FRAMES = {"body": "the ground part's (config) frame", "local": "the element's own, fixed "
               "to its first part: a bushing's (z axial), a joint's (z its axis; a ball joint: "
               "the part's axes), the steering gear's (z along the rack); links, springs, "
               "stops: z from its first part's point to the second's (fz > 0 in tension)"}
LOAD_SIGN = ("force or moment the element applies to its first part (a connection's "
             "parts[0]; a contact patch: the wheel's part) about its point on it")

_LOAD = re.compile(r"(.+)_([fm])([xyz])_(body|local)_(N|Nmm)")
_SPRING = re.compile(r"spring_(.+)_force_N")
_LENGTH = re.compile(r"(spring|damper)_(.+)_length_mm")
_RATIO = re.compile(r"(spring|damper)_(.+)_motion_ratio")
_STOP = re.compile(r"stop_(.+)_force_N")
_BUSHING = re.compile(r"bushing_(.+)_(r?)([xyz])_(mm|deg)")


def bushing_columns(bushing: str) -> list[str]:
    """kc.csv columns of a bushing's deflection: x y z (mm), rx ry rz (deg)."""
    units = ("mm", "mm", "mm", "deg", "deg", "deg")
    return [f"bushing_{bushing}_{d}_{u}" for d, u in zip(("x", "y", "z", "rx", "ry", "rz"),
                                                        units)]


def load_column(item: str, component: str, frame: str) -> str:
    """The loads.csv column of an element's load component (:data:`LOAD_COMPONENTS`) in a
    frame (:data:`LOAD_FRAMES`), e.g. ``lca_bushing_fx_body_N``."""
    return f"{item}_{component}_{frame}_{'N' if component[0] == 'f' else 'Nmm'}"


def spring_column(spring: str) -> str:
    return f"spring_{spring}_force_N"


def stop_column(stop: str) -> str:
    return f"stop_{stop}_force_N"


def length_column(kind: str, name: str) -> str:
    """kc.csv column of a spring's or damper's (``kind``) length (mm)."""
    return f"{kind}_{name}_length_mm"


def motion_ratio_column(length: str) -> str | None:
    """The motion-ratio column of a spring's or damper's length column (None: not one)."""
    m = _LENGTH.fullmatch(length)
    return None if m is None else f"{m.group(1)}_{m.group(2)}_motion_ratio"


def item_channel_fields(name: str) -> dict | None:
    """The fields of the :class:`~elastokin.rig.channels.Channel` of a column named after an
    item (None: no such column): name, unit, sign, label and ADAMS name."""
    m = _SPRING.fullmatch(name)
    if m:
        return _fields(name, "N", "coil spring force, positive in compression",
                       f"spring {m.group(1)} force [N] (+ compression)",
                       adams=f"{m.group(1)}_spring_force")
    m = _LENGTH.fullmatch(name) or _RATIO.fullmatch(name)
    if m and name.endswith("_mm"):
        return _fields(name, "mm", f"{m[1]} length between its points",
                       f"{m[1]} {m[2]} length [mm]", adams=f"{m[2]}_{m[1]}_length")
    if m:
        return _fields(name, "-", f"motion ratio: the {m[1]}'s compression per wheel travel "
                       "along the travel load case's motion, + when bump compresses it",
                       f"{m[1]} {m[2]} motion ratio [-]", adams=f"{m[2]}_{m[1]}_motion_ratio")
    m = _STOP.fullmatch(name)
    if m:
        return _fields(name, "N", "bump or rebound stop force, + pushing its points apart "
                       "(bump) or together (rebound); 0 out of contact",
                       f"stop {m.group(1)} force [N]", adams=f"{m.group(1)}_force")
    m = _LOAD.fullmatch(name)
    if m:
        unit, what = ("N", "force") if m.group(2) == "f" else ("N*mm", "moment")
        return _fields(name, unit, f"{LOAD_SIGN}; {m.group(4)}: {LOAD_FRAMES[m.group(4)]}",
                       f"{m.group(1)} {what} {m.group(3)} [{unit}] ({m.group(4)} frame)")
    m = _BUSHING.fullmatch(name)
    if m:
        kind = "rot" if m.group(2) else "disp"
        return _fields(name, m.group(4), "deflection of the part-2 sleeve relative to part 1, "
                       "bushing frame (z axial, x main radial), incl. the preload deflection; "
                       "rotations Tait-Bryan x-y-z",
                       f"bushing {m.group(1)} {m.group(2)}{m.group(3)} [{m.group(4)}]",
                       adams=f"bushing_{m.group(1)}_{kind}_{m.group(3)}")
    return None


def _fields(name: str, unit: str, sign: str, label: str, adams: str | None = None) -> dict:
    return {"name": name, "unit": unit, "sign": sign, "label": label, "adams": adams}
