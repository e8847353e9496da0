"""Design variables: what an optimiser may move, as typed overrides of a template suspension
(the style of :mod:`elastokin.config.variants`: a new, re-resolved suspension; nothing is
edited in place).

A :class:`DesignVariable` is one number of the design:

- ``hardpoint``: one coordinate (mm, config frame) of a hardpoint; on an axle the mirrored
  point moves with it (its x and z alike, its y the other way: the mirror about y = 0),
  unless ``side`` says ``config`` (this corner only) or ``other`` (the other corner only: its
  value is then the other side's coordinate);
- ``bushing_scale``: a factor (-) on a bushing's rates or curves in the chosen directions
  (both sides of an axle unless ``side`` says one);
- ``spring_rate`` (N/mm) and ``spring_preload`` (N; a spring the design balancing does not
  solve for);
- ``rack_position``: an offset (mm, config frame) of the steering rack and everything on it
  (its hardpoints: the rack's own point and the tie rods' inner points);
- ``rack_ratio``: the rack's travel per steering-wheel turn (mm/rev; a ``ratio_curve`` is
  scaled so that its centre slope takes the value).

:func:`design_suspension` applies values of variables to a template. Units as said; config
frame.
"""

from __future__ import annotations

import copy
import dataclasses
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from elastokin.config.frozen import plain_data
from elastokin.config.suspension import Suspension
from elastokin.errors import ConfigError

KINDS = ("hardpoint", "bushing_scale", "spring_rate", "spring_preload", "rack_position",
         "rack_ratio")
UNITS = {"hardpoint": "mm", "bushing_scale": "-", "spring_rate": "N/mm",
         "spring_preload": "N", "rack_position": "mm", "rack_ratio": "mm/rev"}
AXES = "xyz"
DIRECTIONS = ("x", "y", "z", "rx", "ry", "rz")
#: the mirror about the vehicle's centre plane y = 0 (config frame)
MIRROR = np.array([1.0, -1.0, 1.0])


