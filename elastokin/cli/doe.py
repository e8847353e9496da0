"""``elastokin doe``: tolerance / DOE study of the assembly clearances (see docs/doe.md).

Exit codes:
0 every sample solved; 3 the study completed but some samples failed (doe.json counts and lists
them); 1 bad input (one line on stderr; ``--out`` is checked before any solving); 2 a
command-line usage error; 130 interrupted (finished samples are kept; rerun the same command
to resume). The Python warnings of the study are printed once each as ``elastokin: warning:``
lines.
"""

from __future__ import annotations

import os
import sys
import time
from pathlib import Path

import click

from elastokin.cli.common import WarningLog, check_writable, data_option, fail, os_error, rig_option
from elastokin.errors import ElastokinError

EXIT_FAILED_SAMPLES = 3
EXIT_INTERRUPTED = 130


def _cores() -> int:
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # pragma: no cover - not Linux
        return os.cpu_count() or 1


def _check_out(out: Path, store_name: str) -> None:
    if out.exists() and not out.is_dir():
        raise ElastokinError(f"--out {out}: exists and is not a folder")
    if out.is_dir() and any(out.iterdir()) and not (out / store_name).exists() \
            and not (out / "doe.json").exists():
        raise ElastokinError(f"--out {out}: folder is not empty and holds no elastokin DOE "
                             f"study ({store_name}); choose another folder")
    check_writable(out)


@click.command()
@click.option("--config", "config_path", required=True,
              type=click.Path(dir_okay=False, path_type=Path),
              help="Suspension config whose 'measurements.joints' give clearances.")
@click.option("--samples", required=True, type=int, help="Number of as-built samples (>= 1).")
@click.option("--method", type=click.Choice(["lhs", "sobol", "mc"]), default="lhs",
              show_default=True,
              help="Sampling of the unit cube: Latin hypercube, scrambled Sobol (use a power "
                   "of 2 samples) or Monte Carlo. Sobol and mc studies extend in place when "
                   "rerun with more --samples; an LHS study does not.")
@click.option("--seed", type=int, default=0, show_default=True,
              help="Random seed: the samples depend on (seed, method, samples) only.")
@click.option("--load-cases", type=click.Choice(["all", "travel"]), default="all",
              show_default=True,
              help="'all': every load case of the config's rig; 'travel': parallel wheel "
                   "travel only (steer amplitude, bump steer, bump camber).")
@rig_option
@click.option("--scheduler", default=None, metavar="ADDRESS",
              help="Address of a running dask scheduler (e.g. tcp://host:8786); default: a "
                   "LocalCluster on this machine.")
@click.option("--workers", type=int, default=None, show_default="all cores",
              help="Worker processes of the LocalCluster; 1 runs serially without dask. "
                   "Ignored with --scheduler.")
@click.option("--out", "out_dir", type=click.Path(path_type=Path), metavar="DIRECTORY",
              default=None, show_default="results/<config name>_doe",
              help="Folder for samples.jsonl, doe.json, doe_run.json and the charts.")
@click.option("--restart", is_flag=True,
              help="Discard the samples already saved in --out instead of resuming or "
                   "extending them.")
@click.option("--svg", is_flag=True, help="Also write every chart as SVG (PNG only by "
              "default).")
