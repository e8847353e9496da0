"""``elastokin kc``, ``elastokin identify`` and ``elastokin synthesize``: thin commands over
:mod:`elastokin.studies` and :mod:`elastokin.report`. Errors in the input end in one line on
stderr and exit code 1."""

from __future__ import annotations

import sys
from pathlib import Path

import click

from elastokin.cli.common import Output, fail, rig_option
from elastokin.errors import ElastokinError


@click.command()
@click.option("--config", "config_path", required=True,
              type=click.Path(dir_okay=False, path_type=Path),
              help="Suspension config file (YAML, see README 'Config reference').")
@click.option("--out", "out_dir", type=click.Path(file_okay=False, path_type=Path),
              default=None, show_default="results/<config name>",
              help="Folder for kc.csv, summary.json and the charts; replaced as a whole when "
                   "the run succeeds, untouched when it fails.")
@rig_option
@click.option("--quiet", is_flag=True, help="No progress bar, no result table.")
def kc(config_path: Path, out_dir: Path | None, rig_path: Path | None, quiet: bool) -> None:
    """Run the virtual K&C rig: static equilibrium under the design wheel load and every
    load case of the config's rig, for each model (initial and identified with CMM data), and
    compare them with the config's K&C test data (kc_test).

    Writes kc.csv (one row per model, load case and step; units in column names),
    summary.json (characteristics, errors against the test, Table-3 style bushing
    deflections, provenance), the charts (PNG + SVG) and a self-contained report.html.
    """
    from tqdm import tqdm

    from elastokin.config.loading import load_suspension_with_rig
    from elastokin.mbs.model import EXUDYN_VERSION
    from elastokin.report.charts import kc_charts
    from elastokin.report.files import (
        provenance,
        summary_dict,
        write_identification,
        write_kc_csv,
        write_stiffness_identification,
        write_summary,
    )
    from elastokin.report.html import write_report
    from elastokin.studies.kc_job import fits_stiffness, model_labels, run_vertical_kc

    out_dir = out_dir or Path("results") / config_path.stem
    try:
        suspension = load_suspension_with_rig(config_path, rig_path)
        labels = model_labels(suspension)
        stages = (3 + 2 * len(labels) + (suspension.measurements is not None)
                  + 2 * fits_stiffness(suspension))
        with tqdm(total=stages, disable=quiet, file=sys.stderr, leave=False,
                  bar_format="{desc:<52} {bar} {n_fmt}/{total_fmt} [{elapsed}]") as bar:
            def progress(msg: str) -> None:
                bar.set_description_str(msg)
                bar.update(1)
            run = run_vertical_kc(suspension, progress,
                                  lambda m: bar.set_description_str(m, refresh=False))
            progress("writing results")
            with Output(out_dir) as tmp:
                prov = provenance(run, EXUDYN_VERSION)
                sweeps = [sw for m in run.models.values() for sw in m.sweeps]
                write_kc_csv(tmp / "kc.csv", sweeps, prov)
                files = ["kc.csv", "summary.json"]
                if run.identification is not None:
                    write_identification(tmp, run.identification, prov)
                    files += ["identification.json", "identification.txt"]
                if run.stiffness is not None:
                    files += write_stiffness_identification(tmp, run.stiffness, prov)
                charts = kc_charts(sweeps, tmp, prov)
                files += [p.name for p in charts] + ["report.html"]
                summary = summary_dict(run, EXUDYN_VERSION, files)
                write_summary(tmp / "summary.json", summary)
                write_report(tmp / "report.html", summary, charts)
    except ElastokinError as exc:
        fail(str(exc))
    if not quiet:
        click.echo(_report(summary, out_dir))


