"""Design targets files (``elastokin optimize --targets T.yaml``): the design variables and
their bounds, target curves against a channel, target characteristics and constraints, as a
YAML file validated with pydantic; every error names the file and the key.

Units are in the key names (mm, N, N*mm, deg): a curve's points are keyed by the channels'
own names (``wheel_travel_mm``, ``toe_deg``), its tolerance by the unit of its y channel
(``tolerance_deg``); a characteristic is keyed by its name with its unit
(``bump_steer_deg_per_m``, ``axle.roll_centre_height_mm``) and its target, tolerance and
range are in that unit. Format and meaning: README "Design to targets".
"""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import Literal

import numpy as np
from pydantic import Field, ValidationError, model_validator

from elastokin.config.design_variables import AXES, DIRECTIONS, DesignVariable, check_variable
from elastokin.config.loading import format_validation_error, read_yaml
from elastokin.config.schema.base import StrictModel, Vector3
from elastokin.config.suspension import Suspension
from elastokin.errors import ConfigError
from elastokin.rig.channels import AXLE_CHARACTERISTICS, CHARACTERISTICS, LOAD_CASES, channel

Pair = tuple[float, float]


class Units(StrictModel):
    length: Literal["mm"] = "mm"
    force: Literal["N"] = "N"
    angle: Literal["deg"] = "deg"


class VariableSpec(StrictModel):
    """One design variable: exactly one of ``hardpoint`` (with ``axis``), ``bushing``,
    ``spring`` (with ``rate_N_per_mm`` or ``preload_N`` bounds) or ``rack`` (``position``
    with ``axis``, or ``ratio``); bounds absolute (``range_mm``, ``scale``,
    ``rate_N_per_mm``, ``preload_N``, ``ratio_mm_per_rev``) or around the config's value
    (``within_mm``)."""

    hardpoint: str | None = None
    bushing: str | None = None
    spring: str | None = None
    rack: Literal["position", "ratio"] | None = None
    axis: Literal["x", "y", "z"] | None = None
    side: Literal["both", "config", "other"] = "both"
    range_mm: Pair | None = None
    within_mm: float | None = Field(default=None, gt=0)
    scale: Pair | None = None
    directions: list[Literal["x", "y", "z", "rx", "ry", "rz"]] | None = None
    rate_N_per_mm: Pair | None = None
    preload_N: Pair | None = None
    ratio_mm_per_rev: Pair | None = None

    @model_validator(mode="after")
    def _one_kind(self) -> VariableSpec:
        kinds = [k for k in ("hardpoint", "bushing", "spring", "rack") if getattr(self, k)]
        if len(kinds) != 1:
            raise ValueError("give exactly one of 'hardpoint', 'bushing', 'spring', 'rack'")
        needs_axis = self.hardpoint is not None or self.rack == "position"
        if needs_axis != (self.axis is not None):
            raise ValueError("'axis' (x, y or z) goes with a hardpoint or the rack's position"
                             " only, and they need it")
        bounds = {"hardpoint": ("range_mm", "within_mm"), "bushing": ("scale",),
                  "spring": ("rate_N_per_mm", "preload_N"),
                  "rack": ("within_mm",) if self.rack == "position" else ("ratio_mm_per_rev",)}
        given = [k for k in ("range_mm", "within_mm", "scale", "rate_N_per_mm", "preload_N",
                             "ratio_mm_per_rev") if getattr(self, k) is not None]
        if len(given) != 1 or given[0] not in bounds[kinds[0]]:
            raise ValueError(f"a {kinds[0]} variable takes its bounds as one of "
                             f"{', '.join(bounds[kinds[0]])}")
        if self.directions is not None and self.bushing is None:
            raise ValueError("'directions' goes with a bushing")
        return self

    def variable(self, start: float | None = None) -> DesignVariable:
        """The :class:`DesignVariable` (``start``: the config's value, for ``within_mm``)."""
        axis = None if self.axis is None else AXES.index(self.axis)
        if self.within_mm is not None:
            lo, hi = (start or 0.0) - self.within_mm, (start or 0.0) + self.within_mm
        else:
            lo, hi = next(getattr(self, k) for k in ("range_mm", "scale", "rate_N_per_mm",
                                                     "preload_N", "ratio_mm_per_rev")
                          if getattr(self, k) is not None)
        if self.hardpoint is not None:
            return DesignVariable("hardpoint", self.hardpoint, axis, self.side, lo, hi)
        if self.bushing is not None:
            return DesignVariable("bushing_scale", self.bushing, None, self.side, lo, hi,
                                  tuple(self.directions or DIRECTIONS))
        if self.spring is not None:
            kind = "spring_rate" if self.rate_N_per_mm is not None else "spring_preload"
            return DesignVariable(kind, self.spring, None, self.side, lo, hi)
        kind = "rack_position" if self.rack == "position" else "rack_ratio"
        return DesignVariable(kind, "", axis, "both", lo, hi)


