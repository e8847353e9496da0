"""A vehicle file (:mod:`elastokin.config.schema.vehicle`) loaded: its two axles, each its
config with the vehicle's data in place of its own ``axle.vehicle`` and the table's body roll
as its roll case, and the one set of vehicle data (README "The whole car").

The axle configs' paths are confined to the vehicle file's folder and the folders typed with
``--data`` (:mod:`elastokin.config.confined`); each config is validated as it is first (its
own errors name its own keys), then with the vehicle's data. Where an axle's own data contradict the
vehicle's (a vehicle key it types with another value; a design wheel load that does not carry
the vehicle's mass on that axle) a :class:`VehicleDataWarning` names both files and keys.

Units mm, N, kg, deg.
"""

from __future__ import annotations

import hashlib
import math
import warnings
from dataclasses import dataclass
from pathlib import Path

import yaml
from pydantic import ValidationError

from elastokin.config.axle import AXLE_MASS_TOLERANCE
from elastokin.config.confined import Roots, confined_path, typed_folders
from elastokin.config.frozen import plain_data
from elastokin.config.loading import (
    format_validation_error,
    read_rig,
    read_yaml,
    suspension_from_dict,
)
from elastokin.config.schema.rig import RollSpec
from elastokin.config.schema.vehicle import STANDARD_GRAVITY, VehicleFile
from elastokin.config.suspension import Suspension
from elastokin.errors import ConfigError

#: the car's axles, front first
ROLES = ("front", "rear")
#: an axle's design load differing from the vehicle's weight on it by more than this
#: fraction is warned about
LOAD_TOLERANCE = 0.01


class VehicleDataWarning(UserWarning):
    """An axle config's own data contradict the vehicle file's (the vehicle's are used)."""


@dataclass(frozen=True)
class CarData:
    """The car's one set of vehicle data: wheelbase and CG height (mm, the CG above the
    ground), the masses the axles carry (kg), the front axle's share of braking, of drive and
    (None: each axle's own) of the lateral load transfer in the static-load cases (0 ... 1)."""

    wheelbase_mm: float
    cg_height_mm: float
    mass_front_kg: float
    mass_rear_kg: float
    brake_fraction_front: float
    drive_fraction_front: float
    lateral_transfer_fraction_front: float | None = None

    @property
    def mass_kg(self) -> float:
        return self.mass_front_kg + self.mass_rear_kg

    @property
    def front_mass_fraction(self) -> float:
        return self.mass_front_kg / self.mass_kg

    @property
    def cg_behind_front_axle_mm(self) -> float:
        """The CG's distance behind the front axle (mm): the wheelbase times the rear
        axle's share of the mass (moments about the front axle)."""
        return self.wheelbase_mm * self.mass_rear_kg / self.mass_kg

    def weight_N(self, role: str) -> float:
        """The weight the ``role`` axle carries (N): its mass times standard gravity."""
        return (self.mass_front_kg if role == "front" else self.mass_rear_kg) \
            * STANDARD_GRAVITY

    def axle_vehicle(self, role: str) -> dict:
        """The ``axle.vehicle`` keys the vehicle gives the ``role`` axle (its fractions are
        that axle's shares)."""
        def share(front: float) -> float:
            return front if role == "front" else 1.0 - front

        out = {"position": role, "wheelbase_mm": self.wheelbase_mm,
               "cg_height_mm": self.cg_height_mm,
               "brake_fraction": share(self.brake_fraction_front),
               "drive_fraction": share(self.drive_fraction_front),
               "axle_mass_kg": {"front": self.mass_front_kg, "rear": self.mass_rear_kg}}
        if self.lateral_transfer_fraction_front is not None:
            out["lateral_transfer_fraction"] = share(self.lateral_transfer_fraction_front)
        return out

    def as_dict(self) -> dict:
        """summary.json ``vehicle``: the data and what follows from them."""
        return {"wheelbase_mm": self.wheelbase_mm, "cg_height_mm": self.cg_height_mm,
                "axle_mass_kg": {"front": self.mass_front_kg, "rear": self.mass_rear_kg},
                "mass_kg": self.mass_kg, "front_mass_fraction": self.front_mass_fraction,
                "cg_behind_front_axle_mm": self.cg_behind_front_axle_mm,
                "brake_fraction_front": self.brake_fraction_front,
                "drive_fraction_front": self.drive_fraction_front,
                "lateral_transfer_fraction_front": self.lateral_transfer_fraction_front,
                "standard_gravity_m_per_s2": STANDARD_GRAVITY}


