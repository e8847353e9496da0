"""Tolerance and DOE studies: how assembly clearance spreads the K&C characteristics.

A study samples the assembly-clearance shifts of every joint that the config's
``measurements.joints`` gives a clearance (each within its dL_max [1];
:mod:`elastokin.studies.doe_sampling`), builds the as-built suspension of each sample (the
nominal design preloads, joints shifted), runs the K&C load cases on it and reports the
distributions of the summary characteristics and which joints matter
(:mod:`elastokin.studies.doe_statistics`). :func:`evaluate_sample` is a pure function of a
plain, picklable job and one sample's shifts, returning a plain dict (a failed solve is
recorded, not raised): it runs serially or on dask workers (:mod:`elastokin.studies.
doe_runner`). Sampling maps, sensitivity and outputs: docs/doe.md. Shifts mm, config frame.
"""

from __future__ import annotations

import json
import warnings
from dataclasses import dataclass

import numpy as np

from elastokin.config.loading import suspension_from_dict
from elastokin.config.suspension import Suspension
from elastokin.config.variants import DesignState
from elastokin.errors import ConfigError, ElastokinError, SolverError
from elastokin.mbs.design import build_model, design_state
from elastokin.mbs.model import NO_LOADS
from elastokin.physics.wheel import UndeterminedSlopeWarning
from elastokin.rig.characteristics import summary_figures
from elastokin.rig.drives import check_rig
from elastokin.rig.load_cases import (
    drives,
    parallel_travel_drive,
    run_drive,
    static_states,
)
from elastokin.studies.doe_sampling import (
    ClearanceJoint,
    clearance_joints,
    shift_components,
    shifts_mm,
    unit_samples,
)
from elastokin.synthetic.virtual_cmm import as_built, as_built_by_continuation

#: ``all``: every load case of the config's rig; ``travel``: parallel wheel travel only
LOAD_CASES = ("all", "travel")
#: the approach from the design position to the rebound end of the stroke is solved in steps of
#: at most this (mm) and not recorded: the model is elastic, so the stroke does not depend on
#: the path to it (the stroke's toe agrees with the K&C job's 1 mm approach to 1e-10)
APPROACH_STEP_MM = 30.0
STORE_FORMAT = 1
#: samples of one study at most (checked before anything is sampled or allocated)
MAX_SAMPLES = 1_000_000


def study_job(suspension: Suspension, design, load_cases: str = "all") -> dict:
    """Everything a worker needs to evaluate samples, as plain picklable data: the config
    mapping (resolved again on the worker), the nominal design preloads (computed once: the
    clearances do not change them, see :func:`elastokin.synthetic.virtual_cmm.as_built`) and
    the load cases."""
    if load_cases not in LOAD_CASES:
        raise ConfigError(f"--load-cases: expected one of {', '.join(LOAD_CASES)}, "
                          f"got '{load_cases}'")
    return {
        "config": suspension.raw,
        "source": str(suspension.source),
        "sha256": suspension.sha256,
        "design": {"spring_force_N": {k: float(v) for k, v in design.spring_force_N.items()},
                   "bushing_preload": {k: [float(x) for x in v]
                                       for k, v in design.bushing_preload.items()}},
        "load_cases": load_cases,
    }


_CONTEXT: dict[str, tuple] = {}  # per process: job key -> (Suspension, DesignState)


def _context(job: dict):
    key = job["sha256"] + json.dumps(job["design"], sort_keys=True)
    if key not in _CONTEXT:
        s = suspension_from_dict(job["config"], job["source"], job["sha256"])
        d = job["design"]
        design = DesignState(dict(d["spring_force_N"]),
                             {k: np.array(v, float) for k, v in d["bushing_preload"].items()})
        _CONTEXT.clear()
        _CONTEXT[key] = (s, design)
    return _CONTEXT[key]


def as_built_model(suspension: Suspension, shifts: dict[str, np.ndarray], design):
    """The compliant Exudyn model of the as-built suspension (nominal design preloads, joints
    shifted by ``shifts``, mm, config frame), built as ``elastokin synthesize`` builds it;
    the study reads no loads: none recorded."""
    return build_model(as_built(suspension, shifts, design).variant(), NO_LOADS)


def as_built_model_by_continuation(suspension: Suspension, shifts: dict[str, np.ndarray],
                                   design):
    """:func:`as_built_model`, started from its settled state, reached by continuation from
    the nominal geometry
    (:func:`~elastokin.synthetic.virtual_cmm.as_built_by_continuation`)."""
    return as_built_by_continuation(suspension, shifts, design, NO_LOADS)


def travel_sweep(model, label: str = "sample", spec=None, static=None):
    """Parallel wheel travel as the K&C job's (same stroke, same columns), the approach from
    the design position solved in steps of at most :data:`APPROACH_STEP_MM` and left out, no
    unloading: the sweep holds the stroke only (rebound to bump), as the K&C job's gradients
    use (bump camber over the measured rows: a frictionless model's return is its stroke).
    ``static``: the model's static states (:func:`~elastokin.rig.load_cases.static_states`;
    solved when not given)."""
    spec = (spec or model.suspension.rig.parallel_travel).model_copy(update={"unloading": False})
    drive = parallel_travel_drive(model.suspension, spec, APPROACH_STEP_MM,
                                  record_approach=False)
    return run_drive(model, label, drive, static=static)