@dataclass(frozen=True)
class DesignVariable:
    """One design variable (module docstring). ``lower``/``upper``: its bounds in its unit;
    ``axis``: 0, 1, 2 for x, y, z (hardpoint, rack position); ``directions``: the bushing
    directions a scale acts on; ``side``: ``both``, ``config`` or ``other``."""

    kind: str
    item: str = ""
    axis: int | None = None
    side: str = "both"
    lower: float = -np.inf
    upper: float = np.inf
    directions: tuple[str, ...] = DIRECTIONS

    @property
    def unit(self) -> str:
        return UNITS[self.kind]

    @property
    def name(self) -> str:
        """A short label: ``tierod_inner.z``, ``lca_bushing.scale(x,y,z)``, ``coil.rate``,
        ``rack.x``, ``rack.ratio``; `` (left only)`` when one side of an axle moves."""
        base = {
            "hardpoint": f"{self.item}.{AXES[self.axis or 0]}",
            "bushing_scale": f"{self.item}.scale"
            + ("" if self.directions == DIRECTIONS else f"({','.join(self.directions)})"),
            "spring_rate": f"{self.item}.rate", "spring_preload": f"{self.item}.preload",
            "rack_position": f"rack.{AXES[self.axis or 0]}", "rack_ratio": "rack.ratio",
        }[self.kind]
        return base if self.side == "both" else f"{base} ({self.side} side only)"

    def value(self, raw) -> float:
        """The variable's value in the config mapping ``raw``."""
        if self.kind == "hardpoint":
            if self.side == "other":
                return float(_other_point(raw, self.item)[self.axis])
            return float(raw["hardpoints"][self.item][self.axis])
        if self.kind in ("bushing_scale", "rack_position"):
            return 1.0 if self.kind == "bushing_scale" else 0.0
        if self.kind == "spring_rate":
            return float(raw["springs"][self.item]["rate_N_per_mm"])
        if self.kind == "spring_preload":
            return float(raw["springs"][self.item].get("preload_N") or 0.0)
        return _centre_ratio(raw["axle"]["steering"])

    def apply(self, raw: dict, value: float, template) -> None:
        """Set the variable to ``value`` in ``raw`` (plain, mutable config data), from the
        template's own mapping ``template`` (scales and offsets are relative to it)."""
        getattr(self, f"_apply_{self.kind}")(raw, float(value), template)

    def _apply_hardpoint(self, raw, value, template) -> None:
        axle = raw.get("axle")
        other = None
        if axle is not None and (self.side != "both" or self.item in (
                axle.get("other_side") or {}).get("hardpoints", {})):
            other = axle.setdefault("other_side", {}).setdefault("hardpoints", {})
        old = float(self.value(template))
        if self.side == "other":
            point = list(_other_point(template, self.item))
            point[self.axis] = value
            other[self.item] = point
            return
        if other is not None and self.side == "config" and self.item not in other:
            other[self.item] = list(_other_point(template, self.item))
        raw["hardpoints"][self.item][self.axis] = value
        if other is not None and self.side == "both" and self.item in other:
            moved = list(other[self.item])
            moved[self.axis] = float(moved[self.axis]) + MIRROR[self.axis] * (value - old)
            other[self.item] = moved

    def _apply_bushing_scale(self, raw, value, template) -> None:
        targets = []
        if self.side in ("both", "config"):
            targets.append(raw["connections"][self.item]["stiffness"])
        override = ((raw.get("axle") or {}).get("other_side") or {}).get(
            "connections", {}).get(self.item)
        if self.side == "other" and override is None:
            raise ConfigError(f"design variable '{self.name}': the other side's bushing "
                              "follows the mirror; give it its own rates under "
                              "axle.other_side.connections first")
        if override is not None and self.side in ("both", "other"):
            targets.append(override["stiffness"])
        for stiffness in targets:
            for d in self.directions:
                law = stiffness[d]
                if isinstance(law, dict):
                    stiffness[d] = {**law, "load": [value * v for v in law["load"]]}
                else:
                    stiffness[d] = value * law

    def _apply_spring_rate(self, raw, value, template) -> None:
        raw["springs"][self.item]["rate_N_per_mm"] = value

    def _apply_spring_preload(self, raw, value, template) -> None:
        spring = raw["springs"][self.item]
        spring.pop("free_length_mm", None)
        spring["preload_N"] = value

    def _apply_rack_position(self, raw, value, template) -> None:
        for name in rack_points(template):
            raw["hardpoints"][name][self.axis] = float(
                template["hardpoints"][name][self.axis]) + value

    def _apply_rack_ratio(self, raw, value, template) -> None:
        steering = raw["axle"]["steering"]
        if steering.get("ratio_curve") is None:
            steering["ratio_mm_per_rev"] = value
            return
        factor = value / _centre_ratio(template["axle"]["steering"])
        curve = steering["ratio_curve"]
        steering["ratio_curve"] = {**curve, "rack_travel_mm": [factor * v for v in
                                                               curve["rack_travel_mm"]]}


def _other_point(raw, name: str) -> np.ndarray:
    """The other side's position of the corner's hardpoint ``name`` (its override, or the
    mirror)."""
    other = ((raw.get("axle") or {}).get("other_side") or {}).get("hardpoints", {})
    if name in other:
        return np.asarray(other[name], float)
    return MIRROR * np.asarray(raw["hardpoints"][name], float)


def _centre_ratio(steering) -> float:
    """Rack travel per steering-wheel turn at the centre (mm/rev)."""
    if steering.get("ratio_curve") is None:
        return float(steering["ratio_mm_per_rev"])
    c = steering["ratio_curve"]
    return 360.0 * float(np.interp(1e-3, c["steering_wheel_deg"], c["rack_travel_mm"])
                         - np.interp(-1e-3, c["steering_wheel_deg"], c["rack_travel_mm"])) / 2e-3


