"""``elastokin optimize`` (design to targets) and ``elastokin sensitivity`` (the hardpoint
sensitivity table): thin commands over :mod:`elastokin.studies.design_job`,
:mod:`elastokin.studies.sensitivity_table` and :mod:`elastokin.report.design_report`. The
output folder is checked before any computation; errors end in one line on stderr.

Exit codes: 0 done (optimize: every target met); 4 optimize could not meet every target (the
best point is written, with what binds); 1 bad input; 2 a command-line usage error.
"""

from __future__ import annotations

from pathlib import Path

import click

from elastokin.cli.common import Output, WarningLog, one_line_errors, rig_option
from elastokin.cli.kc import progress_bar

EXIT_NOT_MET = 4
#: design runs the progress bar expects of an optimisation
RUNS_EXPECTED = 12


@click.command()
@click.option("--config", "config_path", required=True,
              type=click.Path(dir_okay=False, path_type=Path),
              help="Suspension config file (its nominal geometry: measurements and K&C test "
                   "data are left out).")
@click.option("--targets", "targets_path", required=True,
              type=click.Path(dir_okay=False, path_type=Path),
              help="Design targets file (YAML: variables, target curves and "
                   "characteristics, constraints; README 'Design to targets').")
@rig_option
@click.option("--out", "out_dir", type=click.Path(path_type=Path), metavar="DIRECTORY",
              default=None, show_default="results/<config name>_optimised",
              help="Folder for the optimised config, design.json, the charts and report.html.")
@click.option("--decimals", type=click.IntRange(0, 9), default=6, show_default=True,
              help="Decimals of the values written into the optimised config (mm, N, ...).")
@click.option("--svg", is_flag=True, help="Also write every chart as SVG.")
@click.option("--quiet", is_flag=True, help="No progress bar, no result table.")
def optimize(config_path: Path, targets_path: Path, rig_path: Path | None,
             out_dir: Path | None, decimals: int, svg: bool, quiet: bool) -> None:
    """Move hardpoints, bushing and spring rates, preloads or the rack within their bounds
    to meet target curves and characteristics (scipy SLSQP on exact gradients).

    Writes <config>_optimised.yaml (every moved value with its old one in a comment),
    design.json, before/after charts against the targets and report.html. When the targets
    cannot all be met, the best point is written, the output says what binds, and the exit
    code is 4.
    """
    from elastokin.report.design_report import write_design_results
    from elastokin.report.text import design_table
    from elastokin.studies.design_job import run_optimize

    def work(suspension, tmp, progress):
        result = run_optimize(suspension, targets_path, progress, decimals)
        progress("writing results")
        return result, write_design_results(result, suspension, config_path, targets_path,
                                            tmp, svg, decimals)

    out_dir = out_dir or Path("results") / f"{config_path.stem}_optimised"
    result, files = _study(out_dir, "design.json", config_path, rig_path, RUNS_EXPECTED,
                           quiet, work)
    if not quiet:
        click.echo(design_table(result))
        click.echo(f"Results in {out_dir}/: {', '.join(files)}")
    if not result.met:
        raise SystemExit(EXIT_NOT_MET)


@click.command()
@click.option("--config", "config_path", required=True,
              type=click.Path(dir_okay=False, path_type=Path),
              help="Suspension config file (its nominal geometry).")
@click.option("--model", type=click.Choice(["initial", "initial_kinematic"]),
              default="initial", show_default=True,
              help="The compliant model (bushings) or the kinematic one (ideal joints).")
@rig_option
@click.option("--out", "out_dir", type=click.Path(path_type=Path), metavar="DIRECTORY",
              default=None, show_default="results/<config name>_sensitivity",
              help="Folder for sensitivity.csv, sensitivity.json, the chart and report.html.")
@click.option("--svg", is_flag=True, help="Also write the chart as SVG.")
@click.option("--quiet", is_flag=True, help="No progress bar, no result table.")
def sensitivity(config_path: Path, model: str, rig_path: Path | None, out_dir: Path | None,
                svg: bool, quiet: bool) -> None:
    """The hardpoint sensitivity table: the exact effect of every hardpoint coordinate, per
    mm, on the summary characteristics (bump steer, bump camber, caster, KPI, scrub, roll
    centre height, roll steer, anti-dive, Ackermann, ...), ranked; from one model run with
    sensitivities. Writes sensitivity.csv, sensitivity.json, a chart and report.html."""
    from elastokin.report.design_report import write_sensitivity_results
    from elastokin.report.text import sensitivity_text
    from elastokin.studies.sensitivity_table import sensitivity_table

    def work(suspension, tmp, progress):
        tab = sensitivity_table(suspension, model, progress)
        progress("writing results")
        return tab, write_sensitivity_results(tab, suspension, tmp, svg)

    out_dir = out_dir or Path("results") / f"{config_path.stem}_sensitivity"
    tab, files = _study(out_dir, "sensitivity.json", config_path, rig_path, 2, quiet, work)
    if not quiet:
        click.echo(sensitivity_text(tab))
        click.echo(f"Results in {out_dir}/: {', '.join(files)}")


def _study(out_dir: Path, marker: str, config_path: Path, rig_path: Path | None,
           stages: int, quiet: bool, work):
    """Run ``work(suspension, folder, progress)`` on the config's nominal geometry into
    ``out_dir`` (checked before anything is computed, replaced only when the run
    succeeds); errors as one line; the run's warnings printed once each."""
    output = Output(out_dir, marker=marker)
    with WarningLog() as log, one_line_errors():
        output.check()
        suspension = nominal_suspension(config_path, rig_path)
        with output as tmp, progress_bar(stages, quiet) as progress:
            out = work(suspension, tmp, progress)
    log.echo()
    return out


def nominal_suspension(config_path: Path, rig_path: Path | None = None):
    """The config's nominal geometry: its own hardpoints, without its CMM and K&C test data
    (a design study moves the design, not a measured car; :func:`elastokin.nominal`)."""
    from elastokin.config.design_variables import nominal
    from elastokin.config.loading import load_suspension_with_rig

    return nominal(load_suspension_with_rig(config_path, rig_path))
