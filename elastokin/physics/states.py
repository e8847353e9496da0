"""Plain state types of a solved suspension (config frame; mm, N, N*mm, deg): what a static
step of the multibody model gives, and what the rig reads from it. No solver here."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


@dataclass
class PartPoses:
    """Rigid-body poses of the moving parts at one step: rotation (3, 3) and the displacement
    (mm) of each part's reference point ``reference_mm`` (config frame, design position); of
    a flexible (beam) part, its node line's nodes (:func:`elastokin.physics.beams.node_line`,
    in order): their positions ``node_mm`` (k, 3) and their rotations from the design position
    ``node_rotation`` (k, 3, 3)."""

    rotation: dict[str, np.ndarray] = field(default_factory=dict)
    displacement_mm: dict[str, np.ndarray] = field(default_factory=dict)
    reference_mm: dict[str, np.ndarray] = field(default_factory=dict)
    node_mm: dict[str, np.ndarray] = field(default_factory=dict)
    node_rotation: dict[str, np.ndarray] = field(default_factory=dict)

    def moved(self, part: str, points_mm) -> np.ndarray:
        """Where points of ``part`` given at the design position (mm, (..., 3)) are now; the
        ground part and unknown parts do not move."""
        x = np.asarray(points_mm, float)
        if part not in self.rotation:
            return x.copy()
        ref = self.reference_mm[part]
        return (x - ref) @ self.rotation[part].T + ref + self.displacement_mm[part]

    def transform(self, part: str) -> np.ndarray:
        """4x4 homogeneous transform from the design position to the current one."""
        T = np.eye(4)
        if part in self.rotation:
            T[:3, :3] = self.rotation[part]
            T[:3, 3] = self.moved(part, np.zeros(3))
        return T


@dataclass(frozen=True)
class LoadItem:
    """An element of a model whose load is reported (:mod:`elastokin.physics.loads`): a
    connection, spring, stop, the anti-roll bar, the steering gear, a wheel's contact patch.
    The load acts on ``parts[0]``, its reaction on ``parts[1]``; ``kind`` says what it is
    (``joint``, ``rack``, ``bushing``, ``link``, ``spring``, ``stop``, ``anti_roll_bar``,
    ``steering_gear``, ``contact_patch``, ``idle_spin``, ``support``, ``load``);
    ``two_point``: a force along the line between its two points, no moment (a link, a
    spring, a stop); ``moments``: it may transmit a moment (not a ball joint)."""

    name: str
    kind: str
    parts: tuple[str, str]
    two_point: bool = False
    moments: bool = True


@dataclass
class LoadTable:
    """The loads of ``items`` at one or more steps: ``values`` (..., items, 7, 3), the
    quantities :data:`elastokin.physics.loads.QUANTITIES` of each item (config frame; N, N*mm,
    mm); ``ground``: the model's ground part."""

    items: tuple[LoadItem, ...]
    values: np.ndarray
    ground: str = ""  # the model's ground part (body, subframe, rig frame)

    def step(self, i: int) -> LoadTable:
        """The table of step ``i`` (values (items, 7, 3))."""
        return LoadTable(self.items, self.values[i], self.ground)

    @classmethod
    def stack(cls, tables: list[LoadTable]) -> LoadTable:
        """The steps of one solve (the same items) as one table (values (n, items, 7, 3))."""
        return cls(tables[0].items, np.stack([t.values for t in tables]), tables[0].ground)

    def names(self) -> list[str]:
        return [item.name for item in self.items]