def rack_points(raw) -> list[str]:
    """The hardpoints on the steering rack: the rack connection's and those of every
    connection of the rack part (the tie rods' inner points), by name."""
    raw = plain_data(raw)
    steering = (raw.get("axle") or {}).get("steering")
    if steering is None:
        return []
    connections = raw["connections"]
    part = connections[steering["rack"]]["parts"][1]
    names: list[str] = []
    for c in connections.values():
        parts = list(c.get("parts", ()))
        if part not in parts:
            continue
        at = c.get("at")
        if isinstance(at, list) and len(at) == 2:  # a link: the end on the rack
            at = at[parts.index(part)]
        if isinstance(at, str):
            names.append(at)
    return list(dict.fromkeys(names))


def check_variable(v: DesignVariable, suspension: Suspension, where: str) -> None:
    """Raise :class:`ConfigError` (``where``: the file and key) when ``v`` names nothing of
    ``suspension`` or cannot act on it."""
    raw = suspension.raw
    axle = raw.get("axle")

    def fail(msg: str) -> ConfigError:
        return ConfigError(f"{where}: {msg}")

    if v.side != "both" and axle is None:
        raise fail(f"'side: {v.side}' needs an axle; {suspension.source} is one corner")
    if v.kind == "hardpoint" and v.item not in raw["hardpoints"]:
        known = ", ".join(raw["hardpoints"])
        raise fail(f"no hardpoint '{v.item}' in {suspension.source} (hardpoints: {known})")
    if v.kind == "bushing_scale":
        c = raw["connections"].get(v.item)
        if c is None or c.get("type") != "bushing":
            known = ", ".join(k for k, c in raw["connections"].items()
                              if c.get("type") == "bushing")
            raise fail(f"no bushing '{v.item}' in {suspension.source} (bushings: {known})")
    if v.kind in ("spring_rate", "spring_preload") and v.item not in (raw.get("springs") or {}):
        raise fail(f"no spring '{v.item}' in {suspension.source}")
    if v.kind == "spring_preload" and v.item == (raw.get("design") or {}).get("balance_spring"):
        raise fail(f"spring '{v.item}' is balanced (design.balance_spring): its preload "
                   "follows from the design wheel load, it is not a design variable")
    if v.kind in ("rack_position", "rack_ratio") and not (axle or {}).get("steering"):
        raise fail(f"{suspension.source} has no steering rack (axle.steering)")
    if not v.lower < v.upper:
        raise fail(f"the bounds [{v.lower:g}, {v.upper:g}] are empty")
    start = v.value(raw)
    if not v.lower <= start <= v.upper:
        raise fail(f"the config's value {start:g} {v.unit} lies outside the bounds "
                   f"[{v.lower:g}, {v.upper:g}]")


def design_suspension(template: Suspension, variables: Sequence[DesignVariable],
                      values: Sequence[float]) -> Suspension:
    """``template`` with every variable at its value (re-resolved from the config mapping;
    the template's rig, rig file and kinematic setting kept)."""
    from elastokin.config.axle_resolver import resolve_suspension
    from elastokin.config.resolver import Resolver
    from elastokin.config.schema.suspension import SuspensionFile
    from elastokin.config.variants import kinematic

    base = plain_data(template.raw)
    raw = copy.deepcopy(base)
    for v, x in zip(variables, values):
        v.apply(raw, x, base)
    resolver = Resolver(SuspensionFile.model_validate(raw), template.source)
    out = resolve_suspension(resolver, template.sha256, raw, template.config_sha256,
                             template.rig_sha256)
    out = dataclasses.replace(out, rig=template.rig, rig_source=template.rig_source,
                              label=template.label)
    return kinematic(out) if template.kinematic else out


def nominal(suspension: Suspension) -> Suspension:
    """The config's own design, as a design study moves it: ``suspension`` without its CMM
    measurements and K&C test data (its hardpoints as the config gives them, its rig, rig
    file and kinematic setting kept; re-resolved). A suspension without either is returned
    as it is. Units as in the config (mm, N, N*mm, deg)."""
    if suspension.measurements is None and suspension.kc_test is None:
        return suspension
    bare = dataclasses.replace(suspension, raw={**suspension.raw, "measurements": None,
                                                "kc_test": None})
    return dataclasses.replace(design_suspension(bare, [], []), measurements=None,
                               kc_test=None)
