"""Tolerance and DOE studies: how assembly clearance spreads the K&C characteristics.

A study samples the assembly-clearance shifts of every joint that the config's
``measurements.joints`` gives a clearance (each within its dL_max [1]), builds the as-built
suspension of each sample (:func:`elastokin.synthesize.as_built`: the nominal design preloads,
joints shifted), runs the K&C load cases on it and reports the distributions of the summary
characteristics and which joints matter.

Sampling (mm, deg; frames named per joint). A sample is a point ``u`` of the unit cube
[0, 1)^d drawn by Latin hypercube (``lhs``), scrambled Sobol sequence (``sobol``) or plain Monte
Carlo (``mc``), from ``seed`` alone; each joint takes the next 2 (bushing) or 3 (other joint)
coordinates of ``u`` and maps them uniformly onto its clearance region of radius R = dL_max:

- bushing (inner sleeve bolted through a hole): the disc normal to the housing axis,
  r = R sqrt(u1), phi = 2 pi u2, shift = r (cos phi x_b + sin phi y_b) with x_b, y_b the
  bushing frame's radial axes (``Bushing.frame[:, 0:2]``, config frame);
- other joint (bolted ball joint): the ball, r = R u1^(1/3), cos(theta) = 1 - 2 u2,
  phi = 2 pi u3, shift = r (sin theta cos phi, sin theta sin phi, cos theta) in the joint's
  frame (``Joint.frame``; the config frame for a spherical joint).

Both maps are uniform in area / volume. The study's regression inputs are the shift components
in those directions (``J1.x``, ``J1.y``; ``J8.x``, ``J8.y``, ``J8.z``).

Sensitivity (see :func:`joint_sensitivity`): standardised regression coefficients (SRC) of a
characteristic on the shift components; a joint's figure is the sum of the squared SRCs of its
components, i.e. its share of the characteristic's variance explained linearly.

Execution: :func:`evaluate_sample` is a pure function of a plain, picklable job description and
one sample's shifts, returning a plain dict (a failed solve is recorded, not raised). It runs
serially or on ``dask.distributed`` workers (each worker process resolves the config and builds
its own Exudyn models). Every finished sample is appended to ``samples.jsonl``; a rerun of the
same study skips the samples already there.
"""

from __future__ import annotations

import json
import math
import warnings
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from elastokin.config.loading import suspension_from_dict
from elastokin.config.suspension import Suspension
from elastokin.errors import ConfigError, ElastokinError

METHODS = ("lhs", "sobol", "mc")
#: ``all``: every load case of the config's rig; ``travel``: parallel wheel travel only
LOAD_CASES = ("all", "travel")
#: the approach from the design position to the rebound end of the stroke is solved in steps of
#: at most this (mm) and not recorded: the model is elastic, so the stroke does not depend on
#: the path to it (the stroke's toe agrees with ``kc.parallel_travel``'s 1 mm approach to 1e-10)
APPROACH_STEP_MM = 30.0
STORE = "samples.jsonl"
STORE_FORMAT = 1
#: statistics reported for every characteristic
STATISTICS = ("mean", "std", "p05", "p95", "min", "max")


# ---------------------------------------------------------------------------- sampling
@dataclass(frozen=True)
class ClearanceJoint:
    """One joint with assembly clearance: its clearance region and the directions (unit
    vectors, config frame, columns) in which its shift components are counted."""

    name: str
    kind: str  # "disc" (bushing inner sleeve) or "ball" (bolted joint)
    max_shift_mm: float
    axes: np.ndarray  # (3, 2) disc or (3, 3) ball

    @property
    def dimensions(self) -> int:
        return self.axes.shape[1]

    @property
    def components(self) -> list[str]:
        return [f"{self.name}.{c}" for c in "xyz"[:self.dimensions]]