@dataclass
class PoseSeries:
    """The poses of the moving parts at every step of a sweep (config frame): ``rotation``
    (steps, 3, 3) from the design position and ``displacement_mm`` (steps, 3) of each part's
    reference point ``reference_mm`` (3,) (design position); of a flexible part, ``node_mm``
    (steps, k, 3) and ``node_rotation`` (steps, k, 3, 3); as :class:`PartPoses` per step."""

    rotation: dict[str, np.ndarray] = field(default_factory=dict)
    displacement_mm: dict[str, np.ndarray] = field(default_factory=dict)
    reference_mm: dict[str, np.ndarray] = field(default_factory=dict)
    node_mm: dict[str, np.ndarray] = field(default_factory=dict)
    node_rotation: dict[str, np.ndarray] = field(default_factory=dict)

    @classmethod
    def stack(cls, poses: list[PartPoses]) -> PoseSeries:
        """The series of one :class:`PartPoses` per step (the first step's parts)."""
        names = list(poses[0].rotation) if poses else []
        beams = list(poses[0].node_mm) if poses else []
        return cls({n: np.array([p.rotation[n] for p in poses]) for n in names},
                   {n: np.array([p.displacement_mm[n] for p in poses]) for n in names},
                   {n: np.asarray(poses[0].reference_mm[n], float) for n in names},
                   {n: np.array([p.node_mm[n] for p in poses]) for n in beams},
                   {n: np.array([p.node_rotation[n] for p in poses]) for n in beams})

    @property
    def steps(self) -> int:
        return len(next(iter(self.rotation.values()))) if self.rotation else 0

    def at(self, step: int) -> PartPoses:
        """The poses at one step."""
        return PartPoses({n: r[step] for n, r in self.rotation.items()},
                         {n: d[step] for n, d in self.displacement_mm.items()},
                         dict(self.reference_mm),
                         {n: x[step] for n, x in self.node_mm.items()},
                         {n: r[step] for n, r in self.node_rotation.items()})

    def transforms(self, part: str, steps) -> tuple[np.ndarray, np.ndarray]:
        """(R (k, 3, 3), t (k, 3)) of ``part`` at ``steps`` (indices) with x_now = R x + t for
        a point x at the design position; the identity for the ground and unknown parts."""
        steps = np.asarray(steps, int)
        if part not in self.rotation:
            return np.broadcast_to(np.eye(3), (steps.size, 3, 3)), np.zeros((steps.size, 3))
        R = self.rotation[part][steps]
        ref = self.reference_mm[part]
        return R, ref + self.displacement_mm[part][steps] - R @ ref


@dataclass
class StateSensitivity:
    """Derivatives of one solved step with respect to n parameters (config frame): of each
    point sensor's position (name -> (3, n), mm per unit parameter) and of each recorded part's
    rotation matrix (part -> (3, 3, n))."""

    points: dict[str, np.ndarray] = field(default_factory=dict)
    rotation: dict[str, np.ndarray] = field(default_factory=dict)


@dataclass
class ModelState:
    """One solved step of a suspension model.

    ``poses``: the recorded parts (always the wheel part; every moving part when the model
    records all poses). ``spring_force_N``: compression +. ``bushing_deflection``: x y z mm,
    rx ry rz deg, part 2 relative to part 1 in the bushing frame, including the initial
    deflection; ``bushing_load``: Fx Fy Fz N, Tx Ty Tz N*mm in the bushing frame (+K*u; NaN
    for a bushing modelled by its ideal joint). ``support_force_N``: reaction of each support
    attached to the model (config frame, on the part). ``applied``: the value of each load
    attached to the model at this step (N or N*mm, config frame). ``points``: the position of
    each point sensor (mm, config frame). ``sensitivity``: derivatives with respect to model
    parameters, when the step was solved with them (:mod:`elastokin.mbs.sensitivity`).
    ``loads``: the load every element transmits (:mod:`elastokin.mbs.loads`).
    """

    poses: PartPoses
    spring_force_N: dict[str, float]
    bushing_deflection: dict[str, np.ndarray]
    bushing_load: dict[str, np.ndarray]
    support_force_N: dict[str, np.ndarray] = field(default_factory=dict)
    applied: dict[str, np.ndarray] = field(default_factory=dict)
    points: dict[str, np.ndarray] = field(default_factory=dict)
    sensitivity: StateSensitivity | None = None
    #: scalar outputs by name: ``stop:<name>`` force (N), ``arb:twist_deg``, ``arb:torque_Nmm``,
    #: ``spring_length:<name>``, ``damper_length:<name>`` (mm)
    scalars: dict[str, float] = field(default_factory=dict)
    #: the load of every element (None: not recorded, ``ModelOptions.record_loads``)
    loads: LoadTable | None = None


