"""The ``elastokin kc`` job as a chain of named steps, each a function with explicit inputs
and outputs (units mm, N, N*mm, deg; config frame):

1. ``test_data``: the config's K&C test files as sweeps (bad files fail before any solving);
2. ``geometry``: with CMM measurements, the identified geometry
   (:func:`elastokin.studies.identification.identify_geometry`); with a motion plan
   (``motion``), the joints located from the parts' motion (``motion_geometry``,
   :func:`elastokin.identification.motion.identify.identify_motion`);
3. ``model_variants``: which models run (initial, identified, identified_motion,
   initial_kinematic; a config without measurements runs under its ``label``, e.g.
   ``identified`` for the config that ``elastokin identify`` writes);
4. ``preloads``: each variant's design preloads (one solve per distinct suspension);
5. ``static``: the static equilibrium of the reported model under the design wheel load;
6. ``load_cases``: every load case of the rig on every model, and its compliance matrix;
7. ``fit``: with test data, the bushing-stiffness fit and its model ``identified_stiffness``;
8. ``compare``: every model against the test (errors, warnings).

Entry points run the chain from a config (:func:`run_kc`), from an identification result
(:func:`run_kc_from_identification`) or from built variants (:func:`run_kc_from_variants`).
The result files are written by :mod:`elastokin.report`.
"""

from __future__ import annotations

import pickle
import warnings
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from elastokin.config.loading import suspension_from_dict
from elastokin.config.measurements import hidden_stiffness
from elastokin.config.suspension import Suspension
from elastokin.config.variants import (
    DesignState,
    ModelVariant,
    compliant,
    corner,
    kinematic,
    mirrored_design,
    side_couplings,
)
from elastokin.errors import ConfigError
from elastokin.formats.cmm_parts import measurement_paths
from elastokin.formats.kc_test_sweeps import read_test_sweeps, side_sweeps
from elastokin.identification.geometric import Identification
from elastokin.identification.motion.identify import MotionIdentification
from elastokin.identification.stiffness import StiffnessFit, identify_stiffness, with_stiffness
from elastokin.mbs.design import build_model, design_state
from elastokin.mbs.model import SuspensionModel
from elastokin.physics.wheel import UndeterminedSlopeWarning
from elastokin.rig.axle_summary import axle_characteristics
from elastokin.rig.channels import LOAD_CASE_LIST, LOAD_CASES
from elastokin.rig.characteristics import spring_shares, summary_figures
from elastokin.rig.comparison import errors_by_side, travel_stroke_note
from elastokin.rig.drives import check_rig
from elastokin.rig.load_cases import (
    StaticResult,
    run_load_cases_sides,
    static_equilibrium,
    wheel_compliance,
)
from elastokin.rig.sweeps import Sweep, find_sweep
from elastokin.studies.cache import ResultCache, content_key
from elastokin.studies.identification import (
    cached_step,
    identify_geometry,
    motion_files,
    motion_geometry,
)

Progress = Callable[[str], None]


def _quiet(msg: str) -> None:
    return None


