"""``elastokin kc``, ``elastokin identify`` and ``elastokin synthesize``: thin commands over
:mod:`elastokin.studies` and :mod:`elastokin.report`. The output is checked before any
computation; errors in the input end in one line on stderr and exit code 1; the Python warnings
of a run are printed once each as ``elastokin: warning: ...`` lines."""

from __future__ import annotations

import json
from pathlib import Path

import click

from elastokin.cli.common import (
    FIT_RUNS_EXPECTED,
    Output,
    WarningLog,
    check_writable,
    data_hint,
    data_option,
    kc_stages,
    one_line_errors,
    progress_bar,
    rig_option,
)
from elastokin.errors import ElastokinError


@click.command()
@click.option("--config", "config_path", default=None,
              type=click.Path(dir_okay=False, path_type=Path),
              help="Suspension config file (YAML, see README 'Config reference').")
@click.option("--vehicle", "vehicle_path", default=None,
              type=click.Path(dir_okay=False, path_type=Path),
              help="Instead of --config: a vehicle file (YAML, README 'The whole car') naming "
                   "a front and a rear axle config: both axles on the rig with one set of "
                   "vehicle data, and the car's figures (roll stiffness distribution, roll "
                   "axis, understeer from compliance and roll steer, anti-dive and -squat).")
@click.option("--out", "out_dir", type=click.Path(path_type=Path), metavar="DIRECTORY",
              default=None, show_default="results/<config or vehicle file name>",
              help="Folder for kc.csv, summary.json and the charts (with --vehicle: the car's "
                   "summary.json, car.csv, charts and report, each axle's results in front/ "
                   "and rear/); replaced as a whole when the run succeeds, untouched when it "
                   "fails.")
@rig_option
@click.option("--models", "models", default=None, metavar="NAMES",
              help="Comma-separated models to run (default: every model the config yields: "
                   "initial and identified with CMM data, else initial and initial_kinematic; "
                   "identified_motion with a motion plan; identified_stiffness with K&C test "
                   "data). E.g. --models initial,identified skips the stiffness fit.")
@click.option("--refit", is_flag=True,
              help="Recompute the identification and the stiffness fit even when the "
                   "previous results in --out hold them for the same inputs (their cache).")
@click.option("--svg", is_flag=True, help="Also write every chart as SVG (PNG only by "
              "default).")
@click.option("--quiet", is_flag=True, help="No progress bar, no result table.")
@data_option
def kc(config_path: Path | None, vehicle_path: Path | None, out_dir: Path | None,
       rig_path: Path | None, models: str | None, refit: bool, svg: bool, quiet: bool) -> None:
    """Run the virtual K&C rig: static equilibrium under the design wheel load and every
    load case of the config's rig, for each model (initial and identified with CMM data), and
    compare them with the config's K&C test data (kc_test). With --vehicle instead of
    --config: the whole car, both axles on the rig (README 'The whole car').

    Writes kc.csv (one row per model, load case, wheel side and step; units in column names),
    summary.json (characteristics, errors against the test, Table-3 style bushing
    deflections, provenance), the charts (PNG; --svg: also SVG) and a self-contained
    report.html.
    """
    if (config_path is None) == (vehicle_path is None):
        raise click.UsageError("give --config (one suspension) or --vehicle (the whole car)")
    if vehicle_path is not None:
        from elastokin.cli.vehicle import kc_vehicle

        kc_vehicle(vehicle_path, out_dir, rig_path, models, refit, svg, quiet)
        return
    from elastokin.config.loading import load_suspension_with_rig
    from elastokin.report.files import write_kc_results
    from elastokin.report.text import kc_table
    from elastokin.studies.cache import ResultCache
    from elastokin.studies.kc_job import run_kc, select_models

    out_dir = out_dir or Path("results") / config_path.stem
    output = Output(out_dir)
    with WarningLog() as log, one_line_errors():
        output.check()  # before any computation
        suspension = load_suspension_with_rig(config_path, rig_path)
        chosen = select_models(suspension, models)
        with output as tmp, progress_bar(kc_stages(suspension, chosen), quiet) as progress:
            cache = ResultCache(out_dir / ".cache", tmp / ".cache", enabled=not refit)
            # every model run of the fit advances the bar too
            run = run_kc(suspension, progress, progress, chosen, cache)
            progress("writing results")
            run.add_warnings(log.messages)  # into summary.json
            summary = write_kc_results(run, tmp, svg)
    log.echo(summary["warnings"])
    if not quiet:
        click.echo(kc_table(summary, out_dir))


