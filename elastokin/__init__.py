"""elastokin: suspension elastokinematics and geometric identification on Exudyn.

Units at every interface: mm, N, N*mm, deg; the config frame (README "Sign conventions").

The public Python API (the CLI is a thin layer over it)::

    import elastokin as ek

    s = ek.load_suspension("configs/pseudo_mcpherson.yaml")      # validated, resolved
    run = ek.run_kc(s)                                            # the whole K&C job
    ek.write_kc_results(run, Path("results/mine"))                # kc.csv, summary.json, ...

    moved = ek.with_hardpoints(s, {"J3": s.hardpoints["J3"] + [0, 0, 5]})  # a new one
    model = ek.build_model(ek.kinematic(s))                       # one model variant
    sweeps = ek.run_load_cases(model, "kinematic")                # every load case of the rig
    ident = ek.identify_geometry(s)                               # the paper's method
    motion = ek.identify_motion(s)             # joints from the parts' motion (a 'motion' plan)
    car = ek.run_vehicle(ek.load_vehicle("configs/vehicle_hmmwv.yaml"))   # the whole car

A resolved :class:`Suspension` is read-only: ``s.hardpoints["J3"] = ...`` raises and names
``with_hardpoints``; ``copy.deepcopy(s.raw)`` is the config mapping to edit (numpy numbers
welcome) and ``suspension_from_dict`` loads it.

Names are imported on first use, so ``import elastokin`` stays light (no Exudyn, no
matplotlib until a model is built or a chart drawn).
"""

from __future__ import annotations

from importlib import import_module

from elastokin.version import __version__

#: public name -> module that defines it
_API = {
    # config: load and vary suspensions
    "load_suspension": "elastokin.config.loading",
    "load_suspension_with_rig": "elastokin.config.loading",
    "load_rig": "elastokin.config.loading",
    "suspension_from_dict": "elastokin.config.loading",
    "data_folders": "elastokin.config.confined",
    "Suspension": "elastokin.config.suspension",
    "ModelVariant": "elastokin.config.variants",
    "DesignState": "elastokin.config.variants",
    "kinematic": "elastokin.config.variants",
    "with_hardpoints": "elastokin.config.variants",
    "with_bushing_laws": "elastokin.config.variants",
    "with_joint_shifts": "elastokin.config.variants",
    "corner": "elastokin.config.variants",
    "rigid_beams": "elastokin.config.variants",
    # models
    "build_model": "elastokin.mbs.design",
    "design_state": "elastokin.mbs.design",
    "ModelOptions": "elastokin.mbs.model",
    # the rig
    "run_load_cases": "elastokin.rig.load_cases",
    "run_drive": "elastokin.rig.load_cases",
    "run_drive_sides": "elastokin.rig.load_cases",
    "drives": "elastokin.rig.load_cases",
    "parallel_travel": "elastokin.rig.load_cases",
    "parallel_travel_drive": "elastokin.rig.load_cases",
    "static_equilibrium": "elastokin.rig.load_cases",
    "static_states": "elastokin.rig.load_cases",
    "compliance_matrix": "elastokin.rig.load_cases",
    "run_pad": "elastokin.rig.pad",
    "summary_figures": "elastokin.rig.characteristics",
    "steer_amplitude_deg": "elastokin.rig.characteristics",
    "dependent_axle": "elastokin.rig.axle_channels",
    "Sweep": "elastokin.rig.sweeps",
    "CHANNELS": "elastokin.rig.channels",
    # identification and studies
    "identify_geometry": "elastokin.studies.identification",
    "identify_motion": "elastokin.identification.motion.identify",
    "identify_stiffness": "elastokin.identification.stiffness",
    "run_kc": "elastokin.studies.kc_job",
    "run_kc_from_identification": "elastokin.studies.kc_job",
    "run_kc_from_variants": "elastokin.studies.kc_job",
    "KCRun": "elastokin.studies.kc_job",
    "read_test_sweeps": "elastokin.formats.kc_test_sweeps",
    "real_suspension_model": "elastokin.synthetic.real_suspension",
    # tolerance studies (DOE)
    "make_study": "elastokin.studies.doe",
    "evaluate_sample": "elastokin.studies.doe",
    "as_built_model": "elastokin.studies.doe",
    "travel_sweep": "elastokin.studies.doe",
    "run_dask": "elastokin.studies.doe_runner",
    # design to targets
    "DesignVariable": "elastokin.config.design_variables",
    "design_suspension": "elastokin.config.design_variables",
    "load_targets": "elastokin.formats.targets",
    "run_design": "elastokin.studies.design_runs",
    "run_optimize": "elastokin.studies.design_job",
    "sensitivity_table": "elastokin.studies.sensitivity_table",
    # the whole car
    "load_vehicle": "elastokin.config.vehicle",
    "run_vehicle": "elastokin.studies.vehicle_job",
    "run_vehicle_from_axles": "elastokin.studies.vehicle_job",
    "VehicleRun": "elastokin.studies.vehicle_job",
    # results
    "write_kc_results": "elastokin.report.files",
    "read_results": "elastokin.report.files",
    "draw_kc_charts": "elastokin.report.charts",
    "write_vehicle_results": "elastokin.report.vehicle_files",
    "read_vehicle_results": "elastokin.report.vehicle_files",
    # provenance
    "exudyn_version": "elastokin.version",
}

__all__ = ["__version__", *_API]


def __getattr__(name: str):
    if name in _API:
        value = getattr(import_module(_API[name]), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'elastokin' has no attribute '{name}'")


def __dir__() -> list[str]:
    return sorted(__all__)

