"""Force elements, stops and axle elements in Exudyn: coil springs and dampers (along the
line between two points; a damper carries no force in the quasi-static rig, its length is
recorded), bump and rebound stops (unilateral springs along that line), the anti-roll bar's
torsion spring between its two halves, and the steering lock (the rack held at its travel
along its axis unless the rig drives it).

Units mm, N, N*mm; rotations rad inside Exudyn, the laws take mm and deg; the config frame.
"""

from __future__ import annotations

import numpy as np
from exudyn.itemInterface import ObjectConnectorRigidBodySpringDamper, ObjectConnectorSpringDamper

from elastokin.mbs.geometry import of
from elastokin.mbs.user_functions import (
    DEG_PER_RAD,
    attach_user_function,
    max_function,
)
from elastokin.physics.pose import frame_from_z

#: the support that holds or drives the steering rack (an axle with steering)
STEERING_LOCK = "steering:rack"
RAD = np.pi / 180.0
#: the anti-roll bar's halves held together at its centre (N/mm and N*mm/rad): about 1000
#: times a rubber bushing's rates, a rigid one-piece bar to the solver and its sensitivities
BAR_TRANSLATION_RATE = 1.0e6
BAR_BENDING_RATE = 1.0e10


def add_line_elements(model) -> tuple[dict[str, int], dict[str, int], dict[str, int]]:
    """The springs (each with its design force, ``model.spring_force``), dampers and stops
    of the model's suspension, by name: the elements acting along the line between two
    points."""
    s = model.suspension
    return ({sp.name: add_spring(model, sp) for sp in s.springs},
            {dm.name: add_damper(model, dm) for dm in s.dampers},
            {st.name: add_stop(model, st) for st in s.stops})


def add_spring(model, spring) -> int:
    """The coil spring ``spring`` (:class:`~elastokin.config.suspension.Spring`) between its
    seats, carrying its design force (``model.spring_force``) at its installed length."""
    this = of("springs", spring.name, lambda x: x)
    m0 = model.position_marker(spring.parts[0], lambda s: this(s).seats_mm[0])
    m1 = model.position_marker(spring.parts[1], lambda s: this(s).seats_mm[1])

    def ref_len(s, preloads) -> float:
        # compression force P at the installed length L: reference length L + P / k
        x = this(s)
        return x.installed_length_mm + preloads.spring_force[x.name] / x.rate_N_per_mm

    obj = model.mbs.AddObject(ObjectConnectorSpringDamper(
        markerNumbers=[m0, m1], referenceLength=ref_len(model.suspension, model.preloads),
        stiffness=spring.rate_N_per_mm, damping=0.0, name=f"spring:{spring.name}"))
    model.track("object", obj, "referenceLength", ref_len)
    return model.track("object", obj, "stiffness", lambda s, _: this(s).rate_N_per_mm)


def add_damper(model, damper) -> int:
    """The damper ``damper`` (:class:`~elastokin.config.suspension.Damper`) between its
    points: a connector without stiffness or damping (the rig is quasi-static: a damper
    carries no force at rest), whose length is recorded."""
    this = of("dampers", damper.name, lambda x: x)
    m0 = model.position_marker(damper.parts[0], lambda s: this(s).points_mm[0])
    m1 = model.position_marker(damper.parts[1], lambda s: this(s).points_mm[1])
    return model.track("object", model.mbs.AddObject(ObjectConnectorSpringDamper(
        markerNumbers=[m0, m1], referenceLength=damper.installed_length_mm, stiffness=0.0,
        damping=0.0, name=f"damper:{damper.name}")), "referenceLength",
        lambda s, _: this(s).installed_length_mm)


def stop_function(law, kind: str, symbolic: bool):
    """A ``springForceUserFunction`` of a stop: Exudyn's spring force (+ pulls the points
    together) of the penetration beyond contact, ``deltaL`` being the length less the
    contact length: a bump stop pushes apart when shorter, a rebound stop pulls together
    when longer."""
    maxf = max_function(symbolic)

    def bump(mbs, t, itemNumber, deltaL, deltaL_t, stiffness, damping, force):
        return -law.expression(maxf(-deltaL, 0.0), maxf)

    def rebound(mbs, t, itemNumber, deltaL, deltaL_t, stiffness, damping, force):
        return law.expression(maxf(deltaL, 0.0), maxf)

    return bump if kind == "bump" else rebound