def clearance_joints(suspension: Suspension) -> list[ClearanceJoint]:
    """The joints a study varies, in the order of ``measurements.joints``. Raises
    :class:`ConfigError` when the config gives no clearance."""
    s = suspension
    m = s.measurements
    if m is None:
        raise ConfigError(f"{s.source}: no 'measurements' section: a DOE study samples the "
                          "clearances of 'measurements.joints.<name>.clearance'")
    bushings = {b.name: b for b in s.bushings}
    joints = {j.name: j for j in s.joints}
    out = []
    for name, jm in m.joints.items():
        if jm.clearance is None:
            continue
        radius = float(jm.clearance.max_shift_mm)
        if name in bushings:
            out.append(ClearanceJoint(name, "disc", radius, bushings[name].frame[:, :2].copy()))
        elif name in joints:
            if jm.bolted is None:
                raise ConfigError(f"{s.source}: key 'measurements.joints.{name}': a clearance "
                                  "needs 'bolted: <part>' (the side with the hole)")
            out.append(ClearanceJoint(name, "ball", radius, joints[name].frame.copy()))
        else:
            raise ConfigError(f"{s.source}: key 'measurements.joints.{name}': no bushing or "
                              "joint of that name")
    if not out:
        raise ConfigError(f"{s.source}: key 'measurements.joints': no joint has a "
                          "'clearance': nothing for a DOE study to sample")
    return out


def unit_samples(method: str, samples: int, dimensions: int, seed: int) -> np.ndarray:
    """(samples, dimensions) points of [0, 1)^d: Latin hypercube, scrambled Sobol or Monte
    Carlo, a function of (method, samples, dimensions, seed) only. Sobol points are balanced
    when ``samples`` is a power of 2."""
    from scipy.stats import qmc

    if method not in METHODS:
        raise ConfigError(f"--method: expected one of {', '.join(METHODS)}, got '{method}'")
    if method == "mc":
        return np.random.default_rng(seed).random((samples, dimensions))
    cls = qmc.LatinHypercube if method == "lhs" else qmc.Sobol
    try:
        engine = cls(dimensions, rng=seed)
    except TypeError:  # scipy < 1.15
        engine = cls(dimensions, seed=seed)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)  # Sobol: n not a power of 2
        return engine.random(samples)


def disc_components(u: np.ndarray, radius: float) -> np.ndarray:
    """Unit-square points (..., 2) -> points (..., 2) uniform over the disc of ``radius``:
    r = R sqrt(u1), phi = 2 pi u2."""
    u = np.asarray(u, float)
    r = radius * np.sqrt(u[..., 0])
    phi = 2.0 * np.pi * u[..., 1]
    return np.stack([r * np.cos(phi), r * np.sin(phi)], axis=-1)


def ball_components(u: np.ndarray, radius: float) -> np.ndarray:
    """Unit-cube points (..., 3) -> points (..., 3) uniform over the ball of ``radius``:
    r = R u1^(1/3), cos(theta) = 1 - 2 u2, phi = 2 pi u3."""
    u = np.asarray(u, float)
    r = radius * np.cbrt(u[..., 0])
    cos_t = 1.0 - 2.0 * u[..., 1]
    sin_t = np.sqrt(np.clip(1.0 - cos_t**2, 0.0, None))
    phi = 2.0 * np.pi * u[..., 2]
    return np.stack([r * sin_t * np.cos(phi), r * sin_t * np.sin(phi), r * cos_t], axis=-1)


def shift_components(joints: list[ClearanceJoint], u: np.ndarray) -> np.ndarray:
    """Unit-cube samples (n, d) -> shift components (n, d), mm, each joint's in its own
    directions (``ClearanceJoint.axes``), joints in order."""
    u = np.atleast_2d(np.asarray(u, float))
    cols, k = [], 0
    for j in joints:
        part = u[:, k:k + j.dimensions]
        cols.append(disc_components(part, j.max_shift_mm) if j.kind == "disc"
                    else ball_components(part, j.max_shift_mm))
        k += j.dimensions
    if k != u.shape[1]:
        raise ValueError(f"unit samples have {u.shape[1]} coordinates, the joints need {k}")
    return np.hstack(cols)


def shifts_mm(joints: list[ClearanceJoint], components: np.ndarray) -> dict[str, np.ndarray]:
    """One sample's shift components (d,) -> shift vector (3,) per joint, mm, config frame."""
    out, k = {}, 0
    for j in joints:
        out[j.name] = j.axes @ np.asarray(components[k:k + j.dimensions], float)
        k += j.dimensions
    return out