@click.command()
@click.option("--config", "config_path", required=True,
              type=click.Path(dir_okay=False, path_type=Path),
              help="Suspension config with a 'measurements' section (docs/measurements.md).")
@click.option("--out", "out_dir", type=click.Path(path_type=Path), metavar="DIRECTORY",
              default=None, show_default="results/<config name>-identified",
              help="Folder for identified.yaml, initial.yaml, identification.json and "
                   "identification.txt; replaced as a whole when the run succeeds.")
@click.option("--stiffness", is_flag=True,
              help="Then fit the bushing stiffness of the identified model to the config's "
                   "K&C test data (kc_test) and write identified_stiffness.yaml and "
                   "stiffness_identification.json/.txt.")
@click.option("--quiet", is_flag=True, help="No progress, no table.")
@data_option
def identify(config_path: Path, out_dir: Path | None, stiffness: bool, quiet: bool) -> None:
    """Identify the joint locations from CMM data (the reference paper's method) and, with a
    motion plan, from the parts' motion.

    Reads the parts measured alone and the assembled marks, finds every part's pose, and
    writes the identified model as a config that `elastokin kc` loads (identified.yaml: its
    model labelled 'identified', with the config's kc_test and references, so that kc
    compares it with the test), the model built from the parts alone (initial.yaml),
    identification.json and a readable identification.txt (equation numbers of the paper;
    joints identified beyond their clearance dL_max flagged and warned about). With a
    'motion' section, also the joints located from the parts' motion at several rig
    positions (identified_motion.yaml, motion_identification.json/.txt; docs/measurements.md).
    With --stiffness, also the bushing-stiffness identification against the K&C test data
    (identified_stiffness.yaml: the identified model, else identified_motion, with the fitted
    laws).
    """
    from elastokin.config.loading import load_suspension
    from elastokin.formats.kc_test_sweeps import read_test_sweeps
    from elastokin.report.files import (
        motion_dict,
        write_identification_results,
        write_motion_results,
    )
    from elastokin.report.text import identification_table, motion_table
    from elastokin.studies.identification import identify_geometry, motion_geometry

    out_dir = out_dir or Path("results") / f"{config_path.stem}-identified"
    output = Output(out_dir, marker=("identification.json", "motion_identification.json"))
    with WarningLog() as log, one_line_errors():
        output.check()  # before any computation
        suspension = load_suspension(config_path)
        stages = 4 + (suspension.motion is not None) + (2 + FIT_RUNS_EXPECTED) * stiffness
        with output as tmp, progress_bar(stages, quiet) as progress:
            test = read_test_sweeps(suspension)[0] if stiffness else []
            ident = (identify_geometry(suspension, progress=progress)
                     if suspension.measurements is not None or suspension.motion is None
                     else None)
            motion = motion_geometry(suspension, progress)
            result = _identified_fit(suspension, ident, motion, test, progress) \
                if stiffness else None
            progress("writing results")
            files = [] if ident is None else write_identification_results(
                tmp, ident, result, config_path, out_dir)
            doc = None if ident is None else json.loads(
                (tmp / "identification.json").read_text())
            if motion is not None:
                files += write_motion_results(tmp, motion, result if ident is None
                                              else None, config_path, out_dir, doc)
    log.echo([*(ident.all_warnings if ident is not None else []),
              *(motion.warnings if motion is not None else [])])
    if not quiet:
        if ident is not None:
            click.echo(identification_table(ident))
        if motion is not None:
            click.echo(motion_table(motion_dict(motion, {}, doc)))
        if result is not None:
            click.echo(result.table())
        click.echo(f"Results in {out_dir}/: " + ", ".join(files))
        hint = data_hint(out_dir / ("identified.yaml" if ident is not None
                                    else "identified_motion.yaml"), suspension, ("kc_test",))
        if hint:
            click.echo(f"To run the identified model, {hint}")


def _identified_fit(suspension, ident, motion, test, progress):
    """The stiffness fit from the identified model (else the model from motion)."""
    from elastokin.config.loading import suspension_from_dict
    from elastokin.config.variants import ModelVariant
    from elastokin.mbs.design import design_state
    from elastokin.studies.identification import identified_suspension
    from elastokin.studies.kc_job import fit

    if ident is not None:
        start, label = identified_suspension(ident), "identified"
    else:
        label = "identified_motion"
        start = suspension_from_dict(motion.config, f"{suspension.source} ({label})",
                                     suspension.sha256)
    progress("fitting bushing stiffness to the K&C test data")
    return fit(suspension, ModelVariant(label, start, design_state(start)), test, progress)


@click.command()
@click.option("--config", "config_path", required=True,
              type=click.Path(dir_okay=False, path_type=Path),
              help="Nominal suspension config with a 'measurements' section.")