def _report(summary: dict, out_dir: Path) -> str:
    lines = [f"elastokin {summary['elastokin_version']} (exudyn {summary['exudyn_version']}), "
             f"config {summary['config_file']} sha256 {summary['config_sha256'][:12]}"
             + (f", rig {summary['rig_file']}" if summary.get("rig_file") else ""), ""]
    st = summary["static"]
    residual = st["wheel_assembly_force_residual_N"]
    lines.append(f"Static equilibrium under {st['wheel_load_N']:g} N wheel load "
                 f"(force residual on the wheel assembly {residual:.1e} N)")
    lines.append(f"  {'bushing':<10}{'radial mm':>11}{'axial mm':>10}{'torsion deg':>13}"
                 f"   reference {st['reference_source']}")
    for name, b in st["bushings"].items():
        ref = b.get("reference", {})
        ref_txt = ", ".join(f"{k} {v:g}" for k, v in ref.items())
        lines.append(f"  {name:<10}{b['radial_mm']:>11.3f}{b['axial_mm']:>10.3f}"
                     f"{b['torsion_deg']:>13.4f}   {ref_txt}")
    lines.append("")
    def num(v, fmt):
        return "-" if v is None else format(v, fmt)

    errors = summary.get("errors", {})
    head = f"  {'model':<22}{'steer amplitude deg':>21}{'bump steer deg/m':>18}"
    if errors:
        head += f"{'RMS error: steer/travel deg':>29}{'steer/lateral deg':>19}" \
                f"{'long. disp. mm':>16}"
    lines.append(head)
    for label, m in summary["models"].items():
        row = f"  {label:<22}{num(m['steer_amplitude_deg'], '.4f'):>21}" \
              f"{num(m['bump_steer_deg_per_m'], '.3f'):>18}"
        e = errors.get(label)
        if e:
            row += f"{num(e['steer_vs_travel_rms_deg'], '.4f'):>29}" \
                   f"{num(e['steer_vs_lateral_force_rms_deg'], '.4f'):>19}" \
                   f"{num(e['longitudinal_displacement_rms_mm'], '.3f'):>16}"
        lines.append(row)
    refs = summary["reference"]["steer_amplitude_deg"]
    if refs:
        lines.append("  reference steer amplitude (deg): "
                     + ", ".join(f"{k} {v:g}" for k, v in refs.items()))
    lines += [f"  warning: {w}" for w in summary.get("warnings", [])]
    fit = summary.get("stiffness_identification")
    if fit:
        lines += ["", "Bushing stiffness fitted to the test (model identified_stiffness; "
                  f"details in {fit['file']}):"]
        for key, v in fit["parameters"].items():
            state = "" if v["determined"] else "  not determined"
            lines.append(f"  {key:<26}{v['value']:>10.4g} {v['unit']:<8} 95 % "
                         f"[{v['ci95'][0]:.4g}, {v['ci95'][1]:.4g}]{state}")
    lines.append("")
    lines.append(f"Results in {out_dir}/: " + ", ".join(summary["files"]))
    return "\n".join(lines)


@click.command()
@click.option("--config", "config_path", required=True,
              type=click.Path(dir_okay=False, path_type=Path),
              help="Suspension config with a 'measurements' section (docs/measurements.md).")
@click.option("--out", "out_dir", type=click.Path(file_okay=False, path_type=Path),
              default=None, show_default="results/<config name>-identified",
              help="Folder for identified.yaml, initial.yaml, identification.json and "
                   "identification.txt; replaced as a whole when the run succeeds.")
@click.option("--stiffness", is_flag=True,
              help="Then fit the bushing stiffness of the identified model to the config's "
                   "K&C test data (kc_test) and write identified_stiffness.yaml and "
                   "stiffness_identification.json/.txt.")
