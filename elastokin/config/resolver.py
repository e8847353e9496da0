"""Resolving a validated config file into a :class:`~elastokin.config.suspension.Suspension`:
hardpoint names replaced by coordinates (mm, config frame), axes normalised, bushing frames as
rotation matrices, laws as callables; every error names the key. A config with an ``axle:``
section resolves both corners (:mod:`elastokin.config.axle_resolver`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from elastokin.config.axle import joins_sides, other_copy
from elastokin.config.beams import resolve_beams
from elastokin.config.bounds import MIN_AXIS_ANGLE_DEG
from elastokin.config.schema.base import AxisBetween, AxisSpec, PointSpec
from elastokin.config.schema.suspension import BushingSpec, LinkSpec, RackSpec, SuspensionFile
from elastokin.config.suspension import (
    Bushing,
    Damper,
    Joint,
    Link,
    Spring,
    Stop,
    Suspension,
    Wheel,
    outboard_direction,
)
from elastokin.errors import ConfigError
from elastokin.physics.joints import BUSHING_DIRECTIONS, CONSTRAINED
from elastokin.physics.laws import law_from_spec
from elastokin.physics.pose import frame_from_z


@dataclass(frozen=True)
class CornerItems:
    """What a corner is made of (resolved, config frame)."""

    joints: tuple[Joint, ...]
    links: tuple[Link, ...]
    bushings: tuple[Bushing, ...]
    springs: tuple[Spring, ...]
    stops: tuple[Stop, ...]
    wheel: Wheel
    dampers: tuple[Damper, ...] = ()


class Resolver:
    """Resolves a validated config file into a :class:`Suspension` (errors name the key)."""

    def __init__(self, spec: SuspensionFile, source: str):
        self.spec = spec
        self.source = source
        self.hardpoints = {k: np.asarray(v, float) for k, v in spec.hardpoints.items()}

    def fail(self, key: str, msg: str) -> ConfigError:
        return ConfigError(f"{self.source}: key '{key}': {msg}")

    def point(self, p: PointSpec, key: str) -> np.ndarray:
        if isinstance(p, str):
            if p not in self.hardpoints:
                raise self.fail(key, f"hardpoint '{p}' is not defined under 'hardpoints'")
            return self.hardpoints[p].copy()
        return np.asarray(p, float)

    def point_pair(self, pair, key: str, coincide: str) -> tuple[np.ndarray, np.ndarray]:
        """Two distinct points (mm); ``coincide``: the error when they are the same."""
        pts = (self.point(pair[0], key), self.point(pair[1], key))
        if np.linalg.norm(pts[1] - pts[0]) < 1e-6:
            raise self.fail(key, coincide)
        return pts

    def axis(self, a: AxisSpec, key: str) -> np.ndarray:
        if isinstance(a, AxisBetween):
            v = self.point(a.to, key + ".to") - self.point(a.from_, key + ".from")
            n = np.linalg.norm(v)
            if n < 1e-9:
                raise self.fail(key, "'from' and 'to' are the same point: the axis is undefined")
            return v / n
        v = np.asarray(a, float)
        n = np.linalg.norm(v)
        if n < 1e-9:
            raise self.fail(key, "axis vector is zero; give a unit vector")
        if abs(n - 1.0) > 1e-3:
            raise self.fail(key, f"axis vector {list(v)} has length {n:.4g}; give a unit vector")
        return v / n

    def part(self, name: str, key: str) -> str:
        if name != self.spec.ground and name not in self.spec.parts:
            shared = self.spec.axle.shared if self.spec.axle is not None else ()
            base = other_copy(name, self.spec.side, self.spec.parts, shared)
            if base is not None:
                raise self.fail(key, f"part '{name}' is the other side's copy of '{base}': "
                                + ("an item joining the two sides needs an 'axle:' section"
                                   if self.spec.axle is None else "only a connection, spring, "
                                   "damper or stop joining the two sides may name it"))
            raise self.fail(
                key, f"part '{name}' is not defined (parts: {', '.join(self.spec.parts)}; "
                f"ground: {self.spec.ground})"
            )
        return name

    def parts(self, names: tuple[str, str], key: str) -> tuple[str, str]:
        a, b = (self.part(n, f"{key}.parts") for n in names)
        if a == b:
            raise self.fail(f"{key}.parts", f"connects part '{a}' to itself")
        return a, b

    def bushing_frame(self, c: BushingSpec, key: str) -> np.ndarray:
        if c.euler_zxz_deg is not None:
            from scipy.spatial.transform import Rotation

            return Rotation.from_euler("ZXZ", c.euler_zxz_deg, degrees=True).as_matrix()
        z = self.axis(c.axis, key + ".axis")
        x = self.axis(c.radial, key + ".radial")
        angle = np.degrees(np.arccos(min(1.0, abs(float(x @ z)))))
        if angle < MIN_AXIS_ANGLE_DEG:
            raise self.fail(key + ".radial", f"radial direction is parallel to the axis "
                            f"({angle:.2g} deg apart; at least {MIN_AXIS_ANGLE_DEG:g} deg)")
        x = x - (x @ z) * z
        x /= np.linalg.norm(x)
        return np.column_stack([x, np.cross(z, x), z])

    def check_names(self) -> None:
        """The names of the ground, parts, connections, springs and dampers are distinct."""
        s = self.spec
        seen = {s.ground: "ground"}
        for section in ("parts", "connections", "springs", "dampers"):
            for name in getattr(s, section):
                key = f"{section}.{name}"
                if seen.get(name) == "ground" and section == "parts":
                    raise self.fail(key, "the ground part must not be listed under parts "
                                    "(key 'ground')")
                if name in seen:
                    raise self.fail(key, f"the name '{name}' is taken by key '{seen[name]}'; "
                                    "parts, the ground, connections, springs and dampers need "
                                    "distinct names")
                seen[name] = key

    def spin_axis(self) -> np.ndarray:
        """The wheel's unit spin axis, refused within MIN_AXIS_ANGLE_DEG of vertical."""
        spin = self.axis(self.spec.wheel.spin_axis, "wheel.spin_axis")
        tilt = np.degrees(np.arcsin(min(1.0, float(np.hypot(spin[0], spin[1])))))
        if tilt < MIN_AXIS_ANGLE_DEG:
            raise self.fail("wheel.spin_axis", f"{tilt:.2g} deg from vertical: a wheel spin "
                            f"axis must be at least {MIN_AXIS_ANGLE_DEG:g} deg from vertical "
                            "(toe and camber are undefined)")
        return spin

    # hooks of the other side of an axle (elastokin.config.axle.MirroredResolver)
    @property
    def side(self) -> str:
        return self.spec.side

    def name(self, name: str) -> str:
        """The resolved name of a corner item (connection, spring, stop)."""
        return name

    def keep(self, name: str, parts: tuple[str, str]) -> bool:
        """Whether the connection, spring, damper or stop ``name`` between ``parts`` belongs
        to this corner: not an item joining the two sides of an axle
        (:func:`elastokin.config.axle.joins_sides`, resolved with both corners)."""
        return not self.across(parts)

    def across(self, parts: tuple[str, str]) -> bool:
        """True for an item joining the two sides of an axle (it names the other side's copy
        of a corner part: :func:`elastokin.config.axle.joins_sides`)."""
        a = self.spec.axle
        return a is not None and joins_sides(parts, self.spec.side, self.spec.parts, a.shared)

    def attempt(self, make):
        """``make()``: an item resolved, its error raised (a tolerant resolver,
        :class:`elastokin.config.draft.TolerantResolver`, records it and returns None)."""
        return make()

    def corner(self) -> CornerItems:
        """The corner's joints, links, bushings, springs, stops, dampers and wheel."""
        joints, links, bushings = self.connections()
        return CornerItems(joints, links, bushings, tuple(self.springs()), tuple(self.stops()),
                           self.attempt(self.wheel), tuple(self.dampers()))

    def connections(self) -> tuple[tuple[Joint, ...], tuple[Link, ...], tuple[Bushing, ...]]:
        """The joints, links and bushings of :meth:`keep`'s connections."""
        items = [self.attempt(lambda n=name, c=c: self.connection(n, c))
                 for name, c in self.spec.connections.items() if self.keep(name, c.parts)]
        return (tuple(i for i in items if isinstance(i, Joint)),
                tuple(i for i in items if isinstance(i, Link)),
                tuple(i for i in items if isinstance(i, Bushing)))

    def connection(self, name: str, c) -> Joint | Link | Bushing:
        """One connection of the config (``connections.<name>``) resolved."""
        key = f"connections.{name}"
        parts = self.parts(c.parts, key)
        if isinstance(c, LinkSpec):
            pts = self.point_pair(c.at, key + ".at", "a link needs two distinct points")
            return Link(self.name(name), parts, pts)
        pos = self.point(c.at, key + ".at")
        if isinstance(c, BushingSpec):
            return self.bushing(self.name(name), c, parts, pos, key)
        return self.joint(name, c, parts, pos, key)

    def joint(self, name: str, c, parts, pos, key: str) -> Joint:
        kind = c.type
        if kind in ("spherical", "fixed"):
            frame = np.eye(3)
        elif kind == "universal":
            frame = frame_from_z(self.axis(c.torsion_axis, key + ".torsion_axis"))
        else:
            frame = frame_from_z(self.axis(c.axis, key + ".axis"))
        offset = c.travel_mm if isinstance(c, RackSpec) else 0.0
        d = self.spec.design
        if offset and (d.balance_spring or d.balance_bushing_preloads):
            raise self.fail(key + ".travel_mm", "must be 0 when 'design' balances the "
                            "hardpoints (they are the equilibrium with the rack centred)")
        return Joint(self.name(name), kind, parts, pos, frame, CONSTRAINED[kind], offset)

    def wheel(self) -> Wheel:
        s = self.spec
        w = s.wheel
        wheel_part = self.part(w.part, "wheel.part")
        if wheel_part == s.ground:
            raise self.fail("wheel.part", "the wheel cannot be carried by the ground part")
        centre = self.point(w.centre, "wheel.centre")
        spin = self.spin_axis()
        # orient the spin axis outboard, whatever sign the file used
        if spin @ outboard_direction(s.frame, self.side) < 0:
            spin = -spin
        return Wheel(wheel_part, centre, spin, w.loaded_radius_mm, w.tyre_rate_N_per_mm)

    def resolve(self, sha256: str, raw: dict, config_sha256: str = "",
                rig_sha256: str | None = None) -> Suspension:
        """The resolved suspension; ``sha256`` identifies all its inputs, ``config_sha256``
        the config alone ("": the same), ``rig_sha256`` a rig file (see :class:`Suspension`).
        The config's corner only: :func:`~elastokin.config.axle_resolver.resolve_suspension`
        adds the other side of an axle."""
        s = self.spec
        self.check_names()
        self.check_label()
        for name, p in s.parts.items():
            if p.centre_of_mass is not None:
                self.point(p.centre_of_mass, f"parts.{name}.centre_of_mass")
        c = self.corner()
        self.check_design(list(c.bushings))
        beams = resolve_beams(self)
        res = Suspension(
            name=s.name, source=self.source, sha256=sha256, frame=s.frame, side=s.side,
            ground=s.ground, parts=dict(s.parts), hardpoints=self.hardpoints,
            wheel=c.wheel, joints=c.joints, links=c.links, bushings=c.bushings,
            springs=c.springs, design=s.design, kinematic=s.kinematic, solver=s.solver,
            rig=s.rig, reference=s.reference, raw=raw, measurements=s.measurements,
            motion=s.motion, kc_test=s.kc_test, label=s.label, config_sha256=config_sha256,
            rig_sha256=rig_sha256, stops=c.stops, beams=beams, dampers=c.dampers,
        )
        return res

    def springs(self) -> list[Spring]:
        springs = [self.attempt(lambda n=name, sp=sp: self.spring(n, sp))
                   for name, sp in self.spec.springs.items() if self.keep(name, sp.parts)]
        return [sp for sp in springs if sp is not None]

    def spring(self, name: str, sp) -> Spring:
        key = f"springs.{name}"
        parts = self.parts(sp.parts, key)
        seats = self.point_pair(sp.seats, key + ".seats", "the two spring seats coincide")
        return Spring(self.name(name), parts, seats, sp.rate_N_per_mm, sp.preload_N,
                      sp.free_length_mm)

    def dampers(self) -> list[Damper]:
        dampers = [self.attempt(lambda n=name, dm=dm: self.damper(n, dm))
                   for name, dm in self.spec.dampers.items() if self.keep(name, dm.parts)]
        return [dm for dm in dampers if dm is not None]

    def damper(self, name: str, dm) -> Damper:
        key = f"dampers.{name}"
        parts = self.parts(dm.parts, key)
        pts = self.point_pair(dm.points, key + ".points", "the two points of a damper coincide")
        return Damper(self.name(name), parts, pts, dm.rate_N_s_per_mm)

    def stops(self) -> list[Stop]:
        stops = [self.attempt(lambda n=name, st=st: self.stop(n, st))
                 for name, st in self.spec.stops.items() if self.keep(name, st.parts)]
        return [st for st in stops if st is not None]

    def stop(self, name: str, st) -> Stop:
        key = f"stops.{name}"
        parts = self.parts(st.parts, key)
        pts = self.point_pair(st.points, key + ".points", "the two points of a stop coincide")
        if st.type == "bump" and st.clearance_mm >= np.linalg.norm(pts[1] - pts[0]):
            raise self.fail(key + ".clearance_mm", "a bump stop's clearance must be less "
                            "than the distance of its points")
        try:
            law = law_from_spec(st.curve)
        except ValueError as exc:
            raise self.fail(key + ".curve", str(exc)) from None
        return Stop(self.name(name), st.type, parts, pts, st.clearance_mm, law)

    def check_label(self) -> None:
        """The model's ``label`` is not that of another model of a K&C run."""
        s = self.spec
        if s.label == "test" or s.label.endswith("_kinematic"):
            raise self.fail("label", f"'{s.label}' is the label of another model of a run "
                            "(test, <label>_kinematic)")
        if s.label == "identified_stiffness" and s.kc_test is not None and \
                s.kc_test.stiffness_identification.enabled:
            raise self.fail("label", "'identified_stiffness' is the stiffness fit's model: set "
                            "kc_test.stiffness_identification.enabled: false in its config")

    def check_design(self, bushings: list[Bushing]) -> None:
        """The ``design`` section agrees with the springs' and bushings' own preloads."""
        s = self.spec
        d = s.design
        if d.balance_spring is not None:
            if d.balance_spring not in s.springs:
                raise self.fail("design.balance_spring", f"spring '{d.balance_spring}' is not "
                                f"defined under 'springs' ({', '.join(s.springs) or 'none'})")
            sp = s.springs[d.balance_spring]
            if sp.free_length_mm is not None or sp.preload_N is not None:
                raise self.fail(f"springs.{d.balance_spring}", "its preload is solved from "
                                "design.wheel_load_N: remove free_length_mm / preload_N")
        for sp_name, sp in s.springs.items():
            if sp_name != d.balance_spring and sp.free_length_mm is None and sp.preload_N is None:
                raise self.fail(f"springs.{sp_name}", "give free_length_mm or preload_N, or "
                                "name it in design.balance_spring")
        if d.balance_bushing_preloads:
            for b in bushings:
                if b.preload_given:
                    raise self.fail(f"connections.{b.name}", "preload / initial_deflection "
                                    "conflicts with design.balance_bushing_preloads: true")

    def bushing_laws(self, stiffness, key: str) -> tuple:
        """The laws of ``stiffness`` (config key ``key``) in BUSHING_DIRECTIONS order; None
        where a direction is not given (an override)."""
        laws = []
        for d in BUSHING_DIRECTIONS:
            spec = getattr(stiffness, d)
            try:
                laws.append(None if spec is None else law_from_spec(spec))
            except ValueError as exc:
                raise self.fail(f"{key}.{d}", str(exc)) from None
        return tuple(laws)

    def bushing(self, name: str, c: BushingSpec, parts, pos, key: str) -> Bushing:
        frame = self.bushing_frame(c, key)
        laws = self.bushing_laws(c.stiffness, key + ".stiffness")
        if c.initial_deflection is not None:
            u0 = np.r_[c.initial_deflection.translation_mm, c.initial_deflection.rotation_deg]
        elif c.preload is not None:
            loads = np.r_[c.preload.force_N, c.preload.torque_Nmm]
            try:
                u0 = np.array([law.deflection_at(f) for law, f in zip(laws, loads)])
            except ValueError as exc:
                raise self.fail(f"{key}.preload", str(exc)) from None
        else:
            u0 = np.zeros(6)
        return Bushing(name, parts, pos, frame, laws, u0, c.ideal_joint,
                       c.preload is not None or c.initial_deflection is not None,
                       kinematic=c.kinematic or self.spec.kinematic)

