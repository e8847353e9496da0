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
    m0 = model.rigid_marker(b.parts[0], b.position_mm, b.frame)
    m1 = model.rigid_marker(b.parts[1], b.position_mm, b.frame)
    rates = np.array([law.rate_at_zero for law in b.laws]) * model.options.stiffness_scale
    rates_rad = rates.copy()
    rates_rad[3:] /= DEG  # N*mm/deg -> N*mm/rad
    entry = {"markers": (m0, m1), "ideal": None}
    if b.kinematic or model.balancing:
        return add_ideal_bushing(model, b, entry, rates_rad)
    laws = [law.scaled(model.options.stiffness_scale) for law in b.laws]
    u0 = model.initial_deflection[b.name]
    symbolic = model.options.user_functions == "symbolic"
    parametric = b.name in model.options.parametric_bushings
    if all(law.is_linear for law in laws) and symbolic and not parametric:
        # linear laws: Exudyn's own K * (u - offset), no user function at all
        offset = -np.r_[u0[:3], u0[3:] * DEG]
        obj = mbs.AddObject(ObjectConnectorRigidBodySpringDamper(
            markerNumbers=[m0, m1], stiffness=np.diag(rates_rad), damping=np.zeros((6, 6)),
            offset=offset.tolist(), name=f"bushing:{b.name}"))
        entry.update(object=obj, linear=True, laws=laws, u0=u0)
        return entry
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


def add_ideal_bushing(model, b: Bushing, entry: dict, rates_rad: np.ndarray) -> dict:
    """Bushing ``b`` modelled by its ideal joint (or, balancing, held by it)."""
    m0, m1 = entry["markers"]
    constrained = np.array(CONSTRAINED[b.ideal_joint])
    kr = np.where(constrained[3:], 0.0, REGULARISATION * rates_rad[3:])
    if model.balancing:
        # translations held exactly (constraint reactions are the bushing forces);
        # rotations held by stiff springs, whose torques Exudyn reports in the bushing
        # frame
        kr = np.where(constrained[3:], BALANCING_ROTATION, kr)
        constrained[3:] = 0
    entry["ideal"] = model.mbs.AddObject(ObjectJointGeneric(
        markerNumbers=[m0, m1], constrainedAxes=constrained.tolist(),
        name=f"ideal:{b.name}"))
    offset = np.r_[0.0, 0.0, 0.0, model.balancing_offsets.get(b.name, np.zeros(3))]
    entry["object"] = model.mbs.AddObject(ObjectConnectorRigidBodySpringDamper(
        markerNumbers=[m0, m1], stiffness=np.diag(np.r_[0.0, 0.0, 0.0, kr]),
        damping=np.zeros((6, 6)), offset=offset, name=f"bushing:{b.name}"))
    entry["linear"] = True
    return entry