class CurveTarget(StrictModel):
    """A target curve: channel ``y`` against ``x`` in ``load_case`` (the config side's wheel
    unless ``side``), given at ``points`` (keyed by ``x`` and ``y``: their values);
    ``relative``: compare changes from each curve's value at x = 0; a band
    ``tolerance_<unit of y>`` (every point within it: a constraint) and/or a ``weight`` (its
    mean square error, in units of the tolerance or of y, in the objective; default 1)."""

    model_config = StrictModel.model_config | {"extra": "allow"}

    load_case: str
    x: str
    y: str
    side: Literal["left", "right"] | None = None
    points: dict[str, list[float]]
    relative: bool = False
    weight: float = Field(default=1.0, ge=0)

    @model_validator(mode="after")
    def _keys(self) -> CurveTarget:
        unit = self.y.rsplit("_", 1)[-1]
        extra = dict(self.model_extra or {})
        allowed = f"tolerance_{unit}"
        unknown = [k for k in extra if k != allowed]
        if unknown:
            raise ValueError(f"unknown key '{unknown[0]}' (a curve of {self.y} takes "
                             f"'{allowed}': the band, in the unit of {self.y})")
        tol = extra.get(allowed)
        if tol is not None and not (isinstance(tol, (int, float)) and tol > 0):
            raise ValueError(f"'{allowed}' must be a positive number")
        if set(self.points) != {self.x, self.y}:
            raise ValueError(f"'points' takes the lists '{self.x}' and '{self.y}'")
        if len(self.points[self.x]) != len(self.points[self.y]) or not self.points[self.x]:
            raise ValueError(f"'points': '{self.x}' and '{self.y}' need the same (non-zero) "
                             "number of values")
        if not np.all(np.isfinite(self.points[self.x] + self.points[self.y])):
            raise ValueError("'points' must be finite numbers")
        return self

    @property
    def tolerance(self) -> float | None:
        return (self.model_extra or {}).get(f"tolerance_{self.y.rsplit('_', 1)[-1]}")


class CharacteristicTarget(StrictModel):
    """A characteristic's target value (with a ``tolerance``: a constraint, and a ``weight``
    in the objective) or ``range``; in the characteristic's unit."""

    target: float | None = None
    tolerance: float | None = Field(default=None, gt=0)
    range: Pair | None = None
    weight: float = Field(default=1.0, ge=0)

    @model_validator(mode="after")
    def _one(self) -> CharacteristicTarget:
        if (self.target is None) == (self.range is None):
            raise ValueError("give 'target' (with 'tolerance' and/or 'weight') or 'range'")
        if self.range is not None and not self.range[0] < self.range[1]:
            raise ValueError("'range' must be [low, high] with low < high")
        if self.tolerance is not None and self.target is None:
            raise ValueError("'tolerance' goes with 'target'")
        return self


class LinkLength(StrictModel):
    """The distance between two hardpoints (``between``) or a link connection's (the key)
    within ``range_mm``."""

    between: tuple[str, str] | None = None
    range_mm: Pair


class KeepOut(StrictModel):
    """A box (config frame, mm) a hardpoint must stay out of."""

    hardpoint: str
    min_mm: Vector3
    max_mm: Vector3


class Constraints(StrictModel):
    link_lengths: dict[str, LinkLength] = {}
    keep_out: list[KeepOut] = []


class OptimizerSpec(StrictModel):
    """scipy's SLSQP: at most ``max_iterations``, stopping when the objective changes by less
    than ``tolerance`` (relative)."""

    max_iterations: int = Field(default=40, ge=1, le=1000)
    tolerance: float = Field(default=1e-10, gt=0)


class TargetsFile(StrictModel):
    elastokin_targets: Literal[1]
    units: Units = Units()
    model: Literal["initial", "initial_kinematic"] = "initial"
    variables: list[VariableSpec] = Field(min_length=1, max_length=200)
    curves: dict[str, CurveTarget] = {}
    characteristics: dict[str, CharacteristicTarget] = {}
    constraints: Constraints = Constraints()
    optimizer: OptimizerSpec = OptimizerSpec()


