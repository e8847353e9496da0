"""The synthetic "real suspension" of a case study and the K&C test files it writes.

The paper's test data do not exist here, so the case study's rig data are SYNTHETIC, made from
the config's ``kc_test.synthetic`` section:

1. the **as-built** suspension of the virtual CMM
   (:func:`elastokin.synthetic.virtual_cmm.as_built`, with the same seed, hence the same
   assembly-clearance shifts the CMM files were made from);
2. **bushings that differ from the config's laws** (Table 1): per bushing, a scale on the
   translational and rotational rates and a progressive (stiffening) law
   ``F = scale * k * v * (1 + (v / progression)^2)`` (k the config's rate at zero, v the
   deflection in mm or deg). Each bushing keeps the as-built design load, so the static
   equilibrium under the wheel load, which the CMM measured, is unchanged;
3. **dry friction in ball joints**: a Jenkins element per named spherical joint (breakaway
   torque, presliding rotation; :mod:`elastokin.mbs.friction`), which makes
   loading and unloading differ (hysteresis);
4. optional Gaussian rig noise on the measured channels.

None of this reaches the identification or the models: they know the config's laws only.
:func:`write_kc_test_files` runs the config's rig load cases on this suspension and writes one
K&C test CSV per load case (``docs/kc_test_data.md``), deterministic byte for byte.

Units mm, N, N*mm, deg; per-wheel signs of the test format (lateral outboard +, longitudinal
forward +, aligning torque toe-in +).
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import numpy as np

from elastokin.config.schema import RealSuspensionSpec, SyntheticSpec
from elastokin.config.suspension import Suspension
from elastokin.config.variants import (
    BallJointFriction,
    DesignState,
    ModelVariant,
    relabelled,
    with_bushing_laws,
)
from elastokin.errors import ConfigError
from elastokin.formats.kc_test_sweeps import sweep_to_test_channels
from elastokin.mbs.design import build_model
from elastokin.physics.laws import DirectionLaw
from elastokin.rig.channels import TEST_CHANNELS
from elastokin.rig.load_cases import drives, run_drive, static_equilibrium
from elastokin.rig.sweeps import Sweep
from elastokin.synthetic.virtual_cmm import as_built, clearance_shifts

#: tabulation of a progressive law: points per side, out to this many progression lengths
_TABLE_POINTS = 40
_TABLE_SPAN = 4.0


def progressive_law(rate: float, scale: float, progression: float | None) -> DirectionLaw:
    """``F = scale * rate * v * (1 + (v / progression)^2)`` as a piecewise-linear law
    (tabulated to ``_TABLE_SPAN`` progression lengths, linear beyond); ``progression``
    None gives the linear law ``scale * rate``."""
    if progression is None:
        return DirectionLaw.linear(scale * rate)
    v = np.linspace(-_TABLE_SPAN * progression, _TABLE_SPAN * progression,
                    2 * _TABLE_POINTS + 1)
    f = scale * rate * v * (1.0 + (v / progression) ** 2)
    return DirectionLaw(tuple(v.tolist()), tuple(f.tolist()))


def _spec(suspension: Suspension) -> RealSuspensionSpec:
    s = suspension
    if s.kc_test is None or s.kc_test.synthetic is None:
        raise ConfigError(f"{s.source}: no 'kc_test.synthetic' section: it describes the "
                          "synthetic real suspension whose K&C test files are written")
    if s.measurements is None:
        raise ConfigError(f"{s.source}: key 'kc_test.synthetic': the real suspension is the "
                          "as-built one of the 'measurements' section, which is missing")
    spec = s.kc_test.synthetic
    bushings = {b.name for b in s.bushings}
    for name in spec.bushings:
        if name not in bushings:
            raise ConfigError(f"{s.source}: key 'kc_test.synthetic.bushings.{name}': no "
                              f"bushing '{name}' (bushings: {', '.join(sorted(bushings))})")
    spherical = {j.name for j in s.joints if j.kind == "spherical"}
    for name, torque in spec.ball_joint_friction_Nmm.items():
        if name not in spherical:
            raise ConfigError(f"{s.source}: key 'kc_test.synthetic.ball_joint_friction_Nmm."
                              f"{name}': expected a spherical joint (spherical joints: "
                              f"{', '.join(sorted(spherical)) or 'none'})")
        if not torque > 0:
            raise ConfigError(f"{s.source}: key 'kc_test.synthetic.ball_joint_friction_Nmm."
                              f"{name}': breakaway torque must be positive (N*mm), got {torque}")
    return spec


def _seed(suspension: Suspension, seed: int | None) -> int:
    spec = _spec(suspension)
    if seed is not None:
        return seed
    if spec.seed is not None:
        return spec.seed
    return (suspension.measurements.synthetic or SyntheticSpec()).seed


def real_suspension_variant(suspension: Suspension, seed: int | None = None) -> ModelVariant:
    """The synthetic real suspension as a model variant (see the module docstring): the
    as-built suspension with the real bushing laws, the preloads that keep the as-built
    static state, ball-joint friction. ``seed`` (default ``kc_test.synthetic.seed``, else
    ``measurements.synthetic.seed``) draws the as-built clearance shifts exactly as
    ``elastokin synthesize`` does."""
    s = suspension
    spec = _spec(s)
    built = as_built(s, clearance_shifts(s, np.random.default_rng(_seed(s, seed))))
    laws = {b.name: tuple(progressive_law(law.rate_at_zero,
                                          rb.translation_scale if k < 3 else rb.rotation_scale,
                                          rb.progression_mm if k < 3 else rb.progression_deg)
                          for k, law in enumerate(b.laws))
            for b in built.suspension.bushings if (rb := spec.bushings.get(b.name))}
    real = relabelled(with_bushing_laws(built.suspension, laws),
                      f"{s.source} (synthetic real suspension)")
    # each real bushing carries, at the as-built static equilibrium (what the CMM measured),
    # the as-built bushing's load there: the same state is the real suspension's equilibrium
    design = DesignState(built.spring_force_N, built.bushing_preload)
    settled = static_equilibrium(build_model(built.suspension, design=design)).state
    as_built_laws = {b.name: b.laws for b in built.suspension.bushings}
    preload = dict(built.bushing_preload)
    for b in real.bushings:
        if b.name in spec.bushings:
            u0 = np.array([law.deflection_at(f) for law, f in
                           zip(as_built_laws[b.name], built.bushing_preload[b.name])])
            change = settled.bushing_deflection[b.name] - u0  # design -> static, geometric
            at_static = np.array([law.deflection_at(f) for law, f in
                                  zip(b.laws, settled.bushing_load[b.name])])
            preload[b.name] = np.array([law(u) for law, u in zip(b.laws, at_static - change)])
    friction = BallJointFriction(spec.ball_joint_friction_Nmm, spec.presliding_deg,
                                 spec.substeps)
    return ModelVariant("test", real, DesignState(built.spring_force_N, preload), friction)


def real_suspension_model(suspension: Suspension, seed: int | None = None):
    """The Exudyn model of the synthetic real suspension (:func:`real_suspension_variant`)."""
    return build_model(real_suspension_variant(suspension, seed))


def run_real_suspension(suspension: Suspension, seed: int | None = None,
                        progress: Callable[[str], None] = lambda msg: None) -> list[Sweep]:
    """Every load case of the config's rig on the synthetic real suspension (``progress``
    is told of each load case before it runs)."""
    model = real_suspension_model(suspension, seed)
    sweeps = []
    for drive in drives(model.suspension, None, model.suspension.kinematic):
        progress(f"synthetic real suspension: {drive.load_case}")
        sweeps.append(run_drive(model, "test", drive))
    return sweeps


def write_kc_test_files(suspension: Suspension, folder: Path | None = None,
                        sweeps: list[Sweep] | None = None, seed: int | None = None,
                        progress: Callable[[str], None] = lambda msg: None) -> list[Path]:
    """Run the real suspension on the rig and write one K&C test CSV per load case into
    ``folder`` (default: ``kc_test.folder`` beside the config). Returns the paths."""
    from elastokin.formats.kc_test import write_kc_test

    s = suspension
    spec = _spec(s)
    folder = Path(folder) if folder is not None else Path(s.source).parent / s.kc_test.folder
    folder.mkdir(parents=True, exist_ok=True)
    seed = _seed(s, seed)
    sweeps = sweeps if sweeps is not None else run_real_suspension(s, seed, progress)
    rng = np.random.default_rng([seed, 1])  # independent of the CMM noise stream
    paths = []
    for sw in sweeps:
        channels = sweep_to_test_channels(sw, s)
        rig_input = next(iter(channels))  # the rig's set point: written without noise
        for name, values in channels.items():
            if name == rig_input:
                continue
            sd = (spec.noise.angle_deg if TEST_CHANNELS[name].unit == "deg"
                  else spec.noise.length_mm)
            if sd > 0:
                channels[name] = values + rng.normal(scale=sd, size=values.size)
        notes = [
            "SYNTHETIC K&C test data: the synthetic real suspension of elastokin "
            "(as-built + progressive bushings + ball-joint friction),",
            f"written by `elastokin synthesize --config {Path(s.source).name}`, seed {seed}; "
            "see README 'Case study data'.",
            "units: mm, N, N*mm, deg; per-wheel signs (lateral outboard +, longitudinal "
            "forward +, aligning torque toe-in +)",
        ]
        paths.append(write_kc_test(folder / f"{sw.load_case}.csv", sw.load_case, channels,
                                   notes=notes))
    return paths
