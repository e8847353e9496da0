"""What every benchmark script shares: where its JSON goes and its quick mode.

A benchmark writes ``benchmarks/results/<name>.json`` (committed: the figures the README
quotes). ``--quick`` runs every stage of the script on the smallest inputs, in seconds (the
test suite runs each script so, tests/test_benchmarks.py): its figures mean nothing, so it
writes into the temporary folder (``--out`` elsewhere is fine) and never into
``benchmarks/results``.
"""

from __future__ import annotations

import argparse
import json
import tempfile
from pathlib import Path

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