class Targets:
    """A validated targets file checked against a suspension: its ``variables``
    (:class:`DesignVariable`) and the rest of the spec (``spec``)."""

    def __init__(self, spec: TargetsFile, source: str, suspension: Suspension):
        self.spec, self.source = spec, source
        self.variables = []
        names = set()
        for i, v in enumerate(spec.variables):
            where = f"{source}: key 'variables[{i}]'"
            start = None
            if v.within_mm is not None:
                probe = v.variable(0.0)
                check_variable(dataclasses.replace(probe, lower=-np.inf, upper=np.inf),
                               suspension, where)
                start = probe.value(suspension.raw)
            var = v.variable(start)
            check_variable(var, suspension, where)
            if var.name in names:
                raise ConfigError(f"{where}: '{var.name}' is a design variable twice")
            names.add(var.name)
            self.variables.append(var)
        self._check_names(suspension)

    def _check_names(self, s: Suspension) -> None:
        spec, src = self.spec, self.source
        kinematic = spec.model.endswith("_kinematic")
        for name, c in spec.curves.items():
            key = f"{src}: key 'curves.{name}"
            case = LOAD_CASES.get(c.load_case)
            if case is None:
                raise ConfigError(f"{key}.load_case': unknown load case '{c.load_case}' "
                                  f"(load cases: {', '.join(LOAD_CASES)})")
            if not case.corner and s.axle is None:
                raise ConfigError(f"{key}.load_case': '{c.load_case}' is an axle's load case;"
                                  f" {s.source} is one corner")
            if kinematic and not case.vertical:
                raise ConfigError(f"{key}.load_case': the kinematic model does not run "
                                  f"'{c.load_case}' (a force case): use model: initial")
            for axis in ("x", "y"):
                if channel(getattr(c, axis)) is None:
                    raise ConfigError(f"{key}.{axis}': unknown channel '{getattr(c, axis)}' "
                                      "(the kc.csv columns, README 'Output files')")
            if c.side is not None and c.side not in s.sides:
                raise ConfigError(f"{key}.side': no wheel on the {c.side} side")
        known = target_characteristics(s)
        for name in spec.characteristics:
            if name not in known:
                raise ConfigError(f"{src}: key 'characteristics.{name}': unknown characteristic"
                                  f" (known: {', '.join(sorted(known))})")
        links = {lk.name for lk in s.links}
        for name, lk in spec.constraints.link_lengths.items():
            key = f"{src}: key 'constraints.link_lengths.{name}'"
            points = lk.between or ()
            if lk.between is None and name not in links:
                raise ConfigError(f"{key}: no link '{name}' (links: {', '.join(sorted(links))}"
                                  "); or give 'between: [point, point]'")
            for p in points:
                if p not in s.hardpoints:
                    raise ConfigError(f"{key}.between': no hardpoint '{p}'")
            if not lk.range_mm[0] < lk.range_mm[1]:
                raise ConfigError(f"{key}.range_mm': must be [low, high] with low < high")
        for i, box in enumerate(spec.constraints.keep_out):
            key = f"{src}: key 'constraints.keep_out[{i}]'"
            if box.hardpoint not in s.hardpoints:
                raise ConfigError(f"{key}.hardpoint': no hardpoint '{box.hardpoint}'")
            if not np.all(np.array(box.min_mm) < np.array(box.max_mm)):
                raise ConfigError(f"{key}': min_mm must be below max_mm in x, y and z")
        if not spec.curves and not spec.characteristics:
            raise ConfigError(f"{src}: give at least one target under 'curves' or "
                              "'characteristics'")


def characteristic_unit(name: str) -> str:
    """The unit of a characteristic by a targets file's name (``axle.``, ``right.``
    prefixes allowed), from the channel table."""
    base = name.split(".")[-1]
    table = AXLE_CHARACTERISTICS if name.startswith("axle.") else CHARACTERISTICS
    c = table.get(base)
    return "" if c is None else c.unit


def target_characteristics(s: Suspension) -> set[str]:
    """The characteristics a targets file may name for ``s``: the config side's wheel's
    (``bump_steer_deg_per_m``), the other wheel's (``right.bump_steer_deg_per_m``) and the
    axle's (``axle.roll_centre_height_mm``)."""
    own = set(CHARACTERISTICS)
    out = set(own)
    for side in s.sides[1:]:
        out |= {f"{side}.{c}" for c in own}
    if s.axle is not None:
        out |= {f"axle.{c}" for c in AXLE_CHARACTERISTICS}
    return out


def load_targets(path: str | Path, suspension: Suspension) -> Targets:
    """Read, validate and check a targets file against ``suspension`` (ConfigError naming
    the file and the key)."""
    data, _ = read_yaml(path, "targets file")
    try:
        spec = TargetsFile.model_validate(data)
    except ValidationError as err:
        raise ConfigError(format_validation_error(str(path), err, data, TargetsFile)) from None
    return Targets(spec, str(path), suspension)