@click.option("--quiet", is_flag=True, help="No progress bar, no result table.")
@data_option
def doe(config_path: Path, samples: int, method: str, seed: int, load_cases: str,
        rig_path: Path | None, scheduler: str | None, workers: int | None,
        out_dir: Path | None, restart: bool, svg: bool, quiet: bool) -> None:
    """Tolerance / DOE study of the assembly clearances.

    Samples every clearance of 'measurements.joints' within its dL_max, runs the K&C load cases
    on each as-built suspension (on dask.distributed workers), and writes samples.jsonl (one
    record per sample, resumable), doe.json (distributions of steer amplitude and the
    compliance characteristics, joint sensitivity) and histogram and tornado charts.

    Rerun with more --samples to extend a sobol or mc study in place (the samples already
    run are the first ones of the larger design); a Latin hypercube cannot be extended.
    """
    from elastokin.config.loading import load_suspension_with_rig
    from elastokin.report.text import doe_table
    from elastokin.studies import doe as study_mod
    from elastokin.studies.doe_runner import STORE

    t0 = time.perf_counter()
    out_dir = out_dir or Path("results") / f"{config_path.stem}_doe"
    if samples < 1:
        fail(f"--samples: must be at least 1, got {samples}")
    if samples > study_mod.MAX_SAMPLES:
        fail(f"--samples: {samples:,} samples; at most {study_mod.MAX_SAMPLES:,} per study")
    if workers is not None and workers < 1:
        fail(f"--workers: must be at least 1, got {workers}")
    workers = workers or _cores()
    with WarningLog() as log:
        try:
            _check_out(out_dir, STORE)  # before any solving
            suspension = load_suspension_with_rig(config_path, rig_path)
            study = study_mod.make_study(suspension, samples, method, seed, load_cases)
            doc = _run(study, out_dir, restart, quiet, scheduler, workers, t0, svg)
        except KeyboardInterrupt:
            click.echo(f"elastokin: interrupted: the finished samples are saved in "
                       f"{out_dir / 'samples.jsonl'}; rerun the same command to resume",
                       err=True)
            sys.exit(EXIT_INTERRUPTED)
        except ElastokinError as exc:
            fail(str(exc))
        except OSError as exc:
            fail(f"--out {out_dir}: cannot write ({exc.strerror or exc})"
                 if isinstance(exc.filename, str)
                 and Path(exc.filename).is_relative_to(out_dir)
                 else os_error(exc))
    log.echo(doc["warnings"])
    if not quiet:
        click.echo(doe_table(doc, out_dir))
    if doc["failed"]:
        click.echo(f"elastokin: {doc['failed']} of {samples} samples failed (see 'failures' in "
                   f"{out_dir / 'doe.json'}); the statistics use the {samples - doc['failed']} "
                   "that solved", err=True)
        sys.exit(EXIT_FAILED_SAMPLES)


def _run(study, out_dir: Path, restart: bool, quiet: bool, scheduler: str | None,
         workers: int, t0: float, svg: bool) -> dict:
    """The study into ``out_dir`` (resumed or extended from its samples.jsonl): doe.json's
    content."""
    from tqdm import tqdm

    from elastokin.report.files import write_doe_results
    from elastokin.studies import doe as study_mod
    from elastokin.studies.doe_runner import STORE, SampleStore, execute

    samples = study.samples
    store = SampleStore(out_dir / STORE, study.header(), restart)
    store.check_design(study.shifts)
    if restart:
        for old in out_dir.glob("doe*"):
            old.unlink()
    resumed = len(store.records)
    if store.extended_from is not None and not quiet:
        click.echo(f"extending: the {store.extended_from} samples in {out_dir / STORE} are the "
                   f"first of this {samples}-sample {study.method} design; {resumed} of them "
                   "saved", err=True)
    elif resumed and not quiet:
        click.echo(f"resuming: {resumed} of {samples} samples already in "
                   f"{out_dir / STORE}", err=True)
    nominal = study_mod.nominal_characteristics(study)
    solver = study_mod.solver_settings(study)
    pending = samples - resumed
    with tqdm(total=samples, initial=resumed, disable=quiet, file=sys.stderr, leave=False,
              unit="sample", desc="DOE samples") as bar:
        where = execute(study, store, scheduler, workers, bar.update)
    return write_doe_results(out_dir, study, store.ordered(), nominal, solver, {
        "executed_on": where, "samples_evaluated_this_run": pending,
        "samples_resumed": resumed, "extended_from_samples": store.extended_from,
        "wall_time_s": round(time.perf_counter() - t0, 3)}, svg)
