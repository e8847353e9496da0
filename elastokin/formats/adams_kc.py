"""An elastokin ``kc.csv`` with ADAMS-style channel names (``kc_adams.csv``).

Values keep elastokin's units (mm, N, N*mm, deg) and signs, except the config-frame components
(:data:`FRAME_CHANNELS`: wheel-centre coordinates, contact-patch forces), which are converted to
ADAMS/Car's global frame (X rearward, Y right, Z up). Channel names: ``docs/adams.md``.
"""

from __future__ import annotations

import csv
import re
from collections.abc import Iterable
from pathlib import Path

from elastokin.errors import ConfigError
from elastokin.formats.adams_car import clean, frame_signs
from elastokin.version import __version__

__all__ = [
    "FRAME_CHANNELS",
    "KC_CHANNELS",
    "kc_to_adams_channels",
    "write_adams_kc_csv",
]

#: elastokin kc.csv column -> (ADAMS-style channel, unit, meaning); springs and bushings by
#: pattern (:func:`_channel`). Units and signs are elastokin's (README, sign conventions), except
#: the components in :data:`FRAME_CHANNELS`.
KC_CHANNELS: dict[str, tuple[str, str, str]] = {
    "model": ("model", "", "elastokin model label"),
    "load_case": ("load_case", "", "elastokin load case"),
    "step": ("step", "", "step number"),
    "branch": ("branch", "", "sweep branch"),
    "pad_z_mm": ("pad_vertical_displacement", "mm", "rig pad height from design, + up"),
    "wheel_travel_mm": ("wheel_travel", "mm", "wheel-centre vertical travel, + bump"),
    "toe_deg": ("toe_angle", "deg", "toe angle, + toe-in"),
    "camber_deg": ("camber_angle", "deg", "camber angle, + top of the wheel outboard"),
    "wheel_centre_longitudinal_mm": ("wheel_travel_base", "mm",
                                     "wheel-centre longitudinal displacement, + forward"),
    "wheel_centre_lateral_mm": ("wheel_travel_track", "mm",
                                "wheel-centre lateral displacement, + to the vehicle's left"),
    "wheel_centre_x_mm": ("wheel_center_x", "mm", "wheel-centre x, ADAMS/Car frame"),
    "wheel_centre_y_mm": ("wheel_center_y", "mm", "wheel-centre y, ADAMS/Car frame"),
    "wheel_centre_z_mm": ("wheel_center_z", "mm", "wheel-centre z, ADAMS/Car frame"),
    "contact_patch_fx_N": ("tire_force_x", "N", "rig force on the tyre, x, ADAMS frame"),
    "contact_patch_fy_N": ("tire_force_y", "N", "rig force on the tyre, y, ADAMS frame"),
    "contact_patch_fz_N": ("tire_force_z", "N", "rig force on the tyre, z, ADAMS frame"),
    "vertical_force_N": ("vertical_force", "N", "rig vertical force on the tyre, + up"),
    "lateral_force_N": ("lateral_force", "N", "rig lateral force on the tyre, + left"),
    "longitudinal_force_N": ("longitudinal_force", "N",
                             "rig longitudinal force on the tyre, + forward"),
    "aligning_torque_Nmm": ("aligning_torque", "N*mm", "rig torque about the vertical, + up"),
}

#: config-frame components, converted to the ADAMS/Car frame (X rearward, Y right, Z up)
FRAME_CHANNELS = {f"wheel_centre_{a}_mm": a for a in "xyz"} | {
    f"contact_patch_f{a}_N": a for a in "xyz"}


def _channel(column: str) -> tuple[str, str, str]:
    if column in KC_CHANNELS:
        return KC_CHANNELS[column]
    m = re.fullmatch(r"spring_(.+)_force_N", column)
    if m:
        return f"{m.group(1)}_spring_force", "N", "spring force, + compression"
    m = re.fullmatch(r"bushing_(.+)_(r?)([xyz])_(mm|deg)", column)
    if m:
        kind = "rot" if m.group(2) else "disp"
        return (f"bushing_{m.group(1)}_{kind}_{m.group(3)}", m.group(4),
                "bushing deflection, part 2 rel. part 1, bushing frame")
    return column, "", "not an elastokin column: kept as is"


def kc_to_adams_channels(header: list[str], rows: Iterable[list[str]], frame
                         ) -> tuple[list[str], list[str], list[list[str]]]:
    """Rename elastokin ``kc.csv`` columns to ADAMS-style channels (:data:`KC_CHANNELS`) and
    convert the config-frame components (wheel-centre coordinates, contact-patch forces) to the
    ADAMS/Car frame. Returns (channel names, units, rows); values are text, units unchanged
    (mm, N, N*mm, deg)."""
    signs = frame_signs(frame)
    chans = [_channel(c) for c in header]
    flip = [c in FRAME_CHANNELS and signs["xyz".index(FRAME_CHANNELS[c])] < 0 for c in header]
    out = []
    for row in rows:
        new = []
        for v, neg in zip(row, flip):
            if neg and v not in ("", None):
                x = -float(v)
                v = repr(clean(x))
            new.append(v)
        out.append(new)
    return [c[0] for c in chans], [c[1] for c in chans], out


def write_adams_kc_csv(kc_csv: str | Path, out: str | Path, frame) -> None:
    """Write an elastokin ``kc.csv`` with ADAMS-style channel names (``#`` header lines carry
    the source's provenance and each channel's unit)."""
    src = Path(kc_csv)
    try:
        lines = src.read_text(encoding="utf-8").splitlines()
    except OSError as exc:
        raise ConfigError(f"{src}: cannot read K&C results ({exc.strerror})") from None
    comments = [ln for ln in lines if ln.startswith("#") and not ln.startswith("# units:")]
    body = list(csv.reader([ln for ln in lines if ln and not ln.startswith("#")]))
    if not body or "toe_deg" not in body[0]:
        raise ConfigError(f"{src}: not an elastokin kc.csv (no header with toe_deg)")
    header, rows = body[0], body[1:]
    for i, r in enumerate(rows):
        if len(r) != len(header):
            raise ConfigError(f"{src}: data row {i + 1} has {len(r)} cells, header "
                              f"{len(header)}")
    names, units, rows = kc_to_adams_channels(header, rows, frame)
    with open(out, "w", newline="", encoding="utf-8") as fh:
        fh.write(f"# ADAMS-style channel names (elastokin {__version__}) from {src.name}\n")
        for c in comments:
            fh.write(c + "\n")
        fh.write("# frame of wheel_center_* and tire_force_*: ADAMS/Car global (X rearward, "
                 "Y right, Z up)\n")
        fh.write("# channel units: "
                 + ", ".join(f"{n} {u}" for n, u in zip(names, units) if u) + "\n")
        w = csv.writer(fh, lineterminator="\n")
        w.writerow(names)
        w.writerows(rows)
