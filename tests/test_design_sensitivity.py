"""Exact design sensitivities (mbs/twins.py, mbs/design_tangents.py, studies/design_runs.py)
against central finite differences of full re-runs (the design preloads balanced again, the
model rebuilt, every load case solved again), on both shipped configs, compliant and
kinematic: every column of every sweep of both wheels and every summary figure."""

import numpy as np
import pytest

from elastokin.config.design_variables import DesignVariable, design_suspension
from elastokin.config.loading import read_yaml
from elastokin.mbs.design import design_state
from elastokin.mbs.design_tangents import design_state_tangents
from elastokin.studies.design_runs import run_design

from .conftest import ROOT, make_suspension

DW = ROOT / "configs" / "double_wishbone_axle.yaml"
CASE = ROOT / "configs" / "pseudo_mcpherson.yaml"
#: a channel's change per mm of a hardpoint below which the re-runs (solved to 1e-10 of the
#: residual) do not resolve 1e-4 of it over their +-0.05 mm, by the channel's unit: 1e-4 mm
#: of motion per mm is 0.01 % of the move, nothing a designer sees (per unit of another
#: variable: per 10 % of its value)
FLOOR = {"mm": 1e-4, "deg": 1e-5, "N": 1e-3, "Nmm": 1.0}
#: a summary figure's change below which it is not checked (its unit's resolution)
SUMMARY_FLOOR = {"Nmm": 1.0, "N": 1e-3}
#: short load cases of every kind (a few steps each: the check is per step)
SHORT_RIG = {
    "parallel_travel": {"rebound_mm": -20, "bump_mm": 20, "step_mm": 10},
    "lateral_force": {"amplitude_N": 1000, "step_N": 500},
    "longitudinal_force_patch": {"amplitude_N": 1000, "step_N": 500},
    "longitudinal_force_centre": {"amplitude_N": 1000, "step_N": 500},
    "aligning_torque": {"amplitude_Nmm": 50000, "step_Nmm": 25000},
    "opposite_travel": {"rebound_mm": -20, "bump_mm": 20, "step_mm": 10},
    "single_wheel_travel": {"rebound_mm": -20, "bump_mm": 20, "step_mm": 10},
    "roll_vertical_force": {"amplitude_deg": 1.0, "step_deg": 0.5},
    "lateral_force_anti_phase": {"amplitude_N": 1000, "step_N": 500},
}


@pytest.fixture(autouse=True)
def tight_balancing(monkeypatch):
    """The full re-runs' design balancing to 1e-11 of the wheel load (not 1e-8): its
    iteration stops within the tolerance with an error that varies smoothly with the design,
    a bias of the re-runs' central differences (the double wishbone's coil preload per mm of
    the tie rod's height: 1.414097 at 1e-8, 1.414095 at 1e-11 and exactly)."""
    monkeypatch.setattr("elastokin.mbs.design.BALANCE_TOLERANCE", 1e-11)


def nominal(path, rig: dict):
    """The config's nominal geometry on ``rig``, with the Newton tolerance tightened so that
    full re-runs resolve 1e-4 of a derivative (the balancing's stiff springs allow 1e-10)."""
    data = read_yaml(path)[0]
    data.pop("measurements", None)
    data.pop("kc_test", None)
    data["solver"]["newton_tolerance"] = 1e-10
    data["rig"] = rig
    return make_suspension(data, str(path))


def worst_mismatch(s, variables, labels, step_fd: dict, detail="full"):
    """(worst relative error, where, number of channels checked) of the exact tangents of
    every column and summary figure against central differences of full re-runs."""
    x0 = np.array([v.value(s.raw) for v in variables])
    exact = run_design(s, variables, x0, labels, detail=detail)
    worst, where, checked = 0.0, None, 0
    for k, v in enumerate(variables):
        h = step_fd[v.unit]
        typical = 1.0 if v.unit == "mm" else 0.1 * max(abs(x0[k]), 1.0)
        e = h * np.eye(x0.size)[k]
        runs = [run_design(s, variables, x0 + sign * e, labels, derivatives=False)
                for sign in (1, -1)]
        for label in labels:
            for side in exact.suspension.sides:
                result = exact.models[label]
                sweeps = result.sweeps if side == s.side else result.other_sides[side]
                for sw in sweeps:
                    a, b = (r.sweep(label, sw.load_case, side) for r in runs)
                    for col, tangent in sw.tangents.items():
                        fd = (np.asarray(a.columns[col], float)
                              - np.asarray(b.columns[col], float)) / (2 * h)
                        t = tangent[:, k]
                        ok = np.isfinite(t) & np.isfinite(fd)
                        size = float(np.max(np.abs(fd[ok]), initial=0.0))
                        if size * typical < FLOOR.get(col.rsplit("_", 1)[-1], 1e-5):
                            continue
                        err = float(np.max(np.abs(t[ok] - fd[ok]))) / size
                        checked += 1
                        if err > worst:
                            worst, where = err, (v.name, label, side, sw.load_case, col, size)
            fds = {key: (runs[0].summary[label][key] - runs[1].summary[label][key]) / (2 * h)
                   for key in exact.summary_tangents[label]}
            # the named compliances come from one matrix, a central difference over 10 N
            # whose derivative is exact to ~1e-6 of its largest entry: one that nearly
            # cancels (anti-phase camber of a symmetric axle) is checked against 1 % of the
            # largest of them
            family = max((abs(v) for k, v in fds.items() if "named_compliances" in k),
                         default=0.0)
            # a re-run's figure carries ~1e-8 of its size; a named compliance, a sum of the
            # matrix's entries, ~1e-6 of the largest named compliance in its unit (its
            # solves converge to 1e-10: the entries' noise is absolute; the double
            # wishbone's in-phase longitudinal-force lateral compliance, 1.105 mm/kN, moves
            # by 2e-7 of itself when the model carries the roll case's heave beam, and by up
            # to 5e-7 between force steps of 2.5 to 160 N): over 2 h, its noise
            named = {}
            for key, value in exact.summary[label].items():
                if "named_compliances" in key:
                    unit = "_".join(key.split("_")[-3:])
                    named[unit] = max(named.get(unit, 0.0), abs(value))
            for key, tangent in exact.summary_tangents[label].items():
                fd = fds[key]
                if abs(fd) < SUMMARY_FLOOR.get(key.rsplit("_", 1)[-1], 1e-6):
                    continue
                size = named["_".join(key.split("_")[-3:])] * 1e2 \
                    if "named_compliances" in key else abs(exact.summary[label][key])
                noise = 1e-8 * size / h
                scale = max(abs(fd), 0.01 * family if "named_compliances" in key else 0.0)
                err = max(0.0, abs(tangent[k] - fd) - noise) / scale
                checked += 1
                if err > worst:
                    worst, where = err, (v.name, label, "summary", key)
    return worst, where, checked


