"""Model variants as typed overrides of one template :class:`Suspension`.

Every model elastokin builds is a template (a resolved config) plus overrides: hardpoints,
bushing laws, joint attachments (as-built clearance), which connections are ideal joints
(kinematic), preloads, ball-joint friction. The override functions return a new frozen
:class:`Suspension` (nothing is edited in place and no config mapping is validated again);
:class:`ModelVariant` names a variant with its preloads and friction, ready for
:func:`elastokin.mbs.design.build_model`.

Units: mm, N, N*mm, deg; config frame.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from elastokin.config.suspension import Suspension
from elastokin.errors import ConfigError


@dataclass(frozen=True)
class DesignState:
    """Preloads that make the design hardpoints the static equilibrium under the wheel load.

    spring_force_N: compression force of each spring at its installed length.
    bushing_preload: loads (Fx Fy Fz N, Tx Ty Tz N*mm, bushing frame, +K*u convention) each
    bushing carries at the design position.
    """

    spring_force_N: dict[str, float]
    bushing_preload: dict[str, np.ndarray]


@dataclass(frozen=True)
class BallJointFriction:
    """Dry friction in spherical joints (synthetic real suspension): breakaway torque (N*mm)
    per joint, the stick rotation before a joint slips (deg), and the solver steps per rig
    step that follow the slip."""

    torque_Nmm: Mapping[str, float]
    presliding_deg: float = 0.05
    substeps: int = 1


@dataclass(frozen=True)
class ModelVariant:
    """One model of a study: ``label`` (as in kc.csv and summary.json), the suspension with
    this variant's overrides applied, its preloads (None: solved for the design position,
    :func:`elastokin.mbs.design.design_state`) and friction (None: frictionless)."""

    label: str
    suspension: Suspension
    preloads: DesignState | None = None
    friction: BallJointFriction | None = None

    @property
    def kinematic(self) -> bool:
        """True when every bushing is modelled by its ideal joint."""
        return self.suspension.kinematic


def kinematic(suspension: Suspension) -> Suspension:
    """Every bushing modelled by its ideal joint (``ideal_joint``)."""
    bushings = tuple(dataclasses.replace(b, kinematic=True) for b in suspension.bushings)
    return dataclasses.replace(suspension, bushings=bushings, kinematic=True)


def rigid_beams(suspension: Suspension) -> Suspension:
    """Every flexible beam part built as one rigid part (the same axle with a rigid cross
    beam)."""
    beams = tuple(dataclasses.replace(b, rigid=True) for b in suspension.beams)
    return dataclasses.replace(suspension, beams=beams)


def compliant(suspension: Suspension) -> Suspension:
    """Every bushing modelled by its laws (the design preloads are those of this model)."""
    if not any(b.kinematic for b in suspension.bushings):
        return suspension
    bushings = tuple(dataclasses.replace(b, kinematic=False) for b in suspension.bushings)
    return dataclasses.replace(suspension, bushings=bushings)


def with_bushing_laws(suspension: Suspension, laws: Mapping[str, tuple]) -> Suspension:
    """``suspension`` with the six laws of the named bushings replaced."""
    names = {b.name for b in suspension.bushings}
    unknown = sorted(set(laws) - names)
    if unknown:
        raise ConfigError(f"{suspension.source}: no bushing {', '.join(unknown)} "
                          f"(bushings: {', '.join(sorted(names))})")
    bushings = tuple(dataclasses.replace(b, laws=tuple(laws[b.name])) if b.name in laws else b
                     for b in suspension.bushings)
    return dataclasses.replace(suspension, bushings=bushings)


def with_joint_shifts(suspension: Suspension,
                      shifts: Mapping[str, tuple[np.ndarray, np.ndarray]]) -> Suspension:
    """``suspension`` with the attachments of the named joints moved: per joint, where each
    part's attachment sits relative to the joint position (mm, config frame; an as-built
    joint with assembly clearance, which the static solve closes)."""
    joints = tuple(dataclasses.replace(j, part_shift_mm=tuple(np.asarray(v, float)
                                                              for v in shifts[j.name]))
                   if j.name in shifts else j for j in suspension.joints)
    return dataclasses.replace(suspension, joints=joints)


def with_hardpoints(suspension: Suspension, hardpoints: Mapping[str, np.ndarray]) -> Suspension:
    """``suspension`` with the named hardpoints moved (mm, config frame): every joint, axis
    given by two hardpoints, bushing, spring seat and the wheel that refers to them follows
    (the config is resolved again with the new coordinates). Apply it to the template first:
    other overrides (laws, kinematic, joint shifts) are not carried over."""
    from elastokin.config.axle_resolver import resolve_suspension
    from elastokin.config.resolver import Resolver
    from elastokin.config.schema.suspension import SuspensionFile

    unknown = sorted(set(hardpoints) - set(suspension.hardpoints))
    if unknown:
        raise ConfigError(f"{suspension.source}: no hardpoint {', '.join(unknown)}")
    resolver = Resolver(SuspensionFile.model_validate(suspension.raw), suspension.source)
    resolver.hardpoints.update({k: np.asarray(v, float) for k, v in hardpoints.items()})
    moved = resolve_suspension(resolver, suspension.sha256, suspension.raw,
                               suspension.config_sha256, suspension.rig_sha256)
    return dataclasses.replace(moved, rig=suspension.rig, rig_source=suspension.rig_source)


def relabelled(suspension: Suspension, source: str) -> Suspension:
    """The same suspension under another source name (what error messages call it)."""
    return dataclasses.replace(suspension, source=source)


def corner(suspension: Suspension) -> Suspension:
    """The config side's corner of an axle: its config without the ``axle`` section and the
    items joining the two sides (a heave spring between the rockers), resolved again (what
    CMM identification and the stiffness fit of a decoupled axle work on); overrides applied
    to ``suspension`` through this module are not carried over. A corner is returned as it
    is."""
    if suspension.axle is None:
        return suspension
    from elastokin.config.loading import suspension_from_dict

    across = set(suspension.axle.across)
    raw = {k: ({n: item for n, item in v.items() if n not in across}
               if k in ("connections", "springs", "dampers", "stops") and v else v)
           for k, v in suspension.raw.items() if k != "axle"}
    alone = suspension_from_dict(raw, suspension.source, suspension.sha256,
                                 config_sha256=suspension.config_sha256,
                                 rig_sha256=suspension.rig_sha256)
    return dataclasses.replace(alone, rig=suspension.rig, rig_source=suspension.rig_source)


def side_couplings(suspension: Suspension) -> list[str]:
    """What couples the two sides of an axle (shared parts, items joining the two sides, the
    anti-roll bar, the steering rack); empty for a corner, or an axle whose corners are
    independent (then each side responds to its own wheel's inputs as its corner alone
    would)."""
    a = suspension.axle
    if a is None:
        return []
    out = [f"shared part '{p}'" for p in a.shared]
    out += [f"'{name}', joining the two sides" for name in a.across]
    if a.anti_roll_bar is not None:
        out.append("the anti-roll bar")
    if a.steering is not None and a.steering.part not in a.shared:
        out.append("the steering rack")
    return out


def mirrored_design(corner_state: DesignState, suffix: str) -> DesignState:
    """The design state of a mirrored axle from its corner's: each spring's force and each
    bushing's preload (its frame mirrored: components y, rx, rz negated) again for the other
    side's copy, named with ``suffix``."""
    from elastokin.config.axle import MIRROR_SIGNS

    springs = dict(corner_state.spring_force_N)
    springs.update({n + suffix: f for n, f in corner_state.spring_force_N.items()})
    bushings = dict(corner_state.bushing_preload)
    bushings.update({n + suffix: MIRROR_SIGNS * np.asarray(p, float)
                     for n, p in corner_state.bushing_preload.items()})
    return DesignState(springs, bushings)
