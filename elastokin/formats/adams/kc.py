"""An elastokin ``kc.csv`` with ADAMS-style channel names (``kc_adams.csv``).

Values keep elastokin's units (mm, N, N*mm, deg) and signs, except the config-frame components
(:data:`FRAME_CHANNELS`: wheel-centre coordinates, contact-patch forces), which are converted to
ADAMS/Car's global frame (X rearward, Y right, Z up). Channel names: ``docs/adams.md``.
"""

from __future__ import annotations

import csv
from collections.abc import Iterable
from pathlib import Path

from elastokin.errors import ConfigError
from elastokin.formats.adams.car import clean, frame_signs
from elastokin.rig.channels import CHANNEL_LIST, channel
from elastokin.version import __version__

__all__ = [
    "FRAME_CHANNELS",
    "adams_channel",
    "kc_to_adams_channels",
    "write_adams_kc_csv",
]

#: the columns of kc.csv that are not channels: kept under their own names
_INDEX = {"model": "elastokin model label", "load_case": "elastokin load case",
          "side": "the wheel's side (vehicle left/right)", "step": "step number",
          "branch": "sweep branch"}
#: config-frame components, converted to the ADAMS/Car frame (X rearward, Y right, Z up)
FRAME_CHANNELS = {c.name: c.adams_frame for c in CHANNEL_LIST if c.adams_frame}


def adams_channel(column: str) -> tuple[str, str, str]:
    """(ADAMS-style channel name, unit, meaning) of a kc.csv column, from the channel table
    (:mod:`elastokin.rig.channels`); unknown columns are kept as they are."""
    if column in _INDEX:
        return column, "", _INDEX[column]
    ch = channel(column)
    if ch is None or ch.adams is None:
        return column, "", "not an elastokin column: kept as is"
    meaning = f"{ch.sign}; ADAMS/Car frame" if ch.adams_frame else ch.sign
    return ch.adams, ch.unit, meaning


def kc_to_adams_channels(header: list[str], rows: Iterable[list[str]], frame
                         ) -> tuple[list[str], list[str], list[list[str]]]:
    """Rename elastokin ``kc.csv`` columns to ADAMS-style channels (:func:`adams_channel`) and
    convert the config-frame components (wheel-centre coordinates, contact-patch forces) to the
    ADAMS/Car frame. Returns (channel names, units, rows); values are text, units unchanged
    (mm, N, N*mm, deg). A converted value that is not a number raises ``ValueError`` naming
    its data row and column."""
    signs = frame_signs(frame)
    chans = [adams_channel(c) for c in header]
    flip = [c in FRAME_CHANNELS and signs["xyz".index(FRAME_CHANNELS[c])] < 0 for c in header]
    out = []
    for i, row in enumerate(rows, start=1):
        new = []
        for v, neg, name in zip(row, flip, header):
            if neg and v not in ("", None):
                try:
                    x = -float(v)
                except ValueError:
                    raise ValueError(f"data row {i}, column {name}: '{v}' is not a "
                                     "number") from None
                v = repr(clean(x))
            new.append(v)
        out.append(new)
    return [c[0] for c in chans], [c[1] for c in chans], out


def _read_kc_csv(src: Path) -> tuple[list[str], list[str], list[list[str]]]:
    """(comment lines, header, rows) of an elastokin kc.csv; unreadable, binary or non-UTF-8
    files and malformed rows raise :class:`ConfigError` naming the file and the line."""
    try:
        data = src.read_bytes()
    except OSError as exc:
        raise ConfigError(f"{src}: cannot read K&C results ({exc.strerror or exc})") from None
    bad = data.find(b"\0")  # a NUL byte: binary data
    if bad < 0:
        try:
            text = data.decode("utf-8")
        except UnicodeDecodeError as exc:
            bad = exc.start
    if bad >= 0:
        line = data.count(b"\n", 0, bad) + 1
        raise ConfigError(f"{src}: line {line}: binary or non-UTF-8 data (byte {bad}); expected "
                          "an elastokin kc.csv (UTF-8 text from 'elastokin kc')")
    lines = text.splitlines()
    comments = [ln for ln in lines if ln.startswith("#") and not ln.startswith("# units:")]
    numbered = [(n, ln) for n, ln in enumerate(lines, start=1) if ln and not ln.startswith("#")]
    try:
        body = list(csv.reader([ln for _, ln in numbered]))
    except csv.Error as exc:
        raise ConfigError(f"{src}: unreadable CSV ({exc}); expected an elastokin kc.csv") from None
    if not body or "toe_deg" not in body[0]:
        raise ConfigError(f"{src}: not an elastokin kc.csv (no header with toe_deg)")
    header, rows = body[0], body[1:]
    for i, r in enumerate(rows):
        if len(r) != len(header):
            raise ConfigError(f"{src}: line {numbered[i + 1][0]}: data row {i + 1} has {len(r)} "
                              f"cells, header {len(header)}")
    return comments, header, rows


def write_adams_kc_csv(kc_csv: str | Path, out: str | Path, frame) -> None:
    """Write an elastokin ``kc.csv`` with ADAMS-style channel names (``#`` header lines carry
    the source's provenance and each channel's unit)."""
    src = Path(kc_csv)
    comments, header, rows = _read_kc_csv(src)
    try:
        names, units, rows = kc_to_adams_channels(header, rows, frame)
    except ValueError as exc:
        raise ConfigError(f"{src}: {exc} (expected an elastokin kc.csv)") from None
    try:
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
    except OSError as exc:
        raise ConfigError(f"{out}: cannot write ({exc.strerror or exc})") from None
