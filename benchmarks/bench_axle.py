"""Per-point cost of an axle's load cases, for every shipped kind, against its corner's
(issues 18 and 25, "Measures").

For each suspension, in one run on this machine: the axle (both wheels, the config as it is)
and, for an independent axle, its corner (the config side alone,
``ek.corner``: the config without its ``axle`` section; a solid
axle has none: one part carries both wheels), each built once; then every load case timed on
both (parallel travel, vertical force, and the in-phase force cases), and the axle's own cases
(opposite and single wheel travel, roll, steering, lateral force in anti-phase) on the axle. A
load case's time is that of ``ek.run_drive_sides`` (the solve of
every step, as one ``SolveStatic``, and every channel of both wheels), best of ``--repeat``;
per point = time / the drive's steps. The ratio axle / corner is per point of the same load
case. Suspensions, each at its own rig: the double wishbone axle (rack, anti-roll bar,
bushings, stops), the case study (a decoupled mirrored axle), the multi-link, the
semi-trailing arm, the solid axles with a Panhard rod and with a Watt's linkage, the push-rod
axle with rockers and a heave spring.

The twist beam (configs/twist_beam_axle.yaml) is timed against the same axle with a rigid
cross beam (``ek.rigid_beams``; built with the flexible axle's
design preloads: on two ball joints a rigid axle is over-constrained in the assembly check),
load case by load case: what the flexible beam (its elements and the shear-centre chain)
costs per point.

Each model's static state (the zero of every load case) is solved once, as ``elastokin kc``
does, and not timed. Prints the figures and writes them to
``benchmarks/results/bench_axle.json``, with the machine's load average before and after. No
target: the measure the issues ask for. ``--quick``: parallel travel only
(configs/rigs/travel_only.yaml), one run, the double wishbone, the Panhard solid axle and the
twist beam (bench_common). Through elastokin's public API only.
"""

from __future__ import annotations

import argparse
import os
import platform
import sys
import time
import warnings
from pathlib import Path

import elastokin as ek

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_common import add_output_options, output_path, write_json  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
CONFIGS = {name: ROOT / "configs" / f"{file}.yaml" for name, file in (
    ("double_wishbone_axle", "double_wishbone_axle"), ("case_study", "pseudo_mcpherson"),
    ("multilink", "multilink_axle"), ("semi_trailing_arm", "semi_trailing_arm_axle"),
    ("solid_axle_panhard", "solid_axle_panhard"), ("solid_axle_watt", "solid_axle_watt"),
    ("fsae_pushrod", "fsae_pushrod_axle"))}
TWIST_BEAM = ROOT / "configs" / "twist_beam_axle.yaml"
#: the quick mode (bench_common): parallel travel only, +-50 mm in 2 mm steps, on an
#: independent axle and a solid one (the two ways compare goes) and the twist beam
QUICK_RIG = ROOT / "configs" / "rigs" / "travel_only.yaml"
QUICK_CONFIGS = ("double_wishbone_axle", "solid_axle_panhard")


def best_of(fn, repeat: int) -> float:
    best = float("inf")
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best


def load_case_times(s, repeat: int, design=None) -> tuple[float, dict[str, dict]]:
    """(build s, {load case: {points, total_ms, ms_per_point}}) of suspension ``s`` (with
    these design preloads, or its own)."""
    t0 = time.perf_counter()
    model = ek.build_model(s, design=design)
    build = time.perf_counter() - t0
    static = ek.static_states(model)  # every load case's zero, solved once (as elastokin kc)
    out = {}
    for d in ek.drives(s, kinematic=s.kinematic):
        ek.run_drive_sides(model, "bench", d, static=static)  # paths and sensors set up
        t = best_of(lambda d=d: ek.run_drive_sides(model, "bench", d, static=static), repeat)
        n = int(d.inputs.size)
        out[d.load_case] = {"points": n, "total_ms": 1e3 * t, "ms_per_point": 1e3 * t / n}
    return build, out