@dataclass
class ModelResult:
    """Everything the K&C run produced for one model: the config side's sweeps and, on an
    axle, the other wheel's (``other_sides``), the model's suspension (None: the test) and
    the compliance of every wheel centre (:func:`elastokin.rig.load_cases.wheel_compliance`:
    6x6 on a corner, the axle's 12x12 with the config side's wheel first; config frame; None:
    kinematic)."""

    label: str
    kinematic: bool
    sweeps: list[Sweep]
    solver: dict
    compliance: np.ndarray | None = None
    other_sides: dict[str, list[Sweep]] = field(default_factory=dict)
    suspension: Suspension | None = None  # the model's (its geometry for the 3D view)

    def sweep(self, load_case: str) -> Sweep | None:
        return find_sweep(self.sweeps, load_case)

    def summary(self) -> dict:
        """Summary figures (:func:`elastokin.rig.characteristics.summary_figures`) of the
        config side's wheel; the other wheel's under its side (an axle, or a test with both
        wheels) and on an axle the axle's (``axle``,
        :func:`elastokin.rig.axle_summary.axle_characteristics`)."""
        c, k = self.compliance, self.kinematic
        sp = None if self.suspension is None else spring_shares(self.suspension)
        out = summary_figures(self.sweeps, k, None if c is None else c[:6, :6], sp)
        sides = {side: summary_figures(sweeps, k, None if c is None else c[6:, 6:], sp)
                 for side, sweeps in self.other_sides.items()}  # the test's other wheel too
        out.update(sides)
        s = self.suspension
        if s is None or s.axle is None:
            return out
        by_side = {s.side: self.sweeps, **self.other_sides}
        out["axle"] = axle_characteristics(by_side, {s.side: out, **sides}, s, c)
        return out


@dataclass
class KCRun:
    """A K&C run: ``suspension`` is the config's; ``design`` and ``static`` belong to the model
    whose static equilibrium is reported (the identified one when there are measurements)."""

    suspension: Suspension
    design: DesignState
    static: StaticResult
    models: dict[str, ModelResult]
    identification: Identification | None = None
    errors: dict[str, dict] = field(default_factory=dict)  # model -> errors against the test
    stiffness: StiffnessFit | None = None  # bushing-stiffness identification, with test data
    # on comparing the models with the test, and the Python warnings of the run (add_warnings)
    warnings: list[str] = field(default_factory=list)
    reused: list[str] = field(default_factory=list)  # results taken from the cache
    motion: MotionIdentification | None = None  # joints from motion, with a motion plan

    def summaries(self) -> dict[str, dict]:
        """Every model's summary figures (:meth:`ModelResult.summary`); a figure not
        determined (a slope from too few points, :func:`elastokin.physics.wheel.slope`) is
        None and its warning, issued again, goes into the run's warnings (summary.json)."""
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            out = {label: m.summary() for label, m in self.models.items()}
        self.add_warnings([" ".join(str(w.message).split()) for w in caught
                           if issubclass(w.category, UndeterminedSlopeWarning)])
        for w in caught:
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
        return out

    def add_warnings(self, messages: list[str]) -> None:
        """Add warnings issued while the run was made (e.g. by ``elastokin kc``: the Python
        warnings it caught), each distinct message once; they go into summary.json."""
        self.warnings += [m for m in dict.fromkeys(messages) if m not in self.warnings]


# ------------------------------------------------------------------------------- the steps
def test_data(suspension: Suspension) -> tuple[list[Sweep], list[str]]:
    """Step ``test_data``: the config's K&C test files as sweeps, and the files read."""
    return read_test_sweeps(suspension)


def measurement_files(suspension: Suspension) -> list[Path]:
    """The CMM files the config's ``measurements`` section names (for the cache key)."""
    return list(measurement_paths(suspension).values())


def geometry(suspension: Suspension, progress: Progress = _quiet,
             cache: ResultCache | None = None) -> Identification | None:
    """Step ``geometry``: the identified geometry when the config has CMM measurements (from
    ``cache`` when the config and the CMM files are those it was computed from)."""
    if suspension.measurements is None:
        return None

    def compute() -> Identification:
        progress("identifying the geometry from CMM data")
        return identify_geometry(suspension)

    key = content_key("geometry", suspension.sha256, *measurement_files(suspension))
    return cached_step(cache, "geometry", key, compute, lambda: progress(
        "identified geometry reused (same config and CMM files)"))


