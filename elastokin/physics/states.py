"""Plain state types of a solved suspension (config frame; mm, N, N*mm, deg): what a static
step of the multibody model gives, and what the rig reads from it. No solver here."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


@dataclass
class PartPoses:
    """Rigid-body poses of the moving parts at one step: rotation (3, 3) and the displacement
    (mm) of each part's reference point ``reference_mm`` (config frame, design position)."""

    rotation: dict[str, np.ndarray] = field(default_factory=dict)
    displacement_mm: dict[str, np.ndarray] = field(default_factory=dict)
    reference_mm: dict[str, np.ndarray] = field(default_factory=dict)

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


@dataclass
class StepState:
    """One rig step: the wheel as the K&C rig sees it plus the model state.

    Config frame, mm / N / N*mm / deg. ``pad_force_N``: the force the rig applies to the tyre
    at the contact patch (applied force plus the pad's reaction under displacement control).
    ``poses``: every moving part's pose, or None when the model records the wheel part only.
    ``sensitivity``: when solved with parameter sensitivities, the derivatives of
    ``wheel_centre_mm``, ``contact_patch_mm`` and ``spin_axis`` ((3, n) each, per unit of the
    n parameters).
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