@dataclass
class StepState:
    """One rig step: the wheel as the K&C rig sees it plus the model state.

    Config frame, mm / N / N*mm / deg. ``pad_force_N``: the force the rig applies to the tyre
    at the contact patch (applied force plus the pad's reaction under displacement control).
    ``poses``: every moving part's pose, or None when the model records the wheel part only.
    ``sensitivity``: when solved with parameter sensitivities, the derivatives of
    ``wheel_centre_mm``, ``contact_patch_mm`` and ``spin_axis`` ((3, n) each, per unit of the
    n parameters). ``loads``: every element's load (the whole model's, the same for each
    wheel; None: not recorded).
    """

    wheel_centre_mm: np.ndarray
    spin_axis: np.ndarray
    wheel_rotation: np.ndarray
    contact_patch_mm: np.ndarray
    pad_force_N: np.ndarray
    spring_force_N: dict[str, float]
    bushing_deflection: dict[str, np.ndarray]
    bushing_load: dict[str, np.ndarray]
    poses: PartPoses | None = None
    sensitivity: dict[str, np.ndarray] | None = None
    scalars: dict[str, float] = field(default_factory=dict)  # see ModelState.scalars
    loads: LoadTable | None = None  # the whole model's, see ModelState.loads



@dataclass
class WheelArrays:
    """One wheel's rig steps as arrays over the steps (the fields of :class:`StepState`,
    first axis the step): what the rig's post-processing reads, without an object per step
    (the design sensitivities' twin states). ``poses``: per part (rotation (n, 3, 3),
    displacement (n, 3)) with ``reference_mm``, or None."""

    wheel_centre_mm: np.ndarray
    spin_axis: np.ndarray
    wheel_rotation: np.ndarray
    contact_patch_mm: np.ndarray
    pad_force_N: np.ndarray
    spring_force_N: dict[str, np.ndarray] = field(default_factory=dict)
    bushing_deflection: dict[str, np.ndarray] = field(default_factory=dict)
    bushing_load: dict[str, np.ndarray] = field(default_factory=dict)
    scalars: dict[str, np.ndarray] = field(default_factory=dict)
    poses: dict[str, tuple[np.ndarray, np.ndarray]] | None = None
    reference_mm: dict[str, np.ndarray] = field(default_factory=dict)

    @classmethod
    def of(cls, states, poses: bool = False) -> WheelArrays:
        """The arrays of a list of :class:`StepState` (a WheelArrays is returned as is); the
        parts' poses only with ``poses``."""
        if isinstance(states, WheelArrays):
            return states
        first = states[0]
        poses = None if not poses else poses
        if poses and first.poses is not None:
            poses = {p: (np.array([st.poses.rotation[p] for st in states]),
                         np.array([st.poses.displacement_mm[p] for st in states]))
                     for p in first.poses.rotation}
        return cls(np.array([st.wheel_centre_mm for st in states]),
                   np.array([st.spin_axis for st in states]),
                   np.array([st.wheel_rotation for st in states]),
                   np.array([st.contact_patch_mm for st in states]),
                   np.array([st.pad_force_N for st in states]),
                   {k: np.array([st.spring_force_N[k] for st in states])
                    for k in first.spring_force_N},
                   {k: np.array([st.bushing_deflection[k] for st in states])
                    for k in first.bushing_deflection},
                   {k: np.array([st.bushing_load[k] for st in states])
                    for k in first.bushing_load},
                   {k: np.array([st.scalars[k] for st in states]) for k in first.scalars},
                   poses or None, dict(first.poses.reference_mm) if poses else {})

    def __len__(self) -> int:
        return len(self.wheel_centre_mm)

    def rows(self, index) -> WheelArrays:
        """The steps ``index`` (indices or a mask)."""
        def pick(d):
            return {k: v[index] for k, v in d.items()}

        poses = None if self.poses is None else {p: (r[index], d[index])
                                                 for p, (r, d) in self.poses.items()}
        return WheelArrays(self.wheel_centre_mm[index], self.spin_axis[index],
                           self.wheel_rotation[index], self.contact_patch_mm[index],
                           self.pad_force_N[index], pick(self.spring_force_N),
                           pick(self.bushing_deflection), pick(self.bushing_load),
                           pick(self.scalars), poses, self.reference_mm)

    def step(self, i: int) -> StepState:
        """Step ``i`` as a :class:`StepState`."""
        poses = None if self.poses is None else PartPoses(
            {p: r[i] for p, (r, _) in self.poses.items()},
            {p: d[i] for p, (_, d) in self.poses.items()}, self.reference_mm)
        return StepState(self.wheel_centre_mm[i], self.spin_axis[i], self.wheel_rotation[i],
                         self.contact_patch_mm[i], self.pad_force_N[i],
                         {k: v[i] for k, v in self.spring_force_N.items()},
                         {k: v[i] for k, v in self.bushing_deflection.items()},
                         {k: v[i] for k, v in self.bushing_load.items()}, poses,
                         scalars={k: v[i] for k, v in self.scalars.items()})