def model_characteristics(model, load_cases: str = "all", label: str = "sample",
                          quiet: bool = False) -> dict:
    """The summary characteristics (summary.json names and units) of one model: steer
    amplitude, bump steer and camber from parallel travel; with ``all`` also the wheel rate and
    the lateral, longitudinal, traction and aligning-torque compliances. A characteristic not
    determined (a slope from too few rig steps) is left out; ``quiet``: without its warning
    (the samples of a study: the nominal model's says it once)."""
    static = static_states(model)  # every load case's reference, solved once
    sweeps = [travel_sweep(model, label, static=static)]
    if load_cases == "all":
        sweeps += [run_drive(model, label, d, static=static)
                   for d in drives(model.suspension)[1:]]
    with warnings.catch_warnings():
        if quiet:
            warnings.simplefilter("ignore", UndeterminedSlopeWarning)
        summary = summary_figures(sweeps, False)
    return {k: float(v) for k, v in summary.items()
            if isinstance(v, float) and not isinstance(v, bool)}


def evaluate_sample(job: dict, index: int, shifts: dict[str, list[float]]) -> dict:
    """One sample: as-built model -> K&C load cases -> characteristics. Never raises for a
    failed model or solve: the record then has ``status: failed`` and the error message.
    Shifts in mm, config frame."""
    record = {"sample": int(index), "shifts_mm": {k: [float(x) for x in v]
                                                  for k, v in shifts.items()}}
    try:
        s, design = _context(job)
        sh = {k: np.asarray(v, float) for k, v in shifts.items()}
        try:
            model = as_built_model(s, sh, design)
            values = model_characteristics(model, job["load_cases"], f"sample {index}", True)
        except SolverError:  # far from equilibrium at the design position: continuation
            model = as_built_model_by_continuation(s, sh, design)
            values = model_characteristics(model, job["load_cases"], f"sample {index}", True)
            record["solved_by"] = "continuation from the nominal geometry"
        record.update(status="ok", error=None, characteristics=values)
    except ElastokinError as exc:
        record.update(status="failed", error=str(exc), characteristics={})
    except Exception as exc:  # noqa: BLE001 - a broken sample must not stop the study
        record.update(status="failed", error=f"{type(exc).__name__}: {exc}",
                      characteristics={})
    return record


def evaluate_batch(job: dict, items: list[tuple[int, dict]]) -> list[dict]:
    """Several samples in one worker call (fewer scheduler round trips)."""
    return [evaluate_sample(job, k, sh) for k, sh in items]


@dataclass
class Study:
    """A DOE study: the config, the sampling and the per-sample inputs."""

    suspension: Suspension
    method: str
    samples: int
    seed: int
    load_cases: str
    joints: list[ClearanceJoint]
    components: np.ndarray  # (samples, d) shift components, mm, joints' own directions
    job: dict

    def shifts(self, index: int) -> dict[str, list[float]]:
        return {k: v.tolist() for k, v in shifts_mm(self.joints,
                                                    self.components[index]).items()}

    def header(self) -> dict:
        """What identifies the study in ``samples.jsonl`` (a resume must match it)."""
        return {"elastokin_doe_samples": STORE_FORMAT, "config_sha256": self.suspension.sha256,
                "method": self.method, "samples": self.samples, "seed": self.seed,
                "load_cases": self.load_cases}


def make_study(suspension: Suspension, samples: int, method: str = "lhs", seed: int = 0,
               load_cases: str = "all", design=None) -> Study:
    """Sample a study (no solving except the nominal design preloads)."""
    if samples < 1:
        raise ConfigError(f"--samples: must be at least 1, got {samples}")
    if samples > MAX_SAMPLES:
        raise ConfigError(f"--samples: {samples:,} samples; at most {MAX_SAMPLES:,} (the sample "
                          "table stays below ~100 MB, and a million as-built sweeps already "
                          "take about 5 hours on 2 cores)")
    check_rig(suspension)  # a load case given that cannot run: a warning
    joints = clearance_joints(suspension)
    d = sum(j.dimensions for j in joints)
    u = unit_samples(method, samples, d, seed)
    design = design if design is not None else design_state(suspension)
    job = study_job(suspension, design, load_cases)
    return Study(suspension, method, samples, seed, load_cases, joints,
                 shift_components(joints, u), job)


def nominal_characteristics(study: Study) -> dict:
    """The characteristics of the nominal suspension (no clearance shift), same load cases;
    raises :class:`SolverError` when its own model does not solve."""
    s, design = _context(study.job)
    model = as_built_model(s, {}, design)
    return model_characteristics(model, study.load_cases, "nominal model")


def solver_settings(study: Study) -> dict:
    """The solver settings every sample's model runs with."""
    s, design = _context(study.job)
    return as_built_model(s, {}, design).solver_settings()