# ---------------------------------------------------------------------------- evaluation
def study_job(suspension: Suspension, design, load_cases: str = "all") -> dict:
    """Everything a worker needs to evaluate samples, as plain picklable data: the config
    mapping (resolved again on the worker), the nominal design preloads (computed once: the
    clearances do not change them, see :func:`elastokin.synthesize.as_built`) and the load
    cases."""
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
    from elastokin.mbs.model import DesignState

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
    shifted by ``shifts``, mm, config frame), built as ``elastokin synthesize`` builds it."""
    from elastokin.mbs.model import ModelOptions, SuspensionModel
    from elastokin.synthetic.virtual_cmm import as_built

    ab = as_built(suspension, shifts, design)
    return SuspensionModel(ab.suspension, ModelOptions(), bushing_preload=ab.bushing_preload,
                           spring_force_N=ab.spring_force_N)


def travel_sweep(model, label: str = "sample", spec=None):
    """Parallel wheel travel as ``kc.parallel_travel`` (same stroke, same columns), the
    approach from the design position solved in steps of at most :data:`APPROACH_STEP_MM` and
    left out: the sweep holds the stroke only (rebound to bump), so a gradient over the whole
    sweep (bump camber) is fitted over the stroke."""
    from elastokin.rig.load_cases import Sweep, _leg, characteristics

    s = model.suspension
    spec = spec or s.rig.parallel_travel
    approach = _leg(0.0, spec.rebound_mm, APPROACH_STEP_MM)
    stroke = _leg(spec.rebound_mm, spec.bump_mm, spec.step_mm)
    z = np.r_[approach, stroke]
    states = model.run(pad_z_mm=z, what=f"{label}, parallel travel")[approach.size - 1:]
    cols = {"branch": np.array(["stroke"] * len(states)), "pad_z_mm": z[approach.size - 1:]}
    cols.update(characteristics(states, s))
    return Sweep(label, "parallel_travel", cols)


def model_characteristics(model, load_cases: str = "all", label: str = "sample") -> dict:
    """The summary characteristics (``kc.ModelResult.summary`` names and units) of one model:
    steer amplitude, bump steer and camber from parallel travel; with ``all`` also the wheel
    rate and the lateral, longitudinal, traction and aligning-torque compliances."""
    from elastokin.rig.load_cases import FORCE_CASES, ModelResult, force_sweep, vertical_force

    rig = model.suspension.rig
    sweeps = [travel_sweep(model, label)]
    if load_cases == "all":
        if rig.vertical_force is not None:
            sweeps.append(vertical_force(model, label))
        sweeps += [force_sweep(model, label, case) for case in FORCE_CASES
                   if getattr(rig, case) is not None]
    summary = ModelResult(label, False, sweeps, {}).summary()
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
        model = as_built_model(s, {k: np.asarray(v, float) for k, v in shifts.items()}, design)
        values = model_characteristics(model, job["load_cases"], f"sample {index}")
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


# ---------------------------------------------------------------------------- the study
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
    from elastokin.mbs.model import design_state

    if samples < 1:
        raise ConfigError(f"--samples: must be at least 1, got {samples}")
    joints = clearance_joints(suspension)
    d = sum(j.dimensions for j in joints)
    u = unit_samples(method, samples, d, seed)
    design = design if design is not None else design_state(suspension)
    job = study_job(suspension, design, load_cases)
    return Study(suspension, method, samples, seed, load_cases, joints,
                 shift_components(joints, u), job)


class SampleStore:
    """``samples.jsonl``: a header line identifying the study, then one JSON record per
    finished sample, in the order they finished. Appending is flushed per record, so an
    interrupted study keeps what it finished; a torn last line is dropped on reading. A new
    (or ``restart``) store is written with its first record."""

    def __init__(self, path: Path, header: dict, restart: bool = False):
        self.path = Path(path)
        self.header = header
        self.records: dict[int, dict] = {}
        self.dropped_partial = False
        self._fresh = restart or not self.path.exists()  # header written with the 1st record
        if not self._fresh:
            self._read()

    def _read(self) -> None:
        lines = self.path.read_text().split("\n")
        try:
            found = json.loads(lines[0])
        except json.JSONDecodeError:
            found = None
        if found != self.header:
            def show(v):
                return f"{v[:12]}..." if isinstance(v, str) and len(v) == 64 else repr(v)

            diff = "unreadable header" if not isinstance(found, dict) else ", ".join(
                f"{k} {show(found.get(k))} (now {show(v)})" for k, v in self.header.items()
                if found.get(k) != v)
            raise ElastokinError(f"{self.path}: holds samples of another study ({diff}); use "
                                 "another --out, or --restart to discard them")
        good = [lines[0]]
        for line in lines[1:]:
            if not line.strip():
                continue
            try:
                rec = json.loads(line)
                k = int(rec["sample"])
            except (json.JSONDecodeError, KeyError, TypeError, ValueError):
                self.dropped_partial = True  # torn write of an interrupted run
                continue
            if 0 <= k < self.header["samples"] and k not in self.records:
                self.records[k] = rec
                good.append(line)
        if self.dropped_partial:
            self.path.write_text("\n".join(good) + "\n")

    def add(self, record: dict) -> None:
        self.records[record["sample"]] = record
        if self._fresh:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            self.path.write_text(json.dumps(self.header, sort_keys=True) + "\n")
            self._fresh = False
        with open(self.path, "a") as fh:
            fh.write(json.dumps(record, sort_keys=True) + "\n")
            fh.flush()

    def ordered(self) -> list[dict]:
        """Records in sample order, as read back from JSON (bit-identical floats)."""
        return [json.loads(json.dumps(self.records[k], sort_keys=True))
                for k in sorted(self.records)]


def run_serial(job: dict, items: Iterable[tuple[int, dict]],
               on_record: Callable[[dict], None]) -> None:
    """Evaluate samples one after the other in this process."""
    for k, sh in items:
        on_record(evaluate_sample(job, k, sh))


def run_dask(client, job: dict, items: list[tuple[int, dict]],
             on_record: Callable[[dict], None], batch: int = 1) -> None:
    """Evaluate samples on a ``dask.distributed`` client, ``batch`` samples per task; records
    arrive as tasks finish. A task lost by dask (e.g. a worker that died) is recorded as
    failed for each of its samples."""
    from distributed import as_completed

    if not items:
        return
    [job_future] = client.scatter([job], broadcast=True, hash=False)
    chunks = [items[i:i + batch] for i in range(0, len(items), batch)]
    futures = {client.submit(evaluate_batch, job_future, chunk, pure=False): chunk
               for chunk in chunks}
    try:
        for fut in as_completed(futures):
            try:
                records = fut.result()
            except Exception as exc:  # noqa: BLE001 - lost on the cluster, not a solve
                records = [{"sample": k, "shifts_mm": sh, "status": "failed",
                            "error": f"dask: {type(exc).__name__}: {exc}",
                            "characteristics": {}} for k, sh in futures[fut]]
            for rec in records:
                on_record(rec)
    finally:
        client.cancel(list(futures))


def batch_size(pending: int, workers: int) -> int:
    """Samples per dask task: about 8 tasks per worker, at most 4 samples each (a task of a
    few samples amortises the scheduler's round trip; benchmarks/bench_doe.py)."""
    return max(1, min(4, pending // (8 * max(1, workers))))


def run_study(study: Study, store: SampleStore, client=None, limit: int | None = None,
              progress: Callable[[int], None] = lambda n: None, batch: int = 1) -> int:
    """Evaluate the samples not yet in ``store`` (at most ``limit`` of them, lowest index
    first), serially or on a dask ``client``; returns how many were evaluated."""
    pending = [k for k in range(study.samples) if k not in store.records]
    if limit is not None:
        pending = pending[:limit]
    items = [(k, study.shifts(k)) for k in pending]

    def on_record(rec: dict) -> None:
        store.add(rec)
        progress(1)

    if client is None:
        run_serial(study.job, items, on_record)
    else:
        run_dask(client, study.job, items, on_record, batch)
    return len(items)


# ---------------------------------------------------------------------------- aggregation
def statistics(values: Iterable[float]) -> dict[str, float | None]:
    """mean, sample standard deviation (ddof 1), 5th / 95th percentile (linear
    interpolation), min, max and count of the finite values; None where undefined."""
    x = np.array([v for v in values if v is not None and math.isfinite(v)], float)
    if x.size == 0:
        return {k: None for k in STATISTICS} | {"n": 0}
    return {"mean": float(np.mean(x)),
            "std": float(np.std(x, ddof=1)) if x.size > 1 else None,
            "p05": float(np.percentile(x, 5)), "p95": float(np.percentile(x, 95)),
            "min": float(np.min(x)), "max": float(np.max(x)), "n": int(x.size)}


def standardised_regression(X: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, float]:
    """Standardised regression coefficients of y (n,) on the columns of X (n, p) by least
    squares with an intercept: SRC_i = b_i std(x_i) / std(y); and the R^2 of the fit. Needs
    n >= p + 2. A constant y gives zeros and R^2 = 0."""
    X = np.asarray(X, float)
    y = np.asarray(y, float)
    n, p = X.shape
    if n < p + 2:
        raise ValueError(f"{n} samples cannot fit {p} inputs (need at least {p + 2})")
    sx, sy = X.std(axis=0, ddof=1), y.std(ddof=1)
    if not sy > 0:
        return np.zeros(p), 0.0
    A = np.c_[np.ones(n), X - X.mean(axis=0)]
    coef, *_ = np.linalg.lstsq(A, y, rcond=None)
    resid = y - A @ coef
    r2 = 1.0 - float(resid @ resid) / float(((y - y.mean()) ** 2).sum())
    return coef[1:] * sx / sy, r2


def joint_sensitivity(X: np.ndarray, y: np.ndarray, groups: list[str]) -> dict:
    """Each joint's share of the variance of y explained linearly by its shift components.

    ``groups[i]`` names the joint of column i of X (n, p). With n >= p + 2 samples, one
    multiple regression on every component (``method: src``): a joint's figure is the sum of
    the squared SRCs of its components. With fewer samples, one regression per joint on its
    own components (``method: src_per_joint``): the figure is that regression's R^2 (the same
    quantity when the inputs are independent, noisier). Joints whose figure cannot be
    estimated (too few samples) get None.
    """
    X = np.asarray(X, float)
    y = np.asarray(y, float)
    names = list(dict.fromkeys(groups))
    cols = {j: [i for i, g in enumerate(groups) if g == j] for j in names}
    n, p = X.shape
    if n >= p + 2:
        src, r2 = standardised_regression(X, y)
        joints = {j: float(np.sum(src[cols[j]] ** 2)) for j in names}
        return {"method": "src", "r2": r2, "joints": joints,
                "src": [float(v) for v in src]}
    joints = {}
    for j in names:
        if n >= len(cols[j]) + 2:
            _, r2j = standardised_regression(X[:, cols[j]], y)
            joints[j] = float(r2j)
        else:
            joints[j] = None
    return {"method": "src_per_joint", "r2": None, "joints": joints, "src": None}


def _clean(x):
    """JSON-safe: numpy scalars to Python, NaN/inf to None."""
    if isinstance(x, dict):
        return {k: _clean(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_clean(v) for v in x]
    if isinstance(x, (np.floating, float)):
        return float(x) if math.isfinite(x) else None
    if isinstance(x, np.integer):
        return int(x)
    return x


def aggregate(study: Study, records: list[dict], nominal: dict | None = None) -> dict:
    """The study's results (the body of ``doe.json`` without provenance): counts, the
    distribution of every characteristic over the samples that solved, the sensitivity of
    each to each joint, and the failures. ``records`` in sample order."""
    ok = [r for r in records if r["status"] == "ok"]
    found = {k for r in ok for k in r["characteristics"]}
    names = [k for k in (nominal or {}) if k in found] + sorted(found - set(nominal or {}))
    idx = [r["sample"] for r in ok]
    X = study.components[idx] if idx else np.zeros((0, study.components.shape[1]))
    groups = [j.name for j in study.joints for _ in range(j.dimensions)]
    dists, sens = {}, {}
    for name in names:
        y = np.array([r["characteristics"].get(name, np.nan) for r in ok], float)
        dists[name] = statistics(y)
        good = np.isfinite(y)
        sens[name] = joint_sensitivity(X[good], y[good], groups) if good.sum() > 0 else {
            "method": None, "r2": None, "joints": {j.name: None for j in study.joints},
            "src": None}
    steer = dists.get("steer_amplitude_deg", statistics([]))
    steer_sens = sens.get("steer_amplitude_deg", {"joints": {j.name: None
                                                             for j in study.joints}})
    out = {
        "samples": study.samples,
        "completed": len(records),
        "failed": len(records) - len(ok),
        "seed": study.seed,
        "method": study.method,
        "load_cases": study.load_cases,
        "steer_amplitude_deg": steer,
        "sensitivity": steer_sens["joints"],
        "sensitivity_method": steer_sens.get("method"),
        "sensitivity_r2": steer_sens.get("r2"),
        "characteristics": dists,
        "sensitivity_by_characteristic": {k: {"joints": v["joints"], "method": v["method"],
                                              "r2": v["r2"]} for k, v in sens.items()},
        "src_components": {"inputs": [c for j in study.joints for c in j.components],
                           **{k: v["src"] for k, v in sens.items()}},
        "nominal": nominal,
        "clearances": {j.name: {"region": j.kind, "max_shift_mm": j.max_shift_mm,
                                "axes": j.axes.T.tolist()} for j in study.joints},
        "failures": [{"sample": r["sample"], "error": r["error"]} for r in records
                     if r["status"] != "ok"],
    }
    return _clean(out)


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
