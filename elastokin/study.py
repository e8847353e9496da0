"""The ``elastokin kc`` job: which models are built from a config and which load cases run on
them. Exudyn stays behind :mod:`elastokin.model`; this module only sequences the work."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from .config import Suspension
from .kc import ModelResult, StaticResult, parallel_travel, static_equilibrium
from .model import DesignState, ModelOptions, build_model, design_state


@dataclass
class KCRun:
    suspension: Suspension
    design: DesignState
    static: StaticResult
    models: dict[str, ModelResult]


def model_variants(suspension: Suspension) -> dict[str, ModelOptions]:
    """The models of a vertical K&C run: ``initial`` (from the config's geometry; kinematic
    when the config says ``kinematic: true``) and, for comparison, ``initial_kinematic``
    (every bushing replaced by its ideal joint) when the initial model is compliant."""
    variants = {"initial": ModelOptions(kinematic=suspension.kinematic)}
    if not suspension.kinematic and suspension.bushings:
        variants["initial_kinematic"] = ModelOptions(kinematic=True)
    return variants


def run_vertical_kc(suspension: Suspension,
                    progress: Callable[[str], None] = lambda msg: None) -> KCRun:
    """Design preloads, the static equilibrium and the parallel-travel sweep of every model."""
    progress("balancing the design position")
    design = design_state(suspension)
    static = None
    models = {}
    for label, options in model_variants(suspension).items():
        progress(f"model '{label}': building")
        model = build_model(suspension, options, design)
        if label == "initial":
            progress("static equilibrium")
            static = static_equilibrium(model)
        progress(f"model '{label}': parallel travel")
        sweep = parallel_travel(model, label)
        models[label] = ModelResult(label, options.kinematic, [sweep], model.solver_settings())
    return KCRun(suspension, design, static, models)