def model_labels(suspension: Suspension) -> list[str]:
    """The models of a K&C run.

    With CMM ``measurements``: ``initial`` (joints from the parts measured alone) and
    ``identified`` (see :mod:`elastokin.identification.geometric`). Otherwise ``initial``
    (the config's geometry, under the config's ``label``, ``initial`` by default; kinematic
    when the config says ``kinematic: true``) and, when it is compliant and has no motion
    plan, ``initial_kinematic`` (``<label>_kinematic``: every bushing replaced by its ideal
    joint). With a motion plan (``motion``), ``identified_motion`` (joints located from the
    parts' motion, :mod:`elastokin.identification.motion`) as well.
    """
    motion = ["identified_motion"] if suspension.motion is not None else []
    if suspension.measurements is not None:
        return ["initial", "identified", *motion]
    if motion:
        return [suspension.label, *motion]
    if not suspension.kinematic and suspension.bushings:
        return [suspension.label, f"{suspension.label}_kinematic"]
    return [suspension.label]


def start_label(suspension: Suspension) -> str:
    """The model whose static state is reported and from which the stiffness fit starts:
    ``identified`` with CMM measurements, else ``identified_motion`` with a motion plan,
    else the config's own."""
    if suspension.measurements is not None:
        return "identified"
    return "identified_motion" if suspension.motion is not None else suspension.label


def select_models(suspension: Suspension, names: str | None) -> list[str]:
    """The models a run computes: ``names`` (comma-separated, e.g. ``initial,identified``)
    checked against what the config yields (:func:`model_labels`, plus
    ``identified_stiffness`` with K&C test data); None: all of them."""
    available = model_labels(suspension) + (["identified_stiffness"]
                                            if fits_stiffness(suspension) else [])
    if names is None:
        return available
    chosen = [n.strip() for n in names.split(",") if n.strip()]
    unknown = [n for n in chosen if n not in available]
    if unknown or not chosen:
        what = f"unknown model {', '.join(unknown)}" if unknown else "no model named"
        raise ConfigError(f"--models {names}: {what}; {suspension.source} yields "
                          f"{', '.join(available)}")
    if "identified_stiffness" in chosen:  # the fit starts from it
        chosen = list(dict.fromkeys([*chosen, start_label(suspension)]))
    return chosen


def model_variants(suspension: Suspension, ident: Identification | None = None,
                   motion: MotionIdentification | None = None) -> dict[str, ModelVariant]:
    """Step ``model_variants``: the models of the run (:func:`model_labels`), each the
    template with its overrides."""
    s = suspension

    def from_config(label, cfg):
        return ModelVariant(label, suspension_from_dict(cfg, f"{s.source} ({label})", s.sha256))

    if ident is not None:
        variants = {label: from_config(label, cfg)
                    for label, cfg in (("initial", ident.initial_config),
                                       ("identified", ident.identified_config))}
    else:
        labels = model_labels(s)
        variants = {labels[0]: ModelVariant(labels[0], s)}
        if len(labels) > 1 and labels[1] == f"{s.label}_kinematic":
            variants[labels[1]] = ModelVariant(labels[1], kinematic(s))
    if motion is not None:
        variants["identified_motion"] = from_config("identified_motion", motion.config)
    return variants


def preloads(variants: dict[str, ModelVariant]) -> dict[str, ModelVariant]:
    """Step ``preloads``: every variant with its design preloads (solved once per distinct
    geometry: a kinematic variant shares its template's)."""
    solved: dict[bytes, DesignState] = {}
    out = {}
    for label, v in variants.items():
        if v.preloads is not None:
            out[label] = v
            continue
        # the design state is that of the compliant suspension (mbs.design.design_state)
        key = pickle.dumps(replace(compliant(v.suspension), kinematic=False))
        if key not in solved:
            solved[key] = design_state(v.suspension)
        out[label] = replace(v, preloads=solved[key])
    return out


def static(variant: ModelVariant, model: SuspensionModel | None = None) -> StaticResult:
    """Step ``static``: the static equilibrium under the design wheel load (on ``model``,
    the variant's built model, when given)."""
    return static_equilibrium(model or build_model(variant))


