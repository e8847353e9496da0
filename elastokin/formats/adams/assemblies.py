"""Assembly blocks of ADAMS/Car subsystem files (``[BUSHING_ASSEMBLY]``, ``[NSPRING_ASSEMBLY]``,
``[DAMPER_ASSEMBLY]``...), with left/right pairs kept apart.

Pure Python/numpy. ADAMS/Car writes one block per USAGE with ``SYMMETRY = 'left/right'`` (the
same values on both sides) or ``'single'``, and a left/right pair whose sides differ as two
blocks of the same USAGE, ``SYMMETRY = 'left'`` and ``'right'``: each is read into its side.
Values are in elastokin units (converted by :mod:`elastokin.formats.adams.teimorbit`).
Conventions: ``docs/adams.md``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from elastokin.formats.adams.teimorbit import TeimOrbitFile, read_teimorbit

__all__ = [
    "ASSEMBLY_SIDES",
    "Assembly",
    "read_assemblies",
    "read_bushing_assemblies",
    "read_spring_assemblies",
]

#: the sides a SYMMETRY value puts a block on
ASSEMBLY_SIDES = {"left/right": ("left", "right"), "left": ("left",), "right": ("right",),
                  "single": ("single",)}


@dataclass(frozen=True)
class Assembly:
    """One assembly block: its USAGE, SYMMETRY as written, line, DEFINITION, PROPERTY_FILE
    (and its line) and every ``KEY = value`` (converted to elastokin units where the key is a
    known quantity: preloads N and N*mm, offsets mm and deg)."""

    block: str
    usage: str
    symmetry: str
    line: int
    definition: str | None = None
    property_file: str | None = None
    values: dict[str, float | str] = field(default_factory=dict)
    property_file_line: int | None = None

    def where(self, path: str | Path, side: str) -> str:
        """``FILE, line N, block [BLOCK] USAGE 'u' (side)``: where its PROPERTY_FILE is
        named (errors)."""
        return (f"{path}, line {self.property_file_line or self.line}, block [{self.block}] "
                f"USAGE '{self.usage}' ({side})")

    @property
    def preload(self) -> np.ndarray:
        """(T_PRELOAD_X/Y/Z N, R_PRELOAD_X/Y/Z N*mm), bushing frame; missing keys are 0."""
        return np.array([float(self.values.get(f"{k}_PRELOAD_{a}", 0.0)) for k in "TR"
                         for a in "XYZ"])


def read_assemblies(source: str | Path | TeimOrbitFile, block: str
                    ) -> dict[str, dict[str, Assembly]]:
    """Every ``[block]`` of a TeimOrbit file: USAGE -> side (``left``, ``right`` or ``single``)
    -> :class:`Assembly`. A ``left/right`` block is on both sides; a later block for the same
    USAGE and side replaces the earlier one with a warning in the file's ``warnings`` (pass a
    :class:`TeimOrbitFile` to keep them)."""
    f = source if isinstance(source, TeimOrbitFile) else read_teimorbit(source)
    out: dict[str, dict[str, Assembly]] = {}
    for b in f.blocks_named(block):
        usage = b.value("USAGE")
        if not isinstance(usage, str) or not usage:
            raise f.error(b.line, b.name, "USAGE = 'name' is missing")
        symmetry = str(b.value("SYMMETRY", "single")).strip().lower()
        if symmetry not in ASSEMBLY_SIDES:
            raise f.error(b.entries["SYMMETRY"].line, b.name, f"USAGE '{usage}': SYMMETRY "
                          f"{b.value('SYMMETRY')!r}, expected one of "
                          f"{', '.join(ASSEMBLY_SIDES)}")
        definition, prop = b.value("DEFINITION"), b.value("PROPERTY_FILE")
        a = Assembly(b.name, usage, symmetry, b.line,
                     definition if isinstance(definition, str) else None,
                     prop if isinstance(prop, str) else None,
                     {k: e.value for k, e in b.entries.items()},
                     b.entries["PROPERTY_FILE"].line if "PROPERTY_FILE" in b.entries else None)
        sides = out.setdefault(usage, {})
        for side in ASSEMBLY_SIDES[symmetry]:
            if side in sides:
                f.warn(b.line, b.name, f"USAGE '{usage}' ({side}) is given again (first at "
                       f"line {sides[side].line}): the last block is used")
            sides[side] = a
    return out


def read_bushing_assemblies(path: str | Path | TeimOrbitFile) -> dict[str, dict[str, Assembly]]:
    """The ``[BUSHING_ASSEMBLY]`` blocks: USAGE -> side -> :class:`Assembly` (its ``preload``:
    Fx Fy Fz N, Tx Ty Tz N*mm, bushing frame; ``property_file`` as written)."""
    return read_assemblies(path, "BUSHING_ASSEMBLY")


def read_spring_assemblies(path: str | Path | TeimOrbitFile) -> dict[str, dict[str, Assembly]]:
    """The ``[NSPRING_ASSEMBLY]`` blocks: USAGE -> side -> :class:`Assembly` (``values``:
    VALUE_TYPE, USER_VALUE...; ``property_file``: the ``.spr`` file as written)."""
    return read_assemblies(path, "NSPRING_ASSEMBLY")