def test_design_preload_derivatives_match_rebalancing():
    """The spring force and bushing loads that make the design hardpoints the equilibrium
    move with a hardpoint: exact derivatives against central differences of the balancing
    itself (the case study: ideal-joint balancing, both passes, an axle's two springs)."""
    s = nominal(CASE, {"parallel_travel": SHORT_RIG["parallel_travel"]})
    v = DesignVariable("hardpoint", "J4", 1)
    h, fd_h = 1e-3, 1e-2
    moved = [(design_suspension(s, [v], [v.value(s.raw) + h]),
              design_suspension(s, [v], [v.value(s.raw) - h]), h)]
    _, (tangent,) = design_state_tangents(s, moved)
    a, b = (design_state(design_suspension(s, [v], [v.value(s.raw) + d]))
            for d in (fd_h, -fd_h))
    for name in a.spring_force_N:
        fd = (a.spring_force_N[name] - b.spring_force_N[name]) / (2 * fd_h)
        assert tangent.spring_force_N[name] == pytest.approx(fd, rel=1e-6)
    for name in a.bushing_preload:
        fd = (a.bushing_preload[name] - b.bushing_preload[name]) / (2 * fd_h)
        size = np.max(np.abs(fd))
        assert np.max(np.abs(tangent.bushing_preload[name] - fd)) <= 1e-5 * size, name


def test_case_study_sensitivities_match_full_reruns():
    """The case study, compliant, travel and lateral force, two hardpoint coordinates (the
    tie rod's inner height; the wheel centre's height, on which the travel, the contact
    point and the track depend explicitly): every column and summary figure to 1e-4."""
    rig = {k: v for k, v in SHORT_RIG.items() if k in ("parallel_travel", "lateral_force")}
    rig.update({k: None for k in SHORT_RIG if k not in rig})
    rig["vertical_force"] = None
    s = nominal(CASE, rig)
    variables = [DesignVariable("hardpoint", "J3", 2), DesignVariable("hardpoint", "J9", 2)]
    worst, where, checked = worst_mismatch(s, variables, ("initial",), {"mm": 5e-2})
    assert checked > 100
    assert worst <= 1e-4, where


@pytest.mark.slow
@pytest.mark.parametrize("label", ["initial", "initial_kinematic"])
def test_double_wishbone_sensitivities_match_full_reruns(label):
    """The double wishbone axle (rack, anti-roll bar, stops), every load case of its kind,
    hardpoints (the tie rod's inner height; the wheel centre, on which the contact point, the
    track and the travel depend explicitly), the coil's rate and the rack's ratio: every
    column of both wheels and every summary figure to 1e-4."""
    rig = dict(SHORT_RIG)
    rig["vertical_force"] = {"min_N": 4800, "max_N": 5800, "step_N": 500}
    rig["steering"] = {"amplitude_deg": 90, "step_deg": 45}
    s = nominal(DW, rig)
    variables = [DesignVariable("hardpoint", "tierod_inner", 2),
                 DesignVariable("hardpoint", "wheel_centre", 1),
                 DesignVariable("spring_rate", "coil"), DesignVariable("rack_ratio")]
    steps = {"mm": 5e-2, "N/mm": 5e-2, "mm/rev": 5e-2}
    worst, where, checked = worst_mismatch(s, variables, (label,), steps)
    assert checked > 400
    assert worst <= 1e-4, where


@pytest.mark.slow
@pytest.mark.parametrize("label", ["initial", "initial_kinematic"])
def test_case_study_every_load_case(label):
    """The case study (an axle of two independent corners), every load case, three
    hardpoints and a bushing's translational rates."""
    s = nominal(CASE, {**SHORT_RIG, "vertical_force": {"min_N": 4000, "max_N": 5000,
                                                       "step_N": 500}})
    variables = [DesignVariable("hardpoint", "J3", 2), DesignVariable("hardpoint", "J4", 1),
                 DesignVariable("hardpoint", "J8", 0),
                 DesignVariable("bushing_scale", "J1", directions=("x", "y", "z"))]
    worst, where, checked = worst_mismatch(s, variables, (label,), {"mm": 5e-2, "-": 1e-4})
    assert checked > 300
    assert worst <= 1e-4, where
