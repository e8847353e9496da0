"""How a suspension is turned into an Exudyn model (:class:`ModelOptions`; the model itself:
:mod:`elastokin.mbs.model`)."""

from __future__ import annotations

from dataclasses import dataclass

from elastokin.errors import ModelError


@dataclass(frozen=True)
class ModelOptions:
    """How a suspension is turned into an Exudyn model.

    stiffness_scale: every bushing law's load multiplied by this factor.
    user_functions: how bushing laws and input paths are evaluated: ``"symbolic"`` (Exudyn
        symbolic functions at C++ speed; linear bushings use Exudyn's own stiffness matrix) or
        ``"python"`` (Python callbacks: the straightforward, slow reference).
    part_poses: record every part's pose at every step (needed for the steering-axis
        columns); off, only the wheel part's pose is recorded (the stiffness fit).
    parametric_bushings: bushings whose laws (scale and cubic per direction, the
        :class:`~elastokin.physics.laws.ProgressiveLaw` family on the config's laws) can be
        changed after building, with :meth:`SuspensionModel.set_bushing_laws` (the stiffness
        fit and its sensitivities, :mod:`elastokin.mbs.sensitivity`).
    record_loads: record the load of every element at every step (``ModelState.loads``,
        :mod:`elastokin.mbs.loads`); needs ``part_poses``.
    discontinuous_iterations: passes of the static solver's discontinuous iteration; None:
        one for a frictionless model (no item of it acts after a Newton step: issue 28, the
        same results), Exudyn's default otherwise; 5 is the set-up before issue 28
        (``benchmarks/bench_kc.py`` times both).
    """

    stiffness_scale: float = 1.0
    user_functions: str = "symbolic"
    part_poses: bool = True
    parametric_bushings: tuple[str, ...] = ()
    record_loads: bool = True
    discontinuous_iterations: int | None = None

    @property
    def loads(self) -> bool:
        """Whether loads are recorded (:attr:`record_loads` with :attr:`part_poses`)."""
        return self.record_loads and self.part_poses

    def __post_init__(self):
        if self.user_functions not in ("symbolic", "python"):
            raise ModelError(f"ModelOptions.user_functions must be 'symbolic' or 'python', "
                             f"got '{self.user_functions}'")
        if not self.stiffness_scale > 0:
            raise ModelError(f"ModelOptions.stiffness_scale must be positive, got "
                             f"{self.stiffness_scale}")


#: the options of a model whose loads nobody reads (studies, synthetic test data)
NO_LOADS = ModelOptions(record_loads=False)
