"""The solve behind ``elastokin view --load-case``: one load case of a config's own model
(its geometry as given, its design preloads), every wheel's sweep with the parts' poses.
Units mm, N, N*mm, deg; config frame."""

from __future__ import annotations

from elastokin.config.suspension import Suspension
from elastokin.config.variants import ModelVariant
from elastokin.errors import ConfigError
from elastokin.mbs.design import build_model
from elastokin.rig.drives import drives
from elastokin.rig.load_cases import run_drive_sides
from elastokin.rig.sweeps import Sweep


def load_case_sweeps(suspension: Suspension, load_case: str) -> list[Sweep]:
    """Every wheel's sweep (config side's first) of the rig's ``load_case`` on the config's
    model (``suspension.label``); a case the rig does not run is an error naming those it
    does."""
    s = suspension
    found = {d.load_case: d for d in drives(s, None, s.kinematic)}
    if load_case not in found:
        rig = f"rig file {s.rig_source}" if s.rig_source else f"{s.source} (its 'rig')"
        raise ConfigError(f"--load-case {load_case}: {rig} runs no such load case on this "
                          f"model; it runs {', '.join(found)}")
    return run_drive_sides(build_model(ModelVariant(s.label, s)), s.label, found[load_case])