def load_cases(variant: ModelVariant, progress: Progress = _quiet,
               model: SuspensionModel | None = None) -> ModelResult:
    """Step ``load_cases``: every load case of the rig on one model (``model``, the variant's
    built model, when given), and (compliant models) the compliance of every wheel centre at
    the static equilibrium."""
    progress(f"model '{variant.label}': K&C load cases")
    model = model or build_model(variant)
    s = model.suspension
    by_side = run_load_cases_sides(model, variant.label)
    return ModelResult(variant.label, variant.kinematic, by_side.pop(s.side),
                       model.solver_settings(),
                       None if variant.kinematic else wheel_compliance(model), by_side, s)


def fits_stiffness(suspension: Suspension) -> bool:
    """True when ``elastokin kc`` adds the ``identified_stiffness`` model: K&C test data,
    bushings, a compliant model and ``kc_test.stiffness_identification.enabled``."""
    s = suspension
    return (s.kc_test is not None and s.kc_test.stiffness_identification.enabled
            and bool(s.bushings) and not s.kinematic)


def fit(suspension: Suspension, start: ModelVariant, test: list[Sweep],
        detail: Progress = _quiet) -> StiffnessFit:
    """Step ``fit``: the bushing-stiffness identification of the config ``suspension`` (its
    ``kc_test.stiffness_identification``; the synthetic truth, if any, for the report only),
    starting from the model ``start`` with its preloads."""
    s = suspension
    if not fits_stiffness(s):
        raise ConfigError(f"{s.source}: stiffness identification needs a 'kc_test' section "
                          "with K&C test files, bushings, a compliant model (kinematic: false) "
                          "and kc_test.stiffness_identification.enabled: true")
    check_fit_on_corner(s)
    test = side_sweeps(test, s.side, s)  # the corner's wheel: the test's other wheel is not fitted
    check_fit_test(s, test)
    return identify_stiffness(corner(start.suspension), corner_preloads(start), test,
                              s.kc_test.stiffness_identification, detail,
                              hidden=hidden_stiffness(s))


def check_fit_on_corner(suspension: Suspension) -> None:
    """The stiffness fit runs on the config's corner (the test data are that wheel's): on an
    axle only when its sides are independent (:func:`side_couplings`)."""
    couplings = side_couplings(suspension)
    if couplings and fits_stiffness(suspension):
        raise ConfigError(
            f"{suspension.source}: key 'kc_test.stiffness_identification': the stiffness fit "
            f"runs on one corner, and this axle's sides are coupled by {', '.join(couplings)}; "
            "fit the corner (the config without its 'axle' section) and give the axle its "
            "fitted laws, or set stiffness_identification.enabled: false")


def check_fit_test(suspension: Suspension, test: list[Sweep]) -> None:
    """The stiffness fit runs the corner's load cases of the test data: the test sweeps of
    the config's wheel hold at least one (else one error naming the test folder)."""
    if any(LOAD_CASES[sw.load_case].corner for sw in test):
        return
    s = suspension
    folder = Path(s.source).parent / s.kc_test.folder
    held = ", ".join(dict.fromkeys(sw.load_case for sw in test)) or "none"
    corner_cases = ", ".join(c.name for c in LOAD_CASE_LIST if c.corner)
    raise ConfigError(
        f"{s.source}: key 'kc_test.stiffness_identification': the stiffness fit runs the "
        f"corner load cases of the test data ({corner_cases}), and the K&C test files in "
        f"{folder} hold none for the {s.side} wheel (they hold: {held}); add such a file or "
        "set stiffness_identification.enabled: false")


def corner_preloads(variant: ModelVariant) -> DesignState:
    """The design preloads of the variant's config corner (on an axle: that side's)."""
    c = corner(variant.suspension)
    p = variant.preloads
    springs, bushings = {sp.name for sp in c.springs}, {b.name for b in c.bushings}
    return DesignState({k: v for k, v in p.spring_force_N.items() if k in springs},
                       {k: v for k, v in p.bushing_preload.items() if k in bushings})


