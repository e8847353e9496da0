"""Reading a text file at the boundary: one reader for every text format elastokin reads, so
that a file that cannot be read, is binary or is not UTF-8 ends in one line naming the file,
the line and what it should be."""

from __future__ import annotations

from pathlib import Path

from elastokin.errors import ElastokinError, MeasurementError


def read_text(p: Path, what: str, hint: str,
              error: type[ElastokinError] = MeasurementError) -> str:
    """A text file's contents (UTF-8, a byte-order mark dropped); a file that cannot be read,
    is binary (NUL bytes) or is not UTF-8 raises ``error`` naming the file,
    the line and ``what`` it should be (``hint``: how to fix an encoding)."""
    try:
        data = p.read_bytes()
    except OSError as exc:
        raise error(f"{p}: cannot read {what} ({exc.strerror or exc})") from None
    if data[:2] in (b"\xff\xfe", b"\xfe\xff"):
        raise error(f"{p}: UTF-16 text; expected a {what} in UTF-8: {hint}")
    if b"\0" in data:
        k = data.index(b"\0")
        line = data.count(b"\n", 0, k) + 1
        raise error(f"{p}: line {line}: binary data (a NUL byte at byte {k}); "
                               f"expected a {what} (text)")
    try:
        return data.decode("utf-8").removeprefix("\ufeff")
    except UnicodeDecodeError as exc:
        line = data.count(b"\n", 0, exc.start) + 1
        raise error(f"{p}: line {line}: not UTF-8 text (byte {exc.start}: "
                               f"0x{data[exc.start]:02x}); expected a {what}: {hint}") from None
