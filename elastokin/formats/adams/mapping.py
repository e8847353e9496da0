"""The ADAMS/Car mapping file and the frames: which ADAMS hardpoint, bushing and spring is which
elastokin one, and the template a subsystem file names.

Pure Python/numpy. ADAMS/Car's global frame is X rearward, Y right, Z up; a config declares its
``frame`` (``{x: rearward|forward, y: right|left}``, z up, same origin): :func:`adams_to_config`
and :func:`config_to_adams` convert explicitly. The mapping file (YAML) is read by both
``import-adams`` (ADAMS names -> elastokin) and ``export-adams`` (elastokin names -> ADAMS, the
template and roles of the ``[SUBSYSTEM_HEADER]``). An axle's anti-roll bar and steering are
subsystems of their own in ADAMS/Car: the mapping file's ``anti_roll_bar`` and ``steering``
sections (each a mapping of its own: ``subsystem``, ``hardpoints``, ``bushings``, the
``[PARAMETER]`` names and an optional curve file) name them. Format: ``docs/adams.md``.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from elastokin.config.confined import Roots, confined_path, resolved
from elastokin.config.loading import read_yaml
from elastokin.errors import ConfigError

__all__ = [
    "PARAMETER_KEYS",
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


#: per section (``anti_roll_bar``, ``steering``): the keys naming a ``[PARAMETER]`` of its
#: subsystem, and the default ADAMS parameter names (docs/adams.md, "Axles")
PARAMETER_KEYS: dict[str, dict[str, str]] = {
    "anti_roll_bar": {"stiffness": "arb_torsion_stiffness"},
    "steering": {"rack_ratio": "rack_ratio", "travel_limit": "max_rack_displacement"},
}


@dataclass(frozen=True)
class AdamsMapping:
    """A mapping file: elastokin hardpoint -> (ADAMS hardpoint, side or None for the default);
    elastokin bushing -> property file (``.bus`` or ``.xml``, as written: relative to the
    mapping file's folder; the path: :meth:`bushing_file`) and ADAMS usage; elastokin spring and
    damper -> ADAMS usage; ``subsystem``: the subsystem file's name, template, major and minor role,
    database (export).

    An axle's ``anti_roll_bar`` and ``steering`` subsystems are mappings of their own (None:
    not given; their items are then in the suspension's; ``key``: their keys' prefix), with
    ``parameters`` (role -> ADAMS ``[PARAMETER]`` name, :data:`PARAMETER_KEYS`) and ``curve``
    (an elastokin curve file as written, relative to the mapping file: the bar's torque curve
    or the rack ratio curve; the path: :meth:`curve_file`). The files it names must lie in
    ``roots`` (its folder and the databases it was read with)."""

    path: str
    side: str | None
    hardpoints: dict[str, tuple[str, str | None]]
    bushings: dict[str, str]
    bushing_usage: dict[str, str] = field(default_factory=dict)
    spring_usage: dict[str, str] = field(default_factory=dict)
    subsystem: dict[str, str] = field(default_factory=dict)
    damper_usage: dict[str, str] = field(default_factory=dict)
    anti_roll_bar: AdamsMapping | None = None
    steering: AdamsMapping | None = None
    parameters: dict[str, str] = field(default_factory=dict)
    curve: str | None = None
    key: str = ""
    roots: Roots | None = None

    def _named(self, key: str, text: str, what: str) -> Path:
        folder = Path(self.path).parent
        roots = self.roots or Roots.of([folder], f"the mapping file's folder {folder}")
        return confined_path(text, folder, roots, f"{self.path}: key '{self.key}{key}'", what)

    def bushing_file(self, name: str) -> Path:
        """The property file of bushing ``name``, inside :attr:`roots` (links and ``..``
        followed; nothing is opened)."""
        return self._named(f"bushings.{name}.file", self.bushings[name], "property file")

    def curve_file(self) -> Path | None:
        """The curve file, inside :attr:`roots` (None: none given)."""
        return None if self.curve is None else self._named("curve", self.curve, "curve file")

    def sections(self) -> dict[str, AdamsMapping]:
        """The mapping of each subsystem given: ``suspension`` (this one), ``anti_roll_bar``,
        ``steering``."""
        out = {"suspension": self, "anti_roll_bar": self.anti_roll_bar,
               "steering": self.steering}
        return {k: v for k, v in out.items() if v is not None}

    def all_hardpoints(self) -> set[str]:
        """Every elastokin hardpoint named in any section."""
        return {n for m in self.sections().values() for n in m.hardpoints}


_MAPPING_KEYS = ("elastokin_adams_mapping", "side", "subsystem", "hardpoints", "bushings",
                 "springs", "dampers", "anti_roll_bar", "steering")
_SECTION_KEYS = ("subsystem", "hardpoints", "bushings", "curve")


def _fail(path: str, key: str, msg: str) -> ConfigError:
    return ConfigError(f"{path}: key '{key}': {msg}")


def _hardpoints(p: str, hps, prefix: str = "") -> dict[str, tuple[str, str | None]]:
    if not isinstance(hps, dict) or not hps:
        raise _fail(p, prefix + "hardpoints", "expected a mapping 'elastokin name: ADAMS name'")
    hardpoints = {}
    for name, spec in hps.items():
        key = f"{prefix}hardpoints.{name}"
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


def _subsystem(p: str, subsystem, prefix: str = "") -> dict[str, str]:
    subsystem = subsystem or {}
    if not isinstance(subsystem, dict):
        raise _fail(p, prefix + "subsystem", f"expected a mapping of {', '.join(SUBSYSTEM_KEYS)}")
    for k, v in subsystem.items():
        if k not in SUBSYSTEM_KEYS:
            raise _fail(p, f"{prefix}subsystem.{k}", "unknown key (expected "
                        f"{', '.join(SUBSYSTEM_KEYS)})")
        if not isinstance(v, str) or not v.strip():
            raise _fail(p, f"{prefix}subsystem.{k}", "expected a text")
    return {k: str(v).strip() for k, v in subsystem.items()}


def _section(path: str | Path, data, key: str, side: str | None,
             roots: Roots | None) -> AdamsMapping | None:
    """The ``anti_roll_bar`` or ``steering`` section: a mapping of its own subsystem."""
    if data is None:
        return None
    p = str(path)
    params = PARAMETER_KEYS[key]
    allowed = (*_SECTION_KEYS, *params)
    if not isinstance(data, dict):
        raise _fail(p, key, f"expected a mapping of {', '.join(allowed)}")
    for k in data:
        if k not in allowed:
            raise _fail(p, f"{key}.{k}", f"unknown key (expected {', '.join(allowed)})")
    for k in (*params, "curve"):
        if k in data and (not isinstance(data[k], str) or not data[k].strip()):
            raise _fail(p, f"{key}.{k}", "expected an ADAMS parameter name" if k != "curve"
                        else "expected a curve file name")
    hps = data.get("hardpoints")
    hardpoints = _hardpoints(p, hps, f"{key}.") if hps is not None else {}
    bushings = _named(p, f"{key}.bushings", data.get("bushings"), ("file", "usage"))
    return AdamsMapping(
        p, side, hardpoints, {n: b["file"] for n, b in bushings.items() if "file" in b},
        {n: b["usage"] for n, b in bushings.items() if "usage" in b}, {},
        _subsystem(p, data.get("subsystem"), f"{key}."),
        parameters={k: data.get(k, default).strip() for k, default in params.items()},
        curve=data["curve"].strip() if "curve" in data else None, key=f"{key}.", roots=roots)


def read_mapping(path: str | Path, roots: Roots | None = None) -> AdamsMapping:
    """Read a mapping file (YAML, see ``docs/adams.md``). The files it names (bushing property
    files, curve files, relative to its folder) must lie inside its folder or ``roots`` (the
    databases given with it), links and ``..`` followed, when they are asked for
    (:meth:`AdamsMapping.bushing_file`, :meth:`AdamsMapping.curve_file`)."""
    data, _ = read_yaml(path, "ADAMS mapping file")  # strict YAML: no key twice
    p = str(path)
    if roots is not None and not roots.hold(resolved(Path(path).parent)):
        roots = roots.including([Path(path).parent], f"{roots.what} and the mapping file's "
                                                     "folder")
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
    dampers = _named(p, "dampers", data.get("dampers"), ("usage",))
    return AdamsMapping(
        p, side, hardpoints, {n: b["file"] for n, b in bushings.items() if "file" in b},
        {n: b["usage"] for n, b in bushings.items() if "usage" in b},
        {n: s["usage"] for n, s in springs.items()},
        _subsystem(p, data.get("subsystem")),
        anti_roll_bar=_section(path, data.get("anti_roll_bar"), "anti_roll_bar", side, roots),
        steering=_section(path, data.get("steering"), "steering", side, roots), roots=roots,
        damper_usage={n: d["usage"] for n, d in dampers.items()})