def fitted_variant(start: ModelVariant, stiffness: StiffnessFit) -> ModelVariant:
    """The model ``identified_stiffness``: the fit's own on a corner; on an axle the start's
    axle with the fitted laws and the fit's preloads on both sides (mirrored)."""
    s = start.suspension
    if s.axle is None:
        return ModelVariant("identified_stiffness", stiffness.suspension, stiffness.design)
    suffix = s.axle.suffix
    values = {**stiffness.values, **{n + suffix: v for n, v in stiffness.values.items()}}
    return ModelVariant("identified_stiffness", with_stiffness(s, values),
                        mirrored_design(stiffness.design, suffix))


def compare(models: dict[str, ModelResult], test: list[Sweep], files: list[str],
            side: str = "left") -> tuple[dict[str, ModelResult], dict[str, dict], list[str]]:
    """Step ``compare``: the test as the model ``test`` first (the config ``side``'s wheel;
    the other's, when the test has it, in its ``other_sides``), the errors of every model
    against it on every wheel the test has (:func:`~elastokin.rig.comparison.errors_by_side`)
    and the warnings (none without test data)."""
    if not test:
        return models, {}, []
    by_side: dict[str, list[Sweep]] = {}
    for sw in test:
        by_side.setdefault(sw.side or side, []).append(sw)
    mine = by_side.get(side, [])
    errors = {label: errors_by_side({side: m.sweeps, **m.other_sides}, by_side, side)
              for label, m in models.items()}
    note = travel_stroke_note({k: m.sweeps for k, m in models.items()}, mine)
    result = ModelResult("test", False, mine,
                         {"source": "K&C rig test data (kc_test)", "files": files},
                         other_sides={k: v for k, v in by_side.items() if k != side})
    return {"test": result, **models}, errors, [note] if note else []


# ------------------------------------------------------------------------------- entry points
def run_kc(suspension: Suspension, progress: Progress = _quiet,
           detail: Progress = _quiet, models: list[str] | None = None,
           cache: ResultCache | None = None) -> KCRun:
    """The whole job from a config: identification (with measurements), design preloads, the
    static equilibrium and every load case of every model; with K&C test data, the errors of
    each model and the bushing-stiffness fit (:func:`fits_stiffness`). ``models``: only these
    (:func:`select_models`). ``cache``: reuse the identification and the fit when every input
    is the one they were computed from (:mod:`elastokin.studies.cache`). ``progress`` is
    called once per stage, ``detail`` for steps within one."""
    test, files = test_data(suspension)  # bad test files fail before any solving
    check_rig(suspension)  # a case that cannot run: a warning; that cannot be built: an error
    check_fit_on_corner(suspension)
    if test and fits_stiffness(suspension) and (models is None
                                                or "identified_stiffness" in models):
        check_fit_test(suspension, side_sweeps(test, suspension.side, suspension))
    ident = geometry(suspension, progress, cache)
    motion = motion_geometry(suspension, progress, cache)
    fit_key = content_key("fit", suspension.sha256, *measurement_files(suspension),
                          *motion_files(suspension), *map(Path, files))
    run = run_kc_from_identification(suspension, ident, progress, detail, (test, files),
                                     models, None if cache is None else (cache, fit_key),
                                     motion)
    run.reused = list(cache.reused) if cache is not None else []
    return run