def compare(path: Path, repeat: int, rig: Path | None = None) -> dict:
    """The figures of one suspension: the axle's, and its corner's where it has one."""
    axle = ek.load_suspension_with_rig(path, rig)
    build_axle, times_axle = load_case_times(axle, repeat)
    build_corner, times_corner, ratios = None, {}, {}
    if not ek.dependent_axle(axle):
        build_corner, times_corner = load_case_times(ek.corner(axle), repeat)
        ratios = {case: times_axle[case]["ms_per_point"] / c["ms_per_point"]
                  for case, c in times_corner.items() if case in times_axle}
    return {"config": str(path.relative_to(ROOT)), "config_sha256": axle.sha256,
            "build_s": {"axle": build_axle, "corner": build_corner},
            "axle": times_axle, "corner": times_corner,
            "ratio_axle_to_corner_per_point": ratios}


def compare_beam(path: Path, repeat: int, rig: Path | None = None) -> dict:
    """The twist beam's cost per point against the same axle with a rigid cross beam."""
    flexible = ek.load_suspension_with_rig(path, rig)
    design = ek.design_state(flexible)
    build_flexible, times_flexible = load_case_times(flexible, repeat, design)
    build_rigid, times_rigid = load_case_times(ek.rigid_beams(flexible), repeat, design)
    ratios = {case: t["ms_per_point"] / times_rigid[case]["ms_per_point"]
              for case, t in times_flexible.items()}
    return {"config": str(path.relative_to(ROOT)), "config_sha256": flexible.sha256,
            "beam_elements": sum(b.elements_per_segment * (len(b.nodes_mm) - 1)
                                 for b in flexible.beams),
            "build_s": {"flexible": build_flexible, "rigid": build_rigid},
            "flexible": times_flexible, "rigid": times_rigid,
            "ratio_flexible_to_rigid_per_point": ratios}


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=5)
    add_output_options(ap, "bench_axle")
    args = ap.parse_args(argv)
    out = output_path(args, "bench_axle")
    repeat, rig = (1, QUICK_RIG) if args.quick else (args.repeat, None)
    load_before = os.getloadavg()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # e.g. undefined steering axis at a step
        chosen = QUICK_CONFIGS if args.quick else CONFIGS
        figures = {name: compare(CONFIGS[name], repeat, rig) for name in chosen}
        beam = compare_beam(TWIST_BEAM, repeat, rig)
    result = {"elastokin_version": ek.__version__, "exudyn_version": ek.exudyn_version(),
              "quick": args.quick,
              "machine": {"python": platform.python_version(),
                          "processor": platform.machine(), "cpus": os.cpu_count()},
              "repeat": repeat, "load_average_before": load_before,
              "load_average_after": os.getloadavg(), "suspensions": figures,
              "twist_beam": beam}
    write_json(out, result)
    print(f"load average (1, 5, 15 min) before {load_before[0]:.2f} {load_before[1]:.2f} "
          f"{load_before[2]:.2f}, after {result['load_average_after'][0]:.2f}")
    for name, f in figures.items():
        built = f["build_s"]["corner"]
        print(f"\n{name} ({f['config']}): build axle {f['build_s']['axle']:.2f} s, corner "
              + (f"{built:.2f} s" if built is not None else "- (a solid axle)"))
        print(f"  {'load case':<28}{'points':>7}{'axle ms/pt':>12}{'corner ms/pt':>14}"
              f"{'ratio':>8}")
        for case, a in f["axle"].items():
            c = f["corner"].get(case)
            corner_ms = f"{c['ms_per_point']:14.3f}" if c else f"{'-':>14}"
            ratio = f"{f['ratio_axle_to_corner_per_point'][case]:8.2f}" if c else f"{'-':>8}"
            print(f"  {case:<28}{a['points']:7d}{a['ms_per_point']:12.3f}{corner_ms}{ratio}")
    print(f"\ntwist beam ({beam['config']}, {beam['beam_elements']} beam elements) against "
          f"a rigid cross beam: build {beam['build_s']['flexible']:.2f} s / "
          f"{beam['build_s']['rigid']:.2f} s")
    print(f"  {'load case':<28}{'points':>7}{'beam ms/pt':>12}{'rigid ms/pt':>13}{'ratio':>8}")
    for case, t in beam["flexible"].items():
        print(f"  {case:<28}{t['points']:7d}{t['ms_per_point']:12.3f}"
              f"{beam['rigid'][case]['ms_per_point']:13.3f}"
              f"{beam['ratio_flexible_to_rigid_per_point'][case]:8.2f}")
    print(f"\nwritten to {out}")


if __name__ == "__main__":
    main()