@dataclass(frozen=True)
class Vehicle:
    """A loaded vehicle file: ``front`` and ``rear`` are the axles as the car runs them
    (the vehicle's data in ``axle.vehicle``, the table's ``body_roll`` as the rig's
    ``roll_vertical_force``; ``config_sha256`` still each file's own bytes' hash);
    ``warnings``: where their own data contradicted the vehicle's."""

    name: str
    source: str
    sha256: str
    data: CarData
    body_roll: RollSpec
    front: Suspension
    rear: Suspension
    warnings: tuple[str, ...] = ()
    rig_source: str = ""  # a rig file both axles run (typed on the command line)
    rig_sha256: str | None = None

    def axle(self, role: str) -> Suspension:
        return self.front if role == "front" else self.rear


def is_vehicle_file(path: str | Path) -> bool:
    """Whether the YAML file ``path`` is a vehicle file (names a front and a rear axle, has
    no hardpoints) rather than a suspension config: for tools that take every file of a
    folder of configs."""
    data = read_yaml(path)[0]
    return {"front", "rear"} <= set(data) and "hardpoints" not in data


def load_vehicle(path: str | Path, rig_path: str | Path | None = None) -> Vehicle:
    """Load and validate a vehicle file and its two axle configs (module docstring);
    ``rig_path``: a rig file whose load cases both axles run instead of their own ``rig``
    (the body roll still the vehicle's). Errors name the file and the key."""
    path = Path(path)
    raw, text = read_yaml(path, "vehicle file")
    try:
        spec = VehicleFile.model_validate(raw)
    except ValidationError as err:
        raise ConfigError(format_validation_error(str(path), err, raw, VehicleFile)) from None
    front_kg, rear_kg = spec.masses_kg()
    data = CarData(spec.wheelbase_mm, spec.cg_height_mm, front_kg, rear_kg,
                   spec.brake_fraction_front, spec.drive_fraction_front,
                   spec.lateral_transfer_fraction_front)
    rig = None if rig_path is None else (str(rig_path), *read_rig(rig_path))
    typed = typed_folders()
    roots = Roots.of((path.parent, *typed), "the vehicle file's folder"
                     + (" and the folders given" if typed else ""))
    axles, notes = {}, []
    for role in ROLES:
        axles[role], found = _axle(role, getattr(spec, role).config, path, roots, data,
                                   spec.body_roll, rig)
        notes += found
    for note in notes:
        warnings.warn(VehicleDataWarning(note), stacklevel=2)
    return Vehicle(spec.name, str(path), hashlib.sha256(text).hexdigest(), data,
                   spec.body_roll, axles["front"], axles["rear"], tuple(notes),
                   "" if rig is None else rig[0],
                   None if rig is None else hashlib.sha256(rig[2]).hexdigest())


def _axle(role: str, named: str, vehicle_path: Path, roots: Roots, data: CarData,
          roll: RollSpec, rig: tuple[str, dict, bytes] | None
          ) -> tuple[Suspension, list[str]]:
    """The ``role`` axle's config as the car runs it, and its contradictions."""
    where = f"{vehicle_path}: key '{role}.config'"
    path = confined_path(named, vehicle_path.parent, roots, where, "axle config",
                         remedy="copy it beside the vehicle file, or give its folder with "
                                "--data FOLDER if you trust the vehicle file")
    if not path.is_file():
        raise ConfigError(f"{where}: axle config {named!r} ({path}) "
                          + ("is not a file" if path.exists() else "does not exist"))
    raw, text = read_yaml(path)
    own = suspension_from_dict(raw, str(path))  # its own errors in its own keys
    if own.axle is None:
        raise ConfigError(f"{where}: {path} describes one corner (no 'axle' section); a "
                          "vehicle's axles are axle configs (README 'The axle section')")
    check_axle_load(own, role, data, vehicle_path)
    applied = {**plain_data(raw["axle"].get("vehicle") or {}), **data.axle_vehicle(role)}
    rig_data = dict(rig[1]) if rig is not None else dict(raw.get("rig") or {})
    rig_data["roll_vertical_force"] = roll.model_dump()
    overrides = {"axle": {**raw["axle"], "vehicle": applied}, "rig": rig_data}
    digest = hashlib.sha256(text)
    digest.update(yaml.safe_dump(plain_data(overrides), sort_keys=True).encode())
    s = suspension_from_dict({**raw, **overrides}, str(path), digest.hexdigest(),
                             config_sha256=hashlib.sha256(text).hexdigest(),
                             rig_sha256=None if rig is None
                             else hashlib.sha256(rig[2]).hexdigest(),
                             rig_source="" if rig is None else rig[0])
    return s, contradictions(own, role, data, vehicle_path)


