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

On an axle the real suspension is an axle (:func:`real_axle_variant`): the config side's corner
as built exactly as above, the other corner its mirror image with its **own** clearance shifts:
the mirror images of shifts drawn for the config side's joints, as the CMM's are, from the
independent stream ``default_rng([seed, 2])`` (the CMM uses ``seed``, the rig noise
``[seed, 1]`` for the config side and the per-axle channels, ``[seed, 3]`` for the other
wheel), the same real bushing laws (mirrored) and friction. Every load case of the rig runs on
both wheels and each file holds both. The sides must be independent (no shared part,
anti-roll bar or steering rack; ``config.variants.side_couplings``) and mirrored (no
``axle.other_side``): the corner cases' config-side data then come from the corner alone,
exactly as for a corner config (the axle's own run differs from it by the solver's tolerance
only, up to 1.2e-4 mm on the case study), the other wheel's and the axle cases' from the
axle.

Units mm, N, N*mm, deg; per-wheel signs of the test format (lateral outboard +, longitudinal
forward +, aligning torque toe-in +).
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import numpy as np

from elastokin.config.axle import MIRROR, mirrored_laws, other_side
from elastokin.config.confined import data_file, data_folder
from elastokin.config.schema.suspension import RealSuspensionSpec, SyntheticSpec
from elastokin.config.suspension import Suspension
from elastokin.config.variants import (
    BallJointFriction,
    DesignState,
    ModelVariant,
    corner,
    mirrored_design,
    relabelled,
    side_couplings,
    with_bushing_laws,
    with_joint_shifts,
)
from elastokin.errors import ConfigError
from elastokin.formats.kc_test_channels import column_side, input_columns
from elastokin.formats.kc_test_sweeps import axle_test_channels, sweep_to_test_channels
from elastokin.mbs.design import build_model
from elastokin.mbs.model import NO_LOADS
from elastokin.physics.laws import DirectionLaw
from elastokin.rig.channels import LOAD_CASES, TEST_CHANNELS
from elastokin.rig.load_cases import (
    drives,
    run_drive_sides,
    static_equilibrium,
    static_states,
)
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
    """The synthetic real suspension of the config's corner as a model variant (see the
    module docstring): the as-built suspension with the real bushing laws, the preloads that
    keep the as-built static state, ball-joint friction. ``seed`` (default
    ``kc_test.synthetic.seed``, else ``measurements.synthetic.seed``) draws the as-built
    clearance shifts exactly as ``elastokin synthesize`` does."""
    s = suspension
    return real_corner(s, clearance_shifts(s, np.random.default_rng(_seed(s, seed))))


def real_corner(suspension: Suspension, shifts: dict[str, np.ndarray]) -> ModelVariant:
    """The config corner's synthetic real suspension with the given clearance shifts (mm,
    config frame, by joint: :func:`~elastokin.synthetic.virtual_cmm.clearance_shifts`)."""
    s = suspension
    spec = _spec(s)
    built = as_built(s, shifts)
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
    """The Exudyn model of the config corner's synthetic real suspension
    (:func:`real_suspension_variant`); no loads recorded (the test files have none)."""
    return build_model(real_suspension_variant(suspension, seed), NO_LOADS)


#: the random streams of the synthetic data besides the CMM's (``seed``): ``[seed, n]``
NOISE_STREAM, OTHER_SIDE_SHIFT_STREAM, OTHER_SIDE_NOISE_STREAM = 1, 2, 3


def _check_axle(suspension: Suspension) -> None:
    s = suspension
    couplings = side_couplings(s)
    if couplings:
        raise ConfigError(f"{s.source}: key 'kc_test.synthetic': the synthetic real axle is "
                          "made of two independent corners, and this axle's sides are coupled "
                          f"by {', '.join(couplings)}")
    if s.raw["axle"].get("other_side"):
        raise ConfigError(f"{s.source}: key 'kc_test.synthetic': the synthetic real axle's "
                          "other corner is the mirror image of the measured one; leave "
                          "'axle.other_side' out")


def real_axle_variant(suspension: Suspension, seed: int | None = None,
                      own: ModelVariant | None = None) -> ModelVariant:
    """The synthetic real suspension of an axle (module docstring): the config corner's
    (:func:`real_suspension_variant`; ``own`` when it is made already) and the other corner,
    the mirror image of a real corner whose clearance shifts are drawn from
    ``default_rng([seed, 2])``, in one variant. A corner config: the config corner's."""
    s = suspension
    own = real_suspension_variant(s, seed) if own is None else own
    if s.axle is None:
        return own
    _check_axle(s)
    rng = np.random.default_rng([_seed(s, seed), OTHER_SIDE_SHIFT_STREAM])
    mirror = real_corner(s, clearance_shifts(s, rng))
    suffix = s.axle.suffix
    attachments = {}
    for v, tail, M in ((own, "", np.eye(3)), (mirror, suffix, MIRROR)):
        attachments.update({j.name + tail: tuple(M @ np.asarray(x, float)
                                                 for x in j.part_shift_mm)
                            for j in v.suspension.joints if j.part_shift_mm is not None})
    laws = {b.name: b.laws for b in own.suspension.bushings}
    laws.update({b.name + suffix: mirrored_laws(b.laws) for b in mirror.suspension.bushings})
    real = relabelled(with_bushing_laws(with_joint_shifts(s, attachments), laws),
                      f"{s.source} (synthetic real suspension)")
    both = mirrored_design(mirror.preloads, suffix)  # the mirror's under the other side's names
    design = DesignState({**both.spring_force_N, **own.preloads.spring_force_N},
                         {**both.bushing_preload, **own.preloads.bushing_preload})
    f = own.friction
    friction = BallJointFriction({**f.torque_Nmm, **{n + suffix: v for n, v in
                                                     f.torque_Nmm.items()}},
                                 f.presliding_deg, f.substeps)
    return ModelVariant("test", real, design, friction)


