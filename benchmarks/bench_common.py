"""What every benchmark script shares: where its JSON goes and its quick mode.

A benchmark writes ``benchmarks/results/<name>.json`` (committed: the figures the README
quotes). ``--quick`` runs every stage of the script on the smallest inputs, in seconds (the
test suite runs each script so, tests/test_benchmarks.py): its figures mean nothing, so it
writes into the temporary folder (``--out`` elsewhere is fine) and never into
``benchmarks/results``. And two things the K&C benchmarks do through elastokin's public API:
every load case of a model on both wheels, and a K&C run with a recorded field dropped.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import tempfile
from pathlib import Path

import elastokin as ek

ROOT = Path(__file__).resolve().parents[1]
RESULTS = ROOT / "benchmarks" / "results"


def add_output_options(ap: argparse.ArgumentParser, name: str) -> None:
    """``--quick`` and ``--out`` (default: the committed results, or in quick mode the
    temporary folder)."""
    ap.add_argument("--quick", action="store_true",
                    help="every stage on the smallest inputs, in seconds (a smoke run: the "
                         "JSON goes to the temporary folder unless --out says where)")
    ap.add_argument("--out", default=None,
                    help=f"the JSON written (default {RESULTS.relative_to(ROOT)}/{name}.json; "
                         "with --quick the temporary folder)")


def output_path(args: argparse.Namespace, name: str) -> Path:
    """The JSON a run writes (see :func:`add_output_options`); a quick run refuses the
    committed results folder."""
    if args.out is None:
        folder = Path(tempfile.gettempdir()) / "elastokin-benchmarks" if args.quick else RESULTS
        return folder / f"{name}.json"
    out = Path(args.out).resolve()
    if args.quick and RESULTS.resolve() in (out, *out.parents):
        raise SystemExit(f"--quick writes no committed result: --out {args.out} is in "
                         f"{RESULTS.relative_to(ROOT)}")
    return out


def write_json(path: Path, doc: dict) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(doc, indent=2) + "\n")


def load_cases_by_side(model, label: str) -> dict[str, list]:
    """Every load case of ``model``'s rig on every wheel, as ``elastokin kc`` runs them (the
    static state solved once, then each drive): side -> sweeps (the config side's first)."""
    s = model.suspension
    static = ek.static_states(model)
    out: dict[str, list] = {side: [] for side in s.sides}
    for d in ek.drives(s, kinematic=s.kinematic):
        for sw in ek.run_drive_sides(model, label, d, static=static):
            out[sw.side].append(sw)
    return out


def without(run, field: str):
    """The K&C run ``run`` (:func:`elastokin.run_kc`) with ``field`` of every sweep dropped
    (``"loads"``, ``"poses"``: None, as when a model does not record it): what
    :func:`elastokin.write_kc_results` writes without it."""
    def drop(sweeps):
        return [dataclasses.replace(sw, **{field: None}) for sw in sweeps]

    models = {label: dataclasses.replace(m, sweeps=drop(m.sweeps), other_sides={
        side: drop(sweeps) for side, sweeps in m.other_sides.items()})
        for label, m in run.models.items()}
    return dataclasses.replace(run, models=models)
