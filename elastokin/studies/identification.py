"""Geometric identification as a study: the paper's method (:mod:`elastokin.identification.
geometric`, pure geometry) with its two solves, the bushing loads at the measured poses (the
paper's equations (22)-(23)) and the verification (the paper's check in its section 5). Units
mm, N, N*mm, deg; config frame."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

from elastokin.config.frozen import plain_data
from elastokin.config.loading import suspension_from_dict
from elastokin.config.suspension import Suspension
from elastokin.config.variants import corner
from elastokin.formats.cmm_motion import motion_paths
from elastokin.identification.geometric import (
    Identification,
    apply_design_loads,
    identify,
    verification_deviations,
)
from elastokin.identification.motion.identify import MotionIdentification, identify_motion
from elastokin.mbs.design import build_model, design_state
from elastokin.rig.load_cases import static_equilibrium
from elastokin.studies.cache import content_key


def identified_suspension(ident: Identification) -> Suspension:
    """The identified model's suspension (its config as written to identified.yaml)."""
    return suspension_from_dict(ident.identified_config,
                                f"{ident.suspension.source} (identified)",
                                ident.suspension.sha256)


def identify_geometry(suspension: Suspension, progress: Callable[[str], None] = lambda m: None,
                      verify: bool = True) -> Identification:
    """Identify the geometry of ``suspension`` from its CMM measurements, solve the identified
    model's bushing deflections at the measured poses and (``verify``) check that its static
    equilibrium puts every joint at its measured location. On an axle the measured corner
    (the config's side) is identified and verified alone; the initial and identified configs
    keep the ``axle`` section, so that their other side is the identified corner mirrored."""
    axle = suspension.raw.get("axle") if suspension.axle is not None else None
    suspension = corner(suspension)
    ident = identify(suspension, progress)
    progress("bushing loads at the measured poses")
    balanced = suspension_from_dict(ident.identified_config,
                                    f"{suspension.source} (identified)")
    apply_design_loads(ident, balanced, design_state(balanced))
    if verify:
        progress("verifying the identified model")
        identified = suspension_from_dict(ident.identified_config,
                                          f"{suspension.source} (identified)")
        model = build_model(identified)
        static_equilibrium(model)
        verification_deviations(ident, identified, model.part_poses())
    if axle is not None:
        for cfg in (ident.initial_config, ident.identified_config):
            cfg["axle"] = plain_data(axle)
    return ident


def motion_files(suspension: Suspension) -> list[Path]:
    """The CMM files of the config's motion plan (for the cache key)."""
    return list(motion_paths(suspension).values())


def cached_step(cache, name: str, key: str, compute: Callable[[], object],
                reused: Callable[[], None]):
    """A step's result from ``cache`` (a :class:`~elastokin.studies.cache.ResultCache` or
    None) when stored under ``name`` for ``key`` (``reused()`` then says so), else
    ``compute()``; stored either way."""
    found = cache.get(name, key) if cache is not None else None
    if found is None:
        found = compute()
    else:
        reused()
    if cache is not None:
        cache.put(name, key, found)
    return found


def motion_geometry(suspension: Suspension, progress: Callable[[str], None] = lambda m: None,
                    cache=None) -> MotionIdentification | None:
    """The step ``motion_geometry`` of the K&C job: the joints located from the parts' motion
    when the config has a motion plan (``motion``; from ``cache`` when the config and the
    files are those it was computed from). On an axle its config keeps the ``axle`` section:
    the other side is the located corner mirrored."""
    if suspension.motion is None:
        return None

    def compute() -> MotionIdentification:
        progress("locating the joints from the parts' motion")
        found = identify_motion(suspension, progress)
        if suspension.axle is not None:
            found.config["axle"] = plain_data(suspension.raw["axle"])
        return found

    key = content_key("motion_geometry", suspension.sha256, *motion_files(suspension))
    return cached_step(cache, "motion_geometry", key, compute, lambda: progress(
        "joints from motion reused (same config and CMM files)"))
