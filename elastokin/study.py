"""The ``elastokin kc`` job: which models are built from a config and which load cases run on
them. Exudyn stays behind :mod:`elastokin.model`; this module only sequences the work."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

from .comparison import model_errors, read_test_sweeps
from .config import Suspension, suspension_from_dict
from .identify import Identification, identify
from .kc import (
    ModelResult,
    StaticResult,
    compliance_matrix,
    run_load_cases,
    static_equilibrium,
)
from .model import DesignState, ModelOptions, build_model, design_state


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


def run_vertical_kc(suspension: Suspension,
                    progress: Callable[[str], None] = lambda msg: None) -> KCRun:
    """Identification (with measurements), design preloads, the static equilibrium and the
    parallel-travel sweep of every model."""
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
    for label, (susp, options) in variants.items():
        progress(f"model '{label}': building")
        if id(susp) not in designs:
            designs[id(susp)] = design_state(susp)
        model = build_model(susp, options, designs[id(susp)])
        if label == static_label:
            progress("static equilibrium")
            static, design = static_equilibrium(model), designs[id(susp)]
        progress(f"model '{label}': K&C load cases")
        sweeps = run_load_cases(model, label)
        compliance = None if options.kinematic else compliance_matrix(model)
        models[label] = ModelResult(label, options.kinematic, sweeps, model.solver_settings(),
                                    compliance)
    errors = {}
    if test_sweeps:
        test = ModelResult("test", False, test_sweeps,
                           {"source": "K&C rig test data (kc_test)", "files": test_files})
        errors = {label: model_errors(m.sweeps, test_sweeps) for label, m in models.items()}
        models = {"test": test, **models}
    return KCRun(s, design, static, models, ident, errors)