def check_axle_load(own: Suspension, role: str, data: CarData, vehicle_path: Path) -> None:
    """The vehicle's mass on the ``role`` axle carries its design wheel loads within a factor
    :data:`~elastokin.config.axle.AXLE_MASS_TOLERANCE` (as an axle's own ``axle_mass_kg``
    must): beyond it, a slip (a total mass, the other axle's, a load in N), an error naming
    the vehicle file's key."""
    ratio = data.weight_N(role) / (2.0 * own.design.wheel_load_N)
    if not 1.0 / AXLE_MASS_TOLERANCE <= ratio <= AXLE_MASS_TOLERANCE:
        mass = getattr(data, f"mass_{role}_kg")
        raise ConfigError(
            f"{vehicle_path}: the {role} axle's mass {mass:g} kg is {ratio:.2f} times what its "
            f"design wheel loads carry ({own.source}: design.wheel_load_N "
            f"{own.design.wheel_load_N:g} N, "
            f"{2.0 * own.design.wheel_load_N / STANDARD_GRAVITY:.0f} kg on the axle): "
            "expected the mass this axle carries (axle_mass_kg, or mass_kg and "
            "front_mass_fraction)")


#: the vehicle file's key behind each ``axle.vehicle`` key it sets
VEHICLE_KEYS = {"wheelbase_mm": "wheelbase_mm", "cg_height_mm": "cg_height_mm",
                "brake_fraction": "brake_fraction_front",
                "drive_fraction": "drive_fraction_front",
                "lateral_transfer_fraction": "lateral_transfer_fraction_front",
                "axle_mass_kg.front": "axle_mass_kg.front",
                "axle_mass_kg.rear": "axle_mass_kg.rear"}


def _typed(vehicle) -> dict:
    """The keys an ``axle.vehicle`` section types, ``axle_mass_kg`` as its two entries."""
    out = {k: getattr(vehicle, k) for k in vehicle.model_fields_set}
    masses = out.pop("axle_mass_kg", None)
    if masses is not None:
        out.update({"axle_mass_kg.front": masses.front, "axle_mass_kg.rear": masses.rear})
    return out


def contradictions(own: Suspension, role: str, data: CarData, vehicle_path: Path
                   ) -> list[str]:
    """Where the axle config ``own`` (as its file says) contradicts the vehicle's data for
    the ``role`` axle: a key of its ``axle.vehicle`` it types with another value, and a
    design wheel load that does not carry the vehicle's weight on the axle (within
    :data:`LOAD_TOLERANCE`)."""
    out = []
    given = {} if own.axle.vehicle is None else _typed(own.axle.vehicle)
    wanted = data.axle_vehicle(role)
    wanted.update({f"axle_mass_kg.{r}": m for r, m in wanted.pop("axle_mass_kg").items()})
    if given.get("position", role) != role:
        out.append(f"{own.source}: key 'axle.vehicle.position' is {given['position']}, the "
                   f"vehicle file {vehicle_path} has it as its {role} axle: the vehicle "
                   "file's is used")
    for key, vkey in VEHICLE_KEYS.items():
        mine, theirs = given.get(key), wanted.get(key)
        if mine is None or theirs is None or math.isclose(mine, theirs, rel_tol=1e-9,
                                                          abs_tol=1e-12):
            continue
        front_share = vkey.endswith("_front")
        said = getattr(data, vkey) if front_share else theirs
        share = f", the rear axle's share {theirs:g}" if role == "rear" and front_share else ""
        out.append(f"{own.source}: key 'axle.vehicle.{key}' is {mine:g}, the vehicle file "
                   f"{vehicle_path} says {vkey} {said:g}{share}: the vehicle file's is used")
    axle_load = 2.0 * own.design.wheel_load_N
    weight = data.weight_N(role)
    if abs(axle_load - weight) > LOAD_TOLERANCE * weight:
        mass = getattr(data, f"mass_{role}_kg")
        out.append(
            f"{own.source}: key 'design.wheel_load_N' ({own.design.wheel_load_N:g} N per "
            f"wheel: {axle_load / STANDARD_GRAVITY:.1f} kg on the axle) differs from the "
            f"{mass:.1f} kg the vehicle file {vehicle_path} puts on the {role} axle by "
            f"{100.0 * (axle_load - weight) / weight:+.1f} %: the rig holds the axle at its "
            "design wheel load (its hardpoints' equilibrium); the car's figures that need "
            "the axle loads (understeer contributions, roll gradient) use the vehicle's "
            "masses")
    return out