def _runs(suspension: Suspension) -> list[tuple[str, list]]:
    """(model, drives) of the real suspension's rig runs: on a corner its load cases; on an
    axle the corner cases on the config's corner alone, then every case on the axle."""
    s = suspension
    runs = [("corner", drives(corner(s), s.rig))]
    if s.axle is not None:
        runs.append(("axle", drives(s, s.rig)))
    return runs


def kc_test_runs(suspension: Suspension) -> int:
    """How many load-case runs (progress messages) :func:`run_real_suspension` makes."""
    return sum(len(ds) for _, ds in _runs(suspension))


def run_real_suspension(suspension: Suspension, seed: int | None = None,
                        progress: Callable[[str], None] = lambda msg: None) -> list[Sweep]:
    """Every load case of the config's rig on the synthetic real suspension (``progress``
    is told of each run before it starts): one sweep per load case and wheel, the config
    side's first; on an axle the corner cases' config side from the corner alone (module
    docstring), everything else from the axle."""
    s = suspension
    if s.axle is not None:
        _check_axle(s)  # before any run
    out: dict[tuple[str, str], Sweep] = {}
    own = real_suspension_variant(s, seed)
    for kind, ds in _runs(s):
        model = build_model(real_axle_variant(s, seed, own) if kind == "axle" else own,
                            NO_LOADS)
        static = static_states(model)  # the rig's zero: the real suspension at rest
        for drive in ds:
            progress(f"synthetic real suspension ({kind}): {drive.load_case}")
            for sw in run_drive_sides(model, "test", drive, static=static):
                out.setdefault((drive.load_case, sw.side), sw)
    return [out[case, side] for case in dict.fromkeys(c for c, _ in out) for side in s.sides
            if (case, side) in out]


def _with_noise(channels: dict[str, np.ndarray], inputs: list[str], spec,
                rngs: dict[str, np.random.Generator]) -> dict[str, np.ndarray]:
    """Rig noise on the measured angle and length channels (not on the rig's inputs, forces
    and torques): each wheel's channels from its own stream (``rngs`` by side; "" the config
    side's and the per-axle channels')."""
    out = {}
    for name, values in channels.items():
        base, side = column_side(name)
        unit = TEST_CHANNELS[base].unit
        sd = {"deg": spec.noise.angle_deg, "mm": spec.noise.length_mm}.get(unit, 0.0)
        if name not in inputs and sd > 0:
            values = values + rngs.get(side, rngs[""]).normal(scale=sd, size=values.size)
        out[name] = values
    return out


def write_kc_test_files(suspension: Suspension, folder: Path | None = None,
                        sweeps: list[Sweep] | None = None, seed: int | None = None,
                        progress: Callable[[str], None] = lambda msg: None) -> list[Path]:
    """Run the real suspension on the rig and write one K&C test CSV per load case into
    ``folder`` (default: ``kc_test.folder`` beside the config), named as ``kc_test.files``
    names it (default ``<load case>.csv``): one wheel's file when the sweeps hold the config
    side only, else both wheels'. Returns the paths."""
    from elastokin.formats.kc_test import write_kc_test

    s = suspension
    spec = _spec(s)
    for case in LOAD_CASES:  # written inside the config's folders (or ``folder``) only
        key = f"kc_test.files.{case}" if case in s.kc_test.files else "kc_test.folder"
        data_file(s, "kc_test", s.kc_test.files.get(case, f"{case}.csv"), key, folder)
    folder = Path(folder) if folder is not None else data_folder(s, "kc_test")
    folder.mkdir(parents=True, exist_ok=True)
    seed = _seed(s, seed)
    sweeps = sweeps if sweeps is not None else run_real_suspension(s, seed, progress)
    rngs = {"": np.random.default_rng([seed, NOISE_STREAM])}  # independent of the CMM noise
    if s.axle is not None:
        rngs[other_side(s.side)] = np.random.default_rng([seed, OTHER_SIDE_NOISE_STREAM])
    paths = []
    for case in dict.fromkeys(sw.load_case for sw in sweeps):
        mine = [sw for sw in sweeps if sw.load_case == case]
        two = any(sw.side not in ("", s.side) for sw in mine)
        channels = axle_test_channels(mine, s) if two else sweep_to_test_channels(mine[0], s)
        inputs = input_columns(case, list(channels))  # the rig's set points: without noise
        channels = _with_noise(channels, inputs, spec, {**rngs, s.side: rngs[""]})
        name = s.kc_test.files.get(case, f"{case}.csv")  # where elastokin kc reads it
        paths.append(write_kc_test(folder / name, case, channels, notes=_notes(s, seed, two)))
    return paths


def _notes(s: Suspension, seed: int, two: bool) -> list[str]:
    notes = [
        "SYNTHETIC K&C test data: the synthetic real suspension of elastokin "
        "(as-built + progressive bushings + ball-joint friction),",
        f"written by `elastokin synthesize --config {Path(s.source).name}`, seed {seed}; "
        "see README 'Case study data'.",
        "units: mm, N, N*mm, deg; per-wheel signs (lateral outboard +, longitudinal "
        "forward +, aligning torque toe-in +)",
    ]
    if two:
        other = other_side(s.side)
        notes.append(f"both wheels (_left, _right): the {other} corner is the {s.side} one's "
                     f"mirror image with its own clearance shifts (stream [{seed}, "
                     f"{OTHER_SIDE_SHIFT_STREAM}])")
    return notes
