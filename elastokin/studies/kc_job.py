"""The ``elastokin kc`` job: which models are built from a config and which load cases run on
them. Exudyn stays behind :mod:`elastokin.model`; this module only sequences the work."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

from elastokin.config.loading import suspension_from_dict
from elastokin.config.measurements import hidden_stiffness
from elastokin.config.suspension import Suspension
from elastokin.errors import ConfigError
from elastokin.identification.geometric import Identification, identify
from elastokin.identification.stiffness import StiffnessFit, identify_stiffness, stiffness_model
from elastokin.mbs.model import (
    DesignState,
    ModelOptions,
    SuspensionModel,
    build_model,
    design_state,
)
from elastokin.rig.load_cases import (
    ModelResult,
    StaticResult,
    compliance_matrix,
    run_load_cases,
    static_equilibrium,
)
from elastokin.studies.comparison import model_errors, read_test_sweeps, travel_stroke_note


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
    warnings: list[str] = field(default_factory=list)  # on comparing the models with the test


def model_labels(suspension: Suspension) -> list[str]:
    """The models of a K&C run.

    With CMM ``measurements``: ``initial`` (joints from the parts measured alone) and
    ``identified`` (see :mod:`elastokin.identify`). Otherwise ``initial`` (the config's
    geometry; kinematic when the config says ``kinematic: true``) and, when it is compliant,
    ``initial_kinematic`` (every bushing replaced by its ideal joint) for comparison.
    """
    if suspension.measurements is not None:
        return ["initial", "identified"]
    if not suspension.kinematic and suspension.bushings:
        return ["initial", "initial_kinematic"]
    return ["initial"]


def fits_stiffness(suspension: Suspension) -> bool:
    """True when ``elastokin kc`` adds the ``identified_stiffness`` model: K&C test data,
    bushings, a compliant model and ``kc_test.stiffness_identification.enabled``."""
    s = suspension
    return (s.kc_test is not None and s.kc_test.stiffness_identification.enabled
            and bool(s.bushings) and not s.kinematic)


def fit_stiffness(suspension: Suspension, start: Suspension, design: DesignState,
                  test: list, detail: Callable[[str], None] = lambda msg: None) -> StiffnessFit:
    """The bushing-stiffness identification of the config ``suspension`` (its
    ``kc_test.stiffness_identification``; the synthetic truth, if any, for the report only),
    starting from the model ``start`` with the preloads of ``design``."""
    s = suspension
    if not fits_stiffness(s):
        raise ConfigError(f"{s.source}: stiffness identification needs a 'kc_test' section "
                          "with K&C test files, bushings, a compliant model (kinematic: false) "
                          "and kc_test.stiffness_identification.enabled: true")
    return identify_stiffness(start, design, test, s.kc_test.stiffness_identification, detail,
                              hidden=hidden_stiffness(s))


def run_vertical_kc(suspension: Suspension,
                    progress: Callable[[str], None] = lambda msg: None,
                    detail: Callable[[str], None] = lambda msg: None) -> KCRun:
    """Identification (with measurements), design preloads, the static equilibrium and every
    load case of every model; with K&C test data, the errors of each model and (see
    :func:`fits_stiffness`) the bushing-stiffness identification, whose model
    ``identified_stiffness`` starts from the static model (identified, else initial).
    ``progress`` is called once per stage, ``detail`` for steps within one."""
    s = suspension
    ident = None
    test_sweeps, test_files = read_test_sweeps(s)  # bad test files fail before any solving
    if s.measurements is not None:
        progress("identifying the geometry from CMM data")
        ident = identify(s)
        variants = {
            label: (suspension_from_dict(cfg, f"{s.source} ({label})", s.sha256),
                    ModelOptions(kinematic=s.kinematic))
            for label, cfg in (("initial", ident.initial_config),
                               ("identified", ident.identified_config))}
        static_label = "identified"
    else:
        variants = {"initial": (s, ModelOptions(kinematic=s.kinematic))}
        if "initial_kinematic" in model_labels(s):
            variants["initial_kinematic"] = (s, ModelOptions(kinematic=True))
        static_label = "initial"
    designs: dict[int, DesignState] = {}
    static = design = None
    models = {}

    def run_model(label: str, model: SuspensionModel, kinematic: bool) -> None:
        progress(f"model '{label}': K&C load cases")
        sweeps = run_load_cases(model, label)
        compliance = None if kinematic else compliance_matrix(model)
        models[label] = ModelResult(label, kinematic, sweeps, model.solver_settings(),
                                    compliance)

    for label, (susp, options) in variants.items():
        progress(f"model '{label}': building")
        if id(susp) not in designs:
            designs[id(susp)] = design_state(susp)
        model = build_model(susp, options, designs[id(susp)])
        if label == static_label:
            progress("static equilibrium")
            static, design = static_equilibrium(model), designs[id(susp)]
        run_model(label, model, options.kinematic)
    fit = None
    if test_sweeps and fits_stiffness(s):
        progress("identifying bushing stiffness from the K&C test data")
        fit = fit_stiffness(s, variants[static_label][0], design, test_sweeps, detail)
        run_model("identified_stiffness", stiffness_model(fit.suspension, design), False)
    errors, warnings = {}, []
    if test_sweeps:
        test = ModelResult("test", False, test_sweeps,
                           {"source": "K&C rig test data (kc_test)", "files": test_files})
        errors = {label: model_errors(m.sweeps, test_sweeps) for label, m in models.items()}
        note = travel_stroke_note({k: m.sweeps for k, m in models.items()}, test_sweeps)
        warnings += [note] if note else []
        models = {"test": test, **models}
    return KCRun(s, design, static, models, ident, errors, fit, warnings)