@click.option("--quiet", is_flag=True, help="No progress, no table.")
def identify(config_path: Path, out_dir: Path | None, stiffness: bool, quiet: bool) -> None:
    """Identify the joint locations from CMM data (the reference paper's method).

    Reads the parts measured alone and the assembled marks, finds every part's pose, and
    writes the identified model as a config that `elastokin kc` loads (identified.yaml), the
    model built from the parts alone (initial.yaml), identification.json and a readable
    identification.txt. With --stiffness, also the bushing-stiffness identification against
    the K&C test data (identified_stiffness.yaml: the identified model with the fitted laws).
    """
    from elastokin.config.loading import load_suspension, suspension_from_dict
    from elastokin.identification.geometric import identify as run_identification
    from elastokin.identification.geometric import write_config
    from elastokin.identification.stiffness import stiffness_config
    from elastokin.mbs.model import EXUDYN_VERSION, design_state
    from elastokin.report.files import (
        config_provenance,
        identification_table,
        write_identification,
        write_stiffness_identification,
    )
    from elastokin.studies.comparison import read_test_sweeps
    from elastokin.studies.kc_job import fit_stiffness

    out_dir = out_dir or Path("results") / f"{config_path.stem}-identified"
    try:
        suspension = load_suspension(config_path)
        say = (lambda m: None) if quiet else (lambda m: click.echo(f"  {m} ...", err=True))
        test = read_test_sweeps(suspension)[0] if stiffness else []
        ident = run_identification(suspension, progress=say)
        fit = None
        if stiffness:
            start = suspension_from_dict(ident.identified_config,
                                         f"{suspension.source} (identified)", suspension.sha256)
            say("fitting bushing stiffness to the K&C test data (about a minute)")
            fit = fit_stiffness(suspension, start, design_state(start), test)
        prov = config_provenance(suspension, EXUDYN_VERSION)
        with Output(out_dir, marker="identification.json") as tmp:
            header = (f"elastokin {prov['elastokin_version']} (exudyn "
                      f"{prov['exudyn_version']}): {{what}} of {config_path} (sha256 "
                      f"{prov['config_sha256'][:12]}).\nUnits: lengths mm, forces N, torques "
                      "N*mm, angles deg; config frame.")
            write_config(tmp / "identified.yaml", ident.identified_config,
                         header.format(what="identified model (joints from the assembled "
                                       "measurement, bushing deflections at equilibrium)"))
            write_config(tmp / "initial.yaml", ident.initial_config,
                         header.format(what="initial model (joints from the parts measured "
                                       "alone, undeflected bushings)"))
            write_identification(tmp, ident, prov)
            files = ["identified.yaml", "initial.yaml", "identification.json",
                     "identification.txt"]
            if fit is not None:
                write_config(tmp / "identified_stiffness.yaml",
                             stiffness_config(ident.identified_config, fit),
                             header.format(what="identified model with the bushing laws "
                                           "fitted to the K&C test data"))
                files += ["identified_stiffness.yaml",
                          *write_stiffness_identification(tmp, fit, prov)]
    except ElastokinError as exc:
        fail(str(exc))
    if not quiet:
        click.echo(identification_table(ident))
        if fit is not None:
            click.echo(fit.table())
        click.echo(f"Results in {out_dir}/: " + ", ".join(files))


@click.command()
@click.option("--config", "config_path", required=True,
              type=click.Path(dir_okay=False, path_type=Path),
              help="Nominal suspension config with a 'measurements' section.")
@click.option("--seed", type=int, default=None,
              help="Random seed (default: measurements.synthetic.seed of the config).")
@click.option("--out", "out_dir", type=click.Path(file_okay=False, path_type=Path),
              default=None, show_default="the config's measurements.folder",
              help="Folder for the CMM files (the config's measurements.folder by default).")
@click.option("--kc-test-out", "kc_test_dir", type=click.Path(file_okay=False, path_type=Path),
              default=None, show_default="the config's kc_test.folder",
              help="Folder for the synthetic K&C test files.")
@click.option("--only", type=click.Choice(["cmm", "kc-test"]), default=None,
              help="Write only the CMM files or only the K&C test files (default: both, the "
                   "K&C test files when the config has kc_test.synthetic).")
def synthesize(config_path: Path, seed: int | None, out_dir: Path | None,
               kc_test_dir: Path | None, only: str | None) -> None:
    """Synthetic case-study data: virtual CMM files and K&C rig test files.

    Makes an as-built suspension (bolted joints shifted within their clearance), solves its
    static equilibrium under the design wheel load, and writes what a CMM would give: every
    part measured alone and the assembled marks (IGES and CSV; noisy, scrambled, one wrong
    mark), plus truth.yaml. With a 'kc_test.synthetic' section it also runs the synthetic
    real suspension (as-built + progressive bushings + ball-joint friction) on the rig and
    writes one K&C test CSV per load case. The same config and seed give the same bytes.
    """
    from elastokin.config.loading import load_suspension
    from elastokin.synthetic.real_suspension import write_kc_test_files
    from elastokin.synthetic.virtual_cmm import synthesize as run_synthesis

    try:
        s = load_suspension(config_path)
        written = []
        if only in (None, "cmm"):
            files = run_synthesis(s, seed, out_dir)
            written.append(f"wrote {len(files)} files in {files[0].parent}/: "
                           + ", ".join(f.name for f in files))
        if only == "kc-test" or (only is None and s.kc_test is not None
                                 and s.kc_test.synthetic is not None):
            files = write_kc_test_files(s, kc_test_dir, seed=seed)
            written.append(f"wrote {len(files)} K&C test files in {files[0].parent}/: "
                           + ", ".join(f.name for f in files))
    except ElastokinError as exc:
        fail(str(exc))
    click.echo("\n".join(written))
