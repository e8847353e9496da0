"""``elastokin kc --vehicle``: the whole car on the rig, a thin command over
:mod:`elastokin.studies.vehicle_job` and :mod:`elastokin.report.vehicle_files`. The output
is checked before any computation; errors end in one line on stderr and exit code 1; the
warnings (the vehicle's data contradicting an axle's, and every warning of both axles' runs)
are printed once each."""

from __future__ import annotations

from pathlib import Path

import click

from elastokin.cli.common import (
    Output,
    WarningLog,
    kc_stages,
    one_line_errors,
    progress_bar,
)


def kc_vehicle(vehicle_path: Path, out_dir: Path | None, rig_path: Path | None,
               models: str | None, refit: bool, svg: bool, quiet: bool) -> None:
    """Run both axles of the vehicle file and write the car's results (README 'The whole
    car')."""
    from elastokin.config.vehicle import ROLES, load_vehicle
    from elastokin.report.vehicle_files import write_vehicle_results
    from elastokin.report.vehicle_text import vehicle_table
    from elastokin.studies.cache import ResultCache
    from elastokin.studies.kc_job import select_models
    from elastokin.studies.vehicle_job import run_vehicle

    out_dir = out_dir or Path("results") / vehicle_path.stem
    output = Output(out_dir)
    with WarningLog() as log, one_line_errors():
        output.check()  # before any computation
        vehicle = load_vehicle(vehicle_path, rig_path)
        stages = 2 + sum(kc_stages(vehicle.axle(role), select_models(vehicle.axle(role),
                                                                   models))
                         for role in ROLES)
        with output as tmp, progress_bar(stages, quiet) as progress:
            caches = {role: ResultCache(out_dir / role / ".cache", tmp / role / ".cache",
                                        enabled=not refit) for role in ROLES}
            run = run_vehicle(vehicle, progress, progress, models, caches)
            progress("writing results")
            run.add_warnings(log.messages)  # into summary.json
            summary = write_vehicle_results(run, tmp, svg)
    log.echo(summary["warnings"])
    if not quiet:
        click.echo(vehicle_table(summary, out_dir))
