"""A config as far as it resolves, with every error listed: what ``elastokin view`` shows of a
config being written. A valid config is its whole :class:`~elastokin.config.suspension
.Suspension` (both corners of an axle); a config with errors keeps every item of its corner
that resolves on its own (a hardpoint, a part, a connection, a spring, a damper, a stop, the
wheel) and lists each error in the words of :func:`elastokin.config.loading.load_suspension`
(file, key, what is expected). Nothing is guessed: an item with an error is left out, never
replaced.

How: the sections are validated one by one (``hardpoints``, ``parts``, ``connections``,
``springs``, ``dampers`` and ``stops`` item by item) against the schema's own fields; the
valid ones are resolved strictly when the geometry has no error, else item by item by a
:class:`TolerantResolver` (the resolver's :meth:`~elastokin.config.resolver.Resolver.attempt`
records an item's error instead of raising it). Units mm, deg; the config frame.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from pydantic import ValidationError, create_model

from elastokin.config.axle import joins_sides
from elastokin.config.axle_resolver import resolve_suspension
from elastokin.config.frozen import plain_data
from elastokin.config.loading import format_validation_error, load_suspension, read_yaml
from elastokin.config.resolver import Resolver
from elastokin.config.schema.base import StrictModel
from elastokin.config.schema.suspension import DesignSpec, Frame, PartSpec, SuspensionFile
from elastokin.config.suspension import (
    Axle,
    Beam,
    Bushing,
    Damper,
    Joint,
    Link,
    Spring,
    Stop,
    Suspension,
    Wheel,
)
from elastokin.errors import ConfigError

#: the sections validated item by item (a mapping of named items each)
ITEM_SECTIONS = ("hardpoints", "parts", "connections", "springs", "dampers", "stops")
#: the sections the geometry is made of: with an error in one, the config resolves item by item
GEOMETRY = (*ITEM_SECTIONS, "frame", "side", "ground", "wheel", "design", "axle")
#: stand-ins of required sections with an error, for the items that do not read them
_STAND_INS = {**{k: {} for k in ITEM_SECTIONS}, "frame": Frame(x="forward", y="left"),
              "side": "left", "ground": "ground", "wheel": None, "name": "",
              "design": DesignSpec.model_construct(wheel_load_N=1.0, balance_spring=None,
                                                   balance_bushing_preloads=False)}


@dataclass(frozen=True)
class SuspensionDraft:
    """What resolved of a config (the fields of :class:`Suspension` that describe its
    geometry; mm, config frame) and the errors (each one line naming the file and the key;
    none for a valid config, whose ``suspension`` is then the whole of it)."""

    name: str
    source: str
    frame: Frame
    side: str
    ground: str
    parts: Mapping[str, PartSpec]
    hardpoints: Mapping[str, np.ndarray]
    joints: tuple[Joint, ...] = ()
    links: tuple[Link, ...] = ()
    bushings: tuple[Bushing, ...] = ()
    springs: tuple[Spring, ...] = ()
    stops: tuple[Stop, ...] = ()
    wheels: Mapping[str, Wheel] = field(default_factory=dict)
    axle: Axle | None = None
    errors: tuple[str, ...] = ()
    suspension: Suspension | None = None
    beams: tuple[Beam, ...] = ()  # the flexible parts (none resolved item by item)
    dampers: tuple[Damper, ...] = ()


def draft_of(s: Suspension, errors: tuple[str, ...] = ()) -> SuspensionDraft:
    """The draft of a resolved suspension (with ``errors`` of sections beside its geometry)."""
    return SuspensionDraft(s.name, s.source, s.frame, s.side, s.ground, s.parts, s.hardpoints,
                           s.joints, s.links, s.bushings, s.springs, s.stops, s.wheels,
                           s.axle, tuple(errors), s, s.beams, s.dampers)


def draft_suspension(path: str | Path) -> SuspensionDraft:
    """The config file at ``path`` as far as it resolves (module docstring); an unreadable
    file or malformed YAML is a draft with nothing but that error."""
    try:
        data, _ = read_yaml(path)
    except ConfigError as exc:
        return SuspensionDraft(Path(path).stem, str(path), _STAND_INS["frame"], "left",
                               "ground", {}, {}, errors=(str(exc),))
    try:
        return draft_of(load_suspension(path))
    except ConfigError as exc:
        return draft_from_dict(data, str(path), str(exc))


def draft_from_dict(data: Mapping, source: str, error: str | None = None) -> SuspensionDraft:
    """A config mapping as far as it resolves; ``error``: the strict loader's, listed when
    the sections' own checks do not find it (a check across sections)."""
    data = plain_data(data)
    valid, errors = validated_sections(data, source)
    spec = SuspensionFile.model_construct(**{**_STAND_INS, **valid})
    bad = any(k in data and k not in valid for k in GEOMETRY) or any(
        _item_errors(errors, source, k) for k in ITEM_SECTIONS)
    if not bad and "wheel" in valid and "design" in valid:
        try:
            s = resolve_suspension(Resolver(spec, source), "", data)
            return draft_of(s, _with(errors, error))
        except ConfigError as exc:
            error = error or str(exc)
    # the corner alone: an item joining the two sides of an axle is left out with the axle
    tolerant = TolerantResolver(spec.model_copy(update={"axle": None}), source,
                                across=spec.axle if "axle" in valid else None)
    corner = tolerant.corner()
    for check in (tolerant.check_names, tolerant.check_label):
        tolerant.attempt(check)
    wheels = {spec.side: corner.wheel} if corner.wheel is not None else {}
    return SuspensionDraft(
        spec.name or Path(source).stem, source, spec.frame, spec.side, spec.ground,
        dict(spec.parts) if "parts" in valid else {}, tolerant.hardpoints, corner.joints,
        corner.links, corner.bushings, tuple(corner.springs), tuple(corner.stops), wheels,
        errors=_with(errors + tolerant.errors, error), dampers=tuple(corner.dampers))