@click.option("--seed", type=int, default=None,
              help="Random seed (default: measurements.synthetic.seed of the config; for the "
                   "motion plan's files motion.synthetic.seed).")
@click.option("--out", "out_dir", type=click.Path(path_type=Path), metavar="DIRECTORY",
              default=None, show_default="the config's measurements.folder",
              help="Folder for the CMM files (the config's measurements.folder by default).")
@click.option("--kc-test-out", "kc_test_dir", type=click.Path(path_type=Path), metavar="DIRECTORY",
              default=None, show_default="the config's kc_test.folder",
              help="Folder for the synthetic K&C test files.")
@click.option("--motion-out", "motion_dir", type=click.Path(path_type=Path),
              metavar="DIRECTORY", default=None, show_default="the config's motion.folder",
              help="Folder for the CMM files of the motion plan (joints from motion).")
@click.option("--only", type=click.Choice(["cmm", "kc-test", "motion"]), default=None,
              help="Write only the CMM files, only the K&C test files or only the motion "
                   "plan's CMM files (default: each the config has a section for; the K&C "
                   "test files with kc_test.synthetic).")
@data_option
def synthesize(config_path: Path, seed: int | None, out_dir: Path | None,
               kc_test_dir: Path | None, motion_dir: Path | None, only: str | None) -> None:
    """Synthetic case-study data: virtual CMM files and K&C rig test files.

    Makes an as-built suspension (bolted joints shifted within their clearance), solves its
    static equilibrium under the design wheel load, and writes what a CMM would give: every
    part measured alone and the assembled marks (IGES and CSV; noisy, scrambled, one wrong
    mark), plus truth.yaml. With a 'kc_test.synthetic' section it also runs the synthetic
    real suspension (as-built + progressive bushings + ball-joint friction) on the rig and
    writes one K&C test CSV per load case. With a 'motion' section, the marks of every part
    of the same as-built suspension at each rig position of the motion plan (seed:
    motion.synthetic.seed). The same config and seed give the same bytes.
    """
    from elastokin.config.confined import data_folder
    from elastokin.config.loading import load_suspension
    from elastokin.synthetic.real_suspension import kc_test_runs, write_kc_test_files
    from elastokin.synthetic.virtual_cmm import synthesize as run_synthesis
    from elastokin.synthetic.virtual_motion import synthesize_motion

    with WarningLog() as log, one_line_errors():
        for option, folder in (("--out", out_dir), ("--kc-test-out", kc_test_dir),
                               ("--motion-out", motion_dir)):
            if folder is not None:  # before any computation
                _check_data_folder(folder, option)
        s = load_suspension(config_path)
        cmm = only == "cmm" or (only is None and (s.measurements is not None
                                                  or s.motion is None))
        kc_test = only == "kc-test" or (only is None and s.kc_test is not None
                                        and s.kc_test.synthetic is not None)
        motion = only == "motion" or (only is None and s.motion is not None)
        # the config's folders: inside its own folder or the working folder (README)
        if cmm and out_dir is None and s.measurements is not None:
            _check_data_folder(data_folder(s, "measurements"), "measurements.folder")
        if kc_test and kc_test_dir is None and s.kc_test is not None:
            _check_data_folder(data_folder(s, "kc_test"), "kc_test.folder")
        if motion and motion_dir is None and s.motion is not None:
            _check_data_folder(data_folder(s, "motion"), "motion.folder")
        written = []
        with progress_bar(cmm + motion + (kc_test_runs(s) if kc_test else 0)) as progress:
            if cmm:
                progress("virtual CMM: as-built suspension and its measurements")
                files = run_synthesis(s, seed, out_dir)
                written.append(f"wrote {len(files)} files in {files[0].parent}/: "
                               + ", ".join(f.name for f in files))
            if motion:
                progress("virtual CMM: the as-built suspension at every rig position")
                files = synthesize_motion(s, seed, motion_dir)
                written.append(f"wrote {len(files)} files in {files[0].parent}/ (the "
                               "motion plan)")
            if kc_test:
                files = write_kc_test_files(s, kc_test_dir, seed=seed, progress=progress)
                written.append(f"wrote {len(files)} K&C test files in "
                               f"{files[0].parent}/: " + ", ".join(f.name for f in files))
    log.echo()
    click.echo("\n".join(written))


def _check_data_folder(folder: Path, option: str) -> None:
    """A folder synthesize writes its files into (keeping other files): not a file, and
    writable."""
    if folder.exists() and not folder.is_dir():
        raise ElastokinError(f"{option} {folder}: exists and is not a folder")
    check_writable(folder, option)