def run_kc_from_identification(suspension: Suspension, ident: Identification | None,
                               progress: Progress = _quiet, detail: Progress = _quiet,
                               test: tuple[list[Sweep], list[str]] | None = None,
                               models: list[str] | None = None,
                               fit_cache: tuple[ResultCache, str] | None = None,
                               motion: MotionIdentification | None = None) -> KCRun:
    """The job from an identification result (None: the config's own geometry) and the
    joints located from the motion (``motion``, with a motion plan); ``models``: only these
    (:func:`select_models`); ``fit_cache``: a cache and the fit's key."""
    test = test if test is not None else test_data(suspension)
    variants = model_variants(suspension, ident, motion)
    static_label = "identified" if ident is not None else (
        "identified_motion" if motion is not None else suspension.label)
    if models is not None:
        variants = {k: v for k, v in variants.items() if k in models}
        if static_label not in variants:
            static_label = next(iter(variants))
    fit = models is None or "identified_stiffness" in models
    run = run_kc_from_variants(suspension, variants, static_label, test, progress, detail,
                               fit, fit_cache)
    run.identification, run.motion = ident, motion
    if ident is not None:
        run.add_warnings(ident.all_warnings)  # printed by kc and kept in summary.json
    if motion is not None:
        run.add_warnings(motion.warnings)
    return run


def run_kc_from_variants(suspension: Suspension, variants: dict[str, ModelVariant],
                         static_label: str, test: tuple[list[Sweep], list[str]] = ([], []),
                         progress: Progress = _quiet, detail: Progress = _quiet,
                         fit_stiffness: bool = True,
                         fit_cache: tuple[ResultCache, str] | None = None) -> KCRun:
    """The job from model variants: ``static_label`` names the one whose static equilibrium
    is reported and from which the stiffness fit starts (``fit_stiffness``: when the config
    asks for it, :func:`fits_stiffness`). ``fit_cache``: a cache and the key of every input
    the variants come from (config, rig, CMM and test files): the fit and every model's load
    cases are reused when they were computed from the same inputs."""
    cache, key = fit_cache or (None, "")
    test_sweeps, files = test
    fit_stiffness = bool(test_sweeps) and fit_stiffness and fits_stiffness(suspension)
    models_key = content_key("models", key, static_label, *variants, fit_stiffness)
    stored = cache.get("models", models_key) if cache is not None else None
    if stored is not None:
        progress("K&C load cases of every model reused (same inputs)")
        design, static_result, models, stiffness = stored
        if stiffness is not None:  # the fit's own entry, carried over (and listed reused)
            stiffness = cache.get("stiffness_fit", key) or stiffness
            cache.put("stiffness_fit", key, stiffness)
    else:
        design, static_result, models, stiffness = _solve_models(
            suspension, variants, static_label, test_sweeps if fit_stiffness else [],
            progress, detail, fit_cache)
    if cache is not None:
        cache.put("models", models_key, (design, static_result, models, stiffness))
    models, errors, warnings = compare(models, test_sweeps, files, suspension.side)
    return KCRun(suspension, design, static_result, models, None, errors, stiffness, warnings)


def _solve_models(suspension, variants, static_label, test_sweeps, progress, detail,
                  fit_cache):
    """(design preloads of the reported model, its static equilibrium, every model's
    results, the stiffness fit or None): the steps ``preloads``, ``static``, ``load_cases``
    and (with test sweeps) ``fit``."""
    variants = preloads(variants)
    models, static_result = {}, None
    for label, v in variants.items():
        progress(f"model '{label}': building")
        model = build_model(v)
        if label == static_label:
            progress("static equilibrium")
            static_result = static(v, model)
        models[label] = load_cases(v, progress, model)
    stiffness = None
    if test_sweeps:
        cache, key = fit_cache or (None, "")
        stiffness = cache.get("stiffness_fit", key) if cache is not None else None
        if stiffness is None:
            progress("identifying bushing stiffness from the K&C test data")
            stiffness = fit(suspension, variants[static_label], test_sweeps, detail)
        else:
            progress("bushing stiffness fit reused (same config, CMM and test files)")
        if cache is not None:
            cache.put("stiffness_fit", key, stiffness)
        models["identified_stiffness"] = load_cases(
            fitted_variant(variants[static_label], stiffness), progress)
    return variants[static_label].preloads, static_result, models, stiffness