def _with(errors: list[str], error: str | None) -> tuple[str, ...]:
    """``errors`` once each, and ``error`` first when it is not among them (nor one of them
    with more problems counted)."""
    out = list(dict.fromkeys(errors))
    if error and not any(error.startswith(e) or e.startswith(error.split(" (")[0])
                         for e in out):
        out.insert(0, error)
    return tuple(out)


def _item_errors(errors: list[str], source: str, section: str) -> bool:
    return any(e.startswith(f"{source}: key '{section}.") for e in errors)


# ------------------------------------------------------------------------- section by section
def _field_model(name: str) -> type[StrictModel]:
    """A model of the one top-level field ``name`` of the config (its type and checks)."""
    f = SuspensionFile.model_fields[name]
    return create_model(f"Only_{name}", __base__=StrictModel, **{name: (f.annotation, f)})


_FIELD_MODELS = {name: _field_model(name) for name in SuspensionFile.model_fields}
_NOTHING = create_model("Nothing", __base__=StrictModel)


def validated_sections(data: Mapping, source: str) -> tuple[dict, list[str]]:
    """(the valid top-level fields of ``data`` as the schema makes them, the errors): the
    item sections keep their valid items; a missing required section, an unknown key and
    an invalid section or item are one error each, in the config's key paths."""
    valid: dict = {}
    errors: list[str] = []

    def check(key: str, value) -> object | None:
        try:
            return getattr(_FIELD_MODELS[key].model_validate({key: value}), key)
        except ValidationError as err:
            errors.append(format_validation_error(source, err, {key: value}, SuspensionFile))
            return None

    for key, value in data.items():
        if key not in _FIELD_MODELS:
            try:
                _NOTHING.model_validate({key: value})
            except ValidationError as err:
                errors.append(format_validation_error(source, err, {key: value},
                                                      SuspensionFile))
            continue
        if key in ITEM_SECTIONS and isinstance(value, dict):
            items = {name: check(key, {name: item}) for name, item in value.items()}
            valid[key] = {name: v[name] for name, v in items.items() if v is not None}
            continue
        result = check(key, value)
        if result is not None or value is None:
            valid[key] = result
    for key, f in SuspensionFile.model_fields.items():
        if f.is_required() and key not in data:
            errors.append(f"{source}: key '{key}': required key is missing")
        elif key not in valid and not f.is_required() and key not in data:
            valid[key] = f.get_default(call_default_factory=True)
    return valid, errors


class TolerantResolver(Resolver):
    """A resolver that records the error of an item (in ``errors``) and goes on without it:
    the items of a config that resolve on their own (:func:`draft_from_dict`)."""

    def __init__(self, spec: SuspensionFile, source: str, across=None):
        super().__init__(spec, source)
        self.errors: list[str] = []
        self.axle_spec = across  # the config's axle section: its items across are left out

    def keep(self, name: str, parts: tuple[str, str]) -> bool:
        a, s = self.axle_spec, self.spec
        return a is None or not joins_sides(parts, s.side, s.parts, a.shared or ())

    def attempt(self, make):
        try:
            return make()
        except ConfigError as exc:
            self.errors.append(str(exc))
            return None

    def wheel(self) -> Wheel | None:
        return None if self.spec.wheel is None else super().wheel()