def add_stop(model, stop) -> int:
    """The stop ``stop`` (:class:`~elastokin.config.suspension.Stop`) between its parts."""
    mbs = model.mbs
    this = of("stops", stop.name, lambda x: x)
    m0 = model.position_marker(stop.parts[0], lambda s: this(s).points_mm[0])
    m1 = model.position_marker(stop.parts[1], lambda s: this(s).points_mm[1])
    obj = model.track("object", mbs.AddObject(ObjectConnectorSpringDamper(
        markerNumbers=[m0, m1], referenceLength=stop.contact_length_mm, stiffness=0.0,
        damping=0.0, name=f"stop:{stop.name}")), "referenceLength",
        lambda s, _: this(s).contact_length_mm)
    model.geometry.fixed.append(lambda s, _: (this(s).kind, this(s).law))
    symbolic = model.options.user_functions == "symbolic"
    attach_user_function(model, obj, "springForceUserFunction",
                         stop_function(stop.law, stop.kind, symbolic), symbolic)
    return obj


def add_anti_roll_bar(model, bar) -> int:
    """The anti-roll bar's centre (:class:`~elastokin.config.suspension.AntiRollBar`): a
    rigid-body spring between the two halves, the torsion spring about the bar's axis and,
    in the other five directions, the one-piece bar (:data:`BAR_TRANSLATION_RATE`,
    :data:`BAR_BENDING_RATE`: its halves keep their relative position and bending angle, as
    ADAMS/Car's revolute joint between them, without a redundant constraint when the mounts
    are ideal revolutes)."""
    mbs = model.mbs
    this = of("anti_roll_bar", None, lambda x: x)
    m0, m1 = (model.rigid_marker(part, lambda s: this(s).position_mm, lambda s: this(s).frame)
              for part in bar.parts)
    model.geometry.fixed.append(lambda s, _: this(s).law)
    k = bar.law.rate_at_zero / RAD  # N*mm/rad
    rates = [BAR_TRANSLATION_RATE] * 3 + [BAR_BENDING_RATE] * 2
    obj = mbs.AddObject(ObjectConnectorRigidBodySpringDamper(
        markerNumbers=[m0, m1], stiffness=np.diag(rates + [k]), damping=np.zeros((6, 6)),
        useIntrinsicFormulation=True, name="anti_roll_bar"))
    if not bar.law.is_linear:
        symbolic = model.options.user_functions == "symbolic"
        maxf = max_function(symbolic)
        law = bar.law

        def torsion(mbs, t, itemNumber, displacement, rotation, velocity, angularVelocity,
                    stiffness, damping, rotJ0, rotJ1, offset):
            return [BAR_TRANSLATION_RATE * displacement[0],
                    BAR_TRANSLATION_RATE * displacement[1],
                    BAR_TRANSLATION_RATE * displacement[2],
                    BAR_BENDING_RATE * rotation[0], BAR_BENDING_RATE * rotation[1],
                    law.expression(rotation[2] * DEG_PER_RAD, maxf)]

        attach_user_function(model, obj, "springForceTorqueUserFunction", torsion, symbolic)
    return obj


def add_steering_lock(model, steering) -> str:
    """The support holding the rack (:class:`~elastokin.config.suspension.Steering`) along
    its axis at its travel; active in every solve, at the travel unless a path is given."""
    # a lock: active from the start, so that every constraint count sees the rack held
    this = of("steering", None, lambda x: x)
    model.geometry.fixed.append(lambda s, _: this(s).travel_mm)  # the lock's offset
    model.add_support(STEERING_LOCK, steering.part, lambda s: this(s).position_mm,
                      (0, 0, 1, 0, 0, 0), frame=lambda s: frame_from_z(this(s).axis),
                      lock=np.array([0.0, 0.0, steering.travel_mm, 0.0, 0.0, 0.0]),
                      item=("steering_gear", "steering_gear"))
    return STEERING_LOCK
