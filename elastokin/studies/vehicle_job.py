"""The whole car on the K&C rig (``elastokin kc --vehicle``) as a chain of named steps over
the K&C job's pieces (:mod:`elastokin.studies.kc_job`):

1. ``axle_runs``: each axle's K&C job (:func:`~elastokin.studies.kc_job.run_kc`) on its
   config as the car runs it (:func:`elastokin.config.vehicle.load_vehicle`: the vehicle's
   data in place of the axle's own, the table's body roll as its roll case), each with its
   own cache;
2. ``model_pairs``: which of the axles' models make the car's models (the labels both axles
   have, e.g. ``initial`` and ``initial_kinematic``; otherwise the two reported models);
3. ``body_roll``: the table's body roll of each car model from both axles' roll cases
   (:func:`elastokin.rig.vehicle_summary.body_roll_sweep`);
4. ``figures``: the car's figures (:func:`elastokin.rig.vehicle_summary.car_figures`).

:func:`run_vehicle` runs the chain from a loaded vehicle, :func:`run_vehicle_from_axles` from
the axles' K&C runs. Units mm, N, N*mm, deg. The files are written by
:mod:`elastokin.report.vehicle_files`.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field

from elastokin.config.vehicle import ROLES, Vehicle
from elastokin.physics.wheel import UndeterminedSlopeWarning
from elastokin.rig.sweeps import Sweep
from elastokin.rig.vehicle_summary import axle_in_car, body_roll_sweep, car_figures
from elastokin.studies.cache import ResultCache
from elastokin.studies.kc_job import KCRun, Progress, run_kc, select_models, start_label


def _quiet(msg: str) -> None:
    return None


@dataclass(frozen=True)
class CarModel:
    """A model of the car: ``label`` (summary.json ``models``), and the models of the front
    and the rear axle it pairs."""

    label: str
    front: str
    rear: str

    def of(self, role: str) -> str:
        return self.front if role == "front" else self.rear


@dataclass
class VehicleRun:
    """The car on the rig: each axle's K&C run (``axles``, front and rear), the car's models,
    their table roll sweeps and figures (``figures[label]``: ``front``, ``rear``, ``car``)."""

    vehicle: Vehicle
    axles: dict[str, KCRun]
    models: dict[str, CarModel]
    roll: dict[str, Sweep] = field(default_factory=dict)
    figures: dict[str, dict] = field(default_factory=dict)
    warnings: list[str] = field(default_factory=list)

    def add_warnings(self, messages: list[str]) -> None:
        """Add warnings of the run (each distinct message once): they go into the car's
        summary.json."""
        self.warnings += [m for m in dict.fromkeys(messages) if m not in self.warnings]


# ------------------------------------------------------------------------------- the steps
def axle_runs(vehicle: Vehicle, progress: Progress = _quiet, detail: Progress = _quiet,
              models: str | None = None,
              caches: dict[str, ResultCache] | None = None) -> dict[str, KCRun]:
    """Step ``axle_runs``: the K&C job of each axle (``models``: the models to run, as
    ``elastokin kc --models`` gives them, checked on each axle; ``caches``: each axle's)."""
    out = {}
    for role in ROLES:
        s = vehicle.axle(role)
        chosen = select_models(s, models)
        out[role] = run_kc(s, _prefixed(progress, role), _prefixed(detail, role), chosen,
                           (caches or {}).get(role))
    return out


def _prefixed(progress: Progress, role: str) -> Progress:
    return lambda msg: progress(f"{role} axle: {msg}")


def model_pairs(runs: dict[str, KCRun]) -> dict[str, CarModel]:
    """Step ``model_pairs``: a car model for each model label both axles have (the test
    data's excepted), in the front axle's order; when they share none, the pair of the
    models each axle reports (its static state's), labelled ``<front>+<rear>``."""
    front, rear = (runs[role].models for role in ROLES)
    common = [m for m in front if m in rear and m != "test"]
    if common:
        return {m: CarModel(m, m, m) for m in common}
    f, r = (start_label(runs[role].suspension) for role in ROLES)
    f = f if f in front else next(m for m in front if m != "test")
    r = r if r in rear else next(m for m in rear if m != "test")
    return {f"{f}+{r}": CarModel(f"{f}+{r}", f, r)}


def _by_side(run: KCRun, label: str) -> dict[str, list[Sweep]]:
    m = run.models[label]
    return {run.suspension.side: m.sweeps, **m.other_sides}


def body_roll(vehicle: Vehicle, runs: dict[str, KCRun], pairs: dict[str, CarModel]
              ) -> dict[str, Sweep]:
    """Step ``body_roll``: each car model's table roll (those whose axles ran their roll
    case)."""
    out = {}
    for label, pair in pairs.items():
        sweep = body_roll_sweep(label, {role: _by_side(runs[role], pair.of(role))
                                        for role in ROLES}, vehicle)
        if sweep is not None:
            out[label] = sweep
    return out


def figures(vehicle: Vehicle, runs: dict[str, KCRun], pairs: dict[str, CarModel],
            roll: dict[str, Sweep], summaries: dict[str, dict] | None = None
            ) -> dict[str, dict]:
    """Step ``figures``: each car model's figures from its axles' summaries (``summaries``:
    each axle's ``KCRun.summaries()``, computed when not given)."""
    summaries = summaries or {role: runs[role].summaries() for role in ROLES}
    out = {}
    for label, pair in pairs.items():
        axles = [axle_in_car(summaries[role][pair.of(role)], runs[role].suspension.side)
                 for role in ROLES]
        out[label] = {"front_model": pair.front, "rear_model": pair.rear,
                      **car_figures(*axles, vehicle.data, roll.get(label))}
    return out


# ------------------------------------------------------------------------------- entry points
def run_vehicle(vehicle: Vehicle, progress: Progress = _quiet, detail: Progress = _quiet,
                models: str | None = None,
                caches: dict[str, ResultCache] | None = None) -> VehicleRun:
    """The whole car from a loaded vehicle (:func:`elastokin.config.vehicle.load_vehicle`):
    every step of the module docstring. ``models``: the axles' models to run (comma-separated,
    as ``--models``); ``caches``: each axle's result cache (``front``, ``rear``)."""
    runs = axle_runs(vehicle, progress, detail, models, caches)
    return run_vehicle_from_axles(vehicle, runs)


def run_vehicle_from_axles(vehicle: Vehicle, runs: dict[str, KCRun]) -> VehicleRun:
    """The car from its axles' K&C runs (``front``, ``rear``; their suspensions the
    vehicle's): the steps ``model_pairs``, ``body_roll`` and ``figures``. The warnings of
    the vehicle's data and of figures not determined go into the run's."""
    pairs = model_pairs(runs)
    roll = body_roll(vehicle, runs, pairs)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        summaries = {role: runs[role].summaries() for role in ROLES}
        values = figures(vehicle, runs, pairs, roll, summaries)
    for w in caught:
        warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
    run = VehicleRun(vehicle, runs, pairs, roll, values, list(vehicle.warnings))
    run.add_warnings([" ".join(str(w.message).split()) for w in caught
                      if issubclass(w.category, UndeterminedSlopeWarning)])
    return run
