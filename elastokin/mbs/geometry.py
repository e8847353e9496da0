"""A built model's geometry as functions of its suspension and design preloads, so that the
model can take another design's values **in place** (a design sensitivity's twin,
:mod:`elastokin.mbs.twins`): no second model is built for a moved hardpoint.

Every item parameter that a design change moves is registered when the item is created,
with the function that computes it from a suspension and its :class:`ItemPreloads`: the
markers' local positions and frames (mm, part frame relative to the part's reference
position; the reference positions are shared by twins), links' lengths, springs' and stops'
reference lengths, rates and the bushings' offsets (rad), the point sensors' local positions.
Exudyn uses a changed marker or object parameter from the next evaluation on (checked against
a model built for the changed design: bit for bit the same residual). Changes a model cannot
take in place (a nonlinear bushing's law or initial deflection, compiled into its symbolic
user function; idle-spin springs, whose axes come from the model's Jacobian) are registered as
``fixed``: a twin that differs there is built as a model of its own.

Units: mm, N, N*mm, rad (inside Exudyn), deg (bushing laws and initial deflections).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field

import numpy as np

#: a parameter's value from a suspension and its item preloads
Getter = Callable[[object, "ItemPreloads"], object]


@dataclass
class ItemPreloads:
    """What the design preloads make of a model's items: each spring's force at the design
    position (N), each bushing's load there (N, N*mm, bushing frame), the initial deflection
    that carries it under the (scaled) law (mm, deg), a balancing model's stiff springs'
    offsets (rad)."""

    spring_force: dict[str, float]
    bushing_preload: dict[str, np.ndarray]
    initial_deflection: dict[str, np.ndarray]
    balancing_offsets: dict[str, np.ndarray] = field(default_factory=dict)


def item_preloads(suspension, stiffness_scale: float, preloads=None,
                  balancing_offsets: Mapping[str, np.ndarray] | None = None) -> ItemPreloads:
    """The :class:`ItemPreloads` of ``suspension`` with ``preloads`` (a
    :class:`~elastokin.config.variants.DesignState`; default: the springs' own preloads and
    the bushings' initial deflections), its laws scaled by ``stiffness_scale``."""
    given = preloads.bushing_preload if preloads is not None else {}
    bushing = {b.name: (np.asarray(given[b.name], float) if b.name in given else
                        np.array([law(u) for law, u in zip(b.laws, b.initial_deflection)]))
               for b in suspension.bushings}
    initial = {b.name: np.array([law.scaled(stiffness_scale).deflection_at(f)
                                 for law, f in zip(b.laws, bushing[b.name])])
               for b in suspension.bushings}
    forces = preloads.spring_force_N if preloads is not None else {}
    springs = {sp.name: forces.get(sp.name, sp.design_force_N()) for sp in suspension.springs}
    return ItemPreloads(springs, bushing, initial,
                        {k: np.asarray(v, float) for k, v in (balancing_offsets or {}).items()})


def named(suspension, collection: str, name: str):
    """The item ``name`` of a suspension's ``collection``: ``joints``, ``links``,
    ``bushings``, ``springs``, ``dampers``, ``stops`` (by name), ``wheels`` (by side),
    ``steering`` and ``anti_roll_bar`` (the axle's; no name)."""
    if collection == "wheels":
        return suspension.wheels[name]
    if collection in ("steering", "anti_roll_bar"):
        return getattr(suspension.axle, collection)
    return next(x for x in getattr(suspension, collection) if x.name == name)


def of(collection: str, name: str, pick: Callable) -> Callable:
    """A getter of a suspension alone: ``pick`` of its item ``name`` (:func:`named`)."""
    return lambda s: pick(named(s, collection, name))


@dataclass
class Geometry:
    """The design-dependent parameters of a built model (module docstring): ``entries``
    (kind ``marker``, ``object``, ``sensor`` or ``point``, item number or point-sensor
    name, parameter, getter) and ``fixed`` getters, whose values a twin must share with the
    model to be evaluated in place. ``in_place``: False when the model holds something a
    twin cannot take in place at all (idle-spin springs)."""

    entries: list[tuple[str, object, str, Getter]] = field(default_factory=list)
    fixed: list[Getter] = field(default_factory=list)
    in_place: bool = True
    #: the model's own values (made as twins ask for them; cleared when the model changes)
    own: list = field(default_factory=list)

    def track(self, kind: str, number, param: str, getter: Getter) -> None:
        self.entries.append((kind, number, param, getter))

    def values(self, suspension, preloads: ItemPreloads, start: int = 0) -> list:
        """The parameters' values (from entry ``start`` on) for a suspension and preloads."""
        return [getter(suspension, preloads) for _, _, _, getter in self.entries[start:]]

    def shares_fixed(self, model_suspension, model_preloads: ItemPreloads, suspension,
                     preloads: ItemPreloads, start: int = 0) -> bool:
        """Whether a twin (``suspension``, ``preloads``) has the model's fixed values (from
        getter ``start`` on)."""
        return self.in_place and all(
            same(g(model_suspension, model_preloads), g(suspension, preloads))
            for g in self.fixed[start:])


def same(a, b) -> bool:
    """Whether two parameter values are bit for bit the same (numbers, arrays, tuples)."""
    if isinstance(a, (tuple, list)) and isinstance(b, (tuple, list)):
        return len(a) == len(b) and all(same(x, y) for x, y in zip(a, b))
    return np.array_equal(np.asarray(a), np.asarray(b))


def set_parameter(model, kind: str, number, param: str, value) -> None:
    """Set one registered parameter of ``model`` (see :class:`Geometry`)."""
    mbs = model.mbs
    if kind == "marker":
        mbs.SetMarkerParameter(number, param, value)
    elif kind == "object":
        mbs.SetObjectParameter(number, param, value)
    elif kind == "sensor":
        mbs.SetSensorParameter(number, param, value)
    else:  # a point sensor's local position as the model's own arrays read it
        part, _ = model.point_sensors[number]
        model.point_sensors[number] = (part, np.asarray(value, float))
