"""The ADAMS/Car mapping file and the frames: which ADAMS hardpoint, bushing and spring is which
elastokin one, and the template a subsystem file names.

Pure Python/numpy. ADAMS/Car's global frame is X rearward, Y right, Z up; a config declares its
``frame`` (``{x: rearward|forward, y: right|left}``, z up, same origin): :func:`adams_to_config`
and :func:`config_to_adams` convert explicitly. The mapping file (YAML) is read by both
``import-adams`` (ADAMS names -> elastokin) and ``export-adams`` (elastokin names -> ADAMS, the
template and roles of the ``[SUBSYSTEM_HEADER]``). Format: ``docs/adams.md``.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from elastokin.config.loading import read_yaml
from elastokin.errors import ConfigError

__all__ = [
    "SUBSYSTEM_KEYS",
    "AdamsMapping",
    "adams_to_config",
    "config_to_adams",
    "frame_signs",
    "read_mapping",
]


def frame_signs(frame) -> np.ndarray:
    """Diagonal of the (self-inverse) map between the config frame and ADAMS/Car's."""
    if isinstance(frame, Mapping):
        x, y = frame.get("x"), frame.get("y")
    else:
        x, y = getattr(frame, "x", None), getattr(frame, "y", None)
    if (x, y) == ("rearward", "right"):
        return np.array([1.0, 1.0, 1.0])
    if (x, y) == ("forward", "left"):
        return np.array([-1.0, -1.0, 1.0])
    raise ConfigError(f"frame x {x} / y {y}: expected x rearward, y right (ADAMS/Car) or x "
                      "forward, y left (ISO 8855), z up")


def adams_to_config(point, frame) -> np.ndarray:
    """A point (mm) or direction from ADAMS/Car's global frame (X rearward, Y right, Z up) to
    the config frame ``frame`` (``{x: rearward|forward, y: right|left}``, same origin)."""
    return frame_signs(frame) * np.asarray(point, float)


def config_to_adams(point, frame) -> np.ndarray:
    """A point (mm) or direction from the config frame ``frame`` to ADAMS/Car's global frame."""
    return frame_signs(frame) * np.asarray(point, float)


#: keys of the mapping file's ``subsystem`` section (what export-adams writes in the
#: ``[SUBSYSTEM_HEADER]`` and where)
SUBSYSTEM_KEYS = ("name", "template", "major_role", "minor_role", "database")


@dataclass(frozen=True)
class AdamsMapping:
    """A mapping file: elastokin hardpoint -> (ADAMS hardpoint, side or None for the default);
    elastokin bushing -> property file (``.bus`` or ``.xml``, resolved against the mapping
    file's folder) and ADAMS usage; elastokin spring -> ADAMS usage; ``subsystem``: the
    subsystem file's name, template, major and minor role, database (export)."""

    path: str
    side: str | None
    hardpoints: dict[str, tuple[str, str | None]]
    bushings: dict[str, Path]
    bushing_usage: dict[str, str] = field(default_factory=dict)
    spring_usage: dict[str, str] = field(default_factory=dict)
    subsystem: dict[str, str] = field(default_factory=dict)


_MAPPING_KEYS = ("elastokin_adams_mapping", "side", "subsystem", "hardpoints", "bushings",
                 "springs")


def _fail(path: str, key: str, msg: str) -> ConfigError:
    return ConfigError(f"{path}: key '{key}': {msg}")


def _hardpoints(p: str, hps) -> dict[str, tuple[str, str | None]]:
    if not isinstance(hps, dict) or not hps:
        raise _fail(p, "hardpoints", "expected a mapping 'elastokin name: ADAMS name'")
    hardpoints = {}
    for name, spec in hps.items():
        key = f"hardpoints.{name}"
        hp_side = None
        if isinstance(spec, dict):
            extra = set(spec) - {"adams", "side"}
            if extra:
                raise _fail(p, f"{key}.{sorted(extra)[0]}", "unknown key (expected adams, side)")
            hp_side = spec.get("side")
            if hp_side not in (None, "left", "right"):
                raise _fail(p, f"{key}.side", f"expected left or right, got {hp_side!r}")
            spec = spec.get("adams")
        if not isinstance(spec, str) or not spec.strip():
            raise _fail(p, key, "expected an ADAMS hardpoint name or {adams: NAME, side: "
                        "left|right}")
        hardpoints[str(name)] = (spec.strip(), hp_side)
    return hardpoints


def _named(p: str, section: str, data, keys: tuple[str, ...]) -> dict[str, dict[str, str]]:
    """``section``: elastokin name -> {key: text} (a bare text is the first key)."""
    data = data or {}
    if not isinstance(data, dict):
        raise _fail(p, section, f"expected a mapping 'elastokin name: {keys[0]}'")
    out = {}
    for name, spec in data.items():
        bare = not isinstance(spec, dict)
        spec = {keys[0]: spec} if bare else spec
        extra = set(spec) - set(keys)
        if extra:
            raise _fail(p, f"{section}.{name}.{sorted(extra)[0]}",
                        f"unknown key (expected {', '.join(keys)})")
        for k, v in spec.items():
            if not isinstance(v, str) or not v.strip():
                where = f"{section}.{name}" + ("" if bare else f".{k}")
                raise _fail(p, where, "expected a property file name" if k == "file"
                            else f"expected an ADAMS {k} name")
        out[str(name)] = {k: v.strip() for k, v in spec.items()}
    return out


def read_mapping(path: str | Path) -> AdamsMapping:
    """Read a mapping file (YAML, see ``docs/adams.md``)."""
    data, _ = read_yaml(path, "ADAMS mapping file")  # strict YAML: no key twice
    p = str(path)
    for key in data:
        if key not in _MAPPING_KEYS:
            raise _fail(p, str(key), f"unknown key (expected {', '.join(_MAPPING_KEYS)})")
    if data.get("elastokin_adams_mapping") != 1:
        raise _fail(p, "elastokin_adams_mapping", "expected 1 (the mapping file format version)")
    side = data.get("side")
    if side not in (None, "left", "right"):
        raise _fail(p, "side", f"expected left or right, got {side!r}")
    hardpoints = _hardpoints(p, data.get("hardpoints"))
    bushings = _named(p, "bushings", data.get("bushings"), ("file", "usage"))
    springs = _named(p, "springs", data.get("springs"), ("usage",))
    subsystem = data.get("subsystem") or {}
    if not isinstance(subsystem, dict):
        raise _fail(p, "subsystem", f"expected a mapping of {', '.join(SUBSYSTEM_KEYS)}")
    for k, v in subsystem.items():
        if k not in SUBSYSTEM_KEYS:
            raise _fail(p, f"subsystem.{k}", f"unknown key (expected {', '.join(SUBSYSTEM_KEYS)})")
        if not isinstance(v, str) or not v.strip():
            raise _fail(p, f"subsystem.{k}", "expected a text")
    return AdamsMapping(
        p, side, hardpoints,
        {n: Path(path).parent / b["file"] for n, b in bushings.items() if "file" in b},
        {n: b["usage"] for n, b in bushings.items() if "usage" in b},
        {n: s["usage"] for n, s in springs.items()},
        {k: str(v).strip() for k, v in subsystem.items()})
