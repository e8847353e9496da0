"""Bushings of a :class:`~elastokin.mbs.model.SuspensionModel` in Exudyn.

A bushing is an ``ObjectConnectorRigidBodySpringDamper`` between its two parts, in its own
frame (z axial, x main radial). Its six loads are:

- linear laws: Exudyn's own ``K * (u - offset)`` (no user function);
- any other law: a symbolic user function (C++ speed) evaluating each direction's law at the
  deflection plus the initial deflection;
- a **parametric** bushing (``ModelOptions.parametric_bushings``): the family
  ``F(u) = scale * base(u) * (1 + cubic * u^2)`` of :class:`~elastokin.physics.laws.ProgressiveLaw`
  per direction, with ``scale``, ``cubic`` and the initial deflection as named symbolic
  variables: :meth:`ParametricLaws.apply` changes them in place, without rebuilding the model
  (the stiffness fit and its sensitivities);
- modelled by its ideal joint (``Bushing.kinematic``): that joint, plus regularising
  rotational springs on its free rotations.

Units inside Exudyn: mm, N, N*mm, rad; the laws take mm and deg.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from exudyn.itemInterface import ObjectConnectorRigidBodySpringDamper, ObjectJointGeneric

from elastokin.config.suspension import Bushing
from elastokin.errors import ModelError
from elastokin.mbs.exudyn_api import exu
from elastokin.mbs.geometry import of
from elastokin.mbs.user_functions import attach_user_function, make_bushing_function
from elastokin.physics.joints import CONSTRAINED
from elastokin.physics.laws import ProgressiveLaw

DEG = np.pi / 180.0
#: stiffness of the regularising springs on an ideal joint's free rotations, relative to the
#: bushing's rotational rates (bushings modelled by their ideal joints)
REGULARISATION = 1e-3
#: stiffness holding a bushing's ideal-joint rotations while balancing the design preloads
BALANCING_ROTATION = 1e9  # N*mm/rad


def law_parameters(law) -> tuple[object, float, float]:
    """(base law, scale, cubic) of a direction law: a :class:`ProgressiveLaw` or a plain law
    (scale 1, cubic 0)."""
    if isinstance(law, ProgressiveLaw):
        return law.base, float(law.scale), float(law.cubic)
    return law, 1.0, 0.0


class ParametricLaws:
    """The six laws of a parametric bushing as named symbolic variables: per direction the
    scale, the cubic (1/mm^2 or 1/deg^2) and the initial deflection (mm or deg) that makes the
    bushing carry its preload. The base laws are fixed when the model is built."""

    def __init__(self, name: str, laws: Sequence, preload: np.ndarray, serial: int):
        esym = exu.symbolic
        self.name = name
        self.base = tuple(law_parameters(law)[0] for law in laws)
        self.preload = np.asarray(preload, float)
        tag = f"{name}_{serial}"
        self.scale = [esym.Real(f"scale_{tag}_{i}", 1.0) for i in range(6)]
        self.cubic = [esym.Real(f"cubic_{tag}_{i}", 0.0) for i in range(6)]
        self.u0 = [esym.Real(f"u0_{tag}_{i}", 0.0) for i in range(6)]
        self.cache: dict[tuple, np.ndarray] = {}
        self.current = self.values(laws)
        self.apply(self.current)

    def values(self, laws: Sequence) -> np.ndarray:
        """(3, 6) array: scale, cubic and initial deflection per direction for ``laws``
        (each a law on this bushing's base law), the preload kept."""
        params = [law_parameters(law) for law in laws]
        for i, (base, _, _) in enumerate(params):
            if base != self.base[i]:
                raise ModelError(f"bushing '{self.name}': a parametric bushing's laws must "
                                 f"scale its base laws (direction {i} has another base law)")
        key = tuple((s, c) for _, s, c in params)
        if key not in self.cache:
            u0 = [ProgressiveLaw(base, s, c).deflection_at(f) if (s, c) != (1.0, 0.0)
                  else base.deflection_at(f) for (base, s, c), f in zip(params, self.preload)]
            self.cache[key] = np.array([[s for _, s, _ in params], [c for _, _, c in params],
                                        np.asarray(u0, float)])
        return self.cache[key]

    def apply(self, values: np.ndarray) -> None:
        """Set the symbolic variables to ``values`` (from :meth:`values`)."""
        for i in range(6):
            self.scale[i].SetValue(float(values[0, i]))
            self.cubic[i].SetValue(float(values[1, i]))
            self.u0[i].SetValue(float(values[2, i]))
        self.current = values

    def laws(self) -> list:
        """Objects with an ``expression(u, maxf)`` method for the user function: each base law
        scaled and stiffened by the symbolic variables."""
        return [_SymbolicLaw(b, s, c) for b, s, c in zip(self.base, self.scale, self.cubic)]


class _SymbolicLaw:
    def __init__(self, base, scale, cubic):
        self.base, self.scale, self.cubic = base, scale, cubic

    def expression(self, u, maxf=None):
        return self.scale * self.base.expression(u, maxf) * (1.0 + self.cubic * u * u)


def add_bushing(model, b: Bushing) -> dict:
    """The Exudyn objects of bushing ``b`` on ``model`` (see the module docstring)."""
    mbs = model.mbs
    this = of("bushings", b.name, lambda x: x)
    m0, m1 = (model.rigid_marker(part, lambda s: this(s).position_mm, lambda s: this(s).frame)
              for part in b.parts)
    scale = model.options.stiffness_scale

    def rates_of(s, _=None) -> np.ndarray:
        """The rates at zero (N/mm, N*mm/rad) of the bushing in suspension ``s``."""
        rates = np.array([law.rate_at_zero for law in this(s).laws]) * scale
        rates[3:] /= DEG  # N*mm/deg -> N*mm/rad
        return rates

    rates_rad = rates_of(model.suspension)
    entry = {"markers": (m0, m1), "ideal": None}
    if b.kinematic or model.balancing:
        return add_ideal_bushing(model, b, entry, rates_of)
    laws = [law.scaled(scale) for law in b.laws]
    u0 = model.initial_deflection[b.name]
    symbolic = model.options.user_functions == "symbolic"
    parametric = b.name in model.options.parametric_bushings
    if all(law.is_linear for law in laws) and symbolic and not parametric:
        # linear laws: Exudyn's own K * (u - offset), no user function at all
        def offset(s, preloads) -> list:
            u = preloads.initial_deflection[b.name]
            return (-np.r_[u[:3], u[3:] * DEG]).tolist()

        obj = mbs.AddObject(ObjectConnectorRigidBodySpringDamper(
            markerNumbers=[m0, m1], stiffness=np.diag(rates_rad), damping=np.zeros((6, 6)),
            offset=offset(model.suspension, model.preloads), name=f"bushing:{b.name}"))
        model.track("object", obj, "stiffness", lambda s, _: np.diag(rates_of(s)))
        model.track("object", obj, "offset", offset)
        model.geometry.fixed.append(lambda s, _: all(law.is_linear for law in this(s).laws))
        entry.update(object=obj, linear=True, laws=laws, u0=u0)
        return entry
    # the laws and their initial deflections are compiled into the user function
    model.geometry.fixed.append(lambda s, preloads: (this(s).laws,
                                                     preloads.initial_deflection[b.name]))
    obj = mbs.AddObject(ObjectConnectorRigidBodySpringDamper(
        markerNumbers=[m0, m1], stiffness=np.diag(rates_rad), damping=np.zeros((6, 6)),
        name=f"bushing:{b.name}"))
    if parametric:
        if not symbolic:
            raise ModelError(f"bushing '{b.name}': parametric bushings need symbolic user "
                             "functions")
        params = ParametricLaws(b.name, laws, model.bushing_preload[b.name], id(model))
        uf = make_bushing_function(params.laws(), params.u0, symbolic=True)
        entry["parametric"] = params
    else:
        uf = make_bushing_function(laws, u0, symbolic=symbolic)
    attach_user_function(model, obj, "springForceTorqueUserFunction", uf, symbolic)
    entry.update(object=obj, linear=False, laws=laws, u0=u0)
    return entry


def add_ideal_bushing(model, b: Bushing, entry: dict, rates_of) -> dict:
    """Bushing ``b`` modelled by its ideal joint (or, balancing, held by it); ``rates_of``:
    its rates (N/mm, N*mm/rad) in a suspension."""
    m0, m1 = entry["markers"]
    constrained = np.array(CONSTRAINED[b.ideal_joint])
    held = constrained[3:].astype(bool)

    def stiffness(s, _=None) -> np.ndarray:
        kr = np.where(held, 0.0, REGULARISATION * rates_of(s)[3:])
        if model.balancing:
            # translations held exactly (constraint reactions are the bushing forces);
            # rotations held by stiff springs, whose torques Exudyn reports in the bushing
            # frame
            kr = np.where(held, BALANCING_ROTATION, kr)
        return np.diag(np.r_[0.0, 0.0, 0.0, kr])

    def offset(s, preloads) -> np.ndarray:
        return np.r_[0.0, 0.0, 0.0, preloads.balancing_offsets.get(b.name, np.zeros(3))]

    if model.balancing:
        constrained[3:] = 0
    entry["ideal"] = model.mbs.AddObject(ObjectJointGeneric(
        markerNumbers=[m0, m1], constrainedAxes=constrained.tolist(),
        name=f"ideal:{b.name}"))
    entry["object"] = model.mbs.AddObject(ObjectConnectorRigidBodySpringDamper(
        markerNumbers=[m0, m1], stiffness=stiffness(model.suspension),
        damping=np.zeros((6, 6)), offset=offset(model.suspension, model.preloads),
        name=f"bushing:{b.name}"))
    model.track("object", entry["object"], "stiffness", stiffness)
    model.track("object", entry["object"], "offset", offset)
    entry["linear"] = True
    return entry
